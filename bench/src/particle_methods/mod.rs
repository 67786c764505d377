//! The methods DBSMC is compared with on particle scenes, as
//! [`dae_particles::Backend`]s: XPBD with zero compliance and the index-1 reduction
//! with an exact solve at every stage; Vertex Block Descent on stiff springs and
//! Augmented VBD with hard links; and the scenes' generated family models as particle
//! models for DBSMC.

mod avbd;
mod family_models;
mod index1;
mod substeps;
mod vbd;
mod vertex_blocks;
mod xpbd;

pub use family_models::{
    ChainKernels, ClothKernels, HairKernels, generated_chain, generated_grid, generated_strands,
};

pub use avbd::{Avbd, AvbdOptions};
pub use index1::{IndexOneParticles, PilotBounds};
pub use vbd::{DEFAULT_STIFFNESS, Vbd, VbdOptions};
pub use xpbd::{SweepOrder, Xpbd};
