//! Example models and scenes of the DAE compiler (see `examples/models/` and `examples/examples/`).

pub mod chapter5;
