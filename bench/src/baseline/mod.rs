//! The methods DBSMC is compared with.

mod bdf;
mod index1;
mod spsm;

pub use bdf::{BdfSettings, BdfSummary, bdf_index1};
pub use index1::{
    BaselineError, IndexOneRk4, IndexOneSettings, IndexOneSummary, Observer, ZSolver,
};
pub use spsm::{StepSearch, consistent_alg, largest_stable_step, spsm_stable};
