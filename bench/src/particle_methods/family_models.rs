//! The scenes C1-C4 from generated family models: each `.dae` family is compiled once
//! by `dae_file!` into loops over its sets, sized here at run time to the scene, and
//! run behind [`FamilyParticles`] as the particle model of the scene's [`System`].
//!
//! * C1 chains: `examples/models/chain.dae` (`N` links, end-mass ratio `m_end`);
//! * C2 hair: `bench/models/c2_hair.dae` (`S` strands of `N` links; the example
//!   `hair.dae` puts its roots elsewhere and drives them through one head input);
//! * C3 cloth and C4: `bench/models/c3_cloth.dae` (`W`, the far edge's pins `E`, rigid
//!   diagonals `D`, the heavy corner `heavy`; the example `cloth.dae` has shear springs,
//!   only the corner pins of (a) and another link order).
//!
//! Each is the same physics as the builder of `dae_particles` it stands for;
//! [`FamilyParticles::new`] checks it against the system it is given, and
//! `bench/tests/suite/generated_particles.rs` checks `f`, `w`, `s`, `alpha_hat`, `J_Omega` and `beta`
//! against the hand-written [`dae_particles::ParticleModel`].

use dae_particles::{FamilyParticles, GridPins, System};
use dae_runtime::family::Spec;

mod chain {
    dae_runtime::dae_file!("../examples/models/chain.dae");
}
mod hair {
    dae_runtime::dae_file!("models/c2_hair.dae");
}
mod cloth {
    dae_runtime::dae_file!("models/c3_cloth.dae");
}

/// The generated kernels of `examples/models/chain.dae`.
pub use chain::Chain as ChainKernels;
/// The generated kernels of `bench/models/c3_cloth.dae`.
pub use cloth::ClothScene as ClothKernels;
/// The generated kernels of `bench/models/c2_hair.dae`.
pub use hair::HairScene as HairKernels;

fn sizes(sizes: &[(&str, usize)]) -> Vec<(String, i64)> {
    sizes
        .iter()
        .map(|&(name, v)| (name.to_string(), v as i64))
        .collect()
}

/// `chain.dae` at `links` links and end-mass ratio `end_mass_ratio`, as the particle
/// model of `system` (`dae_particles::chain(links, end_mass_ratio)`, scene C1).
pub fn generated_chain(
    system: &System,
    links: usize,
    end_mass_ratio: f64,
) -> Result<FamilyParticles<ChainKernels>, String> {
    let spec = Spec {
        sizes: sizes(&[("N", links)]),
        params: vec![("m_end".into(), end_mass_ratio)],
        ..Spec::default()
    };
    let model = ChainKernels::new(&spec).map_err(|e| e.to_string())?;
    FamilyParticles::new(model, system).map_err(|e| e.to_string())
}

/// `c2_hair.dae` at `strands` strands of `links` links, as the particle model of
/// `system` (`dae_particles::strands(strands, links)`, scene C2, whose roots' motions
/// drive the inputs).
pub fn generated_strands(
    system: &System,
    strands: usize,
    links: usize,
) -> Result<FamilyParticles<HairKernels>, String> {
    let spec = Spec {
        sizes: sizes(&[("S", strands), ("N", links)]),
        ..Spec::default()
    };
    let model = HairKernels::new(&spec).map_err(|e| e.to_string())?;
    FamilyParticles::new(model, system).map_err(|e| e.to_string())
}

/// `c3_cloth.dae` at `w x w` particles held as `pins` says, with rigid diagonals if
/// `shear` and the far edge's `slack`, as the particle model of `system`
/// (`dae_particles::grid_with_slack(w, pins, shear, slack)`, scenes C3 and C4).
pub fn generated_grid(
    system: &System,
    w: usize,
    pins: GridPins,
    shear: bool,
    slack: f64,
) -> Result<FamilyParticles<ClothKernels>, String> {
    let edge = usize::from(pins == GridPins::Edge);
    let heavy = if pins == GridPins::CornersHeavy {
        100.0
    } else {
        1.0
    };
    let spec = Spec {
        sizes: sizes(&[("W", w), ("E", edge), ("D", usize::from(shear))]),
        params: vec![("heavy".into(), heavy), ("slack".into(), slack)],
        ..Spec::default()
    };
    let model = ClothKernels::new(&spec).map_err(|e| e.to_string())?;
    FamilyParticles::new(model, system).map_err(|e| e.to_string())
}
