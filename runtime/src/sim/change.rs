//! A change of the model during a run that keeps the sliding variables continuous.

use super::control::mu_powers;
use super::{Phase, Simulator};
use crate::{Model, SimError};

impl<M: Model> Simulator<M> {
    /// Change the model between pieces of a run (a particle pinned, grabbed or
    /// released, a parameter switched) without a jump of the sliding variables, and act
    /// on the change at once.
    ///
    /// A change that leaves the states and their lower derivatives alone can still make
    /// each constraint's highest derivative `Omega_i = w_i^(r_i - 1)` jump (releasing a
    /// held particle: its acceleration changes at once), and `s_i` with it by
    /// `mu_i^(r_i - 1) Delta Omega_i`, far outside a thin layer. `Omega` is the part of
    /// `s` that depends on `z`, so the simulator moves `z` to give `Omega` back the value
    /// it had before the change: `z -= J_Omega^{-1} (Omega_after - Omega_before)` with
    /// the new model's `J_Omega` (one exact factorisation; exact when `Omega` is affine
    /// in `z`, as it is for forces that are linear in tensions, a Newton step otherwise).
    /// The ramp of `z` restarts there, and a control update follows before the next step.
    /// A change of the lower derivatives (a particle pinned away from where it is) is not
    /// undone: `z` cannot reach it.
    ///
    /// Returns what `change` returns; an error if the new `J_Omega` is singular at the
    /// current point (the model keeps the change: the run cannot continue from there).
    /// Before [`start`](Self::start) this is [`model_mut`](Self::model_mut): the run
    /// will start from the changed model.
    pub fn change_model<R>(&mut self, change: impl FnOnce(&mut M) -> R) -> Result<R, SimError> {
        if self.run.phase != Phase::Running {
            return Ok(change(self.model_mut()));
        }
        let t = self.pt.t;
        self.ctl.sliding(&self.model, t, &self.pt.x, &self.pt.z);
        self.ctl.omega(&mut self.scratch.omega_before);
        let out = change(&mut self.model);
        self.carry_to_omega_before()?;
        Ok(out)
    }

    /// Move `z` so that `Omega` takes the values in `omega_before` at the current point
    /// (one exact factorisation of the current `J_Omega`), restart the ramp of `z` there,
    /// and ask for an update before the next step; the quantities cached at the point
    /// are evaluated again then.
    fn carry_to_omega_before(&mut self) -> Result<(), SimError> {
        let t = self.pt.t;
        self.ctl.sliding(&self.model, t, &self.pt.x, &self.pt.z);
        self.ctl
            .eval_jacobian(&self.model, t, &self.pt.x, &self.pt.z);
        self.fresh.jacobian = false;
        self.fresh.stale = true;
        self.ctl
            .carry_omega(&self.model, t, &self.scratch.omega_before, &mut self.pt.z)?;
        self.pt.zb.copy_from_slice(&self.pt.z);
        self.pt.tb = t;
        self.pt.va.fill(0.0);
        self.run.update_requested = true;
        Ok(())
    }

    /// Scale every `mu_i` by `factor` during a run, without a jump of the sliding
    /// variables, and with `mu` what a design ties to it: the configured gains by
    /// `1 / factor` (a floor `k_i = g eps_i / mu_i` keeps its `g`), the longest step and
    /// the grazing return (([`GainRule::FollowDrift`](crate::settings::GainRule::FollowDrift))) by `factor`. Returns whether the change
    /// was made.
    ///
    /// `s_i = (mu_i d/dt + 1)^(r_i - 1) w_i` keeps `|w_i| <= eps_i` while `|s_i| <=
    /// eps_i` only from states inside a set that depends on `mu_i`: with `c_k = (mu_i
    /// d/dt + 1)^k w_i`, the free response of the filter is `e^(-t/mu) sum_k c_k
    /// (t/mu)^k / k!`, so `|c_k| <= eps_i` for `k = 0 .. r_i - 2` suffices (and for `r_i =
    /// 3`, where it reads `|w_i| <= eps_i`, `|w_i + mu_i w_i'| <= eps_i`, is also
    /// necessary). The change is refused (`Ok(false)`, nothing changed) if some `|c_k|`
    /// at the new `mu` would exceed the largest of `eps_i` and the `|c_k|` at the old
    /// `mu`: for `r_i <= 3` a shrinking `mu` always passes (`w + f mu w'` lies between
    /// `w` and `w + mu w'` for `0 < f < 1`), a growing one only where the state allows
    /// it.
    ///
    /// `s` is kept where it was by moving `z` (the part of `s` that depends on it is
    /// `mu_i^(r_i - 1) Omega_i`), as [`change_model`](Self::change_model) does: one
    /// exact factorisation, and a control update before the next step. The drift
    /// estimates of [`GainRule::FollowDrift`](crate::settings::GainRule::FollowDrift) are scaled by `factor^(r_i - 1)` where `mu`
    /// grows (the highest term of `s'` grows so) and kept where it shrinks (its lower
    /// terms do not shrink), so that the next gains err high.
    ///
    /// Before [`start`](Self::start) this changes the settings the run will start with.
    /// Errors: a `factor` that is not finite and positive, a `mu_i^(r_i - 1)` that
    /// overflows or underflows, and a singular `J_Omega` at the current point (the run
    /// cannot continue from there).
    pub fn rescale_mu(&mut self, factor: f64) -> Result<bool, SimError> {
        if !(factor.is_finite() && factor > 0.0) {
            return Err(SimError::Settings {
                field: "mu",
                reason: format!("rescale_mu: factor {factor:e} must be finite and > 0"),
            });
        }
        let new_mu: Vec<f64> = self.set.layers.mu.iter().map(|m| m * factor).collect();
        let mu_pow = mu_powers(&self.model, &new_mu)?;
        let running = self.run.phase == Phase::Running;
        let t = self.pt.t;
        if running {
            self.ctl.sliding(&self.model, t, &self.pt.x, &self.pt.z);
            let offs = &self.ctl.offs;
            let admitted = (0..new_mu.len()).all(|i| {
                let w = &self.ctl.w[offs[i]..offs[i + 1]];
                let stages = 0..w.len().saturating_sub(1);
                let bound = stages
                    .clone()
                    .map(|k| filter_stage(w, self.set.layers.mu[i], k).abs())
                    .fold(self.set.layers.eps[i], f64::max);
                { stages }.all(|k| filter_stage(w, new_mu[i], k).abs() <= bound)
            });
            if !admitted {
                return Ok(false);
            }
            // The `Omega` that gives `s` its present value at the new `mu`.
            for (i, (target, &mu)) in self
                .scratch
                .omega_before
                .iter_mut()
                .zip(&new_mu)
                .enumerate()
            {
                let w = &self.ctl.w[self.ctl.offs[i]..self.ctl.offs[i + 1]];
                let top = w.len() - 1;
                *target = (self.ctl.s[i] - filter_terms(w, mu, top)) / mu.powi(top as i32);
            }
        }
        if factor > 1.0 {
            for (d, &r) in self.drift.iter_mut().zip(self.model.indices()) {
                *d *= factor.powi(r as i32 - 1);
            }
        }
        self.set.layers.mu.copy_from_slice(&new_mu);
        for k in &mut self.set.layers.gains {
            *k /= factor;
        }
        self.set.integration.max_step *= factor;
        if let Some(g) = self.set.law.graze_mut() {
            *g *= factor;
        }
        self.mu_min *= factor;
        self.ctl
            .set_mu(&self.set.layers.mu, mu_pow, &self.set.layers.gains);
        if running {
            self.carry_to_omega_before()?;
        }
        Ok(true)
    }
}

/// `sum_{j < terms} C(k, j) mu^j w^(j)`: the first `terms` terms of `(mu d/dt + 1)^k w`
/// from `w = [w, w', ...]`.
fn binomial_sum(w: &[f64], mu: f64, k: usize, terms: usize) -> f64 {
    let (mut c, mut p, mut sum) = (1.0, 1.0, 0.0);
    for (j, wj) in w.iter().enumerate().take(terms.min(k + 1)) {
        sum += c * p * wj;
        c *= (k - j) as f64 / (j + 1) as f64;
        p *= mu;
    }
    sum
}

/// `(mu d/dt + 1)^k w`, the `k`-th stage of the filter from `w` to `s`.
fn filter_stage(w: &[f64], mu: f64, k: usize) -> f64 {
    binomial_sum(w, mu, k, k + 1)
}

/// `s` at `mu` without its highest term `mu^top Omega` (`top = r - 1`).
fn filter_terms(w: &[f64], mu: f64, top: usize) -> f64 {
    binomial_sum(w, mu, top, top)
}
