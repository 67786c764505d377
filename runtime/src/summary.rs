//! The statistics of a finished run.

use serde::{Deserialize, Serialize};

use crate::SolverChoice;

/// What the solver of `J_s` did during a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolverSummary {
    /// The solver that ran (`dense`, `sparse-ldlt`, `sparse-lu`, `tree`, `jacobi`,
    /// `gauss-seidel:K`, `cg:K`, `ilu0`).
    pub name: String,
    /// What the settings asked for (`auto` resolves to one of the exact solvers).
    pub choice: SolverChoice,
    /// Numeric factorisations (one per control update; three per SPSM step with RK4).
    pub factorisations: u64,
    /// Applications of `J_hat^{-1}` (control laws and `z_eq` of recorded samples).
    pub solves: u64,
    /// Gauss-Seidel sweeps or CG iterations, summed (0 for direct solvers).
    pub iterations: u64,
    /// (Update, constraint) pairs in the statistics window failing the robustness
    /// condition (T 3.22) for this solver (0 when not checked; the same count as
    /// [`Summary::robustness_violations`]).
    pub robustness_failures: u64,
    /// Gains raised by [`Settings::raise_gains`](crate::Settings::raise_gains).
    pub gain_raises: u64,
}

/// What a run did and how well the constraints were kept.
///
/// "Window" statistics are taken from `stats_from = max(reaching time, t_start + settle)`
/// to the end; periods count only intervals whose both ends lie in the window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Model name.
    pub model: String,
    /// Constraint names (index of the per-constraint vectors below).
    pub constraints: Vec<String>,
    /// Final time reached.
    pub t_end: f64,
    /// Number of integration steps.
    pub steps: u64,
    /// Number of control updates (for SPSM: control evaluations, one per stage).
    pub updates: u64,
    /// Number of updates during the reaching phase.
    pub reaching_updates: u64,
    /// Time at which all `|s_i| <= eps_i` first held (checked after each step), if ever.
    pub reaching_time: Option<f64>,
    /// Start of the statistics window, if it was entered.
    pub stats_from: Option<f64>,
    /// Shortest update period in the window.
    pub min_period: Option<f64>,
    /// Average update period in the window.
    pub mean_period: Option<f64>,
    /// Largest `|s_i|` in the window, per constraint.
    pub max_abs_s: Vec<f64>,
    /// Largest constraint residual `|w_i|` in the window, per constraint.
    pub max_abs_w: Vec<f64>,
    /// Number of (update, constraint) pairs in the window where the robustness condition
    /// (T 3.22) failed for the solver's `J_hat` (with an exact solver
    /// `k_i > |alpha_i - alpha_hat_i| + k_i^c`); `None` if not checked.
    pub robustness_violations: Option<u64>,
    /// The solver, its counters and its robustness failures.
    pub solver: SolverSummary,
    /// The gains at the end of the run: the configured ones, unless
    /// [`Settings::raise_gains`](crate::Settings::raise_gains) raised some.
    pub gains: Vec<f64>,
    /// Evaluations of `f` ([`Model::rhs`](crate::Model::rhs)).
    pub rhs_evals: u64,
    /// Evaluations of [`Model::sliding`](crate::Model::sliding).
    pub sliding_evals: u64,
    /// Evaluations of [`Model::jacobian`](crate::Model::jacobian) (= factorisations).
    pub jacobian_evals: u64,
    /// Evaluations of [`Model::beta`](crate::Model::beta).
    pub beta_evals: u64,
    /// Wall-clock duration of the run in seconds.
    pub wall_time: f64,
    /// Final states.
    pub x: Vec<f64>,
    /// Final algebraic unknowns.
    pub z: Vec<f64>,
    /// Final `z_eq = z - J_s^{-1} s`.
    pub z_eq: Vec<f64>,
}
