//! What is evaluated at the current point: `s`, and with located crossings `J_Omega`,
//! `beta` and the rate `s'` with `v` on its ramp.

use super::Simulator;
use crate::Model;
use crate::settings::Law;

impl<M: Model> Simulator<M> {
    /// `v` at `t` on its ramp (`v` itself to the last bit without one), into `v_now`.
    pub(super) fn v_at(&mut self, t: f64) {
        let dt = t - self.pt.tb;
        for ((n, v), a) in self.pt.v_now.iter_mut().zip(&self.pt.v).zip(&self.pt.va) {
            *n = v + a * dt;
        }
    }

    /// `s'` at the current point, time `t`, with `v` on its ramp, into `ds`: from
    /// `J_Omega` and `beta` where both are evaluated there, else from the model's rate
    /// of `Omega` in one pass, else from `J_Omega` and `beta` evaluated now.
    pub(super) fn rate_at(&mut self, t: f64) {
        self.v_at(t);
        let (x, z) = (&self.pt.x, &self.pt.z);
        let both = self.fresh.jacobian && self.fresh.beta;
        if !both
            && self
                .ctl
                .rate_from_model(&self.model, t, x, z, &self.pt.v_now, &mut self.ds)
        {
            return;
        }
        if !self.fresh.jacobian {
            self.ctl.eval_jacobian(&self.model, t, x, z);
            self.fresh.jacobian = true;
        }
        if !self.fresh.beta {
            self.ctl.eval_beta(&self.model, t, x, z);
            self.fresh.beta = true;
        }
        self.ctl.s_rate(&self.pt.v_now, &mut self.ds);
    }

    /// Whether crossings are located inside the step (DBSMC with a held control).
    pub(super) fn located(&self) -> bool {
        matches!(self.set.law, Law::Dbsmc(_))
    }

    pub(super) fn crossing_tol(&self) -> f64 {
        self.set.law.crossing_tol().unwrap_or(0.0)
    }

    /// Evaluate at the current point what the next step and an update need: `s`,
    /// and with located crossings, unless the model gives `Omega`'s rate in one pass,
    /// `J_Omega` and `beta` (the rate `s'` follows once `v` is known; an update
    /// evaluates `J_Omega` where it is not).
    pub(super) fn eval_point(&mut self, t: f64) {
        self.ctl.sliding(&self.model, t, &self.pt.x, &self.pt.z);
        self.eval_point_but_s(t, false);
    }

    /// [`Self::eval_point`] with `s` already evaluated there; with `update_likely`
    /// (a step cut at an event) `J_Omega` and `beta` even where the model gives
    /// `Omega`'s rate, since the update will need them.
    pub(super) fn eval_point_but_s(&mut self, t: f64, update_likely: bool) {
        let both = self.located() && (update_likely || !self.ctl.model_rate());
        if both {
            self.ctl
                .eval_jacobian(&self.model, t, &self.pt.x, &self.pt.z);
            self.ctl.eval_beta(&self.model, t, &self.pt.x, &self.pt.z);
        }
        self.fresh.jacobian = both;
        self.fresh.beta = both;
    }
}
