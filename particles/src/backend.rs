//! The seam between a scene and a simulation method.

use crate::motion::{Kinematics, Pin};

/// Work a backend did since it started, in the units each method counts.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Counters {
    /// Integration steps (XPBD: substeps).
    pub steps: u64,
    /// Evaluations of the forces `f` (DBSMC and index-1: right-hand sides; XPBD: 0).
    pub f_evals: u64,
    /// Numeric factorisations of a matrix of the links (`J_s` or `J_Omega`): DBSMC one
    /// per full control update, the index-1 method one per stage.
    pub factorisations: u64,
    /// Iterations: XPBD constraint sweeps (one per iteration of each substep), or the
    /// iterations of an iterative `J_s` solver.
    pub iterations: u64,
    /// What only a sliding-mode backend counts ([`Dbsmc`](crate::Dbsmc)); `None` for
    /// the others.
    pub sliding: Option<SlidingCounters>,
}

/// The counters of a sliding-mode backend: its control updates and its own bound.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SlidingCounters {
    /// Control updates (of every row, or with block-local updates of some blocks).
    pub updates: u64,
    /// With block-local updates ([`dae_runtime::settings::Scope::Blocks`]): the block
    /// solves and the updates of every row among [`updates`](Self::updates); `None`
    /// when every update was of every row.
    pub blocks: Option<BlockCounters>,
    /// Steps cut short at a located crossing.
    pub steps_cut: u64,
    /// The links whose own `s_i` asked for at least one update.
    pub links_asking: u64,
    /// When a sliding variable first left its layer `|s_i| <= eps_i` after reaching
    /// (the method's own bound, on `s`, not on the strain), if it did.
    pub layer_lost_at: Option<f64>,
    /// With [`layer_lost_at`](Self::layer_lost_at): the largest `|s_i| / eps_i` after
    /// reaching so far (how far the layer was left, not only when).
    pub layer_worst_ratio: Option<f64>,
    /// The search for `mu` ([`crate::Dbsmc::adapt_mu`]), if one runs.
    pub mu_search: Option<MuSearchCounters>,
    /// The parts of the system simulated apart, each on a clock of its own
    /// ([`crate::Components`]); 1 for one simulator over the whole system.
    pub parts: u64,
}

/// What block-local updates did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BlockCounters {
    /// Blocks of the partition.
    pub blocks: usize,
    /// Block solves (one factorisation of a block of `J_s` each).
    pub block_solves: u64,
    /// Updates of every row (the first, and those after a pin change or a move of `mu`).
    pub global_updates: u64,
}

/// What a search for `mu` did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MuSearchCounters {
    /// `mu` now as a multiple of the one the run started with.
    pub scale: f64,
    /// The moves of `mu` made.
    pub moves: u64,
    /// The moves the simulator refused (a growth from which the filter would leave its
    /// layer; `mu` stayed where it was).
    pub refused: u64,
}

/// Reads of the sliding-mode counters that are zero or `None` for the other methods,
/// for reports that list every method in one table.
impl Counters {
    /// Control updates (0 for a method without them).
    pub fn updates(&self) -> u64 {
        self.sliding.map_or(0, |d| d.updates)
    }
    /// The links that asked for an update (0 for a method without updates).
    pub fn links_asking(&self) -> u64 {
        self.sliding.map_or(0, |d| d.links_asking)
    }
    /// When the sliding-mode layer was first lost, if it was.
    pub fn layer_lost_at(&self) -> Option<f64> {
        self.sliding.and_then(|d| d.layer_lost_at)
    }
    /// How far the sliding-mode layer was left, if it was.
    pub fn layer_worst_ratio(&self) -> Option<f64> {
        self.sliding.and_then(|d| d.layer_worst_ratio)
    }
    /// What a search for `mu` did, if one ran.
    pub fn mu_search(&self) -> Option<MuSearchCounters> {
        self.sliding.and_then(|d| d.mu_search)
    }
}

/// A failure inside a backend: when, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{method} at t = {t}: {reason}")]
pub struct BackendError {
    /// The backend's name.
    pub method: String,
    /// Simulation time of the failure.
    pub t: f64,
    /// What happened.
    pub reason: String,
    /// The backend stopped at the wall-clock deadline of
    /// [`set_deadline`](Backend::set_deadline), not at a failure: the state is
    /// consistent and the run can go on after a later deadline.
    pub deadline: bool,
}

/// A simulation method that advances a particle system in time.
///
/// A backend owns its state; the [`Scene`](crate::Scene) calls
/// [`advance_to`](Backend::advance_to) once per frame, reads
/// [`positions`](Backend::positions) and changes pins between frames. Implemented by
/// [`Dbsmc`](crate::Dbsmc) (the runtime's simulator on a particle model) and, in
/// `dae-bench`, by XPBD and the index-1 method.
pub trait Backend {
    /// The method and its setting, for reports (e.g. `xpbd k=20 n=1`).
    fn name(&self) -> String;
    /// Number of particles.
    fn n_particles(&self) -> usize;
    /// Current simulation time.
    fn time(&self) -> f64;
    /// Advance to time `t` (later than [`time`](Backend::time)).
    fn advance_to(&mut self, t: f64) -> Result<(), BackendError>;
    /// Current positions of all particles into `out` (`out.len()` particles).
    fn positions(&self, out: &mut [[f64; 3]]);
    /// Current velocities of all particles into `out`.
    fn velocities(&self, out: &mut [[f64; 3]]);
    /// Position, velocity and acceleration of particle `k` now (jerk 0 if unknown).
    /// A grab takes the position and velocity (see [`Scene::grab`](crate::Scene::grab)).
    fn particle(&self, k: usize) -> Kinematics;
    /// Pin particle `k` to `pin` from now on, or release it (`None`). The pin's
    /// motion should start where the particle is.
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), BackendError>;
    /// Work done so far.
    fn counters(&self) -> Counters;
    /// A wall-clock deadline for [`advance_to`](Backend::advance_to) (or none): a
    /// backend that can stop inside a frame does so once it has passed, with an error
    /// whose `deadline` is set. By default ignored: a backend whose frame costs a
    /// bounded amount of work (XPBD, a fixed number of steps) cannot overrun by much.
    fn set_deadline(&mut self, deadline: Option<std::time::Instant>) {
        let _ = deadline;
    }
}

/// A backend borrowed mutably is a backend: a caller can run a [`Scene`](crate::Scene)
/// on it and keep it afterwards.
impl<B: Backend + ?Sized> Backend for &mut B {
    fn name(&self) -> String {
        (**self).name()
    }
    fn n_particles(&self) -> usize {
        (**self).n_particles()
    }
    fn time(&self) -> f64 {
        (**self).time()
    }
    fn advance_to(&mut self, t: f64) -> Result<(), BackendError> {
        (**self).advance_to(t)
    }
    fn positions(&self, out: &mut [[f64; 3]]) {
        (**self).positions(out)
    }
    fn velocities(&self, out: &mut [[f64; 3]]) {
        (**self).velocities(out)
    }
    fn particle(&self, k: usize) -> Kinematics {
        (**self).particle(k)
    }
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), BackendError> {
        (**self).set_pin(k, pin)
    }
    fn counters(&self) -> Counters {
        (**self).counters()
    }
    fn set_deadline(&mut self, deadline: Option<std::time::Instant>) {
        (**self).set_deadline(deadline)
    }
}
