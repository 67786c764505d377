//! Dense LU with partial pivoting in a preallocated column-major buffer, for small `m`:
//! a control update (or an SPSM stage) allocates nothing.

use super::diagnose::dependent_rows;
use super::{
    InverseKind, LinearSolver, PIVOT_TOL, SolveError, SolverStats, Structure, check_finite,
};

/// Packed `L\U` factors of `J_s` and the row swaps that produced them.
#[derive(Clone)]
pub(crate) struct DenseSolver {
    st: Structure,
    m: usize,
    /// Column-major packed factors: strictly lower part `L` (unit diagonal), upper `U`.
    a: Vec<f64>,
    /// `swaps[i]` is the row exchanged with row `i` at elimination step `i`.
    swaps: Vec<usize>,
    /// Smallest and largest pivot magnitude of the last factorisation.
    pivots: Option<(f64, f64)>,
    stats: SolverStats,
}

impl DenseSolver {
    pub(crate) fn new(st: Structure) -> Self {
        let m = st.m;
        Self {
            st,
            m,
            a: vec![0.0; m * m],
            swaps: vec![0; m],
            pivots: None,
            stats: SolverStats::default(),
        }
    }

    pub(crate) fn stored_values(&self) -> usize {
        self.a.len()
    }

    /// Factor the matrix in `a` in place; `false` if a pivot is negligible. Column
    /// slices (no index arithmetic in the inner loops): a 2 x 2 update is tens of ns.
    fn eliminate(&mut self) -> bool {
        let m = self.m;
        let a = &mut self.a;
        let scale = a.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
        let tol = PIVOT_TOL * scale;
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for i in 0..m {
            let (mut piv, mut best) = (i, a[i * m + i].abs());
            for (r, v) in a[i * m + i + 1..(i + 1) * m].iter().enumerate() {
                if v.abs() > best {
                    best = v.abs();
                    piv = i + 1 + r;
                }
            }
            if best.is_nan() || best <= tol {
                return false;
            }
            lo = lo.min(best);
            hi = hi.max(best);
            self.swaps[i] = piv;
            if piv != i {
                for col in a.chunks_exact_mut(m) {
                    col.swap(i, piv);
                }
            }
            let (left, right) = a.split_at_mut((i + 1) * m);
            let col_i = &mut left[i * m..];
            let d = col_i[i];
            for l in &mut col_i[i + 1..] {
                *l /= d;
            }
            let below = &col_i[i + 1..];
            for col in right.chunks_exact_mut(m) {
                let u = col[i];
                if u != 0.0 {
                    for (x, l) in col[i + 1..].iter_mut().zip(below) {
                        *x -= l * u;
                    }
                }
            }
        }
        self.pivots = (m > 0).then_some((lo, hi));
        true
    }
}

impl LinearSolver for DenseSolver {
    fn name(&self) -> &str {
        "dense"
    }
    fn inverse(&self) -> InverseKind {
        InverseKind::Exact
    }

    fn factor(&mut self, values: &[f64], row_scale: &[f64]) -> Result<(), SolveError> {
        self.stats.factorisations += 1;
        let m = self.m;
        let a = &mut self.a[..m * m];
        for x in a.iter_mut() {
            *x = 0.0;
        }
        let d = &row_scale[..m];
        for (&(i, j), v) in self.st.entries.iter().zip(values) {
            a[j * m + i] = d[i] * v;
        }
        if self.eliminate() {
            return Ok(());
        }
        check_finite(&self.st, values, row_scale)?;
        let mut constraints = dependent_rows(&self.st, values, row_scale);
        if constraints.is_empty() {
            // Pivoting declared a pivot negligible that the echelon form kept (a
            // borderline case of the same tolerance): name every row.
            constraints = (0..m).collect();
        }
        Err(SolveError::Singular { constraints })
    }

    fn solve(&mut self, b: &mut [f64]) {
        self.stats.solves += 1;
        self.substitute(b);
    }

    fn pivot_range(&self) -> Option<(f64, f64)> {
        self.pivots
    }
    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}

impl DenseSolver {
    /// `b <- J_s^{-1} b` with the factors of the last factorisation, not counted as a
    /// solve (the controller's conditioning probe, which is not a control law's).
    pub(crate) fn substitute(&self, b: &mut [f64]) {
        let m = self.m;
        if m == 0 {
            // No constraints (an ODE): nothing to solve.
            return;
        }
        for (i, &p) in self.swaps.iter().enumerate() {
            if p != i {
                b.swap(i, p);
            }
        }
        // Forward with unit L, then back with U, column by column. Plain index loops:
        // for the small `m` this solver serves, the vectorised slices' set-up per
        // column cost more than their bodies saved.
        let (a, b) = (&self.a[..m * m], &mut b[..m]);
        for j in 0..m {
            let bj = b[j];
            if bj != 0.0 {
                let col = &a[j * m..j * m + m];
                for i in j + 1..m {
                    b[i] -= col[i] * bj;
                }
            }
        }
        for j in (0..m).rev() {
            let col = &a[j * m..j * m + m];
            let bj = b[j] / col[j];
            b[j] = bj;
            if bj != 0.0 {
                for i in 0..j {
                    b[i] -= col[i] * bj;
                }
            }
        }
    }
}
