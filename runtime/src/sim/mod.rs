//! The DBSMC simulator: integration, update policies, reaching phase, statistics, and
//! a run in pieces (`start`, `advance_to`, `finish`) between which the caller may change
//! the model.

mod adapt;
mod change;
mod control;
mod crossing;
mod drift;
mod evaluate;
mod locate;
mod parts;
mod record;
mod rk;
mod robust;
mod run;
mod stats;
mod step;
mod trigger;
mod update;

use std::time::Instant;

use control::{Check, Controller, Switch};
use parts::{Fresh, Phase, Point, RunState, Scratch};
use rk::Rk;
use stats::{Stats, StepMeasure};

use crate::settings::AlphaChoice;
use crate::solve::LinearSolver;
use crate::summary::{BoundLoss, NEAR_SINGULAR};
use crate::trace::Layout;
use crate::{Model, Settings, SimError};

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
/// # use dae_runtime::{Model, ModelInfo, Settings, Simulator, Trace};
/// # struct Tracking;
/// # impl Model for Tracking {
/// #     fn info(&self) -> &ModelInfo {
/// #         static INFO: std::sync::LazyLock<ModelInfo> = std::sync::LazyLock::new(|| {
/// #             ModelInfo::new("tracking", &["x"], &["z"], &["track"], &[], &[2])
/// #         });
/// #         &INFO
/// #     }
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
    pt: Point,
    scratch: Scratch,
    fresh: Fresh,
    /// `s` and `s'` at the start of the current step (located crossings).
    s0: Vec<f64>,
    ds0: Vec<f64>,
    /// `s'` at the current point (with `v` on its ramp).
    ds: Vec<f64>,
    /// `s'` right after the last update, and the drift `D_i` of `s_i'` the gains
    /// follow ([`GainRule::FollowDrift`](crate::settings::GainRule::FollowDrift)).
    ds_b: Vec<f64>,
    drift: Vec<f64>,
    /// `s` at the start of the step, for the reaching rules' sign changes.
    s_prev: Vec<f64>,
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
    /// The search for `mu` of [`Layers::adapt_mu`](crate::settings::Layers::adapt_mu), while a run is on.
    search: Option<adapt::SearchRun>,
}

impl<M: Model> Simulator<M> {
    /// Prepare a simulator; checks the settings against the model.
    pub fn new(model: M, settings: Settings) -> Result<Self, SimError> {
        model.info().check().map_err(|reason| SimError::Settings {
            field: "model",
            reason: format!("the metadata of model `{}`: {reason}", model.name()),
        })?;
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
            settings.redundant,
            settings.law.scope(),
        )?;
        let layout = Layout {
            states: (0..n).map(|i| model.state_name(i).to_string()).collect(),
            algs: (0..m).map(|i| model.alg_name(i).to_string()).collect(),
            constraints: (0..m)
                .map(|i| model.constraint_name(i).to_string())
                .collect(),
        };
        let vm = || vec![0.0; m];
        let mu_min = settings
            .layers
            .mu
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let t0 = settings.window.t_start;
        Ok(Self {
            model,
            mu_min,
            layout,
            ctl,
            rk: Rk::new(n),
            pt: Point::new(n, m, t0),
            scratch: Scratch::new(n, m),
            fresh: Fresh::default(),
            s0: vm(),
            ds0: vm(),
            ds: vm(),
            ds_b: vm(),
            drift: vm(),
            s_prev: vm(),
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
            run: RunState::new(Phase::Idle, t0),
            set: settings,
            deadline: None,
            search: None,
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
        self.fresh.stale = true;
        &mut self.model
    }
    /// Give the model back.
    pub fn into_model(self) -> M {
        self.model
    }
    /// Current (or final, or failure) time.
    pub fn time(&self) -> f64 {
        self.pt.t
    }
    /// Current states.
    pub fn state(&self) -> &[f64] {
        &self.pt.x
    }
    /// Current algebraic unknowns.
    pub fn alg(&self) -> &[f64] {
        &self.pt.z
    }
    /// Current sliding variables.
    pub fn sliding(&self) -> &[f64] {
        &self.ctl.s
    }
    /// The gains `k_i` in use now: the configured ones, or as raised
    /// ([`GainRule::Raise`](crate::settings::GainRule::Raise)) or followed ([`GainRule::FollowDrift`](crate::settings::GainRule::FollowDrift)) at the last
    /// update.
    pub fn gains(&self) -> &[f64] {
        &self.ctl.gains
    }
    /// The loss of a layer after reaching so far (what [`Summary::bound_loss`](crate::Summary::bound_loss) will
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
    /// [`Summary::triggered_updates`](crate::Summary::triggered_updates) will say), for a run driven in pieces.
    pub fn triggered_updates(&self) -> &[u64] {
        &self.stats.triggered
    }

    /// The counters of the `J_s` solver so far (what [`Summary::solver`](crate::Summary::solver) will say), for a
    /// run driven in pieces.
    /// With block-local updates the blocks' solvers count with it.
    pub fn solver_stats(&self) -> crate::solve::SolverStats {
        let mut s = self.ctl.solver.stats();
        if let Some(b) = self.ctl.blocks() {
            s.add(b.stats());
        }
        s
    }

    /// With block-local updates, what they did so far (what
    /// [`Summary::blocks`](crate::Summary::blocks) will say), for a run driven in pieces.
    pub fn blocks(&self) -> Option<crate::summary::BlockSummary> {
        self.ctl.blocks().map(|b| {
            let (blocks, largest) = b.shape();
            crate::summary::BlockSummary {
                blocks,
                largest,
                block_solves: b.solves,
                global_updates: self.stats.updates - self.stats.block_updates,
            }
        })
    }

    /// Steps cut short at a located crossing so far (what
    /// [`Summary::located_crossings`](crate::Summary::located_crossings) will say).
    pub fn steps_cut(&self) -> u64 {
        self.stats.cuts
    }

    /// Evaluations of `f` so far (what [`Summary::f_evals`](crate::Summary::f_evals)
    /// will say), for a run driven in pieces.
    pub fn f_evals(&self) -> u64 {
        self.stats.rhs_evals
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
}
