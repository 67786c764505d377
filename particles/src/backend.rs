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
    /// DBSMC control updates (0 for the others).
    pub updates: u64,
    /// DBSMC: the links whose own `s_i` asked for at least one update (a few dozen of
    /// thousands on the cloth; 0 for the others).
    pub links_asking: u64,
    /// DBSMC: when a sliding variable first left its layer `|s_i| <= eps_i` after
    /// reaching (the method's own bound, on `s`, not on the strain), if it did.
    pub layer_lost_at: Option<f64>,
    /// DBSMC, with [`layer_lost_at`](Self::layer_lost_at): the largest `|s_i| / eps_i`
    /// after reaching so far (how far the layer was left, not only when).
    pub layer_worst_ratio: Option<f64>,
    /// DBSMC searching for `mu` ([`crate::Dbsmc::adapt_mu`]): `mu` now as a multiple of
    /// the one the run started with (`None` without a search).
    pub mu_scale: Option<f64>,
    /// DBSMC searching for `mu`: the moves of `mu` made.
    pub mu_moves: u64,
    /// DBSMC searching for `mu`: the moves the simulator refused (a growth from which
    /// the filter would leave its layer; `mu` stayed where it was).
    pub mu_refused: u64,
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
