//! Baseline (a): solve for `z` at every RK4 stage so that `s(x, z) = 0` exactly.
//!
//! `s_i = sum_{j<r_i} C(r_i-1, j) mu_i^j w_i^(j)`, so `s = 0` means
//! `Omega_i(x, z) = -(sum_{j<r_i-1} C(r_i-1, j) mu_i^j w_i^(j)) / mu_i^(r_i-1)`: the
//! index-1 reduction with Baumgarte-like stabilisation (all poles at `-1/mu_i`). `z` is
//! found by Newton's method on `s(x, z) = 0` with `J_s = diag(mu^(r-1)) J_Omega`
//! (from [`Model::jacobian`]), warm-started from the previous stage; one iteration is
//! exact when `Omega` is affine in `z` (mechanical models with forces as unknowns).

use std::time::Instant;

use dae_runtime::{
    Model, model::w_offsets, settings::Initial, solve::LinearSolver, solve::SolveError,
    solve::Solver, solve::SolverChoice,
};

/// A callback `observe(t, x, w)` after each step: time, states, constraint residuals.
pub type Observer<'a> = &'a mut dyn FnMut(f64, &[f64], &[f64]);

/// Errors of the index-1 baselines.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaselineError {
    /// `J_s` could not be factored (the runtime's solver seam says why, naming the
    /// dependent constraints of a singular `J_s`).
    #[error("J_s at t = {t}: {reason}")]
    Singular {
        /// Time.
        t: f64,
        /// The solver's error.
        reason: SolveError,
    },
    /// Newton did not bring `max |s|` under the tolerance.
    #[error("Newton on s(x, z) = 0 did not converge at t = {t}: max |s| = {max_s}")]
    NoConvergence {
        /// Time.
        t: f64,
        /// Remaining `max |s_i|`.
        max_s: f64,
    },
    /// A state, unknown or residual became NaN or infinite.
    #[error("non-finite value at t = {t}")]
    NonFinite {
        /// Time.
        t: f64,
    },
    /// Bad settings.
    #[error("invalid settings: {0}")]
    Settings(String),
}

/// Newton solver for `s(t, x, z) = 0` in `z`, with its own buffers and counters.
#[derive(Debug, Clone)]
pub struct ZSolver {
    mu: Vec<f64>,
    mu_pow: Vec<f64>,
    offs: Vec<usize>,
    jvals: Vec<f64>,
    w: Vec<f64>,
    s: Vec<f64>,
    ah: Vec<f64>,
    dz: Vec<f64>,
    solver: Solver,
    /// Absolute tolerance on `max |s_i|`.
    pub tol: f64,
    /// Maximum Newton iterations per solve.
    pub max_iter: usize,
    /// Evaluations of [`Model::sliding`].
    pub sliding_evals: u64,
    /// Factorisations of `J_s` followed by one solve each (= Jacobian evaluations).
    pub j_solves: u64,
}

impl ZSolver {
    /// A solver for `model` with time constants `mu` (one per constraint).
    pub fn new<M: Model + ?Sized>(model: &M, mu: &[f64], tol: f64) -> Result<Self, BaselineError> {
        let m = model.n_constraints();
        let r = model.indices();
        if mu.len() != m
            || r.len() != m
            || r.contains(&0)
            || mu.iter().any(|v| v.is_nan() || *v <= 0.0)
        {
            return Err(BaselineError::Settings(format!(
                "need {m} mu > 0 and indices >= 1, got mu {mu:?}, indices {r:?}"
            )));
        }
        let offs = w_offsets(r);
        let pattern = model.jacobian_pattern();
        let solver = Solver::new(m, pattern, SolverChoice::Auto)
            .map_err(|e| BaselineError::Settings(format!("jacobian pattern: {e}")))?;
        Ok(Self {
            mu_pow: r
                .iter()
                .zip(mu)
                .map(|(&ri, &mi)| mi.powi(ri as i32 - 1))
                .collect(),
            mu: mu.to_vec(),
            w: vec![0.0; offs[m]],
            offs,
            jvals: vec![0.0; pattern.len()],
            s: vec![0.0; m],
            ah: vec![0.0; m],
            dz: vec![0.0; m],
            solver,
            tol,
            max_iter: 20,
            sliding_evals: 0,
            j_solves: 0,
        })
    }

    /// Solve `s(t, x, z) = 0` for `z` in place, starting from the given `z`. Returns the
    /// number of Newton iterations. Afterwards [`ZSolver::residual`] and
    /// [`ZSolver::sliding`] hold the values at the returned `z`.
    pub fn solve<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &mut [f64],
    ) -> Result<usize, BaselineError> {
        let mut iter = 0;
        let mut prev = f64::INFINITY;
        loop {
            model.sliding(t, x, z, &self.mu, &mut self.w, &mut self.s, &mut self.ah);
            self.sliding_evals += 1;
            let max_s = self.s.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if !max_s.is_finite() {
                return Err(BaselineError::NonFinite { t });
            }
            // Converged, or stagnating after at least two iterations: Newton converges
            // quadratically (in one step for affine Omega), so an iteration that does
            // not halve |s| means it is at the round-off floor of s, which scales with
            // mu^(r-1) |Omega| and the conditioning of J_s and can lie above `tol`.
            if max_s <= self.tol || (iter >= 2 && max_s > 0.5 * prev) {
                return Ok(iter);
            }
            prev = max_s;
            if iter == self.max_iter {
                return Err(BaselineError::NoConvergence { t, max_s });
            }
            model.jacobian(t, x, z, &mut self.jvals);
            self.solver
                .factor(&self.jvals, &self.mu_pow)
                .map_err(|reason| BaselineError::Singular { t, reason })?;
            self.dz.copy_from_slice(&self.s);
            self.solver.solve(&mut self.dz);
            self.j_solves += 1;
            let mut small = true;
            for (zi, d) in z.iter_mut().zip(&self.dz) {
                small &= d.abs() <= 4.0 * f64::EPSILON * (1.0 + zi.abs());
                *zi -= d;
            }
            if small {
                // Converged to round-off in z while |s| is still above `tol`: the
                // tolerance is below what s can resolve; accept with current values.
                model.sliding(t, x, z, &self.mu, &mut self.w, &mut self.s, &mut self.ah);
                self.sliding_evals += 1;
                return Ok(iter + 1);
            }
            iter += 1;
        }
    }

    /// Residual `w_i` at the last evaluation.
    pub fn residual(&self, i: usize) -> f64 {
        self.w[self.offs[i]]
    }

    /// Sliding variables at the last evaluation.
    pub fn sliding(&self) -> &[f64] {
        &self.s
    }
}

/// Settings of [`IndexOneRk4`].
#[derive(Debug, Clone, PartialEq)]
pub struct IndexOneSettings {
    /// Time constants `mu_i` of the stabilisation (poles at `-1/mu_i`).
    pub mu: Vec<f64>,
    /// Fixed RK4 step.
    pub step: f64,
    /// Start time.
    pub t_start: f64,
    /// End time.
    pub t_end: f64,
    /// Newton tolerance on `max |s_i|`.
    pub newton_tol: f64,
    /// Start here instead of the model's initial state and guess (as the runtime's
    /// [`Settings::initial`](dae_runtime::Settings::initial)).
    pub initial: Option<Initial>,
}

/// What a run of [`IndexOneRk4`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct IndexOneSummary {
    /// Steps taken.
    pub steps: u64,
    /// Evaluations of `f`.
    pub rhs_evals: u64,
    /// Evaluations of [`Model::sliding`].
    pub sliding_evals: u64,
    /// `J_s` factorisations and solves (Newton iterations).
    pub j_solves: u64,
    /// Largest `|w_i|` at the step ends.
    pub max_abs_w: Vec<f64>,
    /// Largest `|s_i|` left by the stage solves.
    pub max_abs_s: Vec<f64>,
    /// Final time.
    pub t_end: f64,
    /// Final states.
    pub x: Vec<f64>,
    /// Final algebraic unknowns.
    pub z: Vec<f64>,
    /// Wall-clock seconds.
    pub wall_time: f64,
}

/// Baseline (a): classical RK4 on `x' = f(t, x, z(t, x))` with `z` from `s = 0` at
/// every stage.
#[derive(Debug)]
pub struct IndexOneRk4<'a, M: Model + ?Sized> {
    model: &'a M,
    set: IndexOneSettings,
    zs: ZSolver,
    t: f64,
    x: Vec<f64>,
    z: Vec<f64>,
    xs: Vec<f64>,
    k: [Vec<f64>; 4],
    rhs_evals: u64,
    max_w: Vec<f64>,
    max_s: Vec<f64>,
}

impl<'a, M: Model + ?Sized> IndexOneRk4<'a, M> {
    /// Prepare a run; the state starts at the model's initial state and guess.
    pub fn new(model: &'a M, settings: IndexOneSettings) -> Result<Self, BaselineError> {
        let (n, m) = (model.n_states(), model.n_constraints());
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(settings.step) || !positive(settings.t_end - settings.t_start) {
            return Err(BaselineError::Settings(format!(
                "step {} must be > 0 and [{}, {}] non-empty",
                settings.step, settings.t_start, settings.t_end
            )));
        }
        let zs = ZSolver::new(model, &settings.mu, settings.newton_tol)?;
        let mut x = vec![0.0; n];
        let mut z = vec![0.0; m];
        start(model, settings.initial.as_ref(), &mut x, &mut z)?;
        Ok(Self {
            model,
            t: settings.t_start,
            set: settings,
            zs,
            xs: vec![0.0; n],
            k: [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            x,
            z,
            rhs_evals: 0,
            max_w: vec![0.0; m],
            max_s: vec![0.0; m],
        })
    }

    /// Current time.
    pub fn time(&self) -> f64 {
        self.t
    }
    /// Current states.
    pub fn state(&self) -> &[f64] {
        &self.x
    }
    /// Current algebraic unknowns (from the last stage solve).
    pub fn alg(&self) -> &[f64] {
        &self.z
    }

    /// Evaluate `f` at a stage with `z` solved there; the result goes to `k[stage]`.
    fn stage(&mut self, stage: usize, t: f64, use_xs: bool) -> Result<(), BaselineError> {
        let x = if use_xs { &self.xs } else { &self.x };
        self.zs.solve(self.model, t, x, &mut self.z)?;
        for (m, s) in self.max_s.iter_mut().zip(self.zs.sliding()) {
            *m = m.max(s.abs());
        }
        self.model.rhs(t, x, &self.z, &mut self.k[stage]);
        self.rhs_evals += 1;
        Ok(())
    }

    fn track_w(&mut self) {
        for i in 0..self.max_w.len() {
            self.max_w[i] = self.max_w[i].max(self.zs.residual(i).abs());
        }
    }

    /// One RK4 step of size `h` from the current point.
    pub fn step(&mut self, h: f64) -> Result<(), BaselineError> {
        let t = self.t;
        self.stage(0, t, false)?;
        self.track_w();
        for (stage, c) in [(1, 0.5), (2, 0.5), (3, 1.0)] {
            for i in 0..self.x.len() {
                self.xs[i] = self.x[i] + c * h * self.k[stage - 1][i];
            }
            self.stage(stage, t + c * h, true)?;
        }
        let [k1, k2, k3, k4] = &self.k;
        for i in 0..self.x.len() {
            self.x[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        self.t = t + h;
        if self.x.iter().any(|v| !v.is_finite()) {
            return Err(BaselineError::NonFinite { t: self.t });
        }
        Ok(())
    }

    /// Run from `t_start` to `t_end`; if given, call `observe(t, x, w)` at every step
    /// end (with `w` the constraint residuals there, one extra [`Model::sliding`]
    /// evaluation per step).
    pub fn run(
        &mut self,
        mut observe: Option<Observer<'_>>,
    ) -> Result<IndexOneSummary, BaselineError> {
        let clock = Instant::now();
        let (t0, t_end, h) = (self.set.t_start, self.set.t_end, self.set.step);
        let steps = (((t_end - t0) / h) - 1e-9).ceil().max(1.0) as u64;
        let m = self.z.len();
        let mut w = vec![0.0; m];
        for k in 1..=steps {
            let t_new = if k == steps { t_end } else { t0 + k as f64 * h };
            self.step(t_new - self.t)?;
            self.t = t_new;
            if k == steps {
                // Final point: solve once more so that z and w belong to x(t_end).
                self.zs.solve(self.model, self.t, &self.x, &mut self.z)?;
                self.track_w();
            }
            // w at this step end is evaluated by the next step's first stage; for the
            // observer evaluate it now (positions only: w does not depend on z).
            if let Some(obs) = observe.as_mut() {
                self.residuals_now(&mut w);
                obs(self.t, &self.x, &w);
            }
        }
        Ok(IndexOneSummary {
            steps,
            rhs_evals: self.rhs_evals,
            sliding_evals: self.zs.sliding_evals,
            j_solves: self.zs.j_solves,
            max_abs_w: self.max_w.clone(),
            max_abs_s: self.max_s.clone(),
            t_end: self.t,
            x: self.x.clone(),
            z: self.z.clone(),
            wall_time: clock.elapsed().as_secs_f64(),
        })
    }

    fn residuals_now(&mut self, w: &mut [f64]) {
        // Reuses the solver's buffers through one extra sliding evaluation; counted.
        let mut tmp = std::mem::take(&mut self.zs.w);
        let mut s = std::mem::take(&mut self.zs.s);
        let mut ah = std::mem::take(&mut self.zs.ah);
        self.model.sliding(
            self.t,
            &self.x,
            &self.z,
            &self.zs.mu,
            &mut tmp,
            &mut s,
            &mut ah,
        );
        self.zs.sliding_evals += 1;
        for (i, wi) in w.iter_mut().enumerate() {
            *wi = tmp[self.zs.offs[i]];
        }
        self.zs.w = tmp;
        self.zs.s = s;
        self.zs.ah = ah;
    }
}

/// Fill `(x, z)` with `initial` (checked: lengths, finite) or the model's own start.
pub(crate) fn start<M: Model + ?Sized>(
    model: &M,
    initial: Option<&Initial>,
    x: &mut [f64],
    z: &mut [f64],
) -> Result<(), BaselineError> {
    let Some(init) = initial else {
        model.initial_state(x);
        model.initial_alg(z);
        return Ok(());
    };
    for (what, given, out) in [("x0", &init.x0, &mut *x), ("z0", &init.z0, &mut *z)] {
        if given.len() != out.len() {
            return Err(BaselineError::Settings(format!(
                "initial {what} has {} values, the model needs {}",
                given.len(),
                out.len()
            )));
        }
        if let Some((i, v)) = given.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(BaselineError::Settings(format!(
                "initial {what}[{i}] is {v}, must be finite"
            )));
        }
        out.copy_from_slice(given);
    }
    Ok(())
}
