//! The solver seam: everything that solves with `J_s = diag(mu_i^(r_i-1)) J_Omega`.
//!
//! A solver is created once per sparsity pattern (its symbolic analysis happens there),
//! factors the values of `J_Omega` with a row scaling `d` (`J_s = diag(d) J_Omega`) at
//! every control update, and then applies `J_hat^{-1}` to any number of right-hand
//! sides. The row scaling is never multiplied into the factors of the sparse, tree and
//! iterative solvers: `J_s y = b` is solved as `J_Omega y = diag(d)^{-1} b`, so that a
//! symmetric `J_Omega` (particle systems: `-G M^-1 G^T`) keeps its symmetry when the
//! `mu_i` differ per row.
//!
//! Solvers ([`SolverChoice`]): dense LU with partial pivoting, an exact sparse direct
//! solver (ordering and elimination tree once, numeric `LDL^T` or `LU` per update), an
//! exact linear-time elimination for patterns whose graph is a forest, and approximate
//! inverses (Jacobi, Gauss-Seidel sweeps, preconditioned conjugate gradients, `ILU(0)`).
//! See the crate docs for how to choose.

mod approx;
mod dense;
mod diagnose;
mod order;
mod reduced;
mod redundancy;
mod sparse;
mod structure;
mod supernodal;
mod tree;

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use reduced::Reduced;
pub use reduced::RedundantRows;
pub use redundancy::Redundancy;
pub(crate) use structure::Structure;

use approx::{Cg, GaussSeidel, Ilu0, Jacobi};
use dense::DenseSolver;
use sparse::SparseSolver;
use tree::TreeSolver;

/// Largest `m` for which [`SolverChoice::Auto`] keeps the dense LU (it also keeps it
/// for patterns with more than a quarter of the entries): the exact sparse solvers
/// overtake dense LU between 10 and 25 rows, and below 16 rows both take well under a
/// microsecond and dense LU, which pivots, is kept (`cargo run --release -p dae-bench
/// --example solvers`, "Small systems").
pub const DENSE_MAX: usize = 16;

/// Which solver applies `J_hat^{-1}` (the `--solver` of `daec run`).
///
/// Text form (parsed by [`FromStr`], printed by [`fmt::Display`]): `auto`, `dense`,
/// `sparse`, `tree`, `jacobi`, `gauss-seidel:K`, `cg:K`, `ilu0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SolverChoice {
    /// Chosen from the pattern: dense for `m <= DENSE_MAX` or a pattern with more than
    /// `m^2 / 4` entries, the forest elimination when the pattern's graph is a forest,
    /// the sparse direct solver otherwise. Always exact.
    #[default]
    Auto,
    /// Dense LU with partial pivoting: `O(m^3)` per update, `O(m^2)` memory.
    Dense,
    /// Sparse direct: fill-reducing ordering and elimination tree once per pattern,
    /// numeric `LDL^T` (symmetric values) or `LU` with diagonal pivots per update.
    Sparse,
    /// Elimination along a forest (chains, hair strands): `O(m)` per update, no fill.
    /// Rejected when the pattern's graph has a cycle.
    Tree,
    /// Approximate: `J_hat = diag(J_s)`.
    Jacobi,
    /// Approximate: this many forward Gauss-Seidel sweeps, warm-started.
    GaussSeidel(u32),
    /// Approximate: this many Jacobi-preconditioned conjugate-gradient iterations,
    /// warm-started (symmetric `J_Omega` only).
    Cg(u32),
    /// Approximate: incomplete LU without fill, `J_hat = L U` on the pattern of `J_Omega`.
    Ilu0,
}

impl SolverChoice {
    /// Whether the choice applies `J_s^{-1}` exactly (up to rounding).
    pub fn is_exact(&self) -> bool {
        matches!(self, Self::Auto | Self::Dense | Self::Sparse | Self::Tree)
    }
}

impl fmt::Display for SolverChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Auto => f.write_str("auto"),
            Self::Dense => f.write_str("dense"),
            Self::Sparse => f.write_str("sparse"),
            Self::Tree => f.write_str("tree"),
            Self::Jacobi => f.write_str("jacobi"),
            Self::GaussSeidel(k) => write!(f, "gauss-seidel:{k}"),
            Self::Cg(k) => write!(f, "cg:{k}"),
            Self::Ilu0 => f.write_str("ilu0"),
        }
    }
}

impl FromStr for SolverChoice {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        let expected = "expected auto, dense, sparse, tree, jacobi, gauss-seidel:K, cg:K or ilu0";
        let count = |what: &str, k: &str| -> Result<u32, String> {
            match k.parse::<u32>() {
                Ok(k) if k >= 1 => Ok(k),
                _ => Err(format!(
                    "`{text}`: {what} needs a whole number of iterations >= 1 after the colon"
                )),
            }
        };
        match text.trim() {
            "auto" => Ok(Self::Auto),
            "dense" => Ok(Self::Dense),
            "sparse" => Ok(Self::Sparse),
            "tree" => Ok(Self::Tree),
            "jacobi" => Ok(Self::Jacobi),
            "ilu0" => Ok(Self::Ilu0),
            t => {
                if let Some(k) = t.strip_prefix("gauss-seidel:") {
                    count("gauss-seidel", k).map(Self::GaussSeidel)
                } else if let Some(k) = t.strip_prefix("cg:") {
                    count("cg", k).map(Self::Cg)
                } else {
                    Err(format!("unknown solver `{text}`: {expected}"))
                }
            }
        }
    }
}

/// What `J_hat^{-1}` is, which decides how the robustness condition (T 3.22) is
/// evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InverseKind {
    /// `J_hat = J_s` up to rounding: `D = K`, `gamma = alpha - alpha_hat`.
    Exact,
    /// `J_hat = diag(J_s)`: `D = J_s diag(J_s)^{-1} K` is formed row by row.
    Diagonal,
    /// An iteration or an incomplete factorisation: bounded through the residual
    /// `r = b - J_s v` of the computed solve.
    Approximate,
}

/// Counters of a solver since it was created or last reset.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SolverStats {
    /// Numeric factorisations (one per control update).
    pub factorisations: u64,
    /// Applications of `J_hat^{-1}` (control laws and `z_eq`).
    pub solves: u64,
    /// Iterations of the iterative solvers (Gauss-Seidel sweeps, CG iterations), summed
    /// over all solves; 0 for direct solvers.
    pub iterations: u64,
    /// Factorisations that found `J_s` singular and set the implied rows aside
    /// ([`RedundantRows::Drop`]; counted in `factorisations` too).
    #[serde(default)]
    pub set_aside: u64,
    /// The most rows set aside at one factorisation.
    #[serde(default)]
    pub set_aside_rows_max: u64,
}

impl SolverStats {
    /// Add another solver's counts (the blocks' solvers to the global one's).
    pub(crate) fn add(&mut self, other: SolverStats) {
        self.factorisations += other.factorisations;
        self.solves += other.solves;
        self.iterations += other.iterations;
        self.set_aside += other.set_aside;
        self.set_aside_rows_max = self.set_aside_rows_max.max(other.set_aside_rows_max);
    }
}

/// Why a solver could not be built or could not factor.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The pattern is malformed or does not suit the chosen solver.
    #[error("{0}")]
    Pattern(String),
    /// `J_s` is singular: these rows (constraints) are linearly dependent (every
    /// constraint that appears in a dependency among the rows).
    #[error("singular: rows {constraints:?} are linearly dependent")]
    Singular {
        /// Indices of the dependent rows, ascending.
        constraints: Vec<usize>,
    },
    /// An elimination without pivoting (sparse, tree, incomplete factorisation, Jacobi)
    /// met a negligible diagonal pivot although the matrix was not found singular.
    #[error(
        "no usable diagonal pivot at row {row}: this solver eliminates without row exchanges; use the dense solver for this model"
    )]
    Breakdown {
        /// The row whose pivot vanished.
        row: usize,
    },
    /// A symmetric solver met unsymmetric values.
    #[error(
        "J_Omega is not symmetric (entries ({row}, {col}) and ({col}, {row}) differ): conjugate gradients need a symmetric J_Omega; use gauss-seidel, ilu0 or an exact solver"
    )]
    NotSymmetric {
        /// Row of the offending entry.
        row: usize,
        /// Column of the offending entry.
        col: usize,
    },
    /// A value of `J_Omega` or of the row scaling is NaN or infinite.
    #[error("non-finite value in row {row} of J_s")]
    NonFinite {
        /// The row.
        row: usize,
    },
}

/// The seam every solve with `J_s` goes through.
///
/// Lifecycle: built from the pattern once ([`Solver::new`]), then per control update
/// [`factor`](LinearSolver::factor) with the values of `J_Omega` in pattern order and
/// the row scaling `d` (`J_s = diag(d) J_Omega`), then any number of
/// [`solve`](LinearSolver::solve) calls. Nothing allocates after construction, except
/// on the error path.
pub trait LinearSolver {
    /// A short name (`dense`, `sparse-ldlt`, `jacobi`, ...).
    fn name(&self) -> &str;
    /// What `J_hat^{-1}` is.
    fn inverse(&self) -> InverseKind;
    /// Prepare `J_hat^{-1}` for `J_s = diag(row_scale) J_Omega` with `values` the
    /// entries of `J_Omega` in pattern order.
    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError>;
    /// `b <- J_hat^{-1} b` (iterative solvers start from zero). Requires a successful
    /// [`factor`](LinearSolver::factor).
    fn solve(&mut self, b: &mut [f64]);
    /// `x <- J_hat^{-1} b`, where iterative solvers start from the given `x` (warm
    /// start); direct solvers ignore it.
    fn solve_from(&mut self, b: &[f64], x: &mut [f64]) {
        x.copy_from_slice(b);
        self.solve(x);
    }
    /// The smallest and largest magnitude of the pivots of the last successful
    /// [`factor`](LinearSolver::factor) (the diagonal of `U` or `D`; for Jacobi the
    /// diagonal of `J_s`): a cheap conditioning indicator. `None` for the iterations
    /// (Gauss-Seidel, CG), which have no pivots.
    fn pivot_range(&self) -> Option<(f64, f64)> {
        None
    }
    /// Counters since construction or [`reset_stats`](LinearSolver::reset_stats).
    fn stats(&self) -> SolverStats;
    /// Zero the counters.
    fn reset_stats(&mut self);
}

/// `y = J_s x = diag(row_scale) J_Omega x` from the pattern and values, `O(nnz)`.
pub fn mul_js(
    pattern: &[(usize, usize)],
    values: &[f64],
    row_scale: &[f64],
    x: &[f64],
    y: &mut [f64],
) {
    y.fill(0.0);
    for (&(i, j), a) in pattern.iter().zip(values) {
        y[i] += a * x[j];
    }
    for (yi, d) in y.iter_mut().zip(row_scale) {
        *yi *= d;
    }
}

#[derive(Clone)]
enum Kind {
    Dense(DenseSolver),
    // Boxed: its symbolic tables make it much larger than the others.
    Sparse(Box<SparseSolver>),
    Tree(TreeSolver),
    Jacobi(Jacobi),
    GaussSeidel(GaussSeidel),
    Cg(Cg),
    Ilu0(Ilu0),
}

/// A solver chosen by [`SolverChoice`] for one pattern (static dispatch over the
/// built-in solvers).
#[derive(Clone)]
pub struct Solver {
    kind: Kind,
    choice: SolverChoice,
    /// With [`RedundantRows::Drop`]: the system without the implied rows.
    reduced: Option<Box<Reduced>>,
}

impl fmt::Debug for Solver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Solver")
            .field("name", &self.name())
            .field("choice", &self.choice)
            .finish_non_exhaustive()
    }
}

impl Solver {
    /// Build the solver `choice` for an `m x m` pattern of `(row, col)` entries (the
    /// order in which [`LinearSolver::factor`] receives the values). Does the symbolic
    /// analysis of the sparse solvers. [`SolverChoice::Auto`] picks from the pattern.
    pub fn new(
        m: usize,
        pattern: &[(usize, usize)],
        choice: SolverChoice,
    ) -> Result<Self, SolveError> {
        let st = Structure::new(m, pattern)?;
        let resolved = match choice {
            SolverChoice::Auto => auto_choice(&st),
            c => c,
        };
        let kind = match resolved {
            SolverChoice::Auto | SolverChoice::Dense => Kind::Dense(DenseSolver::new(st)),
            SolverChoice::Sparse => Kind::Sparse(Box::new(SparseSolver::new(st))),
            SolverChoice::Tree => Kind::Tree(TreeSolver::new(st)?),
            SolverChoice::Jacobi => Kind::Jacobi(Jacobi::new(st)),
            SolverChoice::GaussSeidel(k) => Kind::GaussSeidel(GaussSeidel::new(st, k)),
            SolverChoice::Cg(k) => Kind::Cg(Cg::new(st, k)?),
            SolverChoice::Ilu0 => Kind::Ilu0(Ilu0::new(st)),
        };
        Ok(Self {
            kind,
            choice,
            reduced: None,
        })
    }

    /// What a singular `J_s` does: with [`RedundantRows::Drop`], the rows the others
    /// imply are set aside and the rest solved (`class[i]`: the constraint family of row
    /// `i`, the later family the one set aside; `pattern` as given to [`Solver::new`]).
    /// The pattern's structure and row orders are found here, once.
    pub(crate) fn redundant_rows(
        mut self,
        rows: RedundantRows,
        pattern: &[(usize, usize)],
        class: &[usize],
    ) -> Result<Self, SolveError> {
        self.reduced = match rows {
            RedundantRows::Refuse => None,
            RedundantRows::Drop => {
                Some(Box::new(Reduced::new(pattern, SolverChoice::Auto, class)?))
            }
        };
        Ok(self)
    }

    fn reduced_active(&mut self) -> Option<&mut Reduced> {
        self.reduced.as_deref_mut().filter(|r| r.active)
    }

    /// The choice this solver was built from (before [`SolverChoice::Auto`] resolved).
    pub fn choice(&self) -> SolverChoice {
        self.choice
    }

    /// Number of `f64` values the solver keeps between calls (factors, values, work
    /// vectors): `m^2` for dense LU, `O(nnz)` for the others; for the sparse solver it
    /// counts the fill-in of its factor (none on chordal patterns).
    pub fn stored_values(&self) -> usize {
        match &self.kind {
            Kind::Dense(s) => s.stored_values(),
            Kind::Sparse(s) => s.stored_values(),
            Kind::Tree(s) => s.stored_values(),
            Kind::Jacobi(s) => s.stored_values(),
            Kind::GaussSeidel(s) => s.stored_values(),
            Kind::Cg(s) => s.stored_values(),
            Kind::Ilu0(s) => s.stored_values(),
        }
    }

    /// Whether the factor's pivots can hide a nearly singular `J_s`: the dense LU, whose
    /// partial pivoting can keep every pivot large.
    pub(crate) fn pivots_can_hide(&self) -> bool {
        matches!(self.kind, Kind::Dense(_))
    }

    /// `x = J_s^{-1} b`, not counted as a solve, where [`Self::pivots_can_hide`] and the
    /// solve is cheap against the factorisation (`O(m^2)` against `O(m^3)`). `false`,
    /// with `x` untouched, for the other solvers.
    pub(crate) fn substitute_if_pivots_can_hide(&self, b: &[f64], x: &mut [f64]) -> bool {
        if self.reduced.as_ref().is_some_and(|r| r.active) {
            return false;
        }
        match &self.kind {
            Kind::Dense(s) => {
                x.copy_from_slice(b);
                s.substitute(x);
                true
            }
            _ => false,
        }
    }

    fn inner(&self) -> &dyn LinearSolver {
        match &self.kind {
            Kind::Dense(s) => s,
            Kind::Sparse(s) => s.as_ref(),
            Kind::Tree(s) => s,
            Kind::Jacobi(s) => s,
            Kind::GaussSeidel(s) => s,
            Kind::Cg(s) => s,
            Kind::Ilu0(s) => s,
        }
    }
}

/// Exact solver for the pattern: dense when small, the forest elimination when the
/// graph is a forest, sparse direct otherwise.
fn auto_choice(st: &Structure) -> SolverChoice {
    if st.m <= DENSE_MAX || 4 * st.entries.len() > st.m * st.m {
        SolverChoice::Dense
    } else if st.is_forest() && st.has_full_diagonal() {
        SolverChoice::Tree
    } else {
        SolverChoice::Sparse
    }
}

// Static dispatch: the dense path of a small model is a few tens of nanoseconds per
// update, where a virtual call would show.
macro_rules! dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        match &mut $self.kind {
            Kind::Dense($s) => $e,
            Kind::Sparse($s) => $e,
            Kind::Tree($s) => $e,
            Kind::Jacobi($s) => $e,
            Kind::GaussSeidel($s) => $e,
            Kind::Cg($s) => $e,
            Kind::Ilu0($s) => $e,
        }
    };
}

impl LinearSolver for Solver {
    fn name(&self) -> &str {
        self.inner().name()
    }
    #[inline]
    fn inverse(&self) -> InverseKind {
        match &self.kind {
            Kind::Dense(_) | Kind::Sparse(_) | Kind::Tree(_) => InverseKind::Exact,
            Kind::Jacobi(_) => InverseKind::Diagonal,
            Kind::GaussSeidel(_) | Kind::Cg(_) | Kind::Ilu0(_) => InverseKind::Approximate,
        }
    }
    #[inline]
    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        let result = dispatch!(self, s => s.factor(values, row_scale));
        match self.reduced.as_deref_mut() {
            None => result,
            Some(r) => {
                r.active = false;
                match result {
                    Err(SolveError::Singular { .. }) => r.factor(values, row_scale),
                    other => other,
                }
            }
        }
    }
    #[inline]
    fn solve(&mut self, b: &mut [f64]) {
        if let Some(r) = self.reduced_active() {
            return r.solve(b);
        }
        dispatch!(self, s => s.solve(b))
    }
    #[inline]
    fn solve_from(&mut self, b: &[f64], x: &mut [f64]) {
        if let Some(r) = self.reduced_active() {
            x.copy_from_slice(b);
            return r.solve(x);
        }
        dispatch!(self, s => s.solve_from(b, x))
    }
    fn pivot_range(&self) -> Option<(f64, f64)> {
        match &self.reduced {
            Some(r) if r.active => r.solver().and_then(|s| s.pivot_range()),
            _ => self.inner().pivot_range(),
        }
    }
    fn stats(&self) -> SolverStats {
        let mut stats = self.inner().stats();
        if let Some(r) = &self.reduced
            && let Some(s) = r.solver()
        {
            // Its factorisations follow a failed one of the whole `J_s`, counted above.
            let reduced = s.stats();
            stats.solves += reduced.solves;
            stats.iterations += reduced.iterations;
            stats.set_aside += reduced.factorisations;
            stats.set_aside_rows_max = stats.set_aside_rows_max.max(r.rows_max);
        }
        stats
    }
    fn reset_stats(&mut self) {
        if let Some(r) = self.reduced.as_deref_mut() {
            r.reset_stats();
        }
        dispatch!(self, s => s.reset_stats())
    }
}

/// Smallest and largest `|v|` of the values (`None` for none).
pub(crate) fn abs_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| {
        let a = v.abs();
        Some(acc.map_or((a, a), |(lo, hi): (f64, f64)| (lo.min(a), hi.max(a))))
    })
}

/// Relative pivot size under which an elimination declares a pivot unusable: a pivot
/// this small compared with the largest entry loses all significant digits.
pub(crate) const PIVOT_TOL: f64 = 1e-13;

/// Largest `|v|` of a slice, or infinity if any value is not finite.
pub(crate) fn max_abs(values: &[f64]) -> f64 {
    let mut s = 0.0f64;
    for v in values {
        if !v.is_finite() {
            return f64::INFINITY;
        }
        s = s.max(v.abs());
    }
    s
}

/// The largest `|value|` (the pivot tolerance's scale), with the values and the scaling
/// checked as [`check_finite`] does: one pass over the values, and the check that names
/// the row only where something is not finite.
pub(crate) fn checked_scale(
    st: &Structure,
    values: &[f64],
    row_scale: &[f64],
) -> Result<f64, SolveError> {
    let scale = max_abs(values);
    if !scale.is_finite() || row_scale.iter().any(|d| !d.is_finite() || *d == 0.0) {
        check_finite(st, values, row_scale)?;
    }
    Ok(scale)
}

/// Check values and scaling for NaN/inf, naming the first row that has one.
pub(crate) fn check_finite(
    st: &Structure,
    values: &[f64],
    row_scale: &[f64],
) -> Result<(), SolveError> {
    if let Some(row) = row_scale.iter().position(|d| !d.is_finite() || *d == 0.0) {
        return Err(SolveError::NonFinite { row });
    }
    if let Some(e) = values.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite {
            row: st.entries[e].0,
        });
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests;
