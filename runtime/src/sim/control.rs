//! The control law `v = J_hat^{-1}(-alpha_hat - K sgn(s))` with `J_hat = J_s`, its
//! buffers, and `z_eq`.

use nalgebra::DVector;

use super::lu::DenseLu;
use crate::{Model, SimError, w_offsets};

/// Switching function: `sgn` for DBSMC, `sat(s/eps)` for SPSM.
#[derive(Clone, Copy)]
pub(crate) enum Switch {
    Sign,
    Saturation,
}

pub(crate) struct Controller {
    pub(crate) offs: Vec<usize>,
    mu: Vec<f64>,
    /// `mu_i^(r_i - 1)`, the row scaling from `J_Omega` to `J_s`.
    mu_pow: Vec<f64>,
    gains: Vec<f64>,
    margin: Vec<f64>,
    eps: Vec<f64>,
    exact_alpha: bool,
    pattern: Vec<(usize, usize)>,
    jvals: Vec<f64>,
    /// w-derivatives, sliding variables and cheap alpha_hat at the last `sliding` call.
    pub(crate) w: Vec<f64>,
    pub(crate) s: Vec<f64>,
    ah: Vec<f64>,
    beta: Vec<f64>,
    rhs: DVector<f64>,
    lu: DenseLu,
    dependent: Vec<usize>,
    pub(crate) sliding_evals: u64,
    pub(crate) jacobian_evals: u64,
    pub(crate) beta_evals: u64,
}

fn sgn(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

impl Controller {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new<M: Model + ?Sized>(
        model: &M,
        mu: &[f64],
        gains: &[f64],
        margin: &[f64],
        eps: &[f64],
        exact_alpha: bool,
    ) -> Result<Self, SimError> {
        let m = model.n_constraints();
        let r = model.indices();
        if r.len() != m || r.contains(&0) {
            return Err(SimError::Settings {
                field: "model",
                reason: format!("indices {r:?} must be {m} values >= 1"),
            });
        }
        let pattern = model.jacobian_pattern().to_vec();
        if let Some(&(i, j)) = pattern.iter().find(|(i, j)| *i >= m || *j >= m) {
            return Err(SimError::Settings {
                field: "model",
                reason: format!("jacobian pattern entry ({i}, {j}) outside {m} x {m}"),
            });
        }
        let offs = w_offsets(r);
        let mu_pow = r
            .iter()
            .zip(mu)
            .map(|(&ri, &mi)| mi.powi(ri as i32 - 1))
            .collect();
        Ok(Self {
            w: vec![0.0; offs[m]],
            offs,
            mu: mu.to_vec(),
            mu_pow,
            gains: gains.to_vec(),
            margin: margin.to_vec(),
            eps: eps.to_vec(),
            exact_alpha,
            jvals: vec![0.0; pattern.len()],
            pattern,
            s: vec![0.0; m],
            ah: vec![0.0; m],
            beta: vec![0.0; m],
            rhs: DVector::zeros(m),
            lu: DenseLu::new(m),
            dependent: Vec::with_capacity(m),
            sliding_evals: 0,
            jacobian_evals: 0,
            beta_evals: 0,
        })
    }

    pub(crate) fn reset_counters(&mut self) {
        self.sliding_evals = 0;
        self.jacobian_evals = 0;
        self.beta_evals = 0;
    }

    /// Evaluate w-derivatives, `s` and the cheap `alpha_hat` at `(t, x, z)`.
    pub(crate) fn sliding<M: Model + ?Sized>(&mut self, model: &M, t: f64, x: &[f64], z: &[f64]) {
        model.sliding(t, x, z, &self.mu, &mut self.w, &mut self.s, &mut self.ah);
        self.sliding_evals += 1;
    }

    /// Constraint residual `w_i` from the last `sliding` call.
    pub(crate) fn residual(&self, i: usize) -> f64 {
        self.w[self.offs[i]]
    }

    /// Assemble `J_s = diag(mu^(r-1)) J_Omega` at `(t, x, z)` and factor it.
    pub(crate) fn factor<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
    ) -> Result<(), SimError> {
        model.jacobian(t, x, z, &mut self.jvals);
        self.jacobian_evals += 1;
        self.lu.a.fill(0.0);
        for (&(i, j), &v) in self.pattern.iter().zip(&self.jvals) {
            self.lu.a[(i, j)] = self.mu_pow[i] * v;
        }
        if self.lu.factor(&mut self.dependent) {
            Ok(())
        } else {
            Err(SimError::SingularJacobian {
                t,
                constraints: self.dependent.clone(),
                names: self
                    .dependent
                    .iter()
                    .map(|&i| model.constraint_name(i).to_string())
                    .collect(),
            })
        }
    }

    /// The control `v` at `(t, x, z)`, using `s`/`alpha_hat` from the last `sliding` call
    /// and the factors from the last `factor` call. Evaluates `beta` when the exact
    /// alpha is used or `check` is set; returns the number of constraints violating the
    /// robustness condition `k_i > |gamma_i| + k_i^c` (0 when not checked).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn law<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
        switch: Switch,
        check: bool,
        v: &mut [f64],
    ) -> u64 {
        let need_beta = self.exact_alpha || check;
        if need_beta {
            model.beta(t, x, z, &mut self.beta);
            self.beta_evals += 1;
        }
        let mut violations = 0;
        for i in 0..self.s.len() {
            let exact_part = self.mu_pow[i] * self.beta[i];
            let alpha_hat = if self.exact_alpha {
                self.ah[i] + exact_part
            } else {
                self.ah[i]
            };
            let sw = match switch {
                Switch::Sign => sgn(self.s[i]),
                Switch::Saturation => (self.s[i] / self.eps[i]).clamp(-1.0, 1.0),
            };
            self.rhs[i] = -alpha_hat - self.gains[i] * sw;
            if check {
                // With J_hat = J_s, D = K and gamma = alpha - alpha_hat (T 3.22).
                let gamma = if self.exact_alpha { 0.0 } else { exact_part };
                // A NaN beta counts as a violation.
                if gamma.is_nan() || self.gains[i] <= gamma.abs() + self.margin[i] {
                    violations += 1;
                }
            }
        }
        self.lu.solve(&mut self.rhs);
        v.copy_from_slice(self.rhs.as_slice());
        violations
    }

    /// `z_eq = z - J_s^{-1} s` with the last factors and the last `s`.
    pub(crate) fn z_eq(&mut self, z: &[f64], out: &mut [f64]) {
        if !self.lu.is_valid() {
            out.copy_from_slice(z);
            return;
        }
        self.rhs.as_mut_slice().copy_from_slice(&self.s);
        self.lu.solve(&mut self.rhs);
        for ((o, zi), d) in out.iter_mut().zip(z).zip(self.rhs.iter()) {
            *o = zi - d;
        }
    }
}
