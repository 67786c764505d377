//! Gains for an approximate inverse `J_hat^{-1}` (T 3.22): how much gain a given
//! quality of `J_hat` needs.
//!
//! With `E = J_s J_hat^{-1}` the condition is, per row,
//! `E_ii k_i > |gamma_i| + sum_{j != i} |E_ij| k_j + k_i^c` (`D = E K`). The part that
//! does not depend on the approximation, `need_i = |gamma_i| + k_i^c`, is what an exact
//! solver needs (e.g. [`robust_gain`](super::robust_gain) with the `beta` bound). The
//! quality of `J_hat` enters through the row-wise dominance margin
//! `delta_i = E_ii - sum_{j != i} |E_ij|` (with equal gains) or, per row, through the
//! whole coupling `|E_off|`.

use super::{DesignError, non_negative, positive};
use crate::solve::{LinearSolver, Solver, SolverChoice};

/// The gain that (T 3.22) needs with equal gains on the coupled rows: `k = need / delta`
/// where `delta = E_ii - sum_{j != i} |E_ij|` is the row's dominance margin (the worst
/// row's for a uniform design). Fails when `delta <= 0`: then no equal gains can hold
/// and the rows need different gains ([`approximate_inverse_gains`]) or a better
/// `J_hat`.
///
/// ```
/// // Jacobi on a bent chain whose rows are 80 % coupled: five times the exact gain.
/// let k = dae_runtime::design::approximate_inverse_gain(2.0, 0.2).unwrap();
/// assert!((k - 10.0).abs() < 1e-12);
/// assert!(dae_runtime::design::approximate_inverse_gain(2.0, 0.0).is_err());
/// ```
pub fn approximate_inverse_gain(need: f64, delta: f64) -> Result<f64, DesignError> {
    non_negative("need", need)?;
    positive("dominance margin delta", delta)?;
    Ok(need / delta)
}

/// `E = J_s diag(J_s)^{-1}` of the inverse diagonal (Jacobi), in pattern order:
/// `E_ij = d_i a_ij / (d_j a_jj)` with `a` the values of `J_Omega` and `d` the row
/// scaling `mu_i^(r_i - 1)`. The diagonal of `E` is 1.
pub fn jacobi_coupling(
    pattern: &[(usize, usize)],
    values: &[f64],
    row_scale: &[f64],
) -> Result<Vec<f64>, DesignError> {
    let m = row_scale.len();
    let mut diag = vec![f64::NAN; m];
    for (&(i, j), &a) in pattern.iter().zip(values) {
        if i == j && i < m {
            diag[i] = row_scale[i] * a;
        }
    }
    for &d in &diag {
        positive("|diagonal of J_s|", d.abs())?;
    }
    Ok(pattern
        .iter()
        .zip(values)
        .map(|(&(i, j), &a)| row_scale[i] * a / diag[j])
        .collect())
}

/// The least gains with which every row satisfies (T 3.22) with a relative `margin`:
/// the solution of `E_ii k_i = (1 + margin)(need_i + sum_{j != i} |E_ij| k_j)`, solved
/// with the runtime's solver seam on the pattern of `E`.
///
/// `pattern`/`coupling`: the entries of `E = J_s J_hat^{-1}` (for Jacobi,
/// [`jacobi_coupling`]); `need_i = |gamma_i| + k_i^c` (bounds). The gains exist exactly
/// when the spectral radius of `(1 + margin) diag(E)^{-1} |E_off|` is below one (then
/// the matrix is an M-matrix and the solution is positive); otherwise the approximation
/// is too poor for any gain and the first row with a non-positive solution is named.
pub fn approximate_inverse_gains(
    pattern: &[(usize, usize)],
    coupling: &[f64],
    need: &[f64],
    margin: f64,
) -> Result<Vec<f64>, DesignError> {
    let m = need.len();
    for &n in need {
        non_negative("need", n)?;
    }
    non_negative("margin", margin)?;
    let f = 1.0 + margin;
    let values: Vec<f64> = pattern
        .iter()
        .zip(coupling)
        .map(|(&(i, j), &e)| if i == j { e } else { -f * e.abs() })
        .collect();
    let mut solver =
        Solver::new(m, pattern, SolverChoice::Auto).map_err(|e| DesignError::NoRobustGain {
            row: 0,
            reason: e.to_string(),
        })?;
    let ones = vec![1.0; m];
    solver
        .factor(&values, &ones)
        .map_err(|e| DesignError::NoRobustGain {
            row: 0,
            reason: e.to_string(),
        })?;
    let mut k: Vec<f64> = need.iter().map(|n| f * n).collect();
    solver.solve(&mut k);
    if let Some(row) = k.iter().position(|k| !(k.is_finite() && *k > 0.0)) {
        return Err(DesignError::NoRobustGain {
            row,
            reason: "the coupling of this J_hat has spectral radius >= 1: no gains satisfy (T 3.22); use a better approximation".into(),
        });
    }
    Ok(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The straight chain of `n` links: diagonal -1 (pinned link), -2, off-diagonal +1.
    fn straight_chain(n: usize) -> (Vec<(usize, usize)>, Vec<f64>) {
        let mut p = Vec::new();
        let mut v = Vec::new();
        for i in 0..n {
            for j in i.saturating_sub(1)..(i + 2).min(n) {
                p.push((i, j));
                v.push(if i == j {
                    if i == 0 { -1.0 } else { -2.0 }
                } else {
                    1.0
                });
            }
        }
        (p, v)
    }

    #[test]
    fn jacobi_gains_on_a_straight_chain_satisfy_every_row() {
        let n = 8;
        let (pat, vals) = straight_chain(n);
        let d: Vec<f64> = (0..n).map(|i| 0.01 * (1.0 + i as f64)).collect();
        let e = jacobi_coupling(&pat, &vals, &d).unwrap();
        let need: Vec<f64> = (0..n).map(|i| 0.5 + 0.1 * i as f64).collect();
        let k = approximate_inverse_gains(&pat, &e, &need, 0.01).unwrap();
        // Oracle: the row inequality itself, each row with a strictly positive margin.
        for i in 0..n {
            let (mut eii, mut off) = (0.0, 0.0);
            for ((&(r, c), &eij), _) in pat.iter().zip(&e).zip(&vals) {
                if r == i {
                    if c == i {
                        eii = eij;
                    } else {
                        off += eij.abs() * k[c];
                    }
                }
            }
            assert!((eii - 1.0).abs() < 1e-15);
            assert!(eii * k[i] > need[i] + off, "row {i}");
        }
        // A uniform design is impossible: the interior rows have no dominance margin.
        assert!(approximate_inverse_gain(1.0, 1.0 - 0.5 - 0.5).is_err());
    }

    #[test]
    fn a_coupling_with_spectral_radius_above_one_has_no_gain() {
        // Two rows each coupled 1.2 to the other.
        let pat = [(0, 0), (0, 1), (1, 0), (1, 1)];
        let e = [1.0, 1.2, 1.2, 1.0];
        let err = approximate_inverse_gains(&pat, &e, &[1.0, 1.0], 0.0).unwrap_err();
        assert!(matches!(err, DesignError::NoRobustGain { .. }), "{err}");
    }
}
