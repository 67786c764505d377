//! When the monitoring policy updates the control, and which constraints asked for it
//! (counted per constraint: `Summary::triggered_updates`).

use super::Simulator;
use crate::Model;

impl<M: Model> Simulator<M> {
    /// The monitoring policy's condition at the end of an accepted step: some `s_i` on
    /// or beyond its layer boundary and moving outward, or (contracting layers in the
    /// reaching phase) arrived at its surface. When it holds, each row that asked for
    /// the update is counted.
    pub(super) fn monitor_due(&mut self) -> bool {
        let located = self.located();
        let steady = self.steady();
        let tol = self.crossing_tol();
        let m = self.ctl.s.len();
        let outward = (0..m).any(|i| self.outward(i, located, steady, tol));
        let due = outward || (!steady && (0..m).any(|i| self.arrived(i, tol)));
        if due {
            for i in 0..m {
                let asked = if outward {
                    self.outward(i, located, steady, tol)
                } else {
                    self.arrived(i, tol)
                };
                if asked {
                    self.stats.triggered[i] += 1;
                    if let Some(blocks) = self.ctl.blocks_mut() {
                        blocks.ask(i);
                    }
                }
            }
        }
        due
    }

    /// Row `i` on (within the crossing tolerance) or beyond its layer boundary and moving
    /// outward: by the exact rate `s'` with located crossings; by the finite difference
    /// over the step with the thesis's step-end rule, which is free (`s` is evaluated
    /// after every step anyway), exact in sign for the motion over the step including
    /// the neglected beta part, and needs no extra model call.
    fn outward(&self, i: usize, located: bool, steady: bool, tol: f64) -> bool {
        let s = self.ctl.s[i];
        let eps = if steady {
            self.set.layers.eps[i]
        } else {
            self.eps_k[i]
        };
        let rate = if located {
            self.ds[i]
        } else {
            s - self.s_prev[i]
        };
        s.abs() >= eps * (1.0 - tol) && s * rate > 0.0
    }

    /// Reaching phase with contracting layers: row `i` started the interval outside its
    /// layer and has arrived at its surface (within the crossing tolerance).
    fn arrived(&self, i: usize, tol: f64) -> bool {
        self.outside_k[i] && self.ctl.s[i] * self.sgn_k[i] <= tol * self.set.layers.eps[i]
    }

    /// The steady rule (the design layers) applies: after reaching, or with attracting
    /// surfaces from the start.
    pub(super) fn steady(&self) -> bool {
        self.stats.reaching_time.is_some()
            || self.set.law.reaching() == crate::settings::Reaching::AttractingSurfaces
    }
}
