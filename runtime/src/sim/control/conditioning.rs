//! How near singular `J_s` came in a run: the least pivot of every factorisation
//! against its largest earlier value, and `|b| / |J_s^{-1} b|` for one fixed `b` against
//! its own (at the run's first factorisation, at every one of the dense LU, whose
//! partial pivoting can keep every pivot large, and where the step control gave up).
//! The run's smallest ratio is `Controller::min_pivot_ratio`, reported with the lost
//! layer or the step-size underflow when below [`NEAR_SINGULAR`](crate::summary::NEAR_SINGULAR).

use super::Controller;
use crate::Model;
use crate::solve::LinearSolver;

impl Controller {
    /// After a factorisation at `t`: its least pivot against the largest earlier, and
    /// for the dense LU also one solve (one `O(m^2)` substitution against the
    /// factorisation's `O(m^3)`, not counted as a solve); the first factorisation of the
    /// run sets the solve's reference.
    pub(super) fn watch_conditioning(&mut self, t: f64) {
        let Some((lo, _)) = self.solver.pivot_range() else {
            return;
        };
        self.pivot_max = self.pivot_max.max(lo);
        self.note_ratio(lo / self.pivot_max, t);
        if self.solve_max.is_none() {
            self.solve_max = Some(self.solve_measure());
            return;
        }
        if self
            .solver
            .substitute_if_pivots_can_hide(&self.probe_b, &mut self.probe)
        {
            let measure = measure_of(&self.probe_b, &self.probe);
            self.note_solve_measure(measure, t);
        }
    }

    /// Where the step control gave up: `J_Omega` at `(t, x, z)` factored, and the
    /// conditioning of `J_s` read from its pivots, as at an update, and from one solve:
    /// `|b|_1 / |J_s^{-1} b|_1` for a fixed `b` ([`Self::solve_measure`]) is at least the
    /// smallest singular value, and is compared with its own largest earlier value
    /// (`solve_max`). Partial pivoting can keep the pivots of a dense nearly singular
    /// `J_s` well above it (the taut far edge of `daec`'s cloth test with `--solver
    /// dense`, `cli/tests/family.rs`); the solve cannot hide it. Not for the iterations,
    /// which have no pivots. A `J_s` found singular counts as a ratio of 0.
    pub(crate) fn probe_singular<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
    ) {
        self.eval_jacobian(model, t, x, z);
        if self.factor_current(model, t).is_err() {
            self.min_pivot_ratio = Some((0.0, t));
            return;
        }
        // The dense LU's factorisation above read the solve already.
        if self.solve_max.is_some() && !self.solver.pivots_can_hide() {
            let measure = self.solve_measure();
            self.note_solve_measure(measure, t);
        }
    }

    /// A factorisation's conditioning at `t`, as a ratio to its own largest earlier
    /// value: the run's smallest is kept.
    fn note_ratio(&mut self, ratio: f64, t: f64) {
        let ratio = if ratio.is_nan() { 0.0 } else { ratio };
        if self.min_pivot_ratio.is_none_or(|(r, _)| ratio < r) {
            self.min_pivot_ratio = Some((ratio, t));
        }
    }

    /// [`Self::solve_measure`]'s value at `t`, against the largest seen before.
    fn note_solve_measure(&mut self, measure: f64, t: f64) {
        let Some(max) = self.solve_max.filter(|m| *m > 0.0) else {
            return;
        };
        if measure > max {
            self.solve_max = Some(measure);
        }
        self.note_ratio(measure / max, t);
    }

    /// `|b|_1 / |J_s^{-1} b|_1` with the current factorisation, for a fixed `b` of mixed
    /// signs and sizes (a few constants, not one pattern a null vector could be
    /// orthogonal to); 0 where the solve is not finite.
    fn solve_measure(&mut self) -> f64 {
        self.probe.copy_from_slice(&self.probe_b);
        self.solver.solve(&mut self.probe);
        measure_of(&self.probe_b, &self.probe)
    }
}

/// The fixed `b` of [`Controller::solve_measure`] for `m` constraints (a few constants of
/// mixed signs and sizes, not one pattern a null vector could be orthogonal to).
pub(super) fn probe_vector(m: usize) -> Vec<f64> {
    const SIGNS: [f64; 7] = [1.0, -0.7, 0.9, -1.3, 0.6, -1.1, 1.2];
    (0..m)
        .map(|i| SIGNS[i % 7] * (1.0 + 0.01 * (i % 11) as f64))
        .collect()
}

/// `|b|_1 / |x|_1` for the solution `x` of the probe `b`, 0 where it is not finite.
fn measure_of(b: &[f64], x: &[f64]) -> f64 {
    let nb: f64 = b.iter().map(|v| v.abs()).sum();
    let nx: f64 = x.iter().map(|v| v.abs()).sum();
    if nx.is_finite() && nx > 0.0 {
        nb / nx
    } else {
        0.0
    }
}
