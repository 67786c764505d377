//! The statistics of a finished run, and their text ([`Summary`]'s `Display`).

use serde::{Deserialize, Serialize};

mod text;

pub use text::{TEXT_LINES_MAX, listed_by, values_text};

use crate::solve::SolverChoice;

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
    /// Gains raised by [`GainRule::Raise`](crate::settings::GainRule::Raise).
    pub gain_raises: u64,
    /// Factorisations that found `J_s` singular and set the constraints the others
    /// imply aside ([`RedundantRows::Drop`](crate::solve::RedundantRows::Drop)), and the
    /// most constraints set aside at one of them.
    #[serde(default)]
    pub set_aside: u64,
    /// See `set_aside`.
    #[serde(default)]
    pub set_aside_max: u64,
}

/// What block-local updates ([`Scope::Blocks`](crate::settings::Scope::Blocks)) did
/// during a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BlockSummary {
    /// Blocks of the partition, and the most rows in one.
    pub blocks: usize,
    /// The most rows in one block.
    pub largest: usize,
    /// Block solves (each one factorisation of its block of `J_s`), over all updates.
    pub block_solves: u64,
    /// Updates of every row: the first, the reaching phase's, those after a change of
    /// the model or of `mu`, and those the progress guard forced.
    pub global_updates: u64,
}

/// What the search for `mu` during a run
/// ([`Layers::adapt_mu`](crate::settings::Layers::adapt_mu)) did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MuSearchSummary {
    /// `mu` at the end, as a multiple of the one the run started with.
    pub scale: f64,
    /// Moves of `mu` made.
    pub moves: u64,
    /// Moves the simulator refused (a growth from which the filter would have left the
    /// layer).
    pub refused: u64,
    /// Of the moves, those made at once after a frame that cost more than
    /// [`AdaptiveMu::surge`](crate::settings::AdaptiveMu::surge) times the last window's.
    #[serde(default)]
    pub surges: u64,
    /// Frames the search weighed.
    pub frames: u64,
}

/// A layer left after the reaching phase: some `|s_i|` exceeded `(1 + tol) eps_i`
/// ([`Settings::bound_tol`](crate::Settings::bound_tol)) after all `|s_i| <= eps_i`
/// had held. The run continues to its end (the trace keeps everything); this record
/// says when, where and by how much.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoundLoss {
    /// When the layer was first left (on the dense output of `s` with located
    /// crossings; the start of the step that ended outside otherwise).
    pub first_time: f64,
    /// The constraint that left first, by name.
    pub first_constraint: String,
    /// The largest `|s_i| / eps_i` after reaching.
    pub worst_ratio: f64,
    /// The end of the step in which it was seen.
    pub worst_time: f64,
    /// The constraint of the worst ratio.
    pub worst_constraint: String,
    /// Every constraint that left its layer.
    pub constraints: Vec<String>,
    /// Integration steps during which some `|s_i|` was beyond its bound.
    pub steps_outside: u64,
    /// Time spent beyond the bound (on the dense output with located crossings, whole
    /// steps otherwise).
    pub time_outside: f64,
    /// Set when `J_s` was nearly singular during the run (see [`NearSingular`]).
    pub near_singular: Option<NearSingular>,
}

/// `J_s` nearly singular: the smallest pivot of a factorisation fell below
/// [`NEAR_SINGULAR`] times the largest value the smallest pivot had in the run so far,
/// or so did `|b| / |J_s^{-1} b|` for one fixed `b` (at least the smallest singular
/// value, which partial pivoting cannot hide) against its own largest earlier value:
/// read at every factorisation of the dense LU, whose partial pivoting can keep every
/// pivot large, and, for every solver with pivots, where the step control gave up.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NearSingular {
    /// The smallest ratio seen (of the pivots, or of the solve's measure).
    pub pivot_ratio: f64,
    /// The time of that update.
    pub t: f64,
}

/// Pivot ratio (smallest pivot of a factorisation of `J_s` over the largest value the
/// smallest pivot had in the run so far) under which `J_s` counts as nearly singular. A ratio `r` means
/// that the control `v = J_s^{-1}(...)` is about `1/r` times larger than it was for the
/// same right-hand side earlier in the run, and with it the drift of `w^(r)` within an
/// interval (`M`, which contains `J_Omega' v`) that the gains were designed for: a
/// thousandfold increase is beyond any design margin (on a model whose `J_Omega = cos t`
/// passes through zero, the layer is lost within updates of the ratio falling below it).
pub const NEAR_SINGULAR: f64 = 1e-3;

/// What a run did and how well the constraints were kept.
///
/// "Window" statistics are taken from `stats_from = max(reaching time, t_start + settle)`
/// to the end; periods count only intervals whose both ends lie in the window. When
/// the window was never entered (the reaching phase did not finish, or the settle time
/// reaches past the end) the window statistics are `None`, and `seen_max_abs_s`,
/// `seen_max_abs_w` and the final `s`, `w` say what the run did.
///
/// Its `Display` is the text `daec run` prints for the run's results, a few dozen lines
/// at most whatever the size of the model (see the `impl Display` below).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Model name.
    pub model: String,
    /// Constraint names (index of the per-constraint vectors below).
    pub constraints: Vec<String>,
    /// The layer half-widths `eps_i` of the run, per constraint.
    #[serde(default)]
    pub eps: Vec<f64>,
    /// Final time reached.
    pub t_end: f64,
    /// Number of accepted integration steps (a step cut at a crossing counts once).
    pub steps: u64,
    /// Steps rejected by the error control: of the embedded pairs, or of a fixed step
    /// on its error in `s` (located crossings; the step is then taken shorter).
    pub rejected_steps: u64,
    /// Steps cut short at a located crossing.
    pub located_crossings: u64,
    /// Steps taken whole, without locating the crossings inside them, by the progress
    /// guard (after two steps in a row shorter than a millionth of the reference step,
    /// the fixed step or at most the smallest `mu_i`: a variable resting on its watch
    /// level with its rate lost in rounding). Their excursions are still measured on
    /// the cubic of each `s_i` and reported as a bound loss when they leave the layer;
    /// a non-zero count says where the located crossings gave way.
    pub unlocated_steps: u64,
    /// Number of control updates (for SPSM: control evaluations, one per stage).
    pub updates: u64,
    /// Number of updates during the reaching phase.
    pub reaching_updates: u64,
    /// With block-local updates, their counts (`None`: every update was of every row).
    #[serde(default)]
    pub blocks: Option<BlockSummary>,
    /// With a search of `mu` during the run, what it did (`None`: `mu` as configured).
    #[serde(default)]
    pub mu_search: Option<MuSearchSummary>,
    /// Per constraint, the updates of the monitoring policy that its own `s_i` asked
    /// for (on its layer boundary moving outward, or in the reaching phase arrived at
    /// its surface). An update several rows asked for at once counts for each of them;
    /// updates of a fixed period, of the progress guard and after a model change count
    /// for none. Says which constraints set the cost of a run: on the cloth of the
    /// particle benchmark a few dozen links out of thousands ask for every update.
    #[serde(default)]
    pub triggered_updates: Vec<u64>,
    /// Time at which all `|s_i| <= eps_i` first held (checked after each step), if ever.
    pub reaching_time: Option<f64>,
    /// Start of the statistics window, if it was entered.
    pub stats_from: Option<f64>,
    /// Shortest update period in the window.
    pub min_period: Option<f64>,
    /// Average update period in the window.
    pub mean_period: Option<f64>,
    /// Largest `|s_i|` in the window, per constraint (on the dense output of `s` with
    /// located crossings, at step ends otherwise); `None` if the window was never
    /// entered.
    pub max_abs_s: Option<Vec<f64>>,
    /// Largest constraint residual `|w_i|` in the window (at step ends), per
    /// constraint; `None` if the window was never entered.
    pub max_abs_w: Option<Vec<f64>>,
    /// Largest `|s_i|` over the whole run, the reaching phase included.
    pub seen_max_abs_s: Vec<f64>,
    /// Largest `|w_i|` over the whole run (at step ends).
    pub seen_max_abs_w: Vec<f64>,
    /// The layer left after reaching, if it was.
    pub bound_loss: Option<BoundLoss>,
    /// The smallest conditioning ratio of `J_s` in the run and its time: of its least
    /// pivot, or of one solve's measure (see [`NearSingular`] and [`NEAR_SINGULAR`]);
    /// `None` for solvers without pivots.
    pub min_pivot_ratio: Option<(f64, f64)>,
    /// Number of (update, constraint) pairs in the window where the robustness condition
    /// (T 3.22) failed for the solver's `J_hat` (with an exact solver
    /// `k_i > |alpha_i - alpha_hat_i| + k_i^c`); `None` if not checked.
    pub robustness_violations: Option<u64>,
    /// The solver, its counters and its robustness failures.
    pub solver: SolverSummary,
    /// The gains at the end of the run: the configured ones, unless
    /// [`GainRule::Raise`](crate::settings::GainRule::Raise) raised some.
    pub gains: Vec<f64>,
    /// Evaluations of `f` ([`Model::rhs`](crate::Model::rhs)), every stage, rejected
    /// step and re-integration included.
    pub f_evals: u64,
    /// Evaluations of [`Model::sliding`](crate::Model::sliding).
    pub sliding_evals: u64,
    /// Evaluations of [`Model::jacobian`](crate::Model::jacobian): at the updates, and
    /// with located crossings at every step's end (for `s'`, reused by an update
    /// there) unless the model gives `Omega`'s rate ([`Self::rate_evals`]); also for
    /// `z*` at recorded samples.
    pub jacobian_evals: u64,
    /// Evaluations of [`Model::beta`](crate::Model::beta).
    pub beta_evals: u64,
    /// Evaluations of [`Model::omega_rate`](crate::Model::omega_rate) that the model
    /// provided: with located crossings `s'` at every step's end and at the updates,
    /// in place of `J_Omega` and `beta` (0 for a model that does not provide it).
    #[serde(default)]
    pub rate_evals: u64,
    /// Wall-clock duration of the run in seconds.
    pub wall_time: f64,
    /// Final states.
    pub x: Vec<f64>,
    /// Final algebraic unknowns.
    pub z: Vec<f64>,
    /// Final `z_eq = z - J_s^{-1} s`.
    pub z_eq: Vec<f64>,
    /// Final `z* = z - J_Omega^{-1} Omega(t, x, z)` (the crate docs say which output to
    /// trust).
    pub z_star: Vec<f64>,
    /// Final sliding variables.
    pub s: Vec<f64>,
    /// Final constraint residuals.
    pub w: Vec<f64>,
}

impl Summary {
    /// Whether the window was entered and no layer was lost after reaching: the run
    /// kept its promise.
    pub fn bound_held(&self) -> bool {
        self.reaching_time.is_some() && self.bound_loss.is_none()
    }
}
