//! Procedural macros for DAE models; all logic lives in `dae-lang`.
