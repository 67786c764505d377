//! Design toolkit: guaranteed update periods, gains and the choice of `mu` (docs/method.md
//! section 5; formula numbers "(T x.y)" refer to F. Rum's 2004 thesis).
//!
//! Everything here is a pure function of a few bounds that describe one constraint
//! ([`ConstraintSpec`]: index `r`, layer half-width `eps`, drift bound `M`, `|beta|`):
//!
//! * [`t_min`] (T 3.14, with the (T 4.6) and (T 4.7) variants selected by
//!   [`LayerBound`]) and its converse [`reachable_bound`] (T 3.13);
//! * gains: [`sufficient_gain`] (T 4.4, corrected), [`robust_gain`] (T 3.17, 3.21) and
//!   the design choices of docs/method.md section 5 in [`GainChoice`];
//! * [`optimise_mu`] / [`design`]: maximise `T_i^min(mu_i)` with the gain substituted
//!   (T corollary 4.1, section 4.3), and take the smallest over the constraints (T 3.15);
//!   [`design_at`]: the same at given `mu_i`;
//! * approximate inverses (T 3.22): [`approximate_inverse_gain`] (from a row's
//!   dominance margin), [`approximate_inverse_gains`] (the least gains for a coupling
//!   `E = J_s J_hat^{-1}`, solved with the solver seam) and [`jacobi_coupling`];
//! * [`PilotEstimator`]: estimates `|beta_i|` and `M_i` from samples of a pilot run;
//!   [`pilot_run`] feeds it from a simulation and [`auto_design`] runs the whole
//!   procedure (pilot, design, pilot again with the design, design);
//! * [`consistent_start`]: the algebraic start values consistent with the states;
//! * [`Online`]: the design without a pilot (the particle benchmark's frame-tied one),
//!   from the layers and a time scale, in one call for a whole run ([`Online::design`]).
//!
//! Invalid input (non-finite numbers, `eps <= 0`, `mu <= 0`, `r = 0`, ...) is reported
//! as a [`DesignError`] or [`PilotError`], never by a panic.

mod approx;
mod bounds;
mod gains;
mod mu_searcher;
mod online;
mod optimise;
mod pilot;
mod pilot_run;
mod start;

pub use approx::{approximate_inverse_gain, approximate_inverse_gains, jacobi_coupling};
pub use bounds::{LayerBound, c_r, reachable_bound, t_min};
pub use gains::{GainChoice, robust_gain, sufficient_gain};
pub use mu_searcher::MuSearcher;
pub use online::{Online, OnlineError};
pub use optimise::{ConstraintDesign, Design, MuSearch, design, design_at, optimise_mu};
pub use pilot::{PilotError, PilotEstimate, PilotEstimator, ROUNDING_FLOOR};
pub use pilot_run::{
    AutoDesign, AutoDesignOptions, DesignPass, MuChoice, PilotRun, PilotRunError, auto_design,
    pilot_run, pilot_specs,
};
pub use start::{ConsistentStart, MAX_NEWTON, StartError, consistent_start, consistent_start_with};

/// The largest constraint index the formulas accept; `mu^(r-1)` and `2^r` are computed
/// in `f64` and no realistic model comes near it.
pub const MAX_INDEX: usize = 64;

/// The bounds that describe one constraint for design purposes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstraintSpec {
    /// Index (relative degree) `r >= 1` of the constraint.
    pub r: usize,
    /// Half-width `eps > 0` of the boundary layer `|s| <= eps`.
    pub eps: f64,
    /// Bound `M >= 0` on the drift of `w^(r)` within a control interval (T 3.5):
    /// `|w^(r)(t) - w^(r)(t_b)| <= M (t - t_b)`.
    pub m: f64,
    /// Bound `|beta| >= 0` on `beta = dOmega/dt + (dOmega/dx) f` (T 2.5).
    pub beta_abs: f64,
    /// Which bound on the sliding terms enters `b` of (T 3.14).
    pub layer: LayerBound,
}

impl ConstraintSpec {
    /// Checks every field; the formulas call this first.
    pub fn validate(&self) -> Result<(), DesignError> {
        check_index(self.r)?;
        positive("eps", self.eps)?;
        non_negative("M", self.m)?;
        non_negative("|beta|", self.beta_abs)?;
        self.layer.validate(self.r)
    }
}

/// Why a design formula could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// A quantity that must be finite and strictly positive was not.
    #[error("{name} must be finite and positive, got {value}")]
    NotPositive {
        /// Name of the quantity (`eps`, `mu`, ...).
        name: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A quantity that must be finite and non-negative was not.
    #[error("{name} must be finite and non-negative, got {value}")]
    Negative {
        /// Name of the quantity (`M`, `|beta|`, `k`, ...).
        name: &'static str,
        /// The offending value.
        value: f64,
    },
    /// The constraint index is outside `1..=MAX_INDEX`.
    #[error("constraint index r must be in 1..={max}, got {r}")]
    BadIndex {
        /// The offending index.
        r: usize,
        /// [`MAX_INDEX`].
        max: usize,
    },
    /// A formula that the thesis states for one index only was used with another.
    #[error("{formula} is stated for index r = 3 only, got r = {r}")]
    IndexNotSupported {
        /// The formula, e.g. "(T 4.6)".
        formula: &'static str,
        /// The index it was asked for.
        r: usize,
    },
    /// (T 3.13) bounds `|s|` only for periods below `1 / lambda` (`= mu / c_r`).
    #[error("period {period} is not below {limit} (mu / c_r): (T 3.13) gives no bound")]
    PeriodTooLong {
        /// The requested period.
        period: f64,
        /// The largest admissible period (exclusive).
        limit: f64,
    },
    /// The search range for `mu` is empty or too coarse.
    #[error("bad mu search range: [{lo}, {hi}] with {points} scan points")]
    BadSearch {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
        /// Number of scan points.
        points: usize,
    },
    /// The best `mu` of the coarse scan lies at an end of the search range, so the
    /// maximum of `T_min(mu)` may lie outside it.
    #[error("T_min(mu) has no interior maximum in [{lo}, {hi}]: best scan point mu = {mu}")]
    NoInteriorMaximum {
        /// Best scan point (an end of the range).
        mu: f64,
        /// Lower end of the range.
        lo: f64,
        /// Upper end of the range.
        hi: f64,
    },
    /// No gains satisfy the robustness condition (T 3.22) with this approximate
    /// inverse.
    #[error("no robust gain for row {row}: {reason}")]
    NoRobustGain {
        /// The first row without a positive gain.
        row: usize,
        /// Why.
        reason: String,
    },
    /// The search for `mu` during a run cannot search
    /// ([`AdaptiveMu::check`](crate::settings::AdaptiveMu::check)).
    #[error("{reason}")]
    BadAdaptiveMu {
        /// Which field, and why.
        reason: String,
    },
    /// [`design`] was given no constraints.
    #[error("no constraints to design for")]
    NoConstraints,
    /// A per-constraint list has the wrong length.
    #[error("{what} has {got} entries, expected {expected} (one per constraint)")]
    CountMismatch {
        /// The list (`mu`).
        what: &'static str,
        /// Its length.
        got: usize,
        /// The number of constraints.
        expected: usize,
    },
    /// An error about one constraint of a [`design`].
    #[error("constraint {index}: {source}")]
    Constraint {
        /// Position of the constraint in the input.
        index: usize,
        /// What went wrong.
        source: Box<DesignError>,
    },
}

pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, DesignError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(DesignError::NotPositive { name, value })
    }
}

pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, DesignError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(DesignError::Negative { name, value })
    }
}

pub(crate) fn check_index(r: usize) -> Result<usize, DesignError> {
    if (1..=MAX_INDEX).contains(&r) {
        Ok(r)
    } else {
        Err(DesignError::BadIndex { r, max: MAX_INDEX })
    }
}

/// `mu^(r-1)`, the scale of `beta` and `w^(r)` in `s'` (T 2.6, 2.7); `r` is checked.
pub(crate) fn mu_pow(mu: f64, e: usize) -> f64 {
    // e <= MAX_INDEX, so the cast is exact.
    mu.powi(e as i32)
}
