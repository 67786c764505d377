//! Which constraints a singular `J_s` makes dependent, for the error report.
//!
//! Run only after a factorisation failed. The dense diagnosis reduces `[J_s | I]` to row
//! echelon form (partial pivoting, skipping columns without a usable pivot): the rows of
//! `J_s` that vanish carry, in the identity part, left null vectors `y` with
//! `y^T J_s = 0`. The dependent constraints are the union of their supports, which is
//! the set of rows that take part in some linear dependency (independent of the choice
//! of null-space basis). It costs `O(m^3)` time and `2 m^2` memory, so larger systems
//! use the null vector of the leading block at the failed pivot instead
//! ([`leading_null_rows`]).

use super::{PIVOT_TOL, SolveError, Structure};

/// Largest `m` diagnosed densely.
pub(crate) const DENSE_DIAGNOSIS_MAX: usize = 1500;

/// Relative size above which a null-vector component names its row.
const SUPPORT_TOL: f64 = 1e-8;

/// The dependent rows of `diag(row_scale) A` (A from pattern and values), ascending;
/// empty if the matrix has full rank at the elimination tolerance.
pub(crate) fn dependent_rows(st: &Structure, values: &[f64], row_scale: &[f64]) -> Vec<usize> {
    let m = st.m;
    let mut a = vec![0.0; m * m];
    for (&(i, j), v) in st.entries.iter().zip(values) {
        a[i * m + j] = row_scale[i] * v;
    }
    let scale = a.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return (0..m).collect();
    }
    let tol = PIVOT_TOL * scale;
    let mut y = vec![0.0; m * m];
    for i in 0..m {
        y[i * m + i] = 1.0;
    }
    let mut rank = 0;
    for col in 0..m {
        if rank == m {
            break;
        }
        let (mut piv, mut best) = (rank, a[rank * m + col].abs());
        for r in rank + 1..m {
            let v = a[r * m + col].abs();
            if v > best {
                best = v;
                piv = r;
            }
        }
        if best <= tol {
            continue;
        }
        if piv != rank {
            for c in 0..m {
                a.swap(rank * m + c, piv * m + c);
                y.swap(rank * m + c, piv * m + c);
            }
        }
        let d = a[rank * m + col];
        for r in rank + 1..m {
            let l = a[r * m + col] / d;
            if l != 0.0 {
                for c in col..m {
                    a[r * m + c] -= l * a[rank * m + c];
                }
                for c in 0..m {
                    y[r * m + c] -= l * y[rank * m + c];
                }
            }
        }
        rank += 1;
    }
    let mut dependent = vec![false; m];
    for r in rank..m {
        let row = &y[r * m..(r + 1) * m];
        let big = row.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        for (j, v) in row.iter().enumerate() {
            if v.abs() > SUPPORT_TOL * big {
                dependent[j] = true;
            }
        }
    }
    (0..m).filter(|&j| dependent[j]).collect()
}

/// For an elimination without pivoting that failed at position `k`: given the left
/// null vector `y` of the leading block (in original row numbering, zero elsewhere),
/// check that it is a null vector of the whole matrix, `|y^T A| <= tol |y| |A|` (always
/// so for a semidefinite symmetric `A`), and return its support; `None` if it is not
/// (the elimination broke down on a nonsingular matrix).
pub(crate) fn leading_null_rows(st: &Structure, values: &[f64], y: &[f64]) -> Option<Vec<usize>> {
    let scale = values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let ymax = y.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let mut z = vec![0.0; st.m];
    for (&(i, j), a) in st.entries.iter().zip(values) {
        z[j] += y[i] * a;
    }
    let zmax = z.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    if zmax > 1e-9 * scale * ymax * (st.m as f64).sqrt() {
        return None;
    }
    Some(
        (0..st.m)
            .filter(|&i| y[i].abs() > SUPPORT_TOL * ymax)
            .collect(),
    )
}

/// The error for an elimination without pivoting whose pivot at original row `row`
/// vanished: [`SolveError::Singular`] with the dependent rows if the matrix is singular,
/// [`SolveError::Breakdown`] otherwise. `leading_null` computes the left null vector of
/// the leading block (used above [`DENSE_DIAGNOSIS_MAX`]).
pub(crate) fn pivot_failure(
    st: &Structure,
    values: &[f64],
    row_scale: &[f64],
    row: usize,
    leading_null: impl FnOnce() -> Vec<f64>,
) -> SolveError {
    let rows = if st.m <= DENSE_DIAGNOSIS_MAX {
        Some(dependent_rows(st, values, row_scale)).filter(|r| !r.is_empty())
    } else {
        leading_null_rows(st, values, &leading_null())
    };
    match rows {
        Some(constraints) => SolveError::Singular { constraints },
        None => SolveError::Breakdown { row },
    }
}
