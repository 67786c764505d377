//! The DBSMC simulator: integration, update policies, reaching phase, statistics.

mod control;
mod robust;

use std::time::Instant;

use control::{Check, Controller, Switch};

use crate::error::Quantity;
use crate::solve::LinearSolver;
use crate::trace::{Layout, Sample, Sink};
use crate::{
    AlphaChoice, Integrator, Model, Policy, Reaching, Settings, SimError, SolverSummary, Summary,
};

/// Simulates a [`Model`] with DBSMC (or SPSM) under given [`Settings`].
///
/// All buffers are allocated by [`Simulator::new`]; [`Simulator::run`] allocates nothing
/// per step (the sink may, e.g. a growing [`Trace`](crate::Trace)).
pub struct Simulator<'a, M: Model + ?Sized> {
    model: &'a M,
    set: Settings,
    layout: Layout,
    ctl: Controller,
    t: f64,
    x: Vec<f64>,
    z: Vec<f64>,
    /// `z` and time at the last update: between updates `z = z_b + v (t - t_b)`.
    zb: Vec<f64>,
    tb: f64,
    v: Vec<f64>,
    xs: Vec<f64>,
    zs: Vec<f64>,
    k: [Vec<f64>; 4],
    kz: [Vec<f64>; 4],
    s_prev: Vec<f64>,
    z_eq: Vec<f64>,
    wres: Vec<f64>,
    /// Contracting layers: `eps_i,k`, `sgn(s_i,k)` and whether `|s_i,k| > eps_i`.
    eps_k: Vec<f64>,
    sgn_k: Vec<f64>,
    outside_k: Vec<bool>,
    stats: Stats,
}

#[derive(Default)]
struct Stats {
    steps: u64,
    updates: u64,
    reaching_updates: u64,
    last_update_step: u64,
    reaching_time: Option<f64>,
    stats_from: Option<f64>,
    last_window_update: Option<f64>,
    min_period: f64,
    period_sum: f64,
    periods: u64,
    max_s: Vec<f64>,
    max_w: Vec<f64>,
    violations: u64,
    rhs_evals: u64,
}

impl<'a, M: Model + ?Sized> Simulator<'a, M> {
    /// Prepare a simulator; checks the settings against the model.
    pub fn new(model: &'a M, settings: Settings) -> Result<Self, SimError> {
        let n = model.n_states();
        let m = model.n_constraints();
        settings.validate(n, m)?;
        let ctl = Controller::new(
            model,
            &settings.mu,
            &settings.gains,
            &settings.crossing_margin,
            &settings.eps,
            settings.alpha == AlphaChoice::Exact,
            settings.solver,
        )?;
        let layout = Layout {
            states: (0..n).map(|i| model.state_name(i).to_string()).collect(),
            algs: (0..m).map(|i| model.alg_name(i).to_string()).collect(),
            constraints: (0..m)
                .map(|i| model.constraint_name(i).to_string())
                .collect(),
        };
        let vn = || vec![0.0; n];
        let vm = || vec![0.0; m];
        Ok(Self {
            model,
            layout,
            ctl,
            t: settings.t_start,
            x: vn(),
            z: vm(),
            zb: vm(),
            tb: settings.t_start,
            v: vm(),
            xs: vn(),
            zs: vm(),
            k: [vn(), vn(), vn(), vn()],
            kz: [vm(), vm(), vm(), vm()],
            s_prev: vm(),
            z_eq: vm(),
            wres: vm(),
            eps_k: settings.eps.clone(),
            sgn_k: vm(),
            outside_k: vec![false; m],
            stats: Stats {
                max_s: vm(),
                max_w: vm(),
                ..Stats::default()
            },
            set: settings,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.set
    }
    /// Current (or final, or failure) time.
    pub fn time(&self) -> f64 {
        self.t
    }
    /// Current states.
    pub fn state(&self) -> &[f64] {
        &self.x
    }
    /// Current algebraic unknowns.
    pub fn alg(&self) -> &[f64] {
        &self.z
    }

    /// Run from the model's initial state and initial algebraic guess (or from
    /// [`Settings::initial`] when given) over
    /// `[t_start, t_end]`, sending samples and update times to `sink`.
    ///
    /// On error the sink keeps everything recorded before the failure.
    pub fn run<S: Sink + ?Sized>(&mut self, sink: &mut S) -> Result<Summary, SimError> {
        let clock = Instant::now();
        let m = self.z.len();
        self.stats = Stats {
            max_s: vec![0.0; m],
            max_w: vec![0.0; m],
            min_period: f64::INFINITY,
            ..Stats::default()
        };
        self.ctl.reset(&self.set.gains);
        let (t0, t_end, h) = (self.set.t_start, self.set.t_end, self.set.step);
        self.t = t0;
        match &self.set.initial {
            Some(init) => {
                self.x.copy_from_slice(&init.x0);
                self.z.copy_from_slice(&init.z0);
            }
            None => {
                self.model.initial_state(&mut self.x);
                self.model.initial_alg(&mut self.z);
            }
        }
        sink.begin(&self.layout)?;
        self.ctl.sliding(self.model, t0, &self.x, &self.z);
        self.check_finite()?;
        self.track_reaching()?;
        self.update(0, sink)?;
        self.record(0, false, sink)?;

        let steps = (((t_end - t0) / h) - 1e-9).ceil().max(1.0) as u64;
        let period_steps = match self.set.policy {
            Policy::Fixed(p) => ((p / h).round() as u64).max(1),
            _ => 1,
        };
        for k in 1..=steps {
            let t_new = if k == steps { t_end } else { t0 + k as f64 * h };
            let hk = t_new - self.t;
            self.s_prev.copy_from_slice(&self.ctl.s);
            match self.set.policy {
                Policy::Spsm => self.spsm_step(hk),
                _ => self.zoh_step(hk),
            }
            self.t = t_new;
            if self.set.policy != Policy::Spsm {
                // Exact ramp: avoids accumulating rounding over many steps.
                let dt = t_new - self.tb;
                for ((z, zb), v) in self.z.iter_mut().zip(&self.zb).zip(&self.v) {
                    *z = zb + v * dt;
                }
            }
            self.stats.steps = k;
            self.ctl.sliding(self.model, t_new, &self.x, &self.z);
            self.check_finite()?;
            self.track_reaching()?;
            let due = match self.set.policy {
                Policy::Spsm => true,
                Policy::Fixed(_) => k - self.stats.last_update_step >= period_steps,
                Policy::Monitor => self.monitor_trigger(),
            };
            if due {
                self.update(k, sink)?;
            }
            let last = k == steps;
            if last || sink.wants(k, t_new) {
                self.record(k, last, sink)?;
            }
        }
        sink.finish()?;
        Ok(self.summary(clock.elapsed().as_secs_f64()))
    }

    /// Whether the monitored update condition holds after the step just taken.
    fn monitor_trigger(&self) -> bool {
        let s = &self.ctl.s;
        let steady =
            self.stats.reaching_time.is_some() || self.set.reaching == Reaching::AttractingSurfaces;
        let eps = if steady { &self.set.eps } else { &self.eps_k };
        // s_i' is estimated by the finite difference over the step (s - s_prev) / h: it
        // is free (s is evaluated after every step anyway), exact in sign for the motion
        // over the step including the neglected beta part, and needs no extra model call.
        let outward =
            (0..s.len()).any(|i| s[i].abs() >= eps[i] && s[i] * (s[i] - self.s_prev[i]) > 0.0);
        if outward || steady {
            return outward;
        }
        (0..s.len()).any(|i| self.outside_k[i] && s[i] * self.sgn_k[i] <= 0.0)
    }

    /// Record the reaching time, enter the statistics window, enforce the reaching limit,
    /// and update the window maxima.
    fn track_reaching(&mut self) -> Result<(), SimError> {
        let t = self.t;
        let s = &self.ctl.s;
        if self.stats.reaching_time.is_none() {
            if s.iter().zip(&self.set.eps).all(|(s, e)| s.abs() <= *e) {
                self.stats.reaching_time = Some(t);
            } else if t - self.set.t_start > self.set.reaching_limit {
                let outside: Vec<usize> = (0..s.len())
                    .filter(|&i| s[i].abs() > self.set.eps[i])
                    .collect();
                return Err(SimError::ReachingTimeout {
                    limit: self.set.reaching_limit,
                    t,
                    names: outside
                        .iter()
                        .map(|&i| self.model.constraint_name(i).to_string())
                        .collect(),
                    s: outside.iter().map(|&i| s[i]).collect(),
                });
            }
        }
        if self.stats.stats_from.is_none()
            && self.stats.reaching_time.is_some()
            && t >= self.set.t_start + self.set.settle
        {
            self.stats.stats_from = Some(t);
        }
        if self.stats.stats_from.is_some() {
            let st = &mut self.stats;
            for (i, (ms, mw)) in st.max_s.iter_mut().zip(&mut st.max_w).enumerate() {
                *ms = ms.max(s[i].abs());
                *mw = mw.max(self.ctl.residual(i).abs());
            }
        }
        Ok(())
    }

    /// A control update at the current point (after `sliding` was evaluated there).
    fn update<S: Sink + ?Sized>(&mut self, step: u64, sink: &mut S) -> Result<(), SimError> {
        let t = self.t;
        self.ctl.factor(self.model, t, &self.x, &self.z)?;
        let switch = if self.set.policy == Policy::Spsm {
            Switch::Saturation
        } else {
            Switch::Sign
        };
        let in_window = self.stats.stats_from.is_some();
        let count = self.set.check_robustness && in_window;
        let check = Check {
            evaluate: count || self.set.raise_gains.is_some(),
            count,
            raise: self.set.raise_gains,
        };
        let violations = self
            .ctl
            .law(self.model, t, &self.x, &self.z, switch, check, &mut self.v);
        if let Some((i, &v)) = self.v.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(self.non_finite(Quantity::Control, i, v));
        }
        self.zb.copy_from_slice(&self.z);
        self.tb = t;
        let st = &mut self.stats;
        st.updates += 1;
        st.last_update_step = step;
        st.violations += violations;
        if st.reaching_time.is_none() {
            st.reaching_updates += 1;
            for (i, s) in self.ctl.s.iter().enumerate() {
                self.eps_k[i] = s.abs().max(self.set.eps[i]);
                self.sgn_k[i] = s.signum();
                self.outside_k[i] = s.abs() > self.set.eps[i];
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
        if self.set.policy != Policy::Spsm {
            sink.update(t)?;
        }
        Ok(())
    }

    fn record<S: Sink + ?Sized>(
        &mut self,
        step: u64,
        last: bool,
        sink: &mut S,
    ) -> Result<(), SimError> {
        self.ctl.z_eq(&self.z, &mut self.z_eq);
        for i in 0..self.wres.len() {
            self.wres[i] = self.ctl.residual(i);
        }
        sink.record(&Sample {
            step,
            t: self.t,
            x: &self.x,
            z: &self.z,
            z_eq: &self.z_eq,
            s: &self.ctl.s,
            w: &self.wres,
            last,
        })?;
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

    fn check_finite(&self) -> Result<(), SimError> {
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

    /// One step with `v` held: `x` by the chosen integrator, `z` along its ramp.
    fn zoh_step(&mut self, h: f64) {
        let (t, model) = (self.t, self.model);
        let [k1, k2, k3, k4] = &mut self.k;
        match self.set.integrator {
            Integrator::Euler => {
                model.rhs(t, &self.x, &self.z, k1);
                axpy_into(&mut self.x, h, k1);
                self.stats.rhs_evals += 1;
            }
            Integrator::Rk4 => {
                model.rhs(t, &self.x, &self.z, k1);
                set_axpy(&mut self.xs, &self.x, 0.5 * h, k1);
                set_axpy(&mut self.zs, &self.z, 0.5 * h, &self.v);
                model.rhs(t + 0.5 * h, &self.xs, &self.zs, k2);
                set_axpy(&mut self.xs, &self.x, 0.5 * h, k2);
                model.rhs(t + 0.5 * h, &self.xs, &self.zs, k3);
                set_axpy(&mut self.xs, &self.x, h, k3);
                set_axpy(&mut self.zs, &self.z, h, &self.v);
                model.rhs(t + h, &self.xs, &self.zs, k4);
                rk4_combine(&mut self.x, h, k1, k2, k3, k4);
                self.stats.rhs_evals += 4;
            }
        }
    }

    /// One SPSM step: `(x, z)` as an ODE with `v` recomputed at every stage. `self.v`
    /// holds the control at the step's start (computed after the previous step).
    fn spsm_step(&mut self, h: f64) {
        let (t, model) = (self.t, self.model);
        match self.set.integrator {
            Integrator::Euler => {
                let k1 = &mut self.k[0];
                model.rhs(t, &self.x, &self.z, k1);
                axpy_into(&mut self.x, h, k1);
                axpy_into(&mut self.z, h, &self.v);
                self.stats.rhs_evals += 1;
            }
            Integrator::Rk4 => {
                model.rhs(t, &self.x, &self.z, &mut self.k[0]);
                self.kz[0].copy_from_slice(&self.v);
                for (stage, c) in [(1, 0.5), (2, 0.5), (3, 1.0)] {
                    set_axpy(&mut self.xs, &self.x, c * h, &self.k[stage - 1]);
                    set_axpy(&mut self.zs, &self.z, c * h, &self.kz[stage - 1]);
                    let ts = t + c * h;
                    model.rhs(ts, &self.xs, &self.zs, &mut self.k[stage]);
                    self.ctl.sliding(model, ts, &self.xs, &self.zs);
                    // A singular J_s inside a step leaves v non-finite; it is reported at
                    // the end of the step as a non-finite z (with its name and time).
                    let ok = self.ctl.factor(model, ts, &self.xs, &self.zs).is_ok();
                    if ok {
                        self.ctl.law(
                            model,
                            ts,
                            &self.xs,
                            &self.zs,
                            Switch::Saturation,
                            Check::OFF,
                            &mut self.kz[stage],
                        );
                    } else {
                        self.kz[stage].fill(f64::NAN);
                    }
                }
                let [k1, k2, k3, k4] = &self.k;
                rk4_combine(&mut self.x, h, k1, k2, k3, k4);
                let [z1, z2, z3, z4] = &self.kz;
                rk4_combine(&mut self.z, h, z1, z2, z3, z4);
                self.stats.rhs_evals += 4;
                self.stats.updates += 3;
            }
        }
    }

    fn summary(&self, wall_time: f64) -> Summary {
        let st = &self.stats;
        let ss = self.ctl.solver.stats();
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
            updates: st.updates,
            reaching_updates: st.reaching_updates,
            reaching_time: st.reaching_time,
            stats_from: st.stats_from,
            min_period: (st.periods > 0).then_some(st.min_period),
            mean_period: (st.periods > 0).then(|| st.period_sum / st.periods as f64),
            max_abs_s: st.max_s.clone(),
            max_abs_w: st.max_w.clone(),
            robustness_violations: self.set.check_robustness.then_some(st.violations),
            rhs_evals: st.rhs_evals,
            sliding_evals: self.ctl.sliding_evals,
            jacobian_evals: self.ctl.jacobian_evals,
            beta_evals: self.ctl.beta_evals,
            wall_time,
            x: self.x.clone(),
            z: self.z.clone(),
            z_eq: self.z_eq.clone(),
        }
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
