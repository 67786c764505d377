//! A change of the model during a run that keeps the sliding variables continuous.

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
        let t = self.t;
        self.ctl.sliding(&self.model, t, &self.x, &self.z);
        self.ctl.omega(&mut self.omega_before);
        let out = change(&mut self.model);
        self.ctl.sliding(&self.model, t, &self.x, &self.z);
        self.ctl.eval_jacobian(&self.model, t, &self.x, &self.z);
        self.run.j_current = false;
        self.run.dirty = true;
        self.ctl
            .carry_omega(&self.model, t, &self.omega_before, &mut self.z)?;
        self.zb.copy_from_slice(&self.z);
        self.tb = t;
        self.va.fill(0.0);
        self.run.update_requested = true;
        Ok(out)
    }
}
