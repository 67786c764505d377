//! What a run reports: the samples sent to the sink, the check that the point is
//! finite (naming what is not), and the summary.

use super::Simulator;
use crate::error::Quantity;
use crate::solve::LinearSolver;
use crate::summary::SolverSummary;
use crate::trace::{Sample, Sink};
use crate::{Model, SimError, Summary};

impl<M: Model> Simulator<M> {
    pub(super) fn record<S: Sink + ?Sized>(
        &mut self,
        last: bool,
        sink: &mut S,
    ) -> Result<(), SimError> {
        let outputs = sink.algebraic_outputs();
        if outputs {
            self.z_eq_now()?;
            if !self.fresh.jacobian {
                self.ctl
                    .eval_jacobian(&self.model, self.pt.t, &self.pt.x, &self.pt.z);
                self.fresh.jacobian = true;
            }
            self.ctl.z_star(&self.pt.z, &mut self.scratch.z_star);
        }
        for i in 0..self.scratch.wres.len() {
            self.scratch.wres[i] = self.ctl.residual(i);
        }
        let (z_eq, z_star): (&[f64], &[f64]) = if outputs {
            (&self.scratch.z_eq, &self.scratch.z_star)
        } else {
            (&[], &[])
        };
        sink.record(&Sample {
            step: self.stats.steps,
            t: self.pt.t,
            x: &self.pt.x,
            z: &self.pt.z,
            z_eq,
            z_star,
            s: &self.ctl.s,
            w: &self.scratch.wres,
            last,
        })?;
        self.run.recorded = Some(self.stats.steps);
        Ok(())
    }

    pub(super) fn non_finite(&self, kind: Quantity, index: usize, value: f64) -> SimError {
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
            t: self.pt.t,
        }
    }

    pub(super) fn check_finite(&self) -> Result<(), SimError> {
        // Nearly every point is finite: one pass without early exit over each vector
        // first (a fold of flags, which the compiler vectorises), the search for what to
        // name only when one is not (every w-derivative is checked there, the
        // residuals among them).
        let all_finite = |v: &[f64]| !v.iter().fold(false, |bad, x| bad | !x.is_finite());
        if all_finite(&self.pt.x)
            && all_finite(&self.pt.z)
            && all_finite(&self.ctl.w)
            && all_finite(&self.ctl.s)
        {
            return Ok(());
        }
        let find = |v: &[f64]| v.iter().position(|x| !x.is_finite());
        if let Some(i) = find(&self.pt.x) {
            return Err(self.non_finite(Quantity::State, i, self.pt.x[i]));
        }
        if let Some(i) = find(&self.pt.z) {
            return Err(self.non_finite(Quantity::Algebraic, i, self.pt.z[i]));
        }
        if let Some(i) = (0..self.scratch.wres.len()).find(|&i| !self.ctl.residual(i).is_finite()) {
            return Err(self.non_finite(Quantity::Residual, i, self.ctl.residual(i)));
        }
        if let Some(i) = find(&self.ctl.s) {
            return Err(self.non_finite(Quantity::Sliding, i, self.ctl.s[i]));
        }
        Ok(())
    }

    /// `z_eq` at the current point, into the scratch: where block updates came after
    /// the last factorisation of all of `J_s`, `J_s` is factored again here first.
    pub(super) fn z_eq_now(&mut self) -> Result<(), SimError> {
        if self.ctl.global_factor_stale() {
            if !self.fresh.jacobian {
                self.ctl
                    .eval_jacobian(&self.model, self.pt.t, &self.pt.x, &self.pt.z);
                self.fresh.jacobian = true;
            }
            self.ctl.factor_current(&self.model, self.pt.t)?;
        }
        self.ctl.z_eq(&self.pt.z, &mut self.scratch.z_eq);
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
                set_aside: ss.set_aside,
                set_aside_max: ss.set_aside_rows_max,
            },
            gains: self.ctl.gains.clone(),
            model: self.model.name().to_string(),
            constraints: self.layout.constraints.clone(),
            eps: self.set.layers.eps.clone(),
            t_end: self.pt.t,
            steps: st.steps,
            rejected_steps: st.rejected,
            located_crossings: st.cuts,
            unlocated_steps: st.unlocated,
            updates: st.updates,
            reaching_updates: st.reaching_updates,
            blocks: self.blocks(),
            mu_search: self.mu_search(),
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
            x: self.pt.x.clone(),
            z: self.pt.z.clone(),
            z_eq: self.scratch.z_eq.clone(),
            z_star: self.scratch.z_star.clone(),
            s: self.ctl.s.clone(),
            w: (0..self.scratch.wres.len())
                .map(|i| self.ctl.residual(i))
                .collect(),
        }
    }
}
