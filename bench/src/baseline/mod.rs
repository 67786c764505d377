//! The methods DBSMC is compared with.

#[cfg(feature = "bdf")]
mod bdf;
mod index1;
mod spsm;

#[cfg(feature = "bdf")]
pub use bdf::{BdfSettings, BdfSummary, bdf_index1};
pub use index1::{
    BaselineError, IndexOneRk4, IndexOneSettings, IndexOneSummary, Observer, ZSolver,
};
pub use spsm::{StepSearch, consistent_alg, largest_stable_step, spsm_stable};
