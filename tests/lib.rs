//! Integration tests of the DAE compiler live in `tests/tests/`.
