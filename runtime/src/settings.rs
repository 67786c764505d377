//! Simulation settings with a builder-like API.

use serde::{Deserialize, Serialize};

use crate::{SimError, SolverChoice};

/// How `x` (and, between updates, `z` along its exact ramp) is integrated over a step.
///
/// Inside every stage `z` follows its exact zero-order-hold ramp
/// `z_b + v (t - t_b)` (evaluated as `z(t) + c h v`), whatever the integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Integrator {
    /// Explicit Euler with the fixed step [`Settings::step`], one `f` evaluation per
    /// step.
    Euler,
    /// Classical fourth-order Runge-Kutta with the fixed step [`Settings::step`], four
    /// `f` evaluations per step.
    Rk4,
    /// The Dormand-Prince 5(4) pair with error control ([`Settings::tolerance`]): six
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
/// [`Settings::tolerance`] is not given: `rtol = atol = TOLERANCE_PER_EPS * min eps_i`.
/// Measured on the double pendulum (docs/work-precision.md): at this factor the position
/// error stays that of the layer and one step usually spans a control interval.
pub const TOLERANCE_PER_EPS: f64 = 0.01;

/// Largest estimated error of one error-controlled step in each sliding variable, as a
/// fraction of its layer: the embedded pairs accept a step only when `|s_i(x) -
/// s_i(x_hat)| <= LAYER_ERROR_PER_STEP eps_i` for the solution `x` and the embedded
/// one `x_hat`, whatever the state tolerance (the fixed-step integrators with located
/// crossings likewise, with an embedded solution built from `f` at the step's end, and
/// [`Settings::step`] as the longest step). The state's error alone does not bound
/// `s`'s: `s` weighs the states by `mu` and the model's derivatives (on the pendulum
/// of `runtime/tests/located.rs` with a thirtieth of its gains, steps of 0.06 s that
/// met the default state tolerance left `s` 10 % beyond its layer, by an independent
/// fine integration). The estimate is of the step's end, and a crossing is cut from the
/// dense output, which is less accurate: with this factor at 0.01 and 0.003 the same
/// run still went 1.6 % and 1.5 % beyond, at 0.001 0.11 %.
pub const LAYER_ERROR_PER_STEP: f64 = 0.001;

/// How the monitoring policy and the reaching-phase rules find the moment to update.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Crossing {
    /// Located inside the step (the default): a cubic Hermite of every `s_i` from `s`
    /// and `s' = J_s v + alpha` at both ends of a step finds the first outward crossing
    /// of a layer boundary (also an excursion that leaves and re-enters within the
    /// step); the crossing is refined on the true `s` along the integrator's dense
    /// output, the step is cut there (re-integrated to the crossing by the fixed-step
    /// integrators) and the control updated. `|s_i|` then exceeds `eps_i` by at most
    /// the relative tolerance `tol` at the updates, for any step.
    Located {
        /// Relative tolerance of the located crossing: `|s_i| / eps_i` in
        /// `[1 - tol, 1 + tol]` at the update.
        tol: f64,
    },
    /// Checked at the end of each step only (the thesis's rule, kept to reproduce its
    /// numbers): `s_i` can overshoot its layer by one step of motion, `|s_i'| h`.
    StepEnd,
}

/// Default relative tolerance of a located crossing.
pub const CROSSING_TOL: f64 = 1e-3;

impl Default for Crossing {
    fn default() -> Self {
        Crossing::Located { tol: CROSSING_TOL }
    }
}

/// When the control `v` is recomputed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Policy {
    /// DBSMC with monitoring (variable period): after every step, update as soon as some
    /// `s_i` is on or beyond its layer boundary and moving outward.
    Monitor,
    /// DBSMC without monitoring: update every `period` seconds, rounded to a whole
    /// number of steps (at least one).
    Fixed(f64),
    /// The continuous predecessor (SPSM): `sat(s/eps)` in place of `sgn(s)` and `v`
    /// recomputed at every integrator stage, i.e. an ordinary (stiff) ODE.
    Spsm,
}

/// Update rule while the motion is still outside some layer (only used by
/// [`Policy::Monitor`]; the other policies do not depend on it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Reaching {
    /// Keep the design gains and layers; update when a trajectory outside its layer
    /// starts to move away from its surface (`s_i s_i' > 0`) or one inside reaches the
    /// far side of its layer. This is the steady monitoring rule applied from the start.
    AttractingSurfaces,
    /// At update `k` use `eps_i,k = max(|s_i,k|, eps_i)`; update when a trajectory that
    /// was outside at the update reaches its surface (its `s_i` changes sign) or one that
    /// was inside reaches the far side of its layer (or any moves outward past
    /// `eps_i,k`); repeat until all are inside.
    ContractingLayers,
}

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

/// Everything a run needs besides the model. Per-constraint vectors are indexed like the
/// model's constraints.
///
/// ```
/// use dae_runtime::{Integrator, Policy, Settings};
/// let s = Settings::new(vec![0.2, 0.2], vec![0.076, 0.066], vec![7.5, 10.0])
///     .step(1e-4)
///     .integrator(Integrator::Rk4)
///     .policy(Policy::Monitor)
///     .t_end(10.0)
///     .settle(1.0);
/// assert_eq!(s.step, 1e-4);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Boundary-layer half widths `eps_i > 0`.
    pub eps: Vec<f64>,
    /// Sliding-surface time constants `mu_i > 0`.
    pub mu: Vec<f64>,
    /// Gains `k_i > 0`.
    pub gains: Vec<f64>,
    /// Crossing margins `k_i^c >= 0` used when counting robustness violations
    /// (T 3.22); zero unless configured.
    pub crossing_margin: Vec<f64>,
    /// Integration step `h > 0` of the fixed-step integrators (Euler, RK4); the
    /// embedded pairs ignore it (their first step is chosen from the tolerance). With
    /// located crossings and the monitored policy it is the longest step: a step is
    /// shortened at a crossing, aimed at the next one, and retried shorter (with the
    /// steps after it) while its estimated error in some `s_i` is above
    /// [`LAYER_ERROR_PER_STEP`] `eps_i`.
    pub step: f64,
    /// Integrator for `x`.
    pub integrator: Integrator,
    /// Tolerances of the embedded pairs; `None` derives them from the layers
    /// ([`TOLERANCE_PER_EPS`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<Tolerance>,
    /// Largest step of the embedded pairs (default: unlimited).
    #[serde(default = "infinite")]
    pub max_step: f64,
    /// How crossings are found (located inside the step by default).
    #[serde(default)]
    pub crossing: Crossing,
    /// Most integration steps (accepted and rejected) a run may take before it stops
    /// with [`SimError::StepLimit`] (default: unlimited).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<u64>,
    /// Relative excess of `|s_i|` over `eps_i` beyond which the layer counts as lost
    /// after reaching ([`Summary::bound_loss`](crate::Summary::bound_loss)); default
    /// [`BOUND_TOL`].
    #[serde(default = "default_bound_tol")]
    pub bound_tol: f64,
    /// Update policy.
    pub policy: Policy,
    /// Reaching-phase rule (monitoring only).
    pub reaching: Reaching,
    /// Cheap or exact `alpha_hat`.
    pub alpha: AlphaChoice,
    /// Start time.
    pub t_start: f64,
    /// End time.
    pub t_end: f64,
    /// Statistics (periods, max |s|, max |w|, violations) are taken from
    /// `max(reaching time, t_start + settle)` on.
    pub settle: f64,
    /// Maximum duration of the reaching phase; exceeding it is an error.
    pub reaching_limit: f64,
    /// Evaluate `beta` at every update to count robustness violations even with the
    /// cheap `alpha_hat` (one extra `beta` evaluation per update). On by default.
    pub check_robustness: bool,
    /// Which solver applies `J_hat^{-1}` at the control updates (see the crate docs).
    #[serde(default)]
    pub solver: SolverChoice,
    /// Raise the gains of the rows that fail the robustness condition (T 3.22) at an
    /// update, to `(1 + margin)` times what the row needs (see
    /// [`Settings::raise_gains`]); `None` keeps the gains and only counts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raise_gains: Option<f64>,
    /// Set each gain at every update from the drift of `s_i'` measured over the
    /// intervals before it (see [`Settings::follow_drift`]); `None` keeps the gains.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub follow_drift: Option<f64>,
    /// With [`Settings::follow_drift`]: raise a gain only as far as its grazing returns
    /// need to stay this long apart (see [`Settings::graze`]); `None` raises it to the
    /// gain that sweeps the layer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub graze: Option<f64>,
    /// Let `v` ramp between updates at the rate that cancels the drift of `s'` found at
    /// each update (see [`Settings::ramp_against_drift`]); `false` holds `v` (the
    /// method's zero-order hold).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub ramp: bool,
    /// Inside the layer, ask for the rate `-k_i s_i / eps_i` instead of `-k_i sgn(s_i)`
    /// (see [`Settings::saturate_in_layer`]); `false` keeps the method's `sgn`.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub saturate: bool,
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

/// Default [`Settings::bound_tol`]: 1 %, ten times the default crossing tolerance
/// [`CROSSING_TOL`], so that located crossings never count as a loss while any real
/// excursion does.
pub const BOUND_TOL: f64 = 0.01;

/// A start point given from outside the model: `n` states and `m` algebraic values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Initial {
    /// Initial states, one per model state.
    pub x0: Vec<f64>,
    /// Initial algebraic unknowns, one per constraint.
    pub z0: Vec<f64>,
}

impl Settings {
    /// Settings with the given layers, time constants and gains, and defaults: RK4 with
    /// `h = 1e-4`, crossings located inside the step, monitoring, attracting surfaces,
    /// cheap `alpha_hat`, `t` from 0 to 1, no settle time, no reaching limit, zero
    /// crossing margins, robustness counting on.
    pub fn new(eps: Vec<f64>, mu: Vec<f64>, gains: Vec<f64>) -> Self {
        let m = eps.len();
        Self {
            eps,
            mu,
            gains,
            crossing_margin: vec![0.0; m],
            step: 1e-4,
            integrator: Integrator::Rk4,
            tolerance: None,
            max_step: f64::INFINITY,
            crossing: Crossing::default(),
            max_steps: None,
            bound_tol: BOUND_TOL,
            policy: Policy::Monitor,
            reaching: Reaching::AttractingSurfaces,
            alpha: AlphaChoice::Cheap,
            t_start: 0.0,
            t_end: 1.0,
            settle: 0.0,
            reaching_limit: f64::INFINITY,
            check_robustness: true,
            solver: SolverChoice::Auto,
            raise_gains: None,
            follow_drift: None,
            graze: None,
            ramp: false,
            saturate: false,
            initial: None,
        }
    }
    /// Set the integration step.
    pub fn step(mut self, h: f64) -> Self {
        self.step = h;
        self
    }
    /// Set the integrator.
    pub fn integrator(mut self, integrator: Integrator) -> Self {
        self.integrator = integrator;
        self
    }
    /// Set the tolerances of the embedded pairs.
    pub fn tolerance(mut self, rtol: f64, atol: f64) -> Self {
        self.tolerance = Some(Tolerance { rtol, atol });
        self
    }
    /// Set the largest step of the embedded pairs.
    pub fn max_step(mut self, h: f64) -> Self {
        self.max_step = h;
        self
    }
    /// Choose how crossings are found.
    pub fn crossing(mut self, crossing: Crossing) -> Self {
        self.crossing = crossing;
        self
    }
    /// Set the relative excess over `eps` that counts as a lost layer.
    pub fn bound_tol(mut self, tol: f64) -> Self {
        self.bound_tol = tol;
        self
    }
    /// Stop a run with [`SimError::StepLimit`] after this many integration steps.
    pub fn max_steps(mut self, n: u64) -> Self {
        self.max_steps = Some(n);
        self
    }

    /// The tolerances the embedded pairs use: the given ones, or
    /// `rtol = atol = TOLERANCE_PER_EPS * min eps_i` (1e-3 without constraints).
    pub fn effective_tolerance(&self) -> Tolerance {
        self.tolerance.unwrap_or_else(|| {
            let e = self.eps.iter().copied().fold(f64::INFINITY, f64::min);
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
    /// Set the update policy.
    pub fn policy(mut self, policy: Policy) -> Self {
        self.policy = policy;
        self
    }
    /// Set the reaching-phase rule.
    pub fn reaching(mut self, reaching: Reaching) -> Self {
        self.reaching = reaching;
        self
    }
    /// Choose cheap or exact `alpha_hat`.
    pub fn alpha(mut self, alpha: AlphaChoice) -> Self {
        self.alpha = alpha;
        self
    }
    /// Set the start time.
    pub fn t_start(mut self, t: f64) -> Self {
        self.t_start = t;
        self
    }
    /// Set the end time.
    pub fn t_end(mut self, t: f64) -> Self {
        self.t_end = t;
        self
    }
    /// Set the settle time before statistics are taken.
    pub fn settle(mut self, duration: f64) -> Self {
        self.settle = duration;
        self
    }
    /// Set the maximum duration of the reaching phase.
    pub fn reaching_limit(mut self, duration: f64) -> Self {
        self.reaching_limit = duration;
        self
    }
    /// Set the crossing margins `k_i^c`.
    pub fn crossing_margin(mut self, kc: Vec<f64>) -> Self {
        self.crossing_margin = kc;
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

    /// Raise failing rows' gains at the updates (T 3.22 policy), with a relative
    /// `margin > 0` above the requirement.
    ///
    /// At every update (also in the reaching phase, which adds one `beta` evaluation
    /// per update) the condition `D_ii > |gamma_i| + sum_{j != i} |D_ij| + k_i^c` is
    /// evaluated for the solver's `J_hat`, and each failing row's gain becomes
    /// `(1 + margin)` times the right-hand side, before `v` is computed:
    ///
    /// * exact solvers: `k_i = (1 + margin)(|alpha_i - alpha_hat_i| + k_i^c)`;
    /// * Jacobi: rows are raised in passes, each with the other rows' current gains;
    ///   the gains grow monotonically to the least solution of
    ///   `(I - (1 + margin)|E_off|) k >= (1 + margin)(|gamma| + k^c)`
    ///   (`E = J_s diag(J_s)^{-1}`), which exists when the absolute Jacobi iteration
    ///   matrix has spectral radius below `1 / (1 + margin)`: then every row holds
    ///   and the crossing condition is restored for all sign patterns;
    /// * iterative and incomplete solvers: `k_i = (1 + margin)(|alpha_i - alpha_hat_i|
    ///   + |r_i| + k_i^c)` with the residual `r` of the solve, then `v` is solved again.
    ///
    /// Raised gains stay raised for the rest of the run (reported in
    /// [`Summary::gains`](crate::Summary::gains)) and never exceed 1000 times the
    /// configured gain; the failures counted are those before the raise.
    pub fn raise_gains(mut self, margin: f64) -> Self {
        self.raise_gains = Some(margin);
        self
    }

    /// Let the gains follow the drift of the sliding variables' rates, measured online.
    ///
    /// Between two updates `v` is held, so `s_i'` moves away from its value `-k_i
    /// sgn(s_i)` right after the update (exact `alpha`) only through the motion of the
    /// state. A rate `s_i'` that drifts at `D_i` can still be swept across the whole
    /// layer `2 eps_i` before it turns if `k_i >= 2 sqrt(eps_i D_i)`. At every update
    /// the drift of the interval just ended, `|s_i'(t^-) - s_i'(t_b^+)| / (t - t_b)`, is
    /// measured (no model evaluation: both rates are known), kept as `D_i =
    /// max(measured, D_i / 2)` (a fading memory of the intervals before), and the gain
    /// becomes `max(k_i configured, safety * 2 sqrt(eps_i D_i))`.
    ///
    /// This is a prediction from the past intervals, not the bound `M_i` of the
    /// sufficient gain (a drift that grows faster than the memory fades can still leave
    /// the layer, and the run reports it). With [`Settings::raise_gains`] as well, each
    /// update starts from the followed gain and raises on top of it. Needs located
    /// crossings ([`Crossing::Located`], the default) and a DBSMC policy; `safety > 0`
    /// (1 is what the particle benchmark uses).
    ///
    /// ```
    /// use dae_runtime::Settings;
    /// let s = Settings::new(vec![1e-3], vec![0.05], vec![0.2]).follow_drift(1.0);
    /// assert_eq!(s.follow_drift, Some(1.0));
    /// ```
    pub fn follow_drift(mut self, safety: f64) -> Self {
        self.follow_drift = Some(safety);
        self
    }

    /// With [`Settings::follow_drift`], let a gain graze its layer instead of sweeping
    /// it: raise it only as far as `safety * D_i * min_return / 2`, the gain whose
    /// grazing returns (`s_i` turned back by the drift before the far side, back at the
    /// level it left after `2 k_i / D_i`) come `min_return` apart, and never above the
    /// sweeping gain `safety * 2 sqrt(eps_i D_i)`.
    ///
    /// Why: the sweeping gain gives one variable alone its fewest updates, but an
    /// update resets every variable, and a raised gain makes all of their next
    /// crossings sooner. On particle chains with heavy ends the gains left at a low
    /// floor and grazing made 5-8x fewer updates than the sweeping ones; a gain too low
    /// for its drift returns ever faster, and `min_return` is where that stops (the
    /// located crossings keep the layer either way). `min_return > 0`, finite.
    ///
    /// ```
    /// use dae_runtime::Settings;
    /// let s = Settings::new(vec![1e-3], vec![0.05], vec![0.2])
    ///     .follow_drift(1.0)
    ///     .graze(5e-4);
    /// assert_eq!(s.graze, Some(5e-4));
    /// ```
    pub fn graze(mut self, min_return: f64) -> Self {
        self.graze = Some(min_return);
        self
    }

    /// Between updates, let `v` ramp instead of holding it: `v(t) = v_b + a (t - t_b)`,
    /// `z` quadratic, with `a = -J_s^{-1} s''` where `s''` is the drift of `s'` at the
    /// update with the new `v` (a finite difference along the flow over `1e-6 min mu`:
    /// one more evaluation of `f`, `s`, `J_Omega` and `beta`, and one solve with the
    /// update's factorisation).
    ///
    /// An extension of the method (which holds `v`): the drift of `s'` is what ends most
    /// control intervals (a drift `D` turns `s` back to a side of its layer within about
    /// `4 sqrt(eps / D)`), and a ramp that cancels it at the update leaves the change of
    /// the drift, so the intervals grow where the drift changes slowly. On the frame-tied
    /// particle design (`cargo run --release -p dae-bench --example relaxed_design`) it
    /// cut the updates per frame from 1,415 to 320 on a light 100-link chain and from
    /// 149 to 54 on a 16 x 16 cloth, and raised them from 152 to 241 on a 100-link chain
    /// with an end 10^4 times heavier, whose drift turns within an interval. Needs
    /// located crossings ([`Crossing::Located`], the default) and a DBSMC policy; the
    /// located crossings and the error test of every step work on the ramped `z` as on
    /// the held one, so the layer is watched the same way.
    ///
    /// ```
    /// use dae_runtime::Settings;
    /// let s = Settings::new(vec![1e-3], vec![0.05], vec![0.2]).ramp_against_drift();
    /// assert!(s.ramp);
    /// ```
    pub fn ramp_against_drift(mut self) -> Self {
        self.ramp = true;
        self
    }

    /// At every update ask each sliding variable inside its layer for the rate
    /// `s_i' = -k_i s_i / eps_i` (the saturation `sat(s_i / eps_i)` in place of `sgn(s_i)`
    /// in the law `v = J_hat^{-1}(-alpha_hat - K sgn(s))`); on and outside the boundary
    /// the two are the same.
    ///
    /// An extension of the method. An update resets every variable, and with `sgn` a
    /// variable found anywhere inside its layer is sent across it at the full gain: of
    /// many variables, the one that happens to sit near its boundary, moving towards the
    /// other side, ends the next interval soon, so the intervals shrink as the number of
    /// constraints grows. With the saturation a variable near the middle of its layer
    /// moves slowly, and the next update is asked for by the variables near their
    /// boundaries. The layer is kept as with `sgn`: a crossing of the boundary moving
    /// outward updates the control there, where the rate asked for is the full gain
    /// inward. What does not carry over is the crossing period of the method's gain
    /// design (T 3.14, T 4.4), which assumes the full gain inside the layer; use it
    /// with a design that does not rely on that period (the frame-tied design of the
    /// particle benchmark, where it cut the updates per frame 1.1-3.2x on the five runs
    /// of `relaxed_design`: `docs/particles-log.md`). Under [`Policy::Spsm`] the law
    /// saturates anyway.
    ///
    /// ```
    /// use dae_runtime::Settings;
    /// let s = Settings::new(vec![1e-3], vec![0.05], vec![0.2]).saturate_in_layer();
    /// assert!(s.saturate);
    /// ```
    pub fn saturate_in_layer(mut self) -> Self {
        self.saturate = true;
        self
    }

    /// Start from `x0` (one value per state) and `z0` (one per constraint) instead of
    /// the model's own initial values, e.g. to start a model in a chosen consistent
    /// configuration without editing it. Lengths and finiteness are checked by
    /// [`Simulator::new`](crate::Simulator::new) (a
    /// [`SimError::Settings`] naming `initial.x0` or `initial.z0`).
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

    /// Check the settings against a model with `n` states and `m` constraints.
    pub(crate) fn validate(&self, n: usize, m: usize) -> Result<(), SimError> {
        let bad = |field: &'static str, reason: String| Err(SimError::Settings { field, reason });
        for (field, v, strict) in [
            ("eps", &self.eps, true),
            ("mu", &self.mu, true),
            ("gains", &self.gains, true),
            ("crossing_margin", &self.crossing_margin, false),
        ] {
            if v.len() != m {
                return bad(field, format!("{} values for {m} constraints", v.len()));
            }
            if let Some((i, x)) = v
                .iter()
                .enumerate()
                .find(|(_, x)| !x.is_finite() || (strict && **x <= 0.0) || **x < 0.0)
            {
                let need = if strict { "> 0" } else { ">= 0" };
                return bad(
                    field,
                    format!("value {i} is {x}, must be finite and {need}"),
                );
            }
        }
        if !(self.step > 0.0 && self.step.is_finite()) {
            return bad("step", format!("{} must be finite and > 0", self.step));
        }
        if !(self.t_start.is_finite() && self.t_end.is_finite() && self.t_end > self.t_start) {
            return bad(
                "t_end",
                format!(
                    "[{}, {}] is not a finite, non-empty interval",
                    self.t_start, self.t_end
                ),
            );
        }
        if let Some(tol) = self.tolerance {
            if !(tol.rtol.is_finite() && tol.rtol >= 0.0 && tol.atol.is_finite() && tol.atol >= 0.0)
                || tol.rtol + tol.atol <= 0.0
            {
                return bad(
                    "tolerance",
                    format!(
                        "rtol {} and atol {} must be finite, >= 0 and not both 0",
                        tol.rtol, tol.atol
                    ),
                );
            }
        }
        if !(self.bound_tol >= 0.0 && self.bound_tol.is_finite()) {
            return bad(
                "bound_tol",
                format!("{} must be finite and >= 0", self.bound_tol),
            );
        }
        if self.max_step.is_nan() || self.max_step <= 0.0 {
            return bad("max_step", format!("{} must be > 0", self.max_step));
        }
        if let Crossing::Located { tol } = self.crossing {
            if !(tol > 0.0 && tol < 0.5) {
                return bad("crossing", format!("tolerance {tol} must be in (0, 0.5)"));
            }
        }
        if self.policy == Policy::Spsm && self.integrator.is_adaptive() {
            return bad(
                "integrator",
                "SPSM is integrated with a fixed step: choose Euler or RK4".into(),
            );
        }
        if let Policy::Fixed(p) = self.policy {
            if !(p > 0.0 && p.is_finite()) {
                return bad("policy", format!("fixed period {p} must be finite and > 0"));
            }
        }
        if self.settle.is_nan() || self.settle < 0.0 {
            return bad("settle", format!("{} must be >= 0", self.settle));
        }
        if self.reaching_limit.is_nan() || self.reaching_limit <= 0.0 {
            return bad(
                "reaching_limit",
                format!("{} must be > 0", self.reaching_limit),
            );
        }
        if let Some(margin) = self.raise_gains {
            if !(margin.is_finite() && margin > 0.0) {
                return bad(
                    "raise_gains",
                    format!("margin {margin} must be finite and > 0"),
                );
            }
        }
        if let Some(safety) = self.follow_drift {
            if !(safety.is_finite() && safety > 0.0) {
                return bad(
                    "follow_drift",
                    format!("safety {safety} must be finite and > 0"),
                );
            }
            if self.policy == Policy::Spsm || !matches!(self.crossing, Crossing::Located { .. }) {
                return bad(
                    "follow_drift",
                    "needs the rates s' at the step ends: located crossings \
                     (Crossing::Located, the default) and a DBSMC policy (not Spsm)"
                        .into(),
                );
            }
        }
        if let Some(t) = self.graze {
            if !(t.is_finite() && t > 0.0) {
                return bad("graze", format!("min_return {t} must be finite and > 0"));
            }
            if self.follow_drift.is_none() {
                return bad(
                    "graze",
                    "grazes the gains that follow the drift: set follow_drift too".into(),
                );
            }
        }
        if self.ramp
            && (self.policy == Policy::Spsm || !matches!(self.crossing, Crossing::Located { .. }))
        {
            return bad(
                "ramp",
                "needs the rates s' at the step ends: located crossings \
                 (Crossing::Located, the default) and a DBSMC policy (not Spsm)"
                    .into(),
            );
        }
        if let Some(init) = &self.initial {
            for (field, v, len, what) in [
                ("initial.x0", &init.x0, n, "states"),
                ("initial.z0", &init.z0, m, "constraints"),
            ] {
                if v.len() != len {
                    return bad(field, format!("{} values for {len} {what}", v.len()));
                }
                if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                    return bad(field, format!("value {i} is {x}, must be finite"));
                }
            }
        }
        Ok(())
    }
}
