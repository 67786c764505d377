//! Everything a run needs besides the model: [`Settings`], grouped into the layers and
//! gains ([`Layers`]), the integration ([`Integration`]), the time window ([`Window`])
//! and the control law ([`Law`]), whose variants carry what each behaviour needs.

mod adapt_mu;
mod law;
mod validate;

use serde::{Deserialize, Serialize};

use crate::solve::{RedundantRows, SolverChoice};

pub use adapt_mu::AdaptiveMu;
pub use law::{
    CROSSING_TOL, Dbsmc, GainRule, Hold, InLayer, Law, Reaching, Scope, StepEnd, Update,
};

/// How `x` (and, between updates, `z` along its exact ramp) is integrated over a step.
///
/// Inside every stage `z` follows its exact zero-order-hold ramp
/// `z_b + v (t - t_b)` (evaluated as `z(t) + c h v`), whatever the integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Integrator {
    /// Explicit Euler with the fixed step [`Integration::step`], one `f` evaluation per
    /// step.
    Euler,
    /// Classical fourth-order Runge-Kutta with the fixed step [`Integration::step`],
    /// four `f` evaluations per step.
    Rk4,
    /// The Dormand-Prince 5(4) pair with error control ([`Integration::tolerance`]): six
    /// `f` evaluations per accepted step (the seventh is the next step's first), and a
    /// free dense output of order 4 on which crossings are located.
    DormandPrince,
    /// The Bogacki-Shampine 3(2) pair with error control: three `f` evaluations per
    /// accepted step, cubic Hermite dense output.
    BogackiShampine,
}

impl Integrator {
    /// Whether the step is chosen by an error estimate (the embedded pairs).
    pub fn is_adaptive(self) -> bool {
        matches!(self, Self::DormandPrince | Self::BogackiShampine)
    }
}

/// Error tolerances of the embedded pairs: a step is accepted when the RMS over the
/// states of `err_i / (atol + rtol max(|x_i|, |x_i,new|))` is at most 1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Tolerance {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

/// Factor between the smallest layer `eps_i` and the tolerance derived from it when
/// [`Integration::tolerance`] is not given: `rtol = atol = TOLERANCE_PER_EPS * min
/// eps_i`. At this factor the position error stays that of the layer and one step
/// usually spans a control interval (docs/work-precision.md).
pub const TOLERANCE_PER_EPS: f64 = 0.01;

/// Largest estimated error of one step in each sliding variable, as a fraction of its
/// layer: with located crossings a step is accepted only when `|s_i(x) - s_i(x_hat)| <=
/// LAYER_ERROR_PER_STEP eps_i` for the solution `x` and the embedded one `x_hat`
/// (the fixed-step integrators build theirs from `f` at the step's end), whatever the
/// state tolerance. The state's error alone does not bound `s`'s: `s` weighs the states
/// by `mu` and the model's derivatives, and a crossing is cut from the dense output,
/// which is less accurate than the step's end (`runtime/tests/simulator/located.rs` checks the
/// layer against an independent fine integration).
pub const LAYER_ERROR_PER_STEP: f64 = 0.001;

/// Default [`Settings::bound_tol`]: 1 %, ten times the default crossing tolerance
/// [`CROSSING_TOL`], so that located crossings never count as a loss while any real
/// excursion does.
pub const BOUND_TOL: f64 = 0.01;

/// Which `alpha_hat` the control law uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum AlphaChoice {
    /// The cheap estimate from [`Model::sliding`](crate::Model::sliding): the neglected
    /// `mu^(r-1) beta` must be covered by the gains.
    Cheap,
    /// The exact `alpha = alpha_hat + mu^(r-1) beta` (one [`Model::beta`](crate::Model::beta)
    /// evaluation per update).
    Exact,
}

/// The per-constraint design: layers, time constants and gains, indexed like the
/// model's constraints.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Layers {
    /// Boundary-layer half widths `eps_i > 0`.
    pub eps: Vec<f64>,
    /// Sliding-surface time constants `mu_i > 0`.
    pub mu: Vec<f64>,
    /// Gains `k_i > 0`.
    pub gains: Vec<f64>,
    /// Crossing margins `k_i^c >= 0` used when counting robustness violations
    /// (T 3.22); zero unless configured.
    pub crossing_margin: Vec<f64>,
    /// Search for the common scale of `mu` at which the run costs least while it runs
    /// ([`AdaptiveMu`]; none by default). The gains, the longest step and the grazing
    /// return move with `mu` ([`Simulator::rescale_mu`](crate::Simulator::rescale_mu)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adapt_mu: Option<AdaptiveMu>,
}

/// How `x` is integrated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Integration {
    /// Integrator for `x`.
    pub integrator: Integrator,
    /// The step `h > 0` of the fixed-step integrators (Euler, RK4), checked only for
    /// them. With located crossings it is the longest step: a step is shortened at a
    /// crossing, aimed at the next one, and retried shorter (with the steps after it)
    /// while its estimated error in some `s_i` is above [`LAYER_ERROR_PER_STEP`] `eps_i`.
    pub step: f64,
    /// Tolerances of the embedded pairs; `None` derives them from the layers
    /// ([`TOLERANCE_PER_EPS`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<Tolerance>,
    /// Largest step of the embedded pairs (default: unlimited).
    #[serde(default = "infinite")]
    pub max_step: f64,
    /// Most integration steps (accepted and rejected) a run may take before it stops
    /// with [`SimError::StepLimit`](crate::SimError::StepLimit) (default: unlimited).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<u64>,
}

/// The time span of a run and of its statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// Start time.
    pub t_start: f64,
    /// End time.
    pub t_end: f64,
    /// Statistics (periods, max |s|, max |w|, violations) are taken from
    /// `max(reaching time, t_start + settle)` on.
    pub settle: f64,
    /// Maximum duration of the reaching phase; exceeding it is
    /// [`SimError::ReachingTimeout`](crate::SimError::ReachingTimeout).
    pub reaching_limit: f64,
}

/// A start point given from outside the model: `n` states and `m` algebraic values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Initial {
    /// Initial states, one per model state.
    pub x0: Vec<f64>,
    /// Initial algebraic unknowns, one per constraint.
    pub z0: Vec<f64>,
}

/// Everything a run needs besides the model.
///
/// ```
/// use dae_runtime::Settings;
/// use dae_runtime::settings::{Dbsmc, GainRule, Integrator, Update};
/// let s = Settings::new(vec![0.2, 0.2], vec![0.076, 0.066], vec![7.5, 10.0])
///     .integrator(Integrator::Rk4)
///     .step(1e-4)
///     .law(Dbsmc::default().update(Update::Fixed { period: 0.01 }))
///     .t_end(10.0)
///     .settle(1.0);
/// assert_eq!(s.integration.step, 1e-4);
/// assert!(!s.law.monitors());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Layers, time constants and gains.
    pub layers: Layers,
    /// The integrator and its step or tolerances.
    pub integration: Integration,
    /// The time span.
    pub window: Window,
    /// The control law and when it is updated.
    pub law: Law,
    /// Cheap or exact `alpha_hat`.
    pub alpha: AlphaChoice,
    /// Which solver applies `J_hat^{-1}` at the control updates (see the crate docs).
    #[serde(default)]
    pub solver: SolverChoice,
    /// What a singular `J_s` does: refuse (stop and name the dependent constraints, the
    /// default) or drop the constraints the others imply and solve the rest
    /// ([`RedundantRows`]; the guarantee is in `docs/method.md`, "Redundant
    /// constraints").
    #[serde(default)]
    pub redundant: RedundantRows,
    /// Evaluate `beta` at every update to count robustness violations even with the
    /// cheap `alpha_hat` (one extra `beta` evaluation per update). On by default.
    pub check_robustness: bool,
    /// Relative excess of `|s_i|` over `eps_i` beyond which the layer counts as lost
    /// after reaching ([`Summary::bound_loss`](crate::Summary::bound_loss)); default
    /// [`BOUND_TOL`].
    #[serde(default = "default_bound_tol")]
    pub bound_tol: f64,
    /// Start from these states `x0` and algebraic values `z0` instead of the model's
    /// [`initial_state`](crate::Model::initial_state) and
    /// [`initial_alg`](crate::Model::initial_alg) (see [`Settings::initial`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<Initial>,
}

fn infinite() -> f64 {
    f64::INFINITY
}

fn default_bound_tol() -> f64 {
    BOUND_TOL
}

impl Settings {
    /// Settings with the given layers, time constants and gains, and defaults: RK4 with
    /// `h = 1e-4`, the DBSMC law with located crossings, monitoring and attracting
    /// surfaces ([`Dbsmc::default`]), cheap `alpha_hat`, `t` from 0 to 1, no settle
    /// time, no reaching limit, zero crossing margins, robustness counting on.
    pub fn new(eps: Vec<f64>, mu: Vec<f64>, gains: Vec<f64>) -> Self {
        let m = eps.len();
        Self {
            layers: Layers {
                eps,
                mu,
                gains,
                crossing_margin: vec![0.0; m],
                adapt_mu: None,
            },
            integration: Integration {
                integrator: Integrator::Rk4,
                step: 1e-4,
                tolerance: None,
                max_step: f64::INFINITY,
                max_steps: None,
            },
            window: Window {
                t_start: 0.0,
                t_end: 1.0,
                settle: 0.0,
                reaching_limit: f64::INFINITY,
            },
            law: Law::default(),
            alpha: AlphaChoice::Cheap,
            solver: SolverChoice::Auto,
            redundant: RedundantRows::Refuse,
            check_robustness: true,
            bound_tol: BOUND_TOL,
            initial: None,
        }
    }
    /// Set the fixed step (and, with located crossings, the longest step) of Euler and
    /// RK4.
    pub fn step(mut self, h: f64) -> Self {
        self.integration.step = h;
        self
    }
    /// Set the integrator.
    pub fn integrator(mut self, integrator: Integrator) -> Self {
        self.integration.integrator = integrator;
        self
    }
    /// Set the tolerances of the embedded pairs.
    pub fn tolerance(mut self, rtol: f64, atol: f64) -> Self {
        self.integration.tolerance = Some(Tolerance { rtol, atol });
        self
    }
    /// Set the largest step of the embedded pairs.
    pub fn max_step(mut self, h: f64) -> Self {
        self.integration.max_step = h;
        self
    }
    /// Stop a run with [`SimError::StepLimit`](crate::SimError::StepLimit) after this
    /// many integration steps.
    pub fn max_steps(mut self, n: u64) -> Self {
        self.integration.max_steps = Some(n);
        self
    }
    /// Set the relative excess over `eps` that counts as a lost layer.
    pub fn bound_tol(mut self, tol: f64) -> Self {
        self.bound_tol = tol;
        self
    }
    /// Set the control law ([`Dbsmc`], [`StepEnd`] or [`Law::Spsm`]).
    pub fn law(mut self, law: impl Into<Law>) -> Self {
        self.law = law.into();
        self
    }
    /// Choose cheap or exact `alpha_hat`.
    pub fn alpha(mut self, alpha: AlphaChoice) -> Self {
        self.alpha = alpha;
        self
    }
    /// Set the start time.
    pub fn t_start(mut self, t: f64) -> Self {
        self.window.t_start = t;
        self
    }
    /// Set the end time.
    pub fn t_end(mut self, t: f64) -> Self {
        self.window.t_end = t;
        self
    }
    /// Set the settle time before statistics are taken.
    pub fn settle(mut self, duration: f64) -> Self {
        self.window.settle = duration;
        self
    }
    /// Set the maximum duration of the reaching phase.
    pub fn reaching_limit(mut self, duration: f64) -> Self {
        self.window.reaching_limit = duration;
        self
    }
    /// Search for `mu` during the run ([`Layers::adapt_mu`]), or not (`None`).
    pub fn adapt_mu(mut self, search: Option<AdaptiveMu>) -> Self {
        self.layers.adapt_mu = search;
        self
    }
    /// Set the crossing margins `k_i^c`.
    pub fn crossing_margin(mut self, kc: Vec<f64>) -> Self {
        self.layers.crossing_margin = kc;
        self
    }
    /// Turn robustness counting (and its `beta` evaluation per update) on or off.
    pub fn check_robustness(mut self, on: bool) -> Self {
        self.check_robustness = on;
        self
    }
    /// Choose the solver of `J_s` (default [`SolverChoice::Auto`]).
    pub fn solver(mut self, solver: SolverChoice) -> Self {
        self.solver = solver;
        self
    }
    /// Choose what a singular `J_s` does (default [`RedundantRows::Refuse`]).
    pub fn redundant(mut self, rows: RedundantRows) -> Self {
        self.redundant = rows;
        self
    }
    /// Start from `x0` (one value per state) and `z0` (one per constraint) instead of
    /// the model's own initial values, e.g. to start a model in a chosen consistent
    /// configuration without editing it. Lengths and finiteness are checked by
    /// [`Simulator::new`](crate::Simulator::new) (a
    /// [`SimError::Settings`](crate::SimError::Settings) naming `initial.x0` or
    /// `initial.z0`).
    ///
    /// ```
    /// use dae_runtime::Settings;
    /// let s = Settings::new(vec![1e-3], vec![0.05], vec![10.0]).initial(vec![1.0, 0.0], vec![0.5]);
    /// assert_eq!(s.initial.unwrap().z0, vec![0.5]);
    /// ```
    pub fn initial(mut self, x0: Vec<f64>, z0: Vec<f64>) -> Self {
        self.initial = Some(Initial { x0, z0 });
        self
    }

    /// The tolerances the embedded pairs use: the given ones, or
    /// `rtol = atol = TOLERANCE_PER_EPS * min eps_i` (1e-3 without constraints).
    pub fn effective_tolerance(&self) -> Tolerance {
        self.integration.tolerance.unwrap_or_else(|| {
            let e = self
                .layers
                .eps
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            let tol = if e.is_finite() {
                TOLERANCE_PER_EPS * e
            } else {
                1e-3
            };
            Tolerance {
                rtol: tol,
                atol: tol,
            }
        })
    }
}

impl Settings {
    /// The DBSMC law's parameters, to change one in place (for example to let `v` ramp
    /// in the settings a design returned); `None` when the law is [`Law::StepEnd`] or
    /// [`Law::Spsm`].
    ///
    /// ```
    /// use dae_runtime::Settings;
    /// use dae_runtime::settings::Hold;
    /// let mut s = Settings::new(vec![1e-3], vec![0.05], vec![0.2]);
    /// s.dbsmc_mut().expect("the default law is DBSMC").hold = Hold::RampAgainstDrift;
    /// assert!(s.law.ramps());
    /// ```
    pub fn dbsmc_mut(&mut self) -> Option<&mut Dbsmc> {
        match &mut self.law {
            Law::Dbsmc(d) => Some(d),
            _ => None,
        }
    }
}
