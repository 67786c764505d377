//! The online design: `mu`, the gains, the law and the step control from the layers and
//! a time scale alone, with no pilot run. Where the motion drifts faster than the gains'
//! floor assumes, the gains follow the drift the run measures between its updates.

use super::{DesignError, consistent_start, positive};
use crate::settings::{AdaptiveMu, Dbsmc, GainRule, InLayer, Integrator};
use crate::{Model, Settings, settings::AlphaChoice};

/// The design of the particle benchmark's frame-tied runs (docs/particles.md, "Methods"),
/// for any model: every constraint gets
///
/// * `mu = mu_per_frame * frame` (a quarter of the frame by default) at the start, then
///   searched for frame by frame ([`search`](Self::search), [`AdaptiveMu::wide`] by
///   default: between 1/16 and 64 times the start);
/// * gains of at least `floor * eps_i / mu` that follow the drift of `s_i'` measured at
///   the updates ([`GainRule::FollowDrift`] with `safety = drift_safety`), raised only as
///   far as grazing returns `graze_per_mu * mu` apart need;
/// * the rate `-k_i s_i / eps_i` inside the layer ([`InLayer::Saturate`]) and the exact
///   `alpha` ([`AlphaChoice::Exact`]), monitoring with located crossings;
/// * Dormand-Prince 5(4) at `rtol = atol = tolerance_per_eps * min eps_i` with steps of at
///   most `step_per_mu * mu`.
///
/// The floor is the sufficient gain of (T 4.4), `k = mu^3 M / 2 + 4 eps / mu`, for an
/// assumed drift `M_i = 2 (floor - 4) eps_i / mu^4` instead of a pilot's worst one. No
/// formula guarantees the crossing when the drift grows faster than the gains follow it:
/// the located crossings then report the layer lost
/// ([`Summary::bound_loss`](crate::Summary::bound_loss)), never silently.
///
/// With `mu` kept (`search: None`) what it costs follows the frame: the grazing returns
/// set about one update per `mu / 8` per active constraint, whatever `eps`. The search
/// finds the larger `mu` at which a slow system at a loose layer is cheaper (the 3-D
/// double pendulum at `eps = 0.2`: 8,926 `f` evaluations over 10 s against 50,085 with
/// `mu` kept; docs/cli.md has the table), at the cost of its trials where the start's
/// `mu` was right (up to 1.35x on the particle runs measured there).
///
/// ```
/// use dae_runtime::design::Online;
/// let s = Online::default().settings(vec![1e-3, 2e-3]).unwrap();
/// assert_eq!(s.layers.mu, vec![Online::default().mu(); 2]);
/// assert!(s.law.follows_drift().is_some());
/// assert_eq!(s.layers.adapt_mu.unwrap().frame, Online::default().frame);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Online {
    /// The time scale at which the motion is looked at, in seconds (a frame).
    pub frame: f64,
    /// `mu` as a fraction of the frame.
    pub mu_per_frame: f64,
    /// The gains' floor `c` in `k_i >= c eps_i / mu` (at least 4: below it the floor is
    /// below the sufficient gain of a motion without drift).
    pub floor: f64,
    /// The longest step as a fraction of `mu`.
    pub step_per_mu: f64,
    /// The state tolerance as a fraction of the smallest layer.
    pub tolerance_per_eps: f64,
    /// Safety factor of the gains over the measured drift.
    pub drift_safety: f64,
    /// The shortest time between grazing returns, as a fraction of `mu`.
    pub graze_per_mu: f64,
    /// The search for `mu` during the run ([`Layers::adapt_mu`](crate::settings::Layers::adapt_mu)),
    /// at frames of [`frame`](Self::frame) (its own `frame` is replaced by it), or none.
    pub search: Option<AdaptiveMu>,
    /// The most constraints a model may have for [`search`](Self::search) to apply: the
    /// search pays on models of few constraints and costs up to 1.35x on the particle
    /// systems of hundreds to thousands of links, where the frame-tied `mu` suits
    /// (docs/cli.md), and on the 32 x 32 cloth at `eps = 1e-2` its smaller `mu` led the
    /// sparse solver to a pivot it could not use.
    pub search_up_to: usize,
}

impl Default for Online {
    /// A frame of 1/60 s, `mu` a quarter of it, the floor `4 eps / mu`, steps of at most
    /// `mu / 2`, the tolerance a tenth of the smallest layer, the gains at the drift
    /// (safety 1), grazing returns `mu / 8` apart: the values docs/particles.md measured.
    fn default() -> Self {
        Online {
            frame: 1.0 / 60.0,
            mu_per_frame: 0.25,
            floor: 4.0,
            step_per_mu: 0.5,
            tolerance_per_eps: 0.1,
            drift_safety: 1.0,
            graze_per_mu: 0.125,
            search: Some(AdaptiveMu::wide(1.0 / 60.0)),
            search_up_to: 256,
        }
    }
}

/// Why [`Online::design`] could not design a run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OnlineError {
    /// A value of the design or a layer is out of range.
    #[error("{0}")]
    Design(#[from] DesignError),
    /// No consistent algebraic start values.
    #[error("consistent start: {0}")]
    Start(#[from] super::StartError),
}

impl Online {
    /// The default design with another frame.
    pub fn frame(frame: f64) -> Self {
        Online {
            frame,
            ..Online::default()
        }
    }

    /// `mu` of every constraint.
    pub fn mu(&self) -> f64 {
        self.mu_per_frame * self.frame
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<(), DesignError> {
        positive("frame", self.frame)?;
        positive("mu_per_frame", self.mu_per_frame)?;
        positive("step_per_mu", self.step_per_mu)?;
        positive("tolerance_per_eps", self.tolerance_per_eps)?;
        positive("drift_safety", self.drift_safety)?;
        positive("graze_per_mu", self.graze_per_mu)?;
        if let Some(search) = &self.search {
            AdaptiveMu {
                frame: self.frame,
                ..*search
            }
            .check()
            .map_err(|reason| DesignError::BadAdaptiveMu { reason })?;
        }
        if !(self.floor.is_finite() && self.floor >= 4.0) {
            return Err(DesignError::Negative {
                name: "floor - 4",
                value: self.floor - 4.0,
            });
        }
        positive("mu", self.mu()).map(|_| ())
    }

    /// The settings for layers `eps` (one per constraint; the time window and the start
    /// are the defaults of [`Settings::new`]).
    pub fn settings(&self, eps: Vec<f64>) -> Result<Settings, DesignError> {
        self.validate()?;
        for (i, &e) in eps.iter().enumerate() {
            positive("eps", e).map_err(|source| DesignError::Constraint {
                index: i,
                source: Box::new(source),
            })?;
        }
        let m = eps.len();
        let mu = self.mu();
        let k: Vec<f64> = eps.iter().map(|e| self.floor * e / mu).collect();
        let tol = self.tolerance_per_eps * eps.iter().copied().fold(f64::INFINITY, f64::min);
        let mut settings = Settings::new(eps, vec![mu; m], k);
        if m > 0 {
            settings = settings.tolerance(tol, tol);
        }
        Ok(settings
            .alpha(AlphaChoice::Exact)
            .integrator(Integrator::DormandPrince)
            .step(self.frame)
            .max_step(self.step_per_mu * mu)
            .law(
                Dbsmc::default()
                    .gains(GainRule::FollowDrift {
                        safety: self.drift_safety,
                        graze: Some(self.graze_per_mu * mu),
                        raise: None,
                    })
                    .in_layer(InLayer::Saturate),
            )
            .adapt_mu(
                self.search
                    .filter(|_| m <= self.search_up_to)
                    .map(|how| AdaptiveMu {
                        frame: self.frame,
                        ..how
                    }),
            ))
    }

    /// A whole run of `model` from `t = 0` to `t_end` in one call: [`Online::settings`]
    /// with `eps` (one value for every constraint, or one per constraint), starting from
    /// the model's states and the algebraic values consistent with them
    /// ([`consistent_start`], in [`Settings::initial`]).
    pub fn design<M: Model + ?Sized>(
        &self,
        model: &M,
        eps: &[f64],
        t_end: f64,
    ) -> Result<Settings, OnlineError> {
        let m = model.n_constraints();
        let eps = match eps.len() {
            1 => vec![eps[0]; m],
            n if n == m => eps.to_vec(),
            n => {
                return Err(DesignError::CountMismatch {
                    what: "eps",
                    got: n,
                    expected: m,
                }
                .into());
            }
        };
        positive("t_end", t_end)?;
        let mut x0 = vec![0.0; model.n_states()];
        let mut z0 = vec![0.0; m];
        model.initial_state(&mut x0);
        model.initial_alg(&mut z0);
        let z0 = if m > 0 {
            consistent_start(model, 0.0, &x0, &z0)?.z0
        } else {
            z0
        };
        Ok(self.settings(eps)?.t_end(t_end).initial(x0, z0))
    }
}
