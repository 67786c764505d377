//! `dae-bench`: speed against accuracy for DAE simulation methods.
#![warn(missing_docs)]

mod baseline;
mod harness;
mod initial;
mod linalg;
mod scenes;
mod stability;
mod standin;
mod truth;

pub use baseline::*;
pub use harness::{
    ErrorAxis, Method, Record, Scene, chart, pilot_beta_bound, run_method, write_csv,
};
pub use initial::WithInitial;
pub use linalg::{Lu, Singular};
pub use scenes::{SceneError, TRUTH_TOL, chain_scene};
pub use stability::{
    DRIFT_GROWTH, Envelope, StabilityRow, Verdict, envelope_run, judge, largest_step_row,
    stability_row, with_step, write_table,
};
pub use standin::{MAX_LINKS, PlanarChainDae};
pub use truth::{
    ChainWork, Extrapolation, PlanarChain, Reference, TruthError, TruthStats, reference,
};
