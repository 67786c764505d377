//! A control update at the current point, and what the run reports there: the sample,
//! the finiteness check and the summary; apart from the run in pieces in `mod.rs`.

use super::{Check, Simulator, Switch};
use crate::error::Quantity;
use crate::settings::Law;
use crate::solve::LinearSolver;
use crate::summary::SolverSummary;
use crate::trace::{Sample, Sink};
use crate::{Model, SimError, Summary};

impl<M: Model> Simulator<M> {
    /// A control update at the current point (after `eval_point` there).
    pub(super) fn update<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        let t = self.t;
        if self.run.j_current {
            self.ctl.factor_current(&self.model, t)?;
        } else {
            self.ctl.factor(&self.model, t, &self.x, &self.z)?;
            self.run.j_current = true;
        }
        let switch = if self.set.law.saturates() {
            Switch::Saturation
        } else {
            Switch::Sign
        };
        let in_window = self.stats.stats_from.is_some();
        let count = self.set.check_robustness && in_window;
        let located = self.located();
        let check = Check {
            evaluate: count || self.set.law.raise_margin().is_some(),
            count,
            raise: self.set.law.raise_margin(),
            beta_ready: self.run.beta_current,
        };
        self.follow_drift(t);
        let violations = self
            .ctl
            .law(&self.model, t, &self.x, &self.z, switch, check, &mut self.v);
        if self.ctl.law_needs_beta(check) {
            self.run.beta_current = true;
        }
        if let Some((i, &v)) = self.v.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(self.non_finite(Quantity::Control, i, v));
        }
        self.va.fill(0.0);
        if located {
            // `s'` with the new `v` (`va` is 0 until the ramp is set).
            self.rate_at(t);
            if self.set.law.ramps() {
                self.ramp_against_drift(t);
            }
            if self.set.law.follows_drift().is_some() {
                self.ds_b.copy_from_slice(&self.ds);
            }
        }
        self.zb.copy_from_slice(&self.z);
        self.tb = t;
        let st = &mut self.stats;
        st.updates += 1;
        st.steps_since_update = 0;
        st.violations += violations;
        if st.reaching_time.is_none() {
            st.reaching_updates += 1;
            for (i, s) in self.ctl.s.iter().enumerate() {
                self.eps_k[i] = s.abs().max(self.set.layers.eps[i]);
                self.sgn_k[i] = s.signum();
                self.outside_k[i] = s.abs() > self.set.layers.eps[i];
            }
        }
        if in_window {
            if let Some(prev) = st.last_window_update {
                st.min_period = st.min_period.min(t - prev);
                st.period_sum += t - prev;
                st.periods += 1;
            }
            st.last_window_update = Some(t);
        }
        if self.set.law != Law::Spsm {
            sink.update(t)?;
        }
        Ok(())
    }

    pub(super) fn record<S: Sink + ?Sized>(
        &mut self,
        last: bool,
        sink: &mut S,
    ) -> Result<(), SimError> {
        let outputs = sink.algebraic_outputs();
        if outputs {
            self.ctl.z_eq(&self.z, &mut self.z_eq);
            if !self.run.j_current {
                self.ctl
                    .eval_jacobian(&self.model, self.t, &self.x, &self.z);
                self.run.j_current = true;
            }
            self.ctl.z_star(&self.z, &mut self.z_star);
        }
        for i in 0..self.wres.len() {
            self.wres[i] = self.ctl.residual(i);
        }
        let (z_eq, z_star): (&[f64], &[f64]) = if outputs {
            (&self.z_eq, &self.z_star)
        } else {
            (&[], &[])
        };
        sink.record(&Sample {
            step: self.stats.steps,
            t: self.t,
            x: &self.x,
            z: &self.z,
            z_eq,
            z_star,
            s: &self.ctl.s,
            w: &self.wres,
            last,
        })?;
        self.run.recorded = Some(self.stats.steps);
        Ok(())
    }

    fn non_finite(&self, kind: Quantity, index: usize, value: f64) -> SimError {
        let name = match kind {
            Quantity::State => self.model.state_name(index),
            Quantity::Algebraic | Quantity::Control => self.model.alg_name(index),
            Quantity::Sliding | Quantity::Residual => self.model.constraint_name(index),
        };
        SimError::NonFinite {
            kind,
            index,
            name: name.to_string(),
            value,
            t: self.t,
        }
    }

    pub(super) fn check_finite(&self) -> Result<(), SimError> {
        // Nearly every point is finite: one pass without early exit over each vector
        // first (a fold of flags, which the compiler vectorises), the search for what to
        // name only when one is not (every w-derivative is checked there, the
        // residuals among them).
        let all_finite = |v: &[f64]| !v.iter().fold(false, |bad, x| bad | !x.is_finite());
        if all_finite(&self.x)
            && all_finite(&self.z)
            && all_finite(&self.ctl.w)
            && all_finite(&self.ctl.s)
        {
            return Ok(());
        }
        let find = |v: &[f64]| v.iter().position(|x| !x.is_finite());
        if let Some(i) = find(&self.x) {
            return Err(self.non_finite(Quantity::State, i, self.x[i]));
        }
        if let Some(i) = find(&self.z) {
            return Err(self.non_finite(Quantity::Algebraic, i, self.z[i]));
        }
        if let Some(i) = (0..self.wres.len()).find(|&i| !self.ctl.residual(i).is_finite()) {
            return Err(self.non_finite(Quantity::Residual, i, self.ctl.residual(i)));
        }
        if let Some(i) = find(&self.ctl.s) {
            return Err(self.non_finite(Quantity::Sliding, i, self.ctl.s[i]));
        }
        Ok(())
    }

    pub(super) fn summary(&self, wall_time: f64) -> Summary {
        let st = &self.stats;
        let ss = self.ctl.solver.stats();
        let window = st.stats_from.is_some();
        Summary {
            solver: SolverSummary {
                name: self.ctl.solver.name().to_string(),
                choice: self.set.solver,
                factorisations: ss.factorisations,
                solves: ss.solves,
                iterations: ss.iterations,
                robustness_failures: st.violations,
                gain_raises: self.ctl.gain_raises,
            },
            gains: self.ctl.gains.clone(),
            model: self.model.name().to_string(),
            constraints: self.layout.constraints.clone(),
            t_end: self.t,
            steps: st.steps,
            rejected_steps: st.rejected,
            located_crossings: st.cuts,
            unlocated_steps: st.unlocated,
            updates: st.updates,
            reaching_updates: st.reaching_updates,
            triggered_updates: st.triggered.clone(),
            reaching_time: st.reaching_time,
            stats_from: st.stats_from,
            min_period: (st.periods > 0).then_some(st.min_period),
            mean_period: (st.periods > 0).then(|| st.period_sum / st.periods as f64),
            max_abs_s: window.then(|| st.max_s.clone()),
            max_abs_w: window.then(|| st.max_w.clone()),
            seen_max_abs_s: st.seen_s.clone(),
            seen_max_abs_w: st.seen_w.clone(),
            bound_loss: st
                .loss
                .record(&self.layout.constraints, self.near_singular()),
            min_pivot_ratio: self.ctl.min_pivot_ratio,
            robustness_violations: self.set.check_robustness.then_some(st.violations),
            f_evals: st.rhs_evals,
            sliding_evals: self.ctl.sliding_evals,
            jacobian_evals: self.ctl.jacobian_evals,
            beta_evals: self.ctl.beta_evals,
            rate_evals: self.ctl.rate_evals,
            wall_time,
            x: self.x.clone(),
            z: self.z.clone(),
            z_eq: self.z_eq.clone(),
            z_star: self.z_star.clone(),
            s: self.ctl.s.clone(),
            w: (0..self.wres.len()).map(|i| self.ctl.residual(i)).collect(),
        }
    }
}
