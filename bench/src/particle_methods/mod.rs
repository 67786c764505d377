//! The methods DBSMC is compared with on particle scenes, as
//! [`dae_particles::Backend`]s: XPBD with zero compliance and the index-1 reduction
//! with an exact solve at every stage.

mod family;
mod index1;
mod xpbd;

pub use family::{ChainKernels, FamilyChain};

pub use index1::{IndexOneParticles, PilotBounds};
pub use xpbd::Xpbd;
