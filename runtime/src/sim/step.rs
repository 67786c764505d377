//! One accepted step: the fixed-step grid or the error-controlled step, the crossing
//! located inside it (the step cut there where [`locate`](super::locate) finds the
//! event), and what the step measured.

use super::rk::{self, BOGACKI_SHAMPINE, DORMAND_PRINCE, Pair};
use super::{Check, Simulator, Switch};
use crate::error::Quantity;
use crate::settings::{Integrator, LAYER_ERROR_PER_STEP, Law, Update};
use crate::{Model, SimError};

/// How far past the crossing predicted from the current `s'` an error-controlled step
/// may reach (`s'` drifts within an interval, so the crossing lands somewhat before or
/// after the prediction).
const AIM_PAST_CROSSING: f64 = 1.3;
/// A step shorter than this fraction of the reference step makes almost no progress:
/// after [`SHORT_STEPS`] such steps in a row the next step is neither aimed nor cut.
/// Events of several variables a few `eps`-scaled moments apart make legitimate steps
/// this short (Andrews' mechanism at eps = 1e-10: 2e-10 s against a reference step of
/// 2e-3 s), hence the many in a row; a variable held on its layer by rounding (Zeno)
/// makes them shrink to nothing, which [`TINY_FRACTION`] catches at once.
const SHORT_FRACTION: f64 = 1e-6;
const SHORT_STEPS: u32 = 64;
/// A step shorter than this fraction of the reference step makes no progress but
/// rounding: after [`TINY_STEPS`] in a row the next step is neither aimed nor cut.
const TINY_FRACTION: f64 = 1e-12;
const TINY_STEPS: u32 = 2;
/// Retries of a fixed step shortened for its error in `s` (each at most a tenth of the
/// last): the estimate follows `h^4` (RK4) or `h^2` (Euler), so one or two suffice; the
/// rest guards a model whose `s` is not smooth.
const MAX_LAYER_RETRIES: usize = 6;
/// Consecutive non-finite trial steps of an embedded pair before the failure is
/// reported (a step too large can leave the model's domain where a smaller one would
/// not).
const MAX_NONFINITE_RETRIES: usize = 8;

/// The estimated error of a step in the sliding variables, `s` at the solution against
/// `s_hat` at the embedded one, as a multiple of [`LAYER_ERROR_PER_STEP`] `eps_i` (the
/// largest over `i`). A non-finite `s` is not judged here: the step is accepted and the
/// point's evaluation reports it, as without this test.
fn layer_error(s: &[f64], s_hat: &[f64], eps: &[f64]) -> f64 {
    let mut worst = 0.0f64;
    for ((a, b), e) in s.iter().zip(s_hat).zip(eps) {
        if !(a.is_finite() && b.is_finite()) {
            return 0.0;
        }
        worst = worst.max((a - b).abs() / (LAYER_ERROR_PER_STEP * e));
    }
    worst
}

impl<M: Model> Simulator<M> {
    /// Steps of the fixed-step grid from `run.origin` to `target` (the last one ends
    /// exactly at `target`).
    pub(super) fn grid_steps(&self, target: f64) -> u64 {
        let h = self.set.integration.step;
        (((target - self.run.origin) / h) - 1e-9).ceil().max(1.0) as u64
    }

    /// One accepted step towards `target`; leaves `s` (and with located crossings
    /// `J_Omega`, `beta` and `s'`) evaluated at the new point and the step's measures in
    /// `self.measure`.
    pub(super) fn step(&mut self, target: f64) -> Result<(), SimError> {
        if self.located() {
            self.s0.copy_from_slice(&self.ctl.s);
            self.ds0.copy_from_slice(&self.ds);
            // What ends the step for each variable, fixed until it is accepted (the
            // aim at the predicted crossing and the location both read it).
            for i in 0..self.watches.len() {
                self.watches[i] = self.watch(i);
            }
        } else {
            self.s_prev.copy_from_slice(&self.ctl.s);
        }
        self.scratch.x0.copy_from_slice(&self.pt.x);
        self.scratch.z0.copy_from_slice(&self.pt.z);
        let t0 = self.pt.t;
        if self.set.law == Law::Spsm {
            let t_new = self.grid_time();
            self.spsm_step(t_new - t0);
            self.pt.t = t_new;
            self.eval_point(t_new);
            self.measure_ends(t_new - t0);
        } else if self.set.integration.integrator.is_adaptive() {
            self.adaptive_step(target)?;
        } else {
            let mut t_new = self.grid_time();
            let monitored = self.located() && self.set.law.monitors();
            let aims = monitored && !self.stalled();
            let mut aim = if aims {
                t0 + AIM_PAST_CROSSING * self.predicted_crossing()
            } else {
                f64::INFINITY
            };
            if let (true, Some(h)) = (monitored, self.run.h_next) {
                aim = aim.min(t0 + h);
            }
            let mut off_grid = aim < t_new;
            if off_grid {
                // The user's step is the longest: a step aimed past the predicted
                // crossing is not wasted on motion after it, and its trial end stays
                // close enough for the cubic of s to find the crossing.
                t_new = aim;
            }
            self.first_stage();
            self.fixed_step(t_new - t0);
            let s_known = monitored && self.fixed_layer_error(t0, &mut t_new, &mut off_grid);
            self.pt.x.copy_from_slice(&self.rk.y1);
            self.pt.t = t_new;
            self.ramp_z();
            if s_known {
                self.eval_point_but_s(t_new, false);
            } else {
                self.eval_point(t_new);
            }
            if self.located() {
                self.rate_at(self.pt.t);
                self.locate(t0);
                if self.rk.f1_known {
                    // The Hermite output needed f at the end: the next first stage.
                    self.pt.f_cur.copy_from_slice(&self.rk.f1);
                    self.fresh.f = true;
                }
            } else {
                self.measure_ends(t_new - t0);
            }
            if off_grid && self.run.origin != self.pt.t {
                self.restart_grid();
            }
        }
        self.measure.h = self.pt.t - t0;
        self.stats.steps += 1;
        // Progress guard: aimed and cut steps shrink without bound when a variable sits
        // on its watch level with a rate lost in rounding (Zeno); after two steps
        // shorter than 1e-12 of the reference step, or 64 shorter than a millionth of
        // it, the next is taken whole.
        let (h, reference) = (self.pt.t - t0, self.reference_step());
        let count = |n: &mut u32, short: bool| *n = if short { *n + 1 } else { 0 };
        count(&mut self.run.short_steps, h < SHORT_FRACTION * reference);
        count(&mut self.run.tiny_steps, h < TINY_FRACTION * reference);
        Ok(())
    }

    /// Start the fixed grid again at the current time (after a cut or an aimed step).
    fn restart_grid(&mut self) {
        self.run.origin = self.pt.t;
        self.run.k = 0;
        self.run.n = self.grid_steps(self.run.grid_target);
    }

    /// The end of the next step on the fixed grid.
    fn grid_time(&mut self) -> f64 {
        self.run.k += 1;
        if self.run.k >= self.run.n {
            self.run.grid_target
        } else {
            self.run.origin + self.run.k as f64 * self.set.integration.step
        }
    }

    /// `z` on its exact ramp at the current time (avoids accumulating rounding).
    fn ramp_z(&mut self) {
        ramp_from(
            &mut self.pt.z,
            &self.pt.zb,
            &self.pt.v,
            &self.pt.va,
            self.pt.t - self.pt.tb,
        );
    }

    /// The error in `s` of the trial step that ends at `t1` with the solution `rk.y1`,
    /// against the embedded solution in `xs` ([`layer_error`]), both with `z` on its
    /// ramp at `t1` (in `z_trial`, as the accepted point will have it). The solution is
    /// evaluated last, so that everything `sliding` leaves (`s`, `w`, `alpha_hat`) is
    /// the point's own when the step is accepted.
    fn trial_layer_error(&mut self, t1: f64) -> f64 {
        let model = &self.model;
        self.ctl
            .sliding(model, t1, &self.scratch.xs, &self.scratch.z_trial);
        self.scratch.s_embedded.copy_from_slice(&self.ctl.s);
        self.ctl
            .sliding(model, t1, &self.rk.y1, &self.scratch.z_trial);
        layer_error(&self.ctl.s, &self.scratch.s_embedded, &self.set.layers.eps)
    }

    /// Without located crossings (or under SPSM), a step's measure is its end.
    fn measure_ends(&mut self, h: f64) {
        for i in 0..self.s0.len() {
            let a = self.ctl.s[i].abs();
            self.measure.max_s[i] = a;
            // A NaN counts as beyond.
            let within = a <= (1.0 + self.set.bound_tol) * self.set.layers.eps[i];
            let beyond = !within;
            self.measure.time_beyond[i] = if beyond { h } else { 0.0 };
        }
    }

    /// `f(t, x, z)` at the current point (the step's start) into `rk.k[0]`, reusing a
    /// known one.
    fn first_stage(&mut self) {
        if self.fresh.f {
            self.rk.k[0].copy_from_slice(&self.pt.f_cur);
        } else {
            self.model
                .rhs(self.pt.t, &self.pt.x, &self.pt.z, &mut self.rk.k[0]);
            self.stats.rhs_evals += 1;
        }
        self.fresh.f = false;
    }

    /// One fixed step of Euler or RK4 from `(t, x0, z0)` over `h` into `rk.y1`, with
    /// `rk.k[0] = f(t, x0, z0)` given and `z` on the ramp `z0 + c h v` in the stages.
    fn fixed_step(&mut self, h: f64) {
        let t = self.pt.t;
        self.v_at(t);
        let (x, z, v, va) = (
            &self.scratch.x0,
            &self.scratch.z0,
            &self.pt.v_now,
            &self.pt.va,
        );
        let model = &self.model;
        let rk = &mut self.rk;
        match self.set.integration.integrator {
            Integrator::Euler => {
                for ((y, x), k) in rk.y1.iter_mut().zip(x).zip(&rk.k[0]) {
                    *y = x + h * k;
                }
            }
            _ => {
                let (xs, zs) = (&mut self.scratch.xs, &mut self.scratch.zs);
                set_axpy(xs, x, 0.5 * h, &rk.k[0]);
                ramp_from(zs, z, v, va, 0.5 * h);
                model.rhs(t + 0.5 * h, xs, zs, &mut rk.k[1]);
                set_axpy(xs, x, 0.5 * h, &rk.k[1]);
                model.rhs(t + 0.5 * h, xs, zs, &mut rk.k[2]);
                set_axpy(xs, x, h, &rk.k[2]);
                ramp_from(zs, z, v, va, h);
                model.rhs(t + h, xs, zs, &mut rk.k[3]);
                let c = h / 6.0;
                let k = &rk.k;
                for i in 0..x.len() {
                    rk.y1[i] = x[i] + c * (k[0][i] + 2.0 * (k[1][i] + k[2][i]) + k[3][i]);
                }
                self.stats.rhs_evals += 3;
            }
        }
        self.rk.fixed_done(&self.scratch.x0, h);
    }

    /// The error control of a fixed step (Euler or RK4, monitored with located
    /// crossings) on its error in `s`: the step just taken from `t0` to `t_new` is
    /// retried shorter while its estimated error in some `s_i` is above
    /// [`LAYER_ERROR_PER_STEP`] `eps_i`, and the next step's limit is set from the
    /// error (at most the user's step). The estimate compares the solution with an
    /// embedded one of one order less built from `f` at the step's end (Heun for Euler;
    /// for RK4 the fourth stage taken at the solution, `x_hat = x + h (f(x) - k_4) / 6`),
    /// which is the next step's first stage, so an accepted step costs no extra `f`.
    /// Leaves `s` (with `w` and `alpha_hat`) evaluated at the end and `f` there in
    /// `rk.f1`; returns whether they are (not when the step is not finite).
    fn fixed_layer_error(&mut self, t0: f64, t_new: &mut f64, off_grid: &mut bool) -> bool {
        // `x_hat = x + h (f(x) - k_last) / d`; the estimate is of order h^2 (Euler) or
        // h^4 (RK4).
        let (order, last, d) = match self.set.integration.integrator {
            Integrator::Euler => (2.0, 0, 2.0),
            _ => (4.0, 3, 6.0),
        };
        let user_step = self.set.integration.step;
        for attempt in 0..=MAX_LAYER_RETRIES {
            let h = *t_new - t0;
            if self.rk.y1.iter().any(|y| !y.is_finite()) {
                return false;
            }
            ramp_from(
                &mut self.scratch.z_trial,
                &self.pt.zb,
                &self.pt.v,
                &self.pt.va,
                *t_new - self.pt.tb,
            );
            let rk = &mut self.rk;
            self.model
                .rhs(*t_new, &rk.y1, &self.scratch.z_trial, &mut rk.f1);
            rk.f1_known = true;
            self.stats.rhs_evals += 1;
            for ((xh, y), (f1, k)) in self
                .scratch
                .xs
                .iter_mut()
                .zip(&rk.y1)
                .zip(rk.f1.iter().zip(&rk.k[last]))
            {
                *xh = y + h / d * (f1 - k);
            }
            let err = self.trial_layer_error(*t_new);
            let factor = |err: f64| 0.9 * err.max(1e-12).powf(-1.0 / order);
            let resolvable = h > 16.0 * f64::EPSILON * t0.abs().max(1.0);
            if err <= 1.0 || attempt == MAX_LAYER_RETRIES || !resolvable {
                // The user's step stands until it fails the test; from then on the
                // limit follows the error until it grows back to the user's step.
                if attempt > 0 || self.run.h_next.is_some() {
                    let next = h * factor(err).min(4.0);
                    self.run.h_next = (next < user_step).then_some(next);
                }
                return true;
            }
            self.stats.rejected += 1;
            *t_new = t0 + h * factor(err).clamp(0.1, 0.9);
            *off_grid = true;
            // rk.k[0] still holds f at the step's start.
            self.fixed_step(*t_new - t0);
        }
        unreachable!("the last attempt returns")
    }

    /// The end derivative of the last fixed step (for its Hermite dense output) at the
    /// current point, its end.
    fn fixed_end_derivative(&mut self) {
        if self.rk.f1_known {
            return;
        }
        self.model
            .rhs(self.pt.t, &self.pt.x, &self.pt.z, &mut self.rk.f1);
        self.stats.rhs_evals += 1;
        self.rk.f1_known = true;
    }

    fn pair(&self) -> &'static Pair {
        match self.set.integration.integrator {
            Integrator::BogackiShampine => &BOGACKI_SHAMPINE,
            _ => &DORMAND_PRINCE,
        }
    }

    /// One error-controlled step towards `target` (and the next fixed-period update),
    /// with the crossing located inside it.
    fn adaptive_step(&mut self, target: f64) -> Result<(), SimError> {
        let pair = self.pair();
        let tol = self.set.effective_tolerance();
        let tol = (tol.rtol, tol.atol);
        let t0 = self.pt.t;
        self.first_stage();
        self.v_at(t0);
        let mut end = target;
        if let Some(Update::Fixed { period: p }) = self.set.law.update() {
            end = end.min(self.pt.tb + p);
        }
        let remaining = end - t0;
        let mut h_max = self.set.integration.max_step.min(remaining);
        if self.located() && self.set.law.monitors() && !self.stalled() {
            // Aim a little beyond the next crossing that s' predicts, so that the cut
            // falls near the step's end: the dense output there is as accurate as the
            // step itself, and one step usually spans a control interval.
            h_max = h_max.min(AIM_PAST_CROSSING * self.predicted_crossing());
        }
        let mut h = match self.run.h_next {
            Some(h) => h,
            None => {
                self.stats.rhs_evals += 1;
                let (ys, fs) = (&mut self.scratch.xs, &mut self.pt.f_cur);
                let mut rhs = ramp_rhs(
                    &self.model,
                    t0,
                    &self.scratch.z0,
                    &self.pt.v_now,
                    &self.pt.va,
                    &mut self.scratch.zs,
                );
                rk::initial_step(
                    pair,
                    &self.scratch.x0,
                    &self.rk.k[0],
                    tol,
                    h_max,
                    ys,
                    fs,
                    &mut rhs,
                )
            }
        };
        let mut rejected_before = false;
        let mut nonfinite = 0;
        let mut last_nonfinite = None;
        let outcome = loop {
            h = h.min(h_max);
            // No sliver of a step before the end of the piece.
            if remaining - h <= 0.01 * h {
                h = remaining;
            }
            let resolvable = h > 16.0 * f64::EPSILON * t0.abs().max(1.0);
            if !resolvable {
                // A step shrunk to nothing by non-finite trials is a value that left its
                // domain (or overflowed): say which.
                break Err(match last_nonfinite {
                    Some((i, value)) => SimError::NonFinite {
                        kind: Quantity::State,
                        index: i,
                        name: self.model.state_name(i).to_string(),
                        value,
                        t: t0,
                    },
                    None => SimError::StepUnderflow {
                        t: t0,
                        h,
                        near_singular: self.near_singular_at_failure(t0),
                    },
                });
            }
            // The trial's end as the accepted point will have it (`ramp_z`), so that
            // `s` there, evaluated for the test below, is the point's own.
            let t1 = if h >= remaining { end } else { t0 + h };
            let mut err = self.rk.embedded(
                pair,
                &self.scratch.x0,
                h,
                tol,
                &mut ramp_rhs(
                    &self.model,
                    t0,
                    &self.scratch.z0,
                    &self.pt.v_now,
                    &self.pt.va,
                    &mut self.scratch.zs,
                ),
            );
            self.stats.rhs_evals += pair.stages() as u64 - 1;
            if let Some(i) = self.rk.y1.iter().position(|y| !y.is_finite()) {
                nonfinite += 1;
                last_nonfinite = Some((i, self.rk.y1[i]));
                if nonfinite > MAX_NONFINITE_RETRIES {
                    break Err(SimError::NonFinite {
                        kind: Quantity::State,
                        index: i,
                        name: self.model.state_name(i).to_string(),
                        value: self.rk.y1[i],
                        t: t0 + h,
                    });
                }
            } else {
                if err <= 1.0 {
                    // The state's error is within the tolerance; so must be the error it
                    // makes in each `s_i` (which weighs the states by `mu` and the
                    // model's derivatives: on the pendulum with long steps, ten times
                    // the state's).
                    for ((xh, y), e) in self
                        .scratch
                        .xs
                        .iter_mut()
                        .zip(&self.rk.y1)
                        .zip(&self.rk.err)
                    {
                        *xh = y - e;
                    }
                    ramp_from(
                        &mut self.scratch.z_trial,
                        &self.pt.zb,
                        &self.pt.v,
                        &self.pt.va,
                        t1 - self.pt.tb,
                    );
                    err = err.max(self.trial_layer_error(t1));
                }
                if err <= 1.0 {
                    break Ok(err);
                }
            }
            self.stats.rejected += 1;
            h *= if nonfinite > 0 {
                0.2
            } else {
                rk::step_factor(pair, err, true)
            };
            rejected_before = true;
            if let Some(limit) = self.set.integration.max_steps {
                if self.stats.steps + self.stats.rejected >= limit {
                    break Err(SimError::StepLimit { limit, t: t0 });
                }
            }
        };
        let err = match outcome {
            Ok(err) => err,
            Err(e) => {
                // The trials' tests of `s` evaluated it elsewhere: back to the point.
                self.pt.t = t0;
                self.ctl.sliding(&self.model, t0, &self.pt.x, &self.pt.z);
                return Err(e);
            }
        };
        self.run.h_next = Some(h * rk::step_factor(pair, err, rejected_before));
        self.pt.x.copy_from_slice(&self.rk.y1);
        self.pt.t = if h >= remaining { end } else { t0 + h };
        self.ramp_z();
        // `s` at the point was evaluated last by the step's test (every accepted step
        // ends with one).
        self.eval_point_but_s(self.pt.t, false);
        // FSAL: the last stage is f at the new point.
        self.pt.f_cur.copy_from_slice(&self.rk.k[pair.stages() - 1]);
        self.fresh.f = true;
        if self.located() {
            self.rate_at(self.pt.t);
            self.locate(t0);
        } else {
            self.measure_ends(self.pt.t - t0);
        }
        Ok(())
    }

    /// Time until the first sliding variable reaches its watched level if its rate
    /// stayed as it is now (infinite if none moves towards one).
    fn predicted_crossing(&self) -> f64 {
        let mut t = f64::INFINITY;
        for (i, w) in self.watches.iter().enumerate() {
            let level = w.level;
            let (s, ds) = (self.s0[i], self.ds0[i]);
            let dist = if ds > 0.0 { level - s } else { level + s };
            if dist > 0.0 && ds != 0.0 {
                t = t.min(dist / ds.abs());
            }
        }
        t
    }

    /// The step against which progress is judged: the fixed step, or for the embedded
    /// pairs the largest step allowed, at most the control's shortest time constant
    /// `mu_i` (and the run's span). Not the span alone: on a 1000 s run a millionth of
    /// it is 1 ms, the length of an ordinary step between updates, and the guard then
    /// took steps whole (uncut) that the control needed cut, and the layer was lost.
    fn reference_step(&self) -> f64 {
        if self.set.integration.integrator.is_adaptive() {
            self.set
                .integration
                .max_step
                .min(self.set.window.t_end - self.set.window.t_start)
                .min(self.mu_min)
        } else {
            self.set.integration.step
        }
    }

    /// Where `J_s` came near singular ([`Self::near_singular`]), read once more at the
    /// point where the step control gave up (`t`, the current state; the run ends
    /// there): the last update can precede the configuration that stopped the run (a
    /// taut edge reached between two updates), and partial pivoting can hide it from
    /// the pivots ([`Controller::probe_singular`](super::control::Controller::probe_singular)).
    fn near_singular_at_failure(&mut self, t: f64) -> Option<crate::summary::NearSingular> {
        if self.near_singular().is_none() {
            self.ctl
                .probe_singular(&self.model, t, &self.pt.x, &self.pt.z);
        }
        self.near_singular()
    }

    /// Whether the last steps stalled (see the progress guard in [`Self::step`]).
    pub(super) fn stalled(&self) -> bool {
        self.run.short_steps >= SHORT_STEPS || self.run.tiny_steps >= TINY_STEPS
    }

    /// The true `s_i` at `t0 + theta h` along the dense output of `x` (which starts at
    /// `t0`, the step's start) with `z` on its ramp.
    pub(super) fn s_along(&mut self, t0: f64, h: f64, theta: f64, i: usize) -> f64 {
        let tau = t0 + theta * h;
        if !self.set.integration.integrator.is_adaptive() {
            self.fixed_end_derivative();
        }
        let th = ((tau - t0) / self.rk.step_length()).clamp(0.0, 1.0);
        self.rk.dense(th, &mut self.scratch.xs);
        ramp_from(
            &mut self.scratch.zs,
            &self.pt.zb,
            &self.pt.v,
            &self.pt.va,
            tau - self.pt.tb,
        );
        self.ctl
            .sliding(&self.model, tau, &self.scratch.xs, &self.scratch.zs);
        self.ctl.s[i]
    }

    /// Shorten the current step from `t0` to `t_cut`: the dense output (embedded
    /// pairs) or a new step (fixed-step integrators), then the end point evaluated.
    pub(super) fn cut(&mut self, t0: f64, t_cut: f64) {
        if self.set.integration.integrator.is_adaptive() {
            let th = (t_cut - t0) / self.rk.step_length();
            self.rk.dense(th, &mut self.pt.x);
            self.fresh.f = false;
        } else {
            // rk.k[0] still holds f at the step's start.
            self.pt.t = t0;
            self.fixed_step(t_cut - t0);
            self.pt.x.copy_from_slice(&self.rk.y1);
            self.pt.t = t_cut;
            self.restart_grid();
        }
        self.pt.t = t_cut;
        self.ramp_z();
        self.ctl.sliding(&self.model, t_cut, &self.pt.x, &self.pt.z);
        self.eval_point_but_s(t_cut, true);
        self.rate_at(t_cut);
    }

    /// One SPSM step: `(x, z)` as an ODE with `v` recomputed at every stage. `self.pt.v`
    /// holds the control at the step's start (computed after the previous step).
    fn spsm_step(&mut self, h: f64) {
        let (t, model) = (self.pt.t, &self.model);
        let k = &mut self.rk.k;
        match self.set.integration.integrator {
            Integrator::Euler => {
                model.rhs(t, &self.pt.x, &self.pt.z, &mut k[0]);
                axpy_into(&mut self.pt.x, h, &k[0]);
                axpy_into(&mut self.pt.z, h, &self.pt.v);
                self.stats.rhs_evals += 1;
            }
            _ => {
                model.rhs(t, &self.pt.x, &self.pt.z, &mut k[0]);
                self.scratch.kz[0].copy_from_slice(&self.pt.v);
                for (stage, c) in [(1, 0.5), (2, 0.5), (3, 1.0)] {
                    set_axpy(&mut self.scratch.xs, &self.pt.x, c * h, &k[stage - 1]);
                    set_axpy(
                        &mut self.scratch.zs,
                        &self.pt.z,
                        c * h,
                        &self.scratch.kz[stage - 1],
                    );
                    let ts = t + c * h;
                    model.rhs(ts, &self.scratch.xs, &self.scratch.zs, &mut k[stage]);
                    self.ctl
                        .sliding(model, ts, &self.scratch.xs, &self.scratch.zs);
                    // A singular J_s inside a step leaves v non-finite; it is reported at
                    // the end of the step as a non-finite z (with its name and time).
                    let ok = self
                        .ctl
                        .factor(model, ts, &self.scratch.xs, &self.scratch.zs)
                        .is_ok();
                    if ok {
                        self.ctl.law(
                            model,
                            ts,
                            &self.scratch.xs,
                            &self.scratch.zs,
                            Switch::Saturation,
                            Check::OFF,
                            &mut self.scratch.kz[stage],
                        );
                    } else {
                        self.scratch.kz[stage].fill(f64::NAN);
                    }
                }
                rk4_combine(&mut self.pt.x, h, &k[0], &k[1], &k[2], &k[3]);
                let [z1, z2, z3, z4] = &self.scratch.kz;
                rk4_combine(&mut self.pt.z, h, z1, z2, z3, z4);
                self.stats.rhs_evals += 4;
                self.stats.updates += 3;
            }
        }
    }
}

/// `f` along a step from `t0` as the embedded pairs call it, with the time `dt` into
/// the step and `z` on its ramp `z0 + dt (v0 + va dt / 2)` from the step's start (`v0`:
/// `v` at `t0`; evaluated into `zs`).
fn ramp_rhs<'a, M: Model>(
    model: &'a M,
    t0: f64,
    z0: &'a [f64],
    v0: &'a [f64],
    va: &'a [f64],
    zs: &'a mut [f64],
) -> impl FnMut(f64, &[f64], &mut [f64]) + 'a {
    move |dt, y, dy| {
        ramp_from(zs, z0, v0, va, dt);
        model.rhs(t0 + dt, y, zs, dy);
    }
}

/// `z = z0 + dt (v0 + va dt / 2)`: the ramp of `z`, `dt` after a point where it was
/// `z0` and `v` was `v0` (from the last update: `z_b`, `v`; with `va = 0`, `z0 + dt
/// v0` to the last bit).
fn ramp_from(z: &mut [f64], z0: &[f64], v0: &[f64], va: &[f64], dt: f64) {
    for (((z, z0), v), a) in z.iter_mut().zip(z0).zip(v0).zip(va) {
        *z = z0 + dt * (v + 0.5 * a * dt);
    }
}

fn axpy_into(y: &mut [f64], a: f64, x: &[f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += a * x;
    }
}

fn set_axpy(out: &mut [f64], y: &[f64], a: f64, x: &[f64]) {
    for ((o, y), x) in out.iter_mut().zip(y).zip(x) {
        *o = y + a * x;
    }
}

fn rk4_combine(y: &mut [f64], h: f64, k1: &[f64], k2: &[f64], k3: &[f64], k4: &[f64]) {
    let c = h / 6.0;
    for i in 0..y.len() {
        y[i] += c * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
    }
}
