//! The robustness condition with an approximate `J_hat` (T 3.22) at a control update,
//! and the policy that raises the gains of the rows that fail it.
//!
//! With `E = J_s J_hat^{-1}`, `D = E K` and `gamma = alpha - E alpha_hat`, the crossing
//! condition holds for every sign pattern of `s` if each row satisfies
//! `D_ii > |gamma_i| + sum_{j != i} |D_ij| + k_i^c`. How it is evaluated depends on the
//! solver ([`InverseKind`]):
//!
//! * exact (`E = I`): `k_i > |alpha_i - alpha_hat_i| + k_i^c`, exactly;
//! * Jacobi (`E = J_s diag(J_s)^{-1}`, unit diagonal, `E_ij = d_i a_ij / (d_j a_jj)`):
//!   formed row by row from the pattern in `O(nnz)`, exactly;
//! * iterations and incomplete factors: `E` is not formed. The computed `v` satisfies
//!   `J_s v = b - r` with the residual `r`, so `s' = (alpha - alpha_hat) - K sgn(s) - r`
//!   at the update, and `k_i > |alpha_i - alpha_hat_i| + |r_i| + k_i^c` guarantees the
//!   crossing of row `i` for the sign pattern of this update: a bound that needs one
//!   multiplication by `J_s` (`O(nnz)`) and is exact for the held `v`.

use crate::solve::{InverseKind, Structure};

/// Row-wise coupling of the Jacobi approximation, evaluated from the pattern.
pub(crate) struct Robustness {
    st: Structure,
    /// Per-row requirement `|gamma_i| + sum_{j != i} |D_ij| + k_i^c` of the last check.
    pub(crate) need: Vec<f64>,
    /// `gamma_i` without the gain terms (Jacobi: `g_i - sum E_ij alpha_hat_j`).
    gamma: Vec<f64>,
}

/// Passes over the rows per update when raising Jacobi gains (each pass is `O(nnz)`).
/// The raise converges monotonically (see [`Robustness::raise_jacobi`]); what a long
/// chain does not finish in one update continues at the next.
pub(crate) const RAISE_PASSES: usize = 64;

impl Robustness {
    pub(crate) fn new(st: Structure) -> Self {
        let m = st.m;
        Self {
            st,
            need: vec![0.0; m],
            gamma: vec![0.0; m],
        }
    }

    fn e_ij(&self, values: &[f64], d: &[f64], p: usize) -> (usize, f64) {
        let i = self.st.row_of(p);
        let j = self.st.cols[p];
        let a = values[self.st.entry[p]];
        let djj = d[j] * values[self.st.diag[j]];
        (j, d[i] * a / djj)
    }

    /// Evaluate every row's requirement `need_i` (so that the row holds iff
    /// `E_ii k_i > need_i`, `E_ii = 1` here) for the given solver kind. `g` is
    /// `alpha - alpha_hat` (the part of alpha the law omits), `ah` the `alpha_hat` the law
    /// uses, `residual` the residual of the computed solve (approximate solvers).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn evaluate(
        &mut self,
        kind: InverseKind,
        values: &[f64],
        d: &[f64],
        g: &[f64],
        ah: &[f64],
        gains: &[f64],
        margin: &[f64],
        residual: &[f64],
    ) {
        let m = self.st.m;
        match kind {
            InverseKind::Exact => {
                for i in 0..m {
                    self.need[i] = g[i].abs() + margin[i];
                }
            }
            InverseKind::Approximate => {
                for i in 0..m {
                    self.need[i] = g[i].abs() + residual[i].abs() + margin[i];
                }
            }
            InverseKind::Diagonal => {
                for i in 0..m {
                    let mut gamma = g[i];
                    let mut off = 0.0;
                    for p in self.st.row_ptr[i]..self.st.row_ptr[i + 1] {
                        let (j, e) = self.e_ij(values, d, p);
                        if j != i {
                            gamma -= e * ah[j];
                            off += e.abs() * gains[j];
                        }
                    }
                    self.gamma[i] = gamma;
                    self.need[i] = gamma.abs() + off + margin[i];
                }
            }
        }
    }

    /// Number of rows with `k_i <= need_i` (a NaN requirement fails).
    pub(crate) fn failures(&self, gains: &[f64]) -> u64 {
        gains
            .iter()
            .zip(&self.need)
            .filter(|(k, n)| k.partial_cmp(n) != Some(std::cmp::Ordering::Greater))
            .count() as u64
    }

    /// Raise the failing rows (exact and approximate kinds): `k_i = (1 + margin) need_i`.
    /// Returns how many gains were raised.
    pub(crate) fn raise_rows(&self, gains: &mut [f64], margin: f64) -> u64 {
        let mut raised = 0;
        for (k, &n) in gains.iter_mut().zip(&self.need) {
            if n.is_finite() && *k <= n {
                *k = (1.0 + margin) * n;
                raised += 1;
            }
        }
        raised
    }

    /// Raise Jacobi gains until every row holds: pass over the rows and set each failing
    /// `k_i` to `(1 + margin) (|gamma_i| + sum_{j != i} |E_ij| k_j + k_i^c)` with the
    /// current other gains. The requirement of a row grows only through the other rows'
    /// gains, so the gains increase monotonically toward the least solution of
    /// `(I - (1 + margin) |E_off|) k >= (1 + margin)(|gamma| + k^c)`, which exists when
    /// the spectral radius of `(1 + margin) |E_off|` is below one (for Jacobi: the
    /// absolute Jacobi iteration matrix of `J_s`, below one for an irreducibly
    /// diagonally dominant `J_Omega` such as a chain's); then all rows hold and the
    /// condition (T 3.22) is restored. Returns how many raises were made.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn raise_jacobi(
        &mut self,
        values: &[f64],
        d: &[f64],
        margin_kc: &[f64],
        gains: &mut [f64],
        margin: f64,
        limit: &[f64],
    ) -> u64 {
        let mut raised = 0;
        for _ in 0..RAISE_PASSES {
            let mut changed = false;
            for i in 0..self.st.m {
                let mut off = 0.0;
                for p in self.st.row_ptr[i]..self.st.row_ptr[i + 1] {
                    let (j, e) = self.e_ij(values, d, p);
                    if j != i {
                        off += e.abs() * gains[j];
                    }
                }
                let need = self.gamma[i].abs() + off + margin_kc[i];
                self.need[i] = need;
                if need.is_finite() && gains[i] <= need && gains[i] < limit[i] {
                    gains[i] = ((1.0 + margin) * need).min(limit[i]);
                    raised += 1;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        raised
    }
}
