//! The DBSMC backend: the runtime's [`Simulator`] driving a [`ParticleDae`] model.
//!
//! The simulator owns the model and is advanced frame by frame
//! ([`Simulator::advance_to`]); a pin change goes to the model between two frames
//! through [`Simulator::change_model`], which moves the tensions so that the sliding
//! variables do not jump (a release changes the particle's acceleration at once) and
//! updates the control for the new `J_Omega` before the next step. A layer left after reaching ends
//! the run with a [`BackendError`] at the end of that frame ([`Simulator::bound_loss`]),
//! unless [`Dbsmc::keep_going_after_bound_loss`] asked to record it and go on.

use std::cell::{Cell, RefCell};
use std::io;

use dae_runtime::{
    Model, ModelInfo, Settings, SimError, Simulator, design::DesignError, design::Online,
    trace::Layout, trace::Sample, trace::Sink,
};

use crate::backend::{
    Backend, BackendError, BlockCounters, Counters, MuSearchCounters, SlidingCounters,
};
use crate::model::ParticleDae;
use crate::motion::{Kinematics, Pin};
use crate::scene::FRAME;
use dae_runtime::design::MuSearcher;
use dae_runtime::settings::AdaptiveMu;

/// The model with call counters (the work a frame cost).
struct Counted<M> {
    model: M,
    rhs_calls: Cell<u64>,
}

impl<M: ParticleDae> Model for Counted<M> {
    fn info(&self) -> &ModelInfo {
        self.model.info()
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
        self.rhs_calls.set(self.rhs_calls.get() + 1);
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
    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        self.model.omega_rate(t, x, z, zdot, rate)
    }
}

/// A sink that records nothing and counts steps and control updates.
#[derive(Default)]
struct Counting {
    steps: Cell<u64>,
    updates: u64,
}

impl Sink for Counting {
    fn begin(&mut self, _: &Layout) -> io::Result<()> {
        Ok(())
    }
    fn wants(&self, step: u64, _: f64) -> bool {
        self.steps.set(step);
        false
    }
    fn algebraic_outputs(&self) -> bool {
        false
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        self.steps.set(s.step);
        Ok(())
    }
    fn update(&mut self, _: f64) -> io::Result<()> {
        self.updates += 1;
        Ok(())
    }
}

/// DBSMC on a particle model: the runtime's [`Simulator`] with the given [`Settings`]
/// (layers `eps_i` in metres, `mu_i`, gains, step, solver), advanced frame by frame.
///
/// A fixed step (Euler, RK4) must divide the frame ([`FRAME`] / step a whole number),
/// so that frames end on steps; an error-controlled integrator needs none. `settings.t_start` must be 0; `settings.t_end` is ignored (the run
/// lasts as long as the backend lives).
pub struct Dbsmc<M: ParticleDae> {
    name: String,
    slots: Vec<(usize, usize)>,
    sim: Simulator<Counted<M>>,
    sink: Counting,
    /// `f` at the current state, for [`Backend::particle`] (allocated once).
    f: RefCell<Vec<f64>>,
    failed: Option<BackendError>,
    /// Go on after a layer was left (recorded in the counters) instead of failing.
    keep_going: bool,
    layer_lost_at: Option<f64>,
    /// The search for `mu` ([`Dbsmc::adapt_mu`]), and the work counted up to the end
    /// of the last frame.
    search: Option<MuSearcher>,
    work_before: u64,
}

impl<M: ParticleDae> std::fmt::Debug for Dbsmc<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Dbsmc")
            .field("name", &self.name)
            .field("t", &self.sim.time())
            .finish()
    }
}

/// The frame-tied design ([`Online`] at a frame of [`FRAME`]) for `model` with every
/// link held within the relative layer (strain bound) `eps`: `eps_i = eps L0_i` for the
/// constraint of a link of rest length `L0_i`; `mu` a quarter of the frame, gains that
/// follow the drift of `s'` the run measures, Dormand-Prince steps of at most `mu / 2`.
/// No pilot run is needed: this is the design of [`Dbsmc::online`].
///
/// An error if `eps` is not positive and finite.
pub fn online_settings<M: ParticleDae + ?Sized>(
    model: &M,
    eps: f64,
) -> Result<Settings, DesignError> {
    if !(eps.is_finite() && eps > 0.0) {
        return Err(DesignError::NotPositive {
            name: "eps",
            value: eps,
        });
    }
    let layers = (0..model.n_constraints())
        .map(|i| eps * model.rest_length(i))
        .collect();
    Online {
        search: None,
        search_up_to: 0,
        ..Online::frame(FRAME)
    }
    .settings(layers)
}

impl<M: ParticleDae> Dbsmc<M> {
    /// DBSMC on `model` in one call: the frame-tied design of [`online_settings`] with
    /// every link within the relative layer `eps` (a strain bound, e.g. `1e-3` for
    /// 0.1 % of each link's length); `name` labels reports. An error if `eps` is not
    /// positive and finite, or as [`Dbsmc::new`].
    ///
    /// The design asks for no pilot and no bounds on the motion: its gains follow the
    /// drift the run measures, and a layer it could not hold is reported (the frame
    /// fails with a [`BackendError`]), never silently.
    pub fn online(model: M, eps: f64, name: &str) -> Result<Self, BackendError> {
        let settings = online_settings(&model, eps).map_err(|e| BackendError {
            method: name.to_string(),
            t: 0.0,
            reason: format!("the online design at eps = {eps}: {e}"),
            deadline: false,
        })?;
        Self::new(model, settings, name)
    }

    /// Start DBSMC on `model` with `settings`; `name` labels reports.
    pub fn new(model: M, settings: Settings, name: &str) -> Result<Self, BackendError> {
        let fail = |t: f64, reason: String| BackendError {
            method: name.to_string(),
            t,
            reason,
            deadline: false,
        };
        // Frames end on steps: a fixed step must divide the frame. An error-controlled
        // integrator ends its steps where it is asked to (its `step` is unused).
        let per_frame = FRAME / settings.integration.step;
        let fixed = !settings.integration.integrator.is_adaptive();
        if fixed
            && !(per_frame.is_finite()
                && per_frame >= 1.0
                && (per_frame - per_frame.round()).abs() < 1e-6)
        {
            return Err(fail(
                0.0,
                format!(
                    "step {} does not divide the frame of 1/60 s (choose 1/(60 k))",
                    settings.integration.step
                ),
            ));
        }
        if settings.window.t_start != 0.0 {
            return Err(fail(
                0.0,
                format!("t_start is {}, must be 0", settings.window.t_start),
            ));
        }
        let slots: Vec<(usize, usize)> = (0..model.n_particles())
            .map(|k| model.state_slots(k))
            .collect();
        let n = model.n_states();
        let mut settings = settings;
        settings.window.t_end = f64::MAX;
        let counted = Counted {
            model,
            rhs_calls: Cell::new(0),
        };
        let mut sim = Simulator::new(counted, settings).map_err(|e| fail(0.0, e.to_string()))?;
        let mut sink = Counting::default();
        sim.start(&mut sink)
            .map_err(|e| fail(sim.time(), e.to_string()))?;
        Ok(Self {
            name: name.to_string(),
            slots,
            sim,
            sink,
            f: RefCell::new(vec![0.0; n]),
            failed: None,
            keep_going: false,
            layer_lost_at: None,
            search: None,
            work_before: 0,
        })
    }

    /// Search for the `mu` at which the run costs least while it runs ([`AdaptiveMu`]):
    /// at the end of each window of frames `mu` moves by a step
    /// ([`Simulator::rescale_mu`], which keeps `s` continuous and refuses a growth
    /// from which the filter would leave the layer), and the gains, the longest step
    /// and the grazing return tied to it move with it. A window counts calls of
    /// [`Backend::advance_to`], one per frame as [`crate::Scene`] and the benchmark's
    /// runner drive it, so `how.frame` must be [`FRAME`]. An error if `how` cannot
    /// search.
    pub fn adapt_mu(mut self, how: AdaptiveMu) -> Result<Self, BackendError> {
        let checked = how.check().and_then(|()| {
            if how.frame == FRAME {
                Ok(())
            } else {
                Err(format!(
                    "mu search: frame {} is not the scene's frame {FRAME} (one call of advance_to is one frame)",
                    how.frame
                ))
            }
        });
        checked.map_err(|reason| BackendError {
            method: self.name.clone(),
            t: self.sim.time(),
            reason,
            deadline: false,
        })?;
        self.search = Some(MuSearcher::new(how));
        self.work_before = self.work();
        Ok(self)
    }

    /// `mu` now as a multiple of the one the run started with (1 without a search).
    pub fn mu_scale(&self) -> f64 {
        self.search.as_ref().map_or(1.0, MuSearcher::scale)
    }

    /// The moves of `mu` the search made so far, and those the simulator refused (a
    /// growth from which the filter would have left the layer).
    pub fn mu_moves(&self) -> (u64, u64) {
        self.search.as_ref().map_or((0, 0), MuSearcher::moves)
    }

    /// The work the search weighs: right-hand side evaluations and factorisations.
    fn work(&self) -> u64 {
        self.sim.model().rhs_calls.get() + self.sim.solver_stats().factorisations
    }

    /// The search's move at the end of a frame, if one is due.
    fn follow_search(&mut self) -> Result<(), BackendError> {
        let work = self.work();
        let frame = work - self.work_before;
        self.work_before = work;
        let Some(factor) = self.search.as_mut().and_then(|s| s.after_frame(frame)) else {
            return Ok(());
        };
        match self.sim.rescale_mu(factor) {
            Ok(true) => Ok(()),
            Ok(false) => {
                if let Some(s) = self.search.as_mut() {
                    s.refused(factor);
                }
                Ok(())
            }
            Err(e) => Err(self.failure(self.sim.time(), &e)),
        }
    }

    /// Do not stop when a layer is left after reaching: record the first time in
    /// [`SlidingCounters::layer_lost_at`] and go on (for benchmarks that measure what follows,
    /// e.g. the strain, which a lost `s`-layer does not necessarily break).
    pub fn keep_going_after_bound_loss(mut self) -> Self {
        self.keep_going = true;
        self
    }

    fn failure(&mut self, t: f64, e: &SimError) -> BackendError {
        let deadline = matches!(e, SimError::Deadline { .. });
        let e = BackendError {
            method: self.name.clone(),
            t,
            reason: e.to_string(),
            deadline,
        };
        // A deadline is not a failure: the simulator stopped at a consistent point.
        if !deadline {
            self.failed = Some(e.clone());
        }
        e
    }

    fn vec3(&self, i: usize) -> [f64; 3] {
        let x = self.sim.state();
        [x[i], x[i + 1], x[i + 2]]
    }

    /// Current states (positions and velocities as the model lays them out).
    pub fn state(&self) -> &[f64] {
        self.sim.state()
    }

    /// Per constraint (in the model's order of constraint links), the monitored
    /// updates its own `s_i` asked for so far ([`Simulator::triggered_updates`]): which
    /// links set the update rate, and so the cost. [`SlidingCounters::links_asking`] counts
    /// the links with at least one.
    pub fn triggered_updates(&self) -> &[u64] {
        self.sim.triggered_updates()
    }
}

impl<M: ParticleDae> Backend for Dbsmc<M> {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn n_particles(&self) -> usize {
        self.slots.len()
    }
    fn time(&self) -> f64 {
        self.sim.time()
    }
    fn advance_to(&mut self, t: f64) -> Result<(), BackendError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if let Err(e) = self.sim.advance_to(t, &mut self.sink) {
            return Err(self.failure(self.sim.time(), &e));
        }
        // DBSMC promises its layers: a run that left one after reaching stops here,
        // loudly, instead of going on as if it held (the simulator itself would only
        // say so in the summary of `finish`, which a frame-driven run never reaches).
        if self.layer_lost_at.is_some() {
            return self.follow_search();
        }
        if let Some(loss) = self.sim.bound_loss() {
            self.layer_lost_at = Some(loss.first_time);
            if self.keep_going {
                return self.follow_search();
            }
            let e = BackendError {
                method: self.name.clone(),
                t: loss.first_time,
                reason: format!(
                    "bound lost: `{}` left its layer at t = {:.6} after reaching; max |s|/eps = {:.4} (`{}`, t = {:.6})",
                    loss.first_constraint,
                    loss.first_time,
                    loss.worst_ratio,
                    loss.worst_constraint,
                    loss.worst_time
                ),
                deadline: false,
            };
            self.failed = Some(e.clone());
            return Err(e);
        }
        self.follow_search()
    }
    fn set_deadline(&mut self, deadline: Option<std::time::Instant>) {
        self.sim.set_deadline(deadline);
    }
    fn positions(&self, out: &mut [[f64; 3]]) {
        for (k, p) in out.iter_mut().enumerate() {
            *p = self.vec3(self.slots[k].0);
        }
    }
    fn velocities(&self, out: &mut [[f64; 3]]) {
        for (k, v) in out.iter_mut().enumerate() {
            *v = self.vec3(self.slots[k].1);
        }
    }
    fn particle(&self, k: usize) -> Kinematics {
        let (p, v) = self.slots[k];
        let mut f = self.f.borrow_mut();
        let model = &self.sim.model().model;
        model.rhs(self.sim.time(), self.sim.state(), self.sim.alg(), &mut f);
        Kinematics {
            pos: self.vec3(p),
            vel: self.vec3(v),
            acc: [f[v], f[v + 1], f[v + 2]],
            jerk: [0.0; 3],
        }
    }
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), BackendError> {
        let t = self.sim.time();
        let err = |reason: String| BackendError {
            method: self.name.clone(),
            t,
            reason,
            deadline: false,
        };
        if k >= self.slots.len() {
            return Err(err(format!("particle {k} does not exist")));
        }
        // Pinning or releasing changes the particle's acceleration, so every `w''` at
        // it and `s` with it would jump; the simulator moves the tensions to keep `s`
        // where it was (positions and velocities are continuous across the switch) and
        // updates the control at once for the new `J_Omega`.
        let changed = self
            .sim
            .change_model(|m| m.model.set_pin(k, pin))
            .map_err(|e| err(e.to_string()))?;
        changed.map_err(|e| err(e.to_string()))
    }
    fn counters(&self) -> Counters {
        let model = self.sim.model();
        let (mu_moves, mu_refused) = self.mu_moves();
        Counters {
            steps: self.sink.steps.get(),
            f_evals: model.rhs_calls.get(),
            factorisations: self.sim.solver_stats().factorisations,
            iterations: 0,
            sliding: Some(SlidingCounters {
                updates: self.sink.updates,
                blocks: self.sim.blocks().map(|b| BlockCounters {
                    blocks: b.blocks,
                    block_solves: b.block_solves,
                    global_updates: b.global_updates,
                }),
                steps_cut: self.sim.steps_cut(),
                links_asking: self
                    .sim
                    .triggered_updates()
                    .iter()
                    .filter(|&&c| c > 0)
                    .count() as u64,
                layer_lost_at: self.layer_lost_at,
                // How far, read once from the simulator's record of the whole run.
                layer_worst_ratio: self
                    .layer_lost_at
                    .and(self.sim.bound_loss().map(|loss| loss.worst_ratio)),
                mu_search: self.search.as_ref().map(|search| MuSearchCounters {
                    scale: search.scale(),
                    moves: mu_moves,
                    refused: mu_refused,
                }),
                parts: 1,
            }),
        }
    }
}
