//! `dae-runtime`: simulation of DAE models by discretized bounded sliding mode control.
#![warn(missing_docs)]

mod model;

pub use model::{Model, w_offsets};
