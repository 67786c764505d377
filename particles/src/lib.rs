//! `dae-particles`: chains, hair strands and cloth made of particles joined by rigid
//! links, simulated frame by frame.
#![warn(missing_docs)]

mod backend;
mod builders;
mod dbsmc;
mod model;
mod motion;
mod scene;
mod system;

pub use backend::{Backend, BackendError, Counters};
pub use builders::{
    FAR_EDGE_SLACK, GridPins, HEAD_RADIUS, STRAND_LENGTH, STRAND_PARTICLE_MASS, chain, grid, grid_index, strands,
};
pub use dbsmc::Dbsmc;
pub use model::{ModelError, ParticleDae, ParticleModel};
pub use motion::{GrabPath, Kinematics, Motion, Pin, Sway, smoothstep7};
pub use scene::{FRAME, Frame, Scene, SceneError, WorstStrain};
pub use system::{
    Edge, GRAVITY, Link, System, SystemError, distance, parse_edge_list, worst_strain,
};
