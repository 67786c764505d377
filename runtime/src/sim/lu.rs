//! In-place dense LU factorisation with partial pivoting on a preallocated nalgebra
//! matrix, so that a control update (or an SPSM stage) allocates nothing.
//!
//! `nalgebra::LU::new` takes its matrix by value and allocates a permutation sequence on
//! every call; the simulator factors once per update (once per stage for SPSM), so the
//! elimination is done here in a buffer that lives as long as the simulator, and the two
//! triangular solves use nalgebra's in-place solvers on the packed factors.

use nalgebra::{DMatrix, DVector};

/// Packed `L\U` factors of a square matrix and the row swaps that produced them.
pub(crate) struct DenseLu {
    /// Packed factors: strictly lower part is `L` (unit diagonal), upper part is `U`.
    pub(crate) a: DMatrix<f64>,
    /// `swaps[i]` is the row exchanged with row `i` at elimination step `i`.
    swaps: Vec<usize>,
    /// `origin[k]` is the original row now stored at position `k` (for error reports).
    origin: Vec<usize>,
    /// Whether `a` currently holds a valid factorisation.
    valid: bool,
}

/// Relative pivot size under which the matrix is declared singular: a pivot this small
/// compared with the largest entry loses all significant digits of the solution.
const PIVOT_TOL: f64 = 1e-13;

impl DenseLu {
    pub(crate) fn new(m: usize) -> Self {
        Self {
            a: DMatrix::zeros(m, m),
            swaps: vec![0; m],
            origin: (0..m).collect(),
            valid: false,
        }
    }

    pub(crate) fn is_valid(&self) -> bool {
        self.valid
    }

    /// Factor the matrix currently stored in `a` in place. On failure returns the original
    /// rows (constraints) that have no usable pivot left: their remaining entries vanish
    /// relative to the matrix scale, so they are linearly dependent on the rows already
    /// eliminated (if no row is individually negligible, all remaining rows are named).
    pub(crate) fn factor(&mut self, dependent: &mut Vec<usize>) -> bool {
        let m = self.a.nrows();
        self.valid = false;
        for (k, o) in self.origin.iter_mut().enumerate() {
            *o = k;
        }
        let scale = self.a.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
        if !scale.is_finite() {
            dependent.clear();
            dependent.extend(0..m);
            return false;
        }
        let tol = PIVOT_TOL * scale;
        for i in 0..m {
            let mut piv = i;
            let mut best = self.a[(i, i)].abs();
            for r in i + 1..m {
                let v = self.a[(r, i)].abs();
                if v > best {
                    best = v;
                    piv = r;
                }
            }
            if best.is_nan() || best <= tol {
                dependent.clear();
                for r in i..m {
                    let negligible = (i..m).all(|c| self.a[(r, c)].abs() <= tol);
                    if negligible {
                        dependent.push(self.origin[r]);
                    }
                }
                if dependent.is_empty() {
                    dependent.extend(self.origin[i..].iter().copied());
                }
                dependent.sort_unstable();
                return false;
            }
            self.swaps[i] = piv;
            if piv != i {
                self.a.swap_rows(i, piv);
                self.origin.swap(i, piv);
            }
            let d = self.a[(i, i)];
            for r in i + 1..m {
                let l = self.a[(r, i)] / d;
                self.a[(r, i)] = l;
                if l != 0.0 {
                    for c in i + 1..m {
                        let u = self.a[(i, c)];
                        self.a[(r, c)] -= l * u;
                    }
                }
            }
        }
        self.valid = true;
        true
    }

    /// Solve `A y = b` in place with the current factors.
    pub(crate) fn solve(&self, b: &mut DVector<f64>) {
        debug_assert!(self.valid);
        for i in 0..b.len() {
            let p = self.swaps[i];
            if p != i {
                b.swap_rows(i, p);
            }
        }
        // Both solvers only fail on a zero diagonal, which `factor` has excluded.
        self.a.solve_lower_triangular_with_diag_mut(b, 1.0);
        self.a.solve_upper_triangular_mut(b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_pivoting_system_against_nalgebra_lu() {
        let m = DMatrix::from_row_slice(3, 3, &[0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.5, 4.0]);
        let b = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let mut lu = DenseLu::new(3);
        lu.a.copy_from(&m);
        let mut dep = Vec::new();
        assert!(lu.factor(&mut dep));
        let mut y = b.clone();
        lu.solve(&mut y);
        let residual = &m * &y - &b;
        assert!(residual.norm() < 1e-14, "residual {residual}");
        let reference = m.lu().solve(&b).unwrap();
        assert!((y - reference).norm() < 1e-14);
    }

    #[test]
    fn names_the_dependent_row_of_a_singular_matrix() {
        // Row 1 = 2 * row 0; row 2 independent.
        let m = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 2.0, 4.0, 0.0, 0.0, 1.0, 1.0]);
        let mut lu = DenseLu::new(3);
        lu.a.copy_from(&m);
        let mut dep = Vec::new();
        assert!(!lu.factor(&mut dep));
        assert!(!lu.is_valid());
        assert_eq!(dep.len(), 1);
        assert!(dep[0] == 0 || dep[0] == 1, "dependent rows {dep:?}");
    }
}
