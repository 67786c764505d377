//! The DBSMC simulator: integration, update policies, reaching phase, statistics, and
//! a run in pieces (`start`, `advance_to`, `finish`) between which the caller may change
//! the model.

mod change;
mod control;
mod crossing;
mod drift;
mod locate;
mod rk;
mod robust;
mod stats;
mod step;
mod trigger;
mod update;

use std::time::Instant;

use control::{Check, Controller, Switch};
use rk::Rk;
use stats::{Stats, StepMeasure};

use crate::settings::{AlphaChoice, Law, Update};
use crate::solve::LinearSolver;
use crate::summary::{BoundLoss, NEAR_SINGULAR};
use crate::trace::{Layout, Sink};
use crate::{Model, Settings, SimError, Summary};

/// Simulates a [`Model`] with DBSMC (or SPSM) under given [`Settings`].
///
/// The simulator owns its model: pass `&model` to borrow it (`Model` is implemented for
/// references), or the model itself to change it between pieces of a run with
/// [`model_mut`](Simulator::model_mut). A run is [`start`](Simulator::start)ed,
/// [`advance_to`](Simulator::advance_to) any number of times, and
/// [`finish`](Simulator::finish)ed; [`run`](Simulator::run) does the three over
/// `[t_start, t_end]`.
///
/// All buffers are allocated by [`Simulator::new`]; a run allocates nothing per step
/// (the sink may, e.g. a growing [`Trace`](crate::Trace)).
///
/// ```
/// # use dae_runtime::{Model, Settings, Simulator, Trace};
/// # struct Tracking;
/// # impl Model for Tracking {
/// #     fn name(&self) -> &str { "tracking" }
/// #     fn n_states(&self) -> usize { 1 }
/// #     fn n_constraints(&self) -> usize { 1 }
/// #     fn n_params(&self) -> usize { 0 }
/// #     fn state_name(&self, _: usize) -> &str { "x" }
/// #     fn alg_name(&self, _: usize) -> &str { "z" }
/// #     fn constraint_name(&self, _: usize) -> &str { "track" }
/// #     fn param_name(&self, _: usize) -> &str { "" }
/// #     fn indices(&self) -> &[usize] { &[2] }
/// #     fn param(&self, _: usize) -> f64 { 0.0 }
/// #     fn set_param(&mut self, _: usize, _: f64) {}
/// #     fn initial_state(&self, x: &mut [f64]) { x[0] = 0.0 }
/// #     fn initial_alg(&self, z: &mut [f64]) { z[0] = 1.0 }
/// #     fn rhs(&self, _: f64, x: &[f64], z: &[f64], dx: &mut [f64]) { dx[0] = z[0] - x[0] }
/// #     fn sliding(&self, t: f64, x: &[f64], z: &[f64], mu: &[f64],
/// #                w: &mut [f64], s: &mut [f64], ah: &mut [f64]) {
/// #         w[0] = x[0] - t.sin(); w[1] = z[0] - x[0] - t.cos();
/// #         s[0] = mu[0] * w[1] + w[0]; ah[0] = w[1];
/// #     }
/// #     fn jacobian_pattern(&self) -> &[(usize, usize)] { &[(0, 0)] }
/// #     fn jacobian(&self, _: f64, _: &[f64], _: &[f64], j: &mut [f64]) { j[0] = 1.0 }
/// #     fn beta(&self, t: f64, x: &[f64], z: &[f64], b: &mut [f64]) { b[0] = t.sin() - (z[0] - x[0]) }
/// # }
/// let settings = Settings::new(vec![1e-3], vec![0.05], vec![0.1]).step(1e-3).t_end(2.0);
/// let mut sim = Simulator::new(Tracking, settings)?;
/// let mut trace = Trace::new();
/// sim.start(&mut trace)?;
/// sim.advance_to(1.0, &mut trace)?;
/// // ... change the model with sim.model_mut() here, then:
/// sim.request_update();
/// sim.advance_to(2.0, &mut trace)?;
/// let summary = sim.finish(&mut trace)?;
/// assert_eq!(summary.t_end, 2.0);
/// # Ok::<(), dae_runtime::SimError>(())
/// ```
pub struct Simulator<M: Model> {
    model: M,
    set: Settings,
    /// Wall-clock time after which a piece stops ([`Simulator::set_deadline`]).
    deadline: Option<Instant>,
    /// The smallest `mu_i` of the settings (changed only by [`Simulator::rescale_mu`]):
    /// the progress guard's reference and the ramp's finite-difference step read it
    /// every step or update.
    mu_min: f64,
    layout: Layout,
    ctl: Controller,
    rk: Rk,
    t: f64,
    x: Vec<f64>,
    z: Vec<f64>,
    /// `z` and time at the last update: between updates `z = z_b + v (t - t_b)`.
    zb: Vec<f64>,
    tb: f64,
    v: Vec<f64>,
    /// The rate of `v` between updates (a ramp against the drift): `v(t) = v + va (t -
    /// t_b)`; zero for the zero-order hold.
    va: Vec<f64>,
    v_now: Vec<f64>,
    fx: Vec<f64>,
    /// The start of the current step, dense-output and stage scratch.
    x0: Vec<f64>,
    z0: Vec<f64>,
    xs: Vec<f64>,
    zs: Vec<f64>,
    /// SPSM stages of `z`.
    kz: [Vec<f64>; 4],
    /// `f(t, x, z)` at the current point, when known (the next step's first stage).
    f_cur: Vec<f64>,
    f_cur_valid: bool,
    /// `s` and `s'` at the start of the current step (located crossings).
    s0: Vec<f64>,
    ds0: Vec<f64>,
    /// `s'` at the current point (with the held `v`).
    ds: Vec<f64>,
    /// `s'` right after the last update, and the drift `D_i` of `s_i'` the gains
    /// follow ([`Settings::follow_drift`]).
    ds_b: Vec<f64>,
    drift: Vec<f64>,
    s_prev: Vec<f64>,
    /// `z` at the end of a trial step, and `s` at its embedded solution (for the
    /// step's error in `s`).
    z_trial: Vec<f64>,
    s_embedded: Vec<f64>,
    z_eq: Vec<f64>,
    z_star: Vec<f64>,
    wres: Vec<f64>,
    /// `Omega` before a [`change_model`](Simulator::change_model).
    omega_before: Vec<f64>,
    /// Contracting layers: `eps_i,k`, `sgn(s_i,k)` and whether `|s_i,k| > eps_i`.
    eps_k: Vec<f64>,
    sgn_k: Vec<f64>,
    outside_k: Vec<bool>,
    measure: StepMeasure,
    /// The cubic of each `s_i` over the current step (located crossings), and what
    /// ends the step for each (set at the step's start, fixed until it is accepted).
    cubics: Vec<crossing::Cubic>,
    watches: Vec<crossing::Watch>,
    stats: Stats,
    run: RunState,
}

/// Where a run in pieces stands.
struct RunState {
    phase: Phase,
    clock: Option<Instant>,
    /// Fixed-step grid: steps `k` of `n` from `origin` to the piece's target.
    origin: f64,
    k: u64,
    n: u64,
    grid_target: f64,
    /// The embedded pairs' next step, once known; for the fixed-step integrators with
    /// located crossings, a limit below the user's step that the error in `s` set.
    h_next: Option<f64>,
    /// The end of the last step was reached at a piece's target before `t_end`; its
    /// sample is recorded by the next piece (or `finish`, as the last one).
    pending_record: bool,
    /// Step number of the last recorded sample.
    recorded: Option<u64>,
    update_requested: bool,
    /// The model may have changed: the quantities cached at the current point are stale.
    dirty: bool,
    /// `J_Omega` in the controller belongs to the current point.
    j_current: bool,
    /// `beta` in the controller belongs to the current point.
    beta_current: bool,
    /// The step just taken was cut at an event that asks for an update.
    force_update: bool,
    /// Steps in a row that made almost no progress (the progress guard of `step`).
    short_steps: u32,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Phase {
    Idle,
    Running,
    Finished,
}

impl<M: Model> Simulator<M> {
    /// Prepare a simulator; checks the settings against the model.
    pub fn new(model: M, settings: Settings) -> Result<Self, SimError> {
        let n = model.n_states();
        let m = model.n_constraints();
        settings.validate(n, m)?;
        let ctl = Controller::new(
            &model,
            &settings.layers.mu,
            &settings.layers.gains,
            &settings.layers.crossing_margin,
            &settings.layers.eps,
            settings.alpha == AlphaChoice::Exact,
            settings.solver,
        )?;
        let layout = Layout {
            states: (0..n).map(|i| model.state_name(i).to_string()).collect(),
            algs: (0..m).map(|i| model.alg_name(i).to_string()).collect(),
            constraints: (0..m)
                .map(|i| model.constraint_name(i).to_string())
                .collect(),
        };
        let vn = || vec![0.0; n];
        let vm = || vec![0.0; m];
        let mu_min = settings
            .layers
            .mu
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        Ok(Self {
            model,
            mu_min,
            layout,
            ctl,
            rk: Rk::new(n),
            t: settings.window.t_start,
            x: vn(),
            z: vm(),
            zb: vm(),
            tb: settings.window.t_start,
            v: vm(),
            va: vm(),
            v_now: vm(),
            fx: vn(),
            x0: vn(),
            z0: vm(),
            xs: vn(),
            zs: vm(),
            kz: [vm(), vm(), vm(), vm()],
            f_cur: vn(),
            f_cur_valid: false,
            s0: vm(),
            ds0: vm(),
            ds: vm(),
            ds_b: vm(),
            drift: vm(),
            s_prev: vm(),
            z_trial: vm(),
            s_embedded: vm(),
            z_eq: vm(),
            z_star: vm(),
            wres: vm(),
            omega_before: vm(),
            eps_k: settings.layers.eps.clone(),
            sgn_k: vm(),
            outside_k: vec![false; m],
            measure: StepMeasure::new(m),
            cubics: vec![crossing::Cubic::hermite(0.0, 0.0, 0.0, 0.0, 1.0); m],
            watches: vec![
                crossing::Watch {
                    level: 0.0,
                    surface_from: None,
                };
                m
            ],
            stats: Stats::new(m),
            run: RunState {
                phase: Phase::Idle,
                clock: None,
                origin: settings.window.t_start,
                k: 0,
                n: 0,
                grid_target: settings.window.t_start,
                h_next: None,
                pending_record: false,
                recorded: None,
                update_requested: false,
                dirty: false,
                j_current: false,
                beta_current: false,
                force_update: false,
                short_steps: 0,
            },
            set: settings,
            deadline: None,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.set
    }
    /// The model.
    pub fn model(&self) -> &M {
        &self.model
    }
    /// The model, to change it between pieces of a run (a parameter, a particle pinned
    /// or released). What the simulator cached at the current point is evaluated again
    /// before the next step; call [`request_update`](Self::request_update) as well when
    /// the change should act on the control at once.
    pub fn model_mut(&mut self) -> &mut M {
        self.run.dirty = true;
        &mut self.model
    }
    /// Give the model back.
    pub fn into_model(self) -> M {
        self.model
    }
    /// Current (or final, or failure) time.
    pub fn time(&self) -> f64 {
        self.t
    }
    /// Current states.
    pub fn state(&self) -> &[f64] {
        &self.x
    }
    /// Current algebraic unknowns.
    pub fn alg(&self) -> &[f64] {
        &self.z
    }
    /// Current sliding variables.
    pub fn sliding(&self) -> &[f64] {
        &self.ctl.s
    }
    /// The gains `k_i` in use now: the configured ones, or as raised
    /// ([`Settings::raise_gains`]) or followed ([`Settings::follow_drift`]) at the last
    /// update.
    pub fn gains(&self) -> &[f64] {
        &self.ctl.gains
    }
    /// The loss of a layer after reaching so far (what [`Summary::bound_loss`] will
    /// say), for a run driven in pieces that must notice it before `finish`. `None`
    /// (without allocating) while every layer held.
    pub fn bound_loss(&self) -> Option<BoundLoss> {
        self.stats
            .loss
            .record(&self.layout.constraints, self.near_singular())
    }

    /// Where `J_s` was nearest singular, if its smallest conditioning ratio (of its
    /// pivots or of one solve, [`crate::summary::NearSingular`]) fell below [`NEAR_SINGULAR`] in
    /// the run so far.
    pub(super) fn near_singular(&self) -> Option<crate::summary::NearSingular> {
        self.ctl
            .min_pivot_ratio
            .filter(|(r, _)| *r < NEAR_SINGULAR)
            .map(|(pivot_ratio, t)| crate::summary::NearSingular { pivot_ratio, t })
    }

    /// Per constraint, the monitored updates its `s_i` asked for so far (what
    /// [`Summary::triggered_updates`] will say), for a run driven in pieces.
    pub fn triggered_updates(&self) -> &[u64] {
        &self.stats.triggered
    }

    /// The counters of the `J_s` solver so far (what [`Summary::solver`] will say), for a
    /// run driven in pieces.
    pub fn solver_stats(&self) -> crate::solve::SolverStats {
        self.ctl.solver.stats()
    }

    /// A wall-clock `deadline` (or none): once it has passed, [`advance_to`](Self::advance_to)
    /// (and [`run`](Self::run)) stops after the step it is in with
    /// [`SimError::Deadline`], at a consistent point that can be read, finished, or run
    /// on from (after a later deadline). For a caller with a budget: a run whose control
    /// updates crowd (near a singular `J_s`, or where the gains cannot hold a layer) can
    /// take hours for one frame, and only the simulator sees its steps.
    pub fn set_deadline(&mut self, deadline: Option<Instant>) {
        self.deadline = deadline;
    }

    /// Force a control update at the current time before the next step (after the
    /// caller changed the model).
    pub fn request_update(&mut self) {
        self.run.update_requested = true;
    }

    /// Run from the model's initial state and initial algebraic guess (or from
    /// [`Settings::initial`] when given) over `[t_start, t_end]`, sending samples and
    /// update times to `sink`: [`start`](Self::start),
    /// [`advance_to`](Self::advance_to)`(t_end)`, [`finish`](Self::finish).
    ///
    /// On error the sink keeps everything recorded before the failure.
    pub fn run<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<Summary, SimError> {
        self.start(sink)?;
        self.advance_to(self.set.window.t_end, sink)?;
        self.finish(sink)
    }

    /// Begin a run at `t_start`: the initial state, the first control update and the
    /// first sample. Starting again restarts the run.
    pub fn start<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        let m = self.z.len();
        self.stats = Stats::new(m);
        self.ctl.reset(&self.set.layers.gains);
        self.drift.fill(0.0);
        let t0 = self.set.window.t_start;
        self.t = t0;
        self.tb = t0;
        match &self.set.initial {
            Some(init) => {
                self.x.copy_from_slice(&init.x0);
                self.z.copy_from_slice(&init.z0);
            }
            None => {
                self.model.initial_state(&mut self.x);
                self.model.initial_alg(&mut self.z);
            }
        }
        self.eps_k.copy_from_slice(&self.set.layers.eps);
        self.run = RunState {
            phase: Phase::Running,
            clock: Some(Instant::now()),
            origin: t0,
            k: 0,
            n: 0,
            grid_target: t0,
            h_next: None,
            pending_record: false,
            recorded: None,
            update_requested: false,
            dirty: false,
            j_current: false,
            beta_current: false,
            force_update: false,
            short_steps: 0,
        };
        self.f_cur_valid = false;
        sink.begin(&self.layout)?;
        self.eval_point(t0);
        self.check_finite()?;
        self.track_reaching()?;
        self.update(sink)?;
        self.record(false, sink)?;
        Ok(())
    }

    /// Integrate to `t` (at most `t_end`; a run not started yet is started first).
    /// Samples and updates go to `sink` as in [`run`](Self::run); the sample at `t`
    /// itself is recorded when the run continues or is finished.
    pub fn advance_to<S: Sink + ?Sized>(&mut self, t: f64, sink: &mut S) -> Result<(), SimError> {
        match self.run.phase {
            Phase::Idle => self.start(sink)?,
            Phase::Finished => {
                return Err(SimError::Backwards {
                    requested: t,
                    now: self.t,
                    finished: true,
                });
            }
            Phase::Running => {}
        }
        let target = t.min(self.set.window.t_end);
        if target.is_nan() || target < self.t {
            return Err(SimError::Backwards {
                requested: t,
                now: self.t,
                finished: false,
            });
        }
        self.resume(sink)?;
        if target > self.t {
            self.run.origin = self.t;
            self.run.k = 0;
            self.run.grid_target = target;
            self.run.n = self.grid_steps(target);
        }
        while self.t < target {
            self.step(target)?;
            self.after_step(sink)?;
            if self.deadline.is_some_and(|d| Instant::now() >= d) {
                return Err(SimError::Deadline { t: self.t });
            }
        }
        Ok(())
    }

    /// End the run: the last sample, the sink's `finish`, and the summary. Finishing
    /// before `t_end` is allowed (the summary says where the run ended).
    pub fn finish<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<Summary, SimError> {
        if self.run.phase == Phase::Idle {
            self.start(sink)?;
        }
        if self.run.phase == Phase::Running {
            self.resume(sink)?;
            let step = self.stats.steps;
            if self.run.recorded != Some(step) {
                self.record(true, sink)?;
            }
            sink.finish()?;
            self.run.phase = Phase::Finished;
        }
        if !self.run.j_current {
            self.ctl
                .eval_jacobian(&self.model, self.t, &self.x, &self.z);
            self.run.j_current = true;
        }
        self.ctl.z_star(&self.z, &mut self.z_star);
        self.ctl.z_eq(&self.z, &mut self.z_eq);
        let wall = self.run.clock.map_or(0.0, |c| c.elapsed().as_secs_f64());
        Ok(self.summary(wall))
    }

    /// Before the next step of a piece: evaluate again what the caller's change of the
    /// model made stale, make a requested update, and record the sample left pending
    /// at the end of the previous piece.
    fn resume<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        if self.run.dirty {
            self.run.dirty = false;
            self.f_cur_valid = false;
            self.eval_point(self.t);
            if self.located() {
                self.rate_at(self.t);
            }
            self.check_finite()?;
        }
        if self.run.update_requested {
            self.run.update_requested = false;
            self.update(sink)?;
        }
        if self.run.pending_record {
            self.run.pending_record = false;
            if sink.wants(self.stats.steps, self.t) {
                self.record(false, sink)?;
            }
        }
        Ok(())
    }

    /// After an accepted step: finiteness, reaching, the window, the policy's update
    /// and the sample.
    fn after_step<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        self.check_finite()?;
        self.track_reaching()?;
        self.stats.steps_since_update += 1;
        let due = match self.set.law.update() {
            None => true,
            Some(Update::Fixed { period: p }) => {
                if self.set.integration.integrator.is_adaptive() {
                    self.t >= self.tb + p
                } else {
                    let period = ((p / self.set.integration.step).round() as u64).max(1);
                    self.stats.steps_since_update >= period
                }
            }
            Some(Update::Monitor { .. }) => {
                let forced = self.located() && std::mem::take(&mut self.run.force_update);
                forced || self.monitor_due()
            }
        };
        if due {
            self.update(sink)?;
        }
        let last = self.t >= self.set.window.t_end;
        if last {
            self.record(true, sink)?;
        } else if self.t >= self.run.grid_target {
            self.run.pending_record = true;
        } else if sink.wants(self.stats.steps, self.t) {
            self.record(false, sink)?;
        }
        if let Some(limit) = self.set.integration.max_steps {
            if self.stats.steps + self.stats.rejected >= limit && !last {
                return Err(SimError::StepLimit { limit, t: self.t });
            }
        }
        Ok(())
    }

    /// [`Settings::follow_drift`]: measure the drift of `s'` over the interval that
    /// ends at `t` (`ds` still holds the rate with the old `v`: the settings only allow
    /// it with located crossings) and set the gains.
    fn follow_drift(&mut self, t: f64) {
        let Some((safety, graze)) = self.set.law.follows_drift() else {
            return;
        };
        let how = drift::Follow {
            safety,
            min_return: graze.unwrap_or(f64::INFINITY),
        };
        if self.stats.updates == 0 || t <= self.tb {
            return;
        }
        let dt = t - self.tb;
        for i in 0..self.drift.len() {
            let measured = (self.ds[i] - self.ds_b[i]).abs() / dt;
            let (d, k) = drift::follow(
                self.set.layers.gains[i],
                self.set.layers.eps[i],
                how,
                self.drift[i],
                measured,
            );
            self.drift[i] = d;
            self.ctl.gains[i] = k;
        }
    }

    /// `v` at `t` on its ramp (`v` itself to the last bit without one), into `v_now`.
    fn v_at(&mut self, t: f64) {
        let dt = t - self.tb;
        for ((n, v), a) in self.v_now.iter_mut().zip(&self.v).zip(&self.va) {
            *n = v + a * dt;
        }
    }

    /// `s'` at the current point, time `t`, with `v` on its ramp, into `ds`: from
    /// `J_Omega` and `beta` where both are evaluated there, else from the model's rate
    /// of `Omega` in one pass, else from `J_Omega` and `beta` evaluated now.
    fn rate_at(&mut self, t: f64) {
        self.v_at(t);
        let (x, z) = (&self.x, &self.z);
        let both = self.run.j_current && self.run.beta_current;
        if !both
            && self
                .ctl
                .rate_from_model(&self.model, t, x, z, &self.v_now, &mut self.ds)
        {
            return;
        }
        if !self.run.j_current {
            self.ctl.eval_jacobian(&self.model, t, x, z);
            self.run.j_current = true;
        }
        if !self.run.beta_current {
            self.ctl.eval_beta(&self.model, t, x, z);
            self.run.beta_current = true;
        }
        self.ctl.s_rate(&self.v_now, &mut self.ds);
    }

    /// The rate of `v` that cancels the drift of `s'` at the update: `s''` by a finite
    /// difference along the flow (`s'` one short step on, evaluated apart from the
    /// point's own `s`, `J_Omega` and `beta`), `va = -J_s^{-1} s''`.
    fn ramp_against_drift(&mut self, t: f64) {
        let delta = 1e-6 * self.mu_min;
        self.model.rhs(t, &self.x, &self.z, &mut self.fx);
        self.stats.rhs_evals += 1;
        for ((xs, x), f) in self.xs.iter_mut().zip(&self.x).zip(&self.fx) {
            *xs = x + delta * f;
        }
        for ((zs, z), v) in self.zs.iter_mut().zip(&self.z).zip(&self.v) {
            *zs = z + delta * v;
        }
        self.ctl.s_rate_at(
            &self.model,
            t + delta,
            &self.xs,
            &self.zs,
            &self.v,
            &mut self.v_now,
        );
        for (n, d) in self.v_now.iter_mut().zip(&self.ds) {
            *n = -(*n - d) / delta;
        }
        self.ctl.solve_factored(&self.v_now, &mut self.va);
        if self.va.iter().any(|a| !a.is_finite()) {
            self.va.fill(0.0);
        }
    }

    /// Whether crossings are located inside the step (DBSMC with a held control).
    fn located(&self) -> bool {
        matches!(self.set.law, Law::Dbsmc(_))
    }

    fn crossing_tol(&self) -> f64 {
        self.set.law.crossing_tol().unwrap_or(0.0)
    }

    /// Evaluate at the current point what the next step and an update need: `s`,
    /// and with located crossings, unless the model gives `Omega`'s rate in one pass,
    /// `J_Omega` and `beta` (the rate `s'` follows once `v` is known; an update
    /// evaluates `J_Omega` where it is not).
    fn eval_point(&mut self, t: f64) {
        self.ctl.sliding(&self.model, t, &self.x, &self.z);
        self.eval_point_but_s(t, false);
    }

    /// [`Self::eval_point`] with `s` already evaluated there; with `update_likely`
    /// (a step cut at an event) `J_Omega` and `beta` even where the model gives
    /// `Omega`'s rate, since the update will need them.
    fn eval_point_but_s(&mut self, t: f64, update_likely: bool) {
        let both = self.located() && (update_likely || !self.ctl.model_rate());
        if both {
            self.ctl.eval_jacobian(&self.model, t, &self.x, &self.z);
            self.ctl.eval_beta(&self.model, t, &self.x, &self.z);
        }
        self.run.j_current = both;
        self.run.beta_current = both;
    }

    /// Record the reaching time, enter the statistics window, enforce the reaching limit,
    /// and update the maxima and the loss record with the step just taken.
    fn track_reaching(&mut self) -> Result<(), SimError> {
        let t = self.t;
        let s = &self.ctl.s;
        let was_reached = self.stats.reaching_time.is_some();
        if !was_reached {
            if s.iter()
                .zip(&self.set.layers.eps)
                .all(|(s, e)| s.abs() <= *e)
            {
                self.stats.reaching_time = Some(t);
            } else if t - self.set.window.t_start > self.set.window.reaching_limit {
                let outside: Vec<usize> = (0..s.len())
                    .filter(|&i| s[i].abs() > self.set.layers.eps[i])
                    .collect();
                return Err(SimError::ReachingTimeout {
                    limit: self.set.window.reaching_limit,
                    t,
                    names: outside
                        .iter()
                        .map(|&i| self.model.constraint_name(i).to_string())
                        .collect(),
                    s: outside.iter().map(|&i| s[i]).collect(),
                });
            }
        }
        let st = &mut self.stats;
        for (i, si) in s.iter().enumerate() {
            let w = self.ctl.residual(i).abs();
            st.seen_s[i] = st.seen_s[i].max(si.abs()).max(self.measure.max_s[i]);
            st.seen_w[i] = st.seen_w[i].max(w);
        }
        if was_reached && st.steps > 0 {
            st.loss.observe(
                t,
                self.measure.h,
                &self.measure,
                &self.set.layers.eps,
                self.set.bound_tol,
            );
        }
        let in_window = st.stats_from.is_some();
        if !in_window
            && st.reaching_time.is_some()
            && t >= self.set.window.t_start + self.set.window.settle
        {
            st.stats_from = Some(t);
        }
        if st.stats_from.is_some() {
            for (i, (ms, mw)) in st.max_s.iter_mut().zip(&mut st.max_w).enumerate() {
                // The step that opens the window counts with its end only.
                let over_step = if in_window {
                    self.measure.max_s[i]
                } else {
                    0.0
                };
                *ms = ms.max(s[i].abs()).max(over_step);
                *mw = mw.max(self.ctl.residual(i).abs());
            }
        }
        Ok(())
    }
}
