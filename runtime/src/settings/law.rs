//! The control law and its update rule, as types whose variants carry what they need:
//! a combination the simulator cannot run cannot be written.

use serde::{Deserialize, Serialize};

/// Default relative tolerance of a located crossing ([`Dbsmc::crossing_tol`]).
pub const CROSSING_TOL: f64 = 1e-3;

/// How the control `v` is computed and when it is recomputed.
///
/// ```
/// use dae_runtime::settings::{Dbsmc, GainRule, Hold, Law, Update};
/// let law: Law = Dbsmc::default()
///     .update(Update::Fixed { period: 0.01 })
///     .gains(GainRule::FollowDrift { safety: 1.0, graze: None, raise: None })
///     .hold(Hold::RampAgainstDrift)
///     .into();
/// assert!(law.ramps());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Law {
    /// DBSMC with crossings located inside the step (the default): `v` is computed at
    /// the updates and held (or ramped) between them; a step ends where some `s_i`
    /// asks for an update, so `|s_i| <= (1 + tol) eps_i` for any step.
    Dbsmc(Dbsmc),
    /// DBSMC with the layers checked at the end of each step only (the thesis's rule,
    /// kept to reproduce its numbers): `s_i` can overshoot its layer by one step of
    /// motion, `|s_i'| h`. Without the rates at the step ends, the gains cannot follow
    /// the drift and `v` cannot ramp.
    StepEnd(StepEnd),
    /// The continuous predecessor (SPSM): `sat(s/eps)` in place of `sgn(s)` and `v`
    /// recomputed at every integrator stage, an ordinary (stiff) ODE integrated with a
    /// fixed step.
    Spsm,
}

impl Default for Law {
    fn default() -> Self {
        Law::Dbsmc(Dbsmc::default())
    }
}

impl From<Dbsmc> for Law {
    fn from(d: Dbsmc) -> Self {
        Law::Dbsmc(d)
    }
}

impl From<StepEnd> for Law {
    fn from(d: StepEnd) -> Self {
        Law::StepEnd(d)
    }
}

/// DBSMC with located crossings: see [`Law::Dbsmc`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Dbsmc {
    /// When `v` is recomputed.
    pub update: Update,
    /// Relative tolerance of a located crossing: `|s_i| / eps_i` is in `[1 - tol, 1 +
    /// tol]` at the update; in `(0, 0.5)`, default [`CROSSING_TOL`].
    pub crossing_tol: f64,
    /// How the gains are set at the updates.
    pub gains: GainRule,
    /// How `v` moves between updates.
    pub hold: Hold,
    /// What the law asks of a variable inside its layer.
    pub in_layer: InLayer,
}

impl Default for Dbsmc {
    /// Monitoring with attracting surfaces, [`CROSSING_TOL`], fixed gains, `v` held,
    /// `sgn(s)` inside the layer: the method as published.
    fn default() -> Self {
        Self {
            update: Update::default(),
            crossing_tol: CROSSING_TOL,
            gains: GainRule::Fixed,
            hold: Hold::Constant,
            in_layer: InLayer::Sign,
        }
    }
}

impl Dbsmc {
    /// Set when `v` is recomputed.
    pub fn update(mut self, update: Update) -> Self {
        self.update = update;
        self
    }
    /// Set the relative tolerance of a located crossing.
    pub fn crossing_tol(mut self, tol: f64) -> Self {
        self.crossing_tol = tol;
        self
    }
    /// Set how the gains are chosen at the updates.
    pub fn gains(mut self, gains: GainRule) -> Self {
        self.gains = gains;
        self
    }
    /// Set how `v` moves between updates.
    pub fn hold(mut self, hold: Hold) -> Self {
        self.hold = hold;
        self
    }
    /// Set what the law asks of a variable inside its layer.
    pub fn in_layer(mut self, in_layer: InLayer) -> Self {
        self.in_layer = in_layer;
        self
    }
}

/// DBSMC checked at step ends: see [`Law::StepEnd`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct StepEnd {
    /// When `v` is recomputed.
    pub update: Update,
    /// Raise the gains of the rows that fail the robustness condition (see
    /// [`GainRule::Raise`]); `None` keeps them.
    pub raise: Option<f64>,
    /// What the law asks of a variable inside its layer.
    pub in_layer: InLayer,
}

/// When a DBSMC control is recomputed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Update {
    /// Monitoring (variable period, the method): update as soon as some `s_i` is on or
    /// beyond its layer boundary and moving outward.
    Monitor {
        /// The rule while the motion is still outside some layer.
        reaching: Reaching,
        /// Which rows an update recomputes once every layer was reached.
        #[serde(default)]
        scope: Scope,
    },
    /// Without monitoring: every `period` seconds (with a fixed step, rounded to a
    /// whole number of steps, at least one).
    Fixed {
        /// The period in seconds, finite and `> 0`.
        period: f64,
    },
}

impl Default for Update {
    fn default() -> Self {
        Update::Monitor {
            reaching: Reaching::AttractingSurfaces,
            scope: Scope::Global,
        }
    }
}

/// Which rows a monitored update recomputes.
///
/// The method as published recomputes every row whenever one asks, which costs a
/// factorisation and solve of all of `J_s` per event: on a large, sparsely coupled
/// system (a long chain, a cloth) the events grow with the system and so does each
/// update. With [`Scope::Blocks`] an event recomputes only the blocks of the rows that
/// asked, each from a solve with its own block of `J_s`, the other rows' `v` held; the
/// layer is kept by the same monitor (docs/method.md, section 4, "Block-local
/// updates").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Scope {
    /// Every row at every update (the method as published).
    #[default]
    Global,
    /// The constraints partitioned into blocks of at most `size` rows that are close in
    /// the graph of `J_Omega` (breadth-first, a block never spans two unconnected
    /// parts); an update recomputes the blocks of the rows that asked for it. The
    /// reaching phase and the updates the caller asks for (a changed model, a new
    /// `mu`) stay global. Needs fixed gains and `v` held between updates.
    Blocks {
        /// The most rows in a block, `>= 1`.
        size: usize,
    },
}

/// Update rule while the motion is still outside some layer (monitoring only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Reaching {
    /// Keep the design gains and layers; update when a trajectory outside its layer
    /// starts to move away from its surface (`s_i s_i' > 0`) or one inside reaches the
    /// far side of its layer. This is the steady monitoring rule applied from the start.
    #[default]
    AttractingSurfaces,
    /// At update `k` use `eps_i,k = max(|s_i,k|, eps_i)`; update when a trajectory that
    /// was outside at the update reaches its surface (its `s_i` changes sign) or one that
    /// was inside reaches the far side of its layer (or any moves outward past
    /// `eps_i,k`); repeat until all are inside.
    ContractingLayers,
}

/// How the gains `k_i` are set at the control updates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub enum GainRule {
    /// The configured gains throughout (the method).
    #[default]
    Fixed,
    /// Raise the gains of the rows that fail the robustness condition (T 3.22) at an
    /// update to `(1 + margin)` times what the row needs, `margin > 0`.
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
    Raise {
        /// Relative margin above the requirement, finite and `> 0`.
        margin: f64,
    },
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
    /// sufficient gain: a drift that grows faster than the memory fades can still leave
    /// the layer, and the run reports it.
    FollowDrift {
        /// Factor on the followed gain, finite and `> 0` (1 is what the particle
        /// benchmark uses).
        safety: f64,
        /// Let a gain graze its layer instead of sweeping it: raise it only as far as
        /// `safety * D_i * min_return / 2`, the gain whose grazing returns (`s_i` turned
        /// back by the drift before the far side, back at the level it left after `2
        /// k_i / D_i`) come `min_return` seconds apart, and never above the sweeping
        /// gain. An update resets every variable and a raised gain makes all of their
        /// next crossings sooner, so on many constraints grazing gains make fewer
        /// updates (docs/particles.md); the located crossings keep the layer either
        /// way. `None` sweeps; `Some(min_return)` finite and `> 0`.
        graze: Option<f64>,
        /// Raise failing rows on top of the followed gain, as [`GainRule::Raise`] does;
        /// `None` does not.
        raise: Option<f64>,
    },
}

/// How `v` moves between two updates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Hold {
    /// The method's zero-order hold: `v` constant, `z` on its exact linear ramp.
    #[default]
    Constant,
    /// Let `v` ramp instead: `v(t) = v_b + a (t - t_b)`, `z` quadratic, with `a =
    /// -J_s^{-1} s''` where `s''` is the drift of `s'` at the update with the new `v` (a
    /// finite difference along the flow over `1e-6 min mu`: one more evaluation of `f`,
    /// `s`, `J_Omega` and `beta`, and one solve with the update's factorisation).
    ///
    /// An extension of the method: the drift of `s'` is what ends most control
    /// intervals (a drift `D` turns `s` back to a side of its layer within about `4
    /// sqrt(eps / D)`), and a ramp that cancels it at the update leaves the change of
    /// the drift, so the intervals grow where the drift changes slowly; where the drift
    /// turns within an interval it can cost updates (docs/particles.md measures both).
    /// The located crossings and the error test of every step work on the ramped `z` as
    /// on the held one, so the layer is watched the same way.
    RampAgainstDrift,
}

/// What the law `v = J_hat^{-1}(-alpha_hat - K phi(s))` asks of a sliding variable
/// inside its layer; on and outside the boundary the two are the same.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum InLayer {
    /// `phi = sgn(s)`, the method: a variable anywhere inside is sent across the layer
    /// at the full gain.
    #[default]
    Sign,
    /// `phi = sat(s / eps)`, the rate `-k_i s_i / eps_i`: a variable near the middle of
    /// its layer moves slowly, and the next update is asked for by the variables near
    /// their boundaries.
    ///
    /// An extension of the method. An update resets every variable, and with `sgn` the
    /// one that happens to sit near its boundary, moving towards the other side, ends
    /// the next interval soon, so the intervals shrink as the number of constraints
    /// grows. The layer is kept as with `sgn`: a crossing of the boundary moving outward
    /// updates the control there, where the rate asked for is the full gain inward.
    /// What does not carry over is the crossing period of the method's gain design (T
    /// 3.14, T 4.4), which assumes the full gain inside the layer: use it with a design
    /// that does not rely on that period (the frame-tied design of the particle
    /// benchmark).
    Saturate,
}

/// What the simulator reads off a law, one question at a time.
impl Law {
    /// The update rule of a DBSMC law; `None` for SPSM (which updates at every stage).
    pub fn update(&self) -> Option<Update> {
        match self {
            Law::Dbsmc(d) => Some(d.update),
            Law::StepEnd(d) => Some(d.update),
            Law::Spsm => None,
        }
    }
    /// Whether the control is updated by monitoring the layers.
    pub fn monitors(&self) -> bool {
        matches!(self.update(), Some(Update::Monitor { .. }))
    }
    /// The reaching rule (attracting surfaces where the law does not monitor).
    pub fn reaching(&self) -> Reaching {
        match self.update() {
            Some(Update::Monitor { reaching, .. }) => reaching,
            _ => Reaching::AttractingSurfaces,
        }
    }
    /// Which rows a monitored update recomputes ([`Scope::Global`] where the law does
    /// not monitor).
    pub fn scope(&self) -> Scope {
        match self.update() {
            Some(Update::Monitor { scope, .. }) => scope,
            _ => Scope::Global,
        }
    }
    /// The tolerance of located crossings, `None` where crossings are not located.
    pub fn crossing_tol(&self) -> Option<f64> {
        match self {
            Law::Dbsmc(d) => Some(d.crossing_tol),
            _ => None,
        }
    }
    /// The margin by which failing rows' gains are raised, if they are.
    pub fn raise_margin(&self) -> Option<f64> {
        match self {
            Law::Dbsmc(d) => match d.gains {
                GainRule::Fixed => None,
                GainRule::Raise { margin } => Some(margin),
                GainRule::FollowDrift { raise, .. } => raise,
            },
            Law::StepEnd(d) => d.raise,
            Law::Spsm => None,
        }
    }
    /// The safety factor and grazing return of gains that follow the drift, if they do.
    pub fn follows_drift(&self) -> Option<(f64, Option<f64>)> {
        match self {
            Law::Dbsmc(Dbsmc {
                gains: GainRule::FollowDrift { safety, graze, .. },
                ..
            }) => Some((*safety, *graze)),
            _ => None,
        }
    }
    /// Whether `v` ramps against the drift between updates.
    pub fn ramps(&self) -> bool {
        matches!(
            self,
            Law::Dbsmc(Dbsmc {
                hold: Hold::RampAgainstDrift,
                ..
            })
        )
    }
    /// Whether the law saturates inside the layer (SPSM always does).
    pub fn saturates(&self) -> bool {
        match self {
            Law::Dbsmc(d) => d.in_layer == InLayer::Saturate,
            Law::StepEnd(d) => d.in_layer == InLayer::Saturate,
            Law::Spsm => true,
        }
    }
    /// The grazing return, to be scaled with `mu` (see
    /// [`Simulator::rescale_mu`](crate::Simulator::rescale_mu)).
    pub(crate) fn graze_mut(&mut self) -> Option<&mut f64> {
        match self {
            Law::Dbsmc(Dbsmc {
                gains: GainRule::FollowDrift { graze: Some(g), .. },
                ..
            }) => Some(g),
            _ => None,
        }
    }
}
