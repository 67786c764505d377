//! The C1 chain from the family model `examples/models/chain.dae`: written once over
//! the sets of particles and links, compiled by `dae_file!` into loops, and sized here
//! at run time (`N` links, end-mass ratio `m_end`), behind the particle seam
//! ([`ParticleDae`]) so that the DBSMC backend runs it exactly as it runs the
//! hand-written [`dae_particles::ParticleModel`].
//!
//! The family model is the same physics as `dae_particles::chain` (links of `1/N` m,
//! particles of `0.1/N` kg, the end `m_end` times heavier, particle 0 pinned at the
//! origin, released horizontal at rest, gravity 9.81 along `-z`); the test
//! `bench/tests/particles.rs` checks `f`, `J_Omega` and `beta` of both at the same point.

use dae_particles::{ModelError, ParticleDae, Pin};
use dae_runtime::Model;
use dae_runtime::family::{FamilyInstance, Spec};

mod generated {
    dae_runtime::dae_file!("../examples/models/chain.dae");
}

/// The generated kernels of `chain.dae`.
pub use generated::Chain as ChainKernels;

/// `chain.dae` sized at `N` links with end-mass ratio `m_end`, as a particle model.
pub struct FamilyChain {
    model: FamilyInstance<ChainKernels>,
    slots: Vec<(usize, usize)>,
    rest: f64,
}

impl std::fmt::Debug for FamilyChain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FamilyChain")
            .field("links", &self.model.n_constraints())
            .finish()
    }
}

impl FamilyChain {
    /// The chain of `links` links with the end particle `end_mass_ratio` times heavier.
    pub fn new(links: usize, end_mass_ratio: f64) -> Result<Self, String> {
        let spec = Spec {
            sizes: vec![("N".into(), links as i64)],
            params: vec![("m_end".into(), end_mass_ratio)],
            ..Spec::default()
        };
        let model = ChainKernels::new(&spec).map_err(|e| e.to_string())?;
        let slot = |name: String| model.state_index(&name).map_err(|e| e.to_string());
        let slots = (0..=links)
            .map(|k| Ok((slot(format!("x[{k}].x"))?, slot(format!("v[{k}].x"))?)))
            .collect::<Result<Vec<_>, String>>()?;
        Ok(Self {
            model,
            slots,
            rest: 1.0 / links as f64,
        })
    }
}

impl Model for FamilyChain {
    fn name(&self) -> &str {
        self.model.name()
    }
    fn n_states(&self) -> usize {
        self.model.n_states()
    }
    fn n_constraints(&self) -> usize {
        self.model.n_constraints()
    }
    fn n_params(&self) -> usize {
        self.model.n_params()
    }
    fn state_name(&self, i: usize) -> &str {
        self.model.state_name(i)
    }
    fn alg_name(&self, i: usize) -> &str {
        self.model.alg_name(i)
    }
    fn constraint_name(&self, i: usize) -> &str {
        self.model.constraint_name(i)
    }
    fn param_name(&self, i: usize) -> &str {
        self.model.param_name(i)
    }
    fn indices(&self) -> &[usize] {
        self.model.indices()
    }
    fn param(&self, i: usize) -> f64 {
        self.model.param(i)
    }
    fn set_param(&mut self, i: usize, value: f64) {
        self.model.set_param(i, value)
    }
    fn initial_state(&self, x: &mut [f64]) {
        self.model.initial_state(x)
    }
    fn initial_alg(&self, z: &mut [f64]) {
        self.model.initial_alg(z)
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        self.model.rhs(t, x, z, dx)
    }
    fn sliding(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        ah: &mut [f64],
    ) {
        self.model.sliding(t, x, z, mu, w, s, ah)
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        self.model.jacobian_pattern()
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        self.model.jacobian(t, x, z, values)
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.model.beta(t, x, z, beta)
    }
}

impl ParticleDae for FamilyChain {
    fn n_particles(&self) -> usize {
        self.slots.len()
    }
    fn state_slots(&self, k: usize) -> (usize, usize) {
        self.slots[k]
    }
    fn constraint_of_link(&self, l: usize) -> Option<usize> {
        (l < self.model.n_constraints()).then_some(l)
    }
    fn rest_length(&self, _: usize) -> f64 {
        self.rest
    }
    /// Grabs go through the model's input `pin` and parameter `free` (see
    /// `docs/rust-api.md`, "Family models"); the C1 scenes have none, and this adapter
    /// does not translate a [`Pin`] motion into inputs.
    fn set_pin(&mut self, k: usize, _: Option<Pin>) -> Result<(), ModelError> {
        Err(ModelError::Unsupported(format!(
            "particle {k}: the generated chain is pinned through its input `pin` and parameter `free`, not through a particle pin"
        )))
    }
}
