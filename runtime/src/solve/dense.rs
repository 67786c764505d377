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
            stats: SolverStats::default(),
        }
    }

    pub(crate) fn stored_values(&self) -> usize {
        self.a.len()
    }

    /// Factor the matrix in `a` in place; `false` if a pivot is negligible.
    fn eliminate(&mut self) -> bool {
        let m = self.m;
        let a = &mut self.a;
        let scale = a.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
        let tol = PIVOT_TOL * scale;
        for i in 0..m {
            let col_i = i * m;
            let mut piv = i;
            let mut best = a[col_i + i].abs();
            for r in i + 1..m {
                let v = a[col_i + r].abs();
                if v > best {
                    best = v;
                    piv = r;
                }
            }
            if best.is_nan() || best <= tol {
                return false;
            }
            self.swaps[i] = piv;
            if piv != i {
                for c in 0..m {
                    a.swap(c * m + i, c * m + piv);
                }
            }
            let d = a[col_i + i];
            for r in i + 1..m {
                a[col_i + r] /= d;
            }
            for c in i + 1..m {
                let u = a[c * m + i];
                if u != 0.0 {
                    for r in i + 1..m {
                        a[c * m + r] -= a[col_i + r] * u;
                    }
                }
            }
        }
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
        self.a.fill(0.0);
        for (&(i, j), v) in self.st.entries.iter().zip(values) {
            self.a[j * m + i] = row_scale[i] * v;
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
        let m = self.m;
        let a = &self.a;
        for i in 0..m {
            let p = self.swaps[i];
            if p != i {
                b.swap(i, p);
            }
        }
        // Forward with unit L (column-oriented), then back with U.
        for j in 0..m {
            let bj = b[j];
            if bj != 0.0 {
                for r in j + 1..m {
                    b[r] -= a[j * m + r] * bj;
                }
            }
        }
        for j in (0..m).rev() {
            let bj = b[j] / a[j * m + j];
            b[j] = bj;
            if bj != 0.0 {
                for r in 0..j {
                    b[r] -= a[j * m + r] * bj;
                }
            }
        }
    }

    fn stats(&self) -> SolverStats {
        self.stats
    }
    fn reset_stats(&mut self) {
        self.stats = SolverStats::default();
    }
}
