//! Typed run-time errors of the simulator.

use std::fmt;

/// Which kind of quantity became non-finite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// A differential state `x_i`.
    State,
    /// An algebraic unknown `z_i`.
    Algebraic,
    /// The control `v_i = z_i'` computed at an update.
    Control,
    /// A sliding variable `s_i`.
    Sliding,
    /// A constraint residual `w_i`.
    Residual,
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quantity::State => "state",
            Quantity::Algebraic => "algebraic unknown",
            Quantity::Control => "control rate v of algebraic unknown",
            Quantity::Sliding => "sliding variable of constraint",
            Quantity::Residual => "residual of constraint",
        })
    }
}

/// An error raised by [`Simulator::new`](crate::Simulator::new) or
/// [`Simulator::run`](crate::Simulator::run).
///
/// A run that fails keeps everything its sink recorded up to the failure: the sink is
/// owned by the caller, so a [`Trace`](crate::Trace) can still be inspected or written
/// out with [`Trace::write_csv`](crate::Trace::write_csv) after the error.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The settings do not fit the model or are out of range.
    #[error("invalid settings: {field}: {reason}")]
    Settings {
        /// The offending setting.
        field: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// A value became NaN or infinite.
    #[error("{kind} `{name}` became non-finite ({value}) at t = {t}")]
    NonFinite {
        /// What kind of quantity.
        kind: Quantity,
        /// Its index among quantities of that kind.
        index: usize,
        /// Its name in the model (for sliding variables and residuals, the constraint).
        name: String,
        /// The offending value.
        value: f64,
        /// Simulation time at which it was detected.
        t: f64,
    },
    /// `J_s = diag(mu^(r-1)) J_Omega` could not be factored at a control update.
    #[error(
        "singular J_s at t = {t}: constraints {} have no independent pivot (the algebraic unknowns do not appear independently in their (r-1)-th derivatives)",
        quoted(names)
    )]
    SingularJacobian {
        /// Simulation time of the update.
        t: f64,
        /// Indices of the constraints whose rows are dependent.
        constraints: Vec<usize>,
        /// Their names.
        names: Vec<String>,
    },
    /// The solver of `J_s` could not be used at a control update (a vanished diagonal
    /// pivot of a solver without row exchanges on a nonsingular `J_s`, unsymmetric
    /// values for CG, a non-finite entry).
    #[error("solver `{solver}` failed at t = {t}: {reason}")]
    SolverFailed {
        /// Simulation time of the update.
        t: f64,
        /// The solver's name.
        solver: String,
        /// What went wrong, naming the constraints involved, and what to do.
        reason: String,
    },
    /// The reaching phase (all `|s_i| <= eps_i`) was not finished within the limit.
    #[error(
        "reaching phase not finished after {limit} s (at t = {t}): {} still outside {}, s = {s:?}",
        quoted(names),
        if names.len() == 1 { "its layer" } else { "their layers" }
    )]
    ReachingTimeout {
        /// The configured limit (duration from the start).
        limit: f64,
        /// Simulation time at which the limit was exceeded.
        t: f64,
        /// Names of the constraints still outside their layers.
        names: Vec<String>,
        /// Their sliding variables.
        s: Vec<f64>,
    },
    /// The run took more integration steps than
    /// [`Settings::max_steps`](crate::Settings::max_steps).
    #[error(
        "step limit of {limit} steps reached at t = {t}: the step needed to meet the tolerance became very small (a stiff model, a state leaving the model's domain)"
    )]
    StepLimit {
        /// The limit.
        limit: u64,
        /// Time reached.
        t: f64,
    },
    /// The error control of an embedded pair drove the step below what the time can
    /// resolve. When `J_s` had come near singular before (its smallest pivot below
    /// [`NEAR_SINGULAR`](crate::summary::NEAR_SINGULAR) of its earlier largest), or is at the
    /// failing point (factored there once more and read from its pivots and from one
    /// solve, `|b| / |J_s^{-1} b|` against its largest earlier value, which partial
    /// pivoting cannot hide), that is the likely cause and is said: the control
    /// `v = J_s^{-1}(...)` grows without bound there, and no step is short enough to
    /// follow it.
    #[error(
        "step size underflow at t = {t} (h = {h:e}): {}",
        underflow_cause(near_singular)
    )]
    StepUnderflow {
        /// Time of the failed step.
        t: f64,
        /// The step that was too small.
        h: f64,
        /// Where `J_s` was nearest singular, if it came near singular in the run.
        near_singular: Option<crate::summary::NearSingular>,
    },
    /// The wall-clock deadline of [`Simulator::set_deadline`](crate::Simulator::set_deadline)
    /// passed; the run stopped at `t`, a consistent point.
    #[error("the wall-clock deadline passed at t = {t}")]
    Deadline {
        /// The time reached.
        t: f64,
    },
    /// [`Simulator::advance_to`](crate::Simulator::advance_to) was asked for a time
    /// before the current one, or called after the run was finished.
    #[error("cannot advance to t = {requested}: the run is at t = {now}{}", if *finished { " and finished (call start to run again)" } else { "" })]
    Backwards {
        /// The requested time.
        requested: f64,
        /// The current time.
        now: f64,
        /// Whether [`Simulator::finish`](crate::Simulator::finish) was called.
        finished: bool,
    },
    /// Writing to the trace sink failed.
    #[error("trace sink failed: {0}")]
    Sink(#[from] std::io::Error),
}

/// Names in backticks, joined by commas: `a`, `b`.
fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// What a step-size underflow says about its cause.
fn underflow_cause(near_singular: &Option<crate::summary::NearSingular>) -> String {
    match near_singular {
        Some(ns) => format!(
            "J_s came near singular at t = {} (its conditioning fell to {:.1e} of what it was earlier in the run), and the control grows without bound there (the constraints nearly lose rank: for example a taut line of rigid links between fixed points)",
            ns.t, ns.pivot_ratio
        ),
        None => "the error control cannot meet the tolerance (a stiff or non-smooth motion, or a tolerance below rounding)".into(),
    }
}
