//! A control update at the current point, and what the run reports there: the sample,
//! the finiteness check and the summary; apart from the run in pieces in `mod.rs`.

use super::{Check, Simulator, Switch};
use crate::error::Quantity;
use crate::settings::Law;
use crate::trace::Sink;
use crate::{Model, SimError};

impl<M: Model> Simulator<M> {
    /// A control update at the current point (after `eval_point` there).
    pub(super) fn update<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<(), SimError> {
        let t = self.pt.t;
        if self.fresh.jacobian {
            self.ctl.factor_current(&self.model, t)?;
        } else {
            self.ctl.factor(&self.model, t, &self.pt.x, &self.pt.z)?;
            self.fresh.jacobian = true;
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
            beta_ready: self.fresh.beta,
        };
        self.follow_drift(t);
        let violations = self.ctl.law(
            &self.model,
            t,
            &self.pt.x,
            &self.pt.z,
            switch,
            check,
            &mut self.pt.v,
        );
        if self.ctl.law_needs_beta(check) {
            self.fresh.beta = true;
        }
        if let Some((i, &v)) = self.pt.v.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(self.non_finite(Quantity::Control, i, v));
        }
        self.pt.va.fill(0.0);
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
        self.pt.zb.copy_from_slice(&self.pt.z);
        self.pt.tb = t;
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
