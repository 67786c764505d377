//! A control update at the current point, of every row or of the blocks that asked
//! (`Scope::Blocks`), and what follows it: the rate, the ramp's base, the counts.

use super::{Check, Simulator, Switch};
use crate::error::Quantity;
use crate::settings::Law;
use crate::trace::Sink;
use crate::{Model, SimError};

impl<M: Model> Simulator<M> {
    /// A control update of every row at the current point (after `eval_point` there).
    pub(super) fn update<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        let t = self.pt.t;
        if let Some(blocks) = self.ctl.blocks_mut() {
            blocks.clear();
        }
        if self.fresh.jacobian {
            self.ctl.factor_current(&self.model, t)?;
        } else {
            self.ctl.factor(&self.model, t, &self.pt.x, &self.pt.z)?;
            self.fresh.jacobian = true;
        }
        let in_window = self.stats.stats_from.is_some();
        let count = self.set.check_robustness && in_window;
        let check = Check {
            evaluate: count || self.set.law.raise_margin().is_some(),
            count,
            raise: self.set.law.raise_margin(),
            beta_ready: self.fresh.beta,
        };
        self.follow_drift(t);
        let violations = self.ctl.law(
            &self.model,
            t,
            &self.pt.x,
            &self.pt.z,
            self.switch(),
            check,
            &mut self.pt.v,
        );
        self.after_update(t, check, violations, sink)
    }

    /// A monitored update of the rows that asked ([`Self::monitor_due`]): with
    /// block-local updates only their blocks, every row otherwise.
    pub(super) fn update_asked<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        if self.ctl.blocks().is_none() {
            return self.update(sink);
        }
        let t = self.pt.t;
        if !self.fresh.jacobian {
            self.ctl
                .eval_jacobian(&self.model, t, &self.pt.x, &self.pt.z);
            self.fresh.jacobian = true;
        }
        let count = self.set.check_robustness && self.stats.stats_from.is_some();
        let check = Check {
            evaluate: count,
            count,
            raise: None,
            beta_ready: self.fresh.beta,
        };
        let tol = self.crossing_tol();
        let outcome = self.ctl.law_blocks(
            &self.model,
            (t, &self.pt.x, &self.pt.z),
            self.switch(),
            check,
            tol,
            &mut self.pt.v,
        )?;
        self.fresh.beta = true;
        if !outcome.settled {
            // The sweeps did not settle at this point: every row, from one solve.
            return self.update(sink);
        }
        self.stats.block_updates += 1;
        self.after_update(t, check, outcome.failures, sink)
    }

    fn switch(&self) -> Switch {
        if self.set.law.saturates() {
            Switch::Saturation
        } else {
            Switch::Sign
        }
    }

    /// What follows a new `v` at `t`: its check, the rate with located crossings (and
    /// the ramp against the drift), the ramp's base, the counts and the sink's note.
    fn after_update<S: Sink + ?Sized>(
        &mut self,
        t: f64,
        check: Check,
        violations: u64,
        sink: &mut S,
    ) -> Result<(), SimError> {
        if self.ctl.law_needs_beta(check) {
            self.fresh.beta = true;
        }
        if let Some((i, &v)) = self.pt.v.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(self.non_finite(Quantity::Control, i, v));
        }
        self.pt.va.fill(0.0);
        if self.located() {
            // `s'` with the new `v` (`va` is 0 until the ramp is set).
            self.rate_at(t);
            if self.set.law.ramps() {
                self.ramp_against_drift(t);
            }
            if self.set.law.follows_drift().is_some() {
                self.ds_b.copy_from_slice(&self.ds);
            }
        }
        // `z` is continuous: every row's ramp restarts from where it is.
        self.pt.zb.copy_from_slice(&self.pt.z);
        self.pt.tb = t;
        let in_window = self.stats.stats_from.is_some();
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
}
