//! The index-1 reduction of a particle system with an exact solve at every stage (the
//! family of Baraff 1996 and Deul et al. 2018): classical RK4 on the positions and
//! velocities, the tensions at every stage from the acceleration-level constraint with
//! Baumgarte stabilisation,
//!
//! ```text
//! w'' + 2 w' / mu + w / mu^2 = 0   <=>   s = mu^2 w'' + 2 mu w' + w = 0,
//! ```
//!
//! solved for `z` by one Newton step from the previous stage's `z` with
//! `J_s = mu^2 J_Omega` (exact: `w''` is affine in `z`) through the runtime's solver
//! seam (the forest elimination on chains and strands, the sparse `LDL^T` on cloth).
//! `mu` is the step itself (both Baumgarte poles at `-1/h`): drift of the link
//! lengths is pulled back within a few steps, and RK4 is stable there (`h/mu = 1`).
//! No projection.

use dae_particles::{Backend, BackendError, Counters, Kinematics, ParticleDae, Pin};
use dae_runtime::{solve::LinearSolver, solve::Solver, solve::SolverChoice};

/// The index-1 method (module docs) on any [`ParticleDae`] model.
#[derive(Debug)]
pub struct IndexOneParticles<M: ParticleDae> {
    model: M,
    solver: Solver,
    steps_per_frame: u32,
    mu: Vec<f64>,
    mu2: Vec<f64>,
    t: f64,
    x: Vec<f64>,
    z: Vec<f64>,
    xs: Vec<f64>,
    k: [Vec<f64>; 4],
    jvals: Vec<f64>,
    w: Vec<f64>,
    s: Vec<f64>,
    ah: Vec<f64>,
    counters: Counters,
    bounds: Option<PilotBounds>,
}

/// What a pilot run of the index-1 method saw of every constraint, for a DBSMC design:
/// the largest `|beta_i|` and the largest rate of change `|d beta_i / dt|` (an
/// estimate of the drift bound `M_i` of the third derivative of `w_i` within a control
/// interval, T 3.5), both at the step starts, where `z` solves `s = 0`.
#[derive(Debug, Clone, PartialEq)]
pub struct PilotBounds {
    /// Largest `|beta_i|`.
    pub beta: Vec<f64>,
    /// Largest `|beta_i(t + h) - beta_i(t)| / h`.
    pub drift: Vec<f64>,
    prev: Vec<f64>,
    now: Vec<f64>,
    prev_t: Option<f64>,
}

impl PilotBounds {
    /// The bounds of the constraints `constraints` alone (a part of the system, in its
    /// order).
    pub fn restricted(&self, constraints: &[usize]) -> Self {
        let pick = |v: &[f64]| constraints.iter().map(|&i| v[i]).collect::<Vec<_>>();
        Self {
            beta: pick(&self.beta),
            drift: pick(&self.drift),
            ..Self::new(constraints.len())
        }
    }

    fn new(m: usize) -> Self {
        Self {
            beta: vec![0.0; m],
            drift: vec![0.0; m],
            prev: vec![0.0; m],
            now: vec![0.0; m],
            prev_t: None,
        }
    }
    fn observe<M: ParticleDae>(&mut self, model: &M, t: f64, x: &[f64], z: &[f64]) {
        model.beta(t, x, z, &mut self.now);
        for i in 0..self.now.len() {
            self.beta[i] = self.beta[i].max(self.now[i].abs());
            if let Some(t0) = self.prev_t {
                let rate = (self.now[i] - self.prev[i]).abs() / (t - t0);
                self.drift[i] = self.drift[i].max(rate);
            }
        }
        std::mem::swap(&mut self.prev, &mut self.now);
        self.prev_t = Some(t);
    }
}

impl<M: ParticleDae> IndexOneParticles<M> {
    /// Track [`PilotBounds`] from now on (one extra `beta` evaluation per step).
    pub fn track_bounds(mut self) -> Self {
        self.bounds = Some(PilotBounds::new(self.z.len()));
        self
    }
    /// The bounds tracked so far, if tracking.
    pub fn bounds(&self) -> Option<&PilotBounds> {
        self.bounds.as_ref()
    }
    /// The method on `model` with `steps_per_frame` RK4 steps per frame of 1/60 s and `solver` for
    /// `J_s` (an exact one: `Auto`, `Tree`, `Sparse`, `Dense`).
    pub fn new(model: M, steps_per_frame: u32, solver: SolverChoice) -> Result<Self, String> {
        if steps_per_frame == 0 {
            return Err("the index-1 method needs at least one step per frame".into());
        }
        let (n, m) = (model.n_states(), model.n_constraints());
        let solver = Solver::new(m, model.jacobian_pattern(), solver).map_err(|e| e.to_string())?;
        let h = 1.0 / (60.0 * steps_per_frame as f64);
        let mut x = vec![0.0; n];
        let mut z = vec![0.0; m];
        model.initial_state(&mut x);
        model.initial_alg(&mut z);
        Ok(Self {
            jvals: vec![0.0; model.jacobian_pattern().len()],
            solver,
            steps_per_frame,
            mu: vec![h; m],
            mu2: vec![h * h; m],
            t: 0.0,
            xs: vec![0.0; n],
            k: [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            w: vec![0.0; 3 * m],
            s: vec![0.0; m],
            ah: vec![0.0; m],
            x,
            z,
            model,
            counters: Counters::default(),
            bounds: None,
        })
    }

    /// The model.
    pub fn model(&self) -> &M {
        &self.model
    }
    /// Current states.
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    fn fail(&self, t: f64, reason: String) -> BackendError {
        BackendError {
            method: self.name(),
            t,
            reason,
            deadline: false,
        }
    }

    /// `z` from `s(t, x, z) = 0` at the stage point, then `f` into `k[stage]`.
    fn stage(&mut self, stage: usize, t: f64, at_xs: bool) -> Result<(), BackendError> {
        let x = if at_xs { &self.xs } else { &self.x };
        self.model.sliding(
            t,
            x,
            &self.z,
            &self.mu,
            &mut self.w,
            &mut self.s,
            &mut self.ah,
        );
        self.model.jacobian(t, x, &self.z, &mut self.jvals);
        if let Err(e) = self.solver.factor(&self.jvals, &self.mu2) {
            return Err(self.fail(t, format!("J_s: {e}")));
        }
        self.solver.solve(&mut self.s);
        for (z, d) in self.z.iter_mut().zip(&self.s) {
            *z -= d;
        }
        let x = if at_xs { &self.xs } else { &self.x };
        self.model.rhs(t, x, &self.z, &mut self.k[stage]);
        self.counters.f_evals += 1;
        self.counters.factorisations += 1;
        Ok(())
    }

    fn step(&mut self, h: f64) -> Result<(), BackendError> {
        let t = self.t;
        self.stage(0, t, false)?;
        if let Some(b) = self.bounds.as_mut() {
            b.observe(&self.model, t, &self.x, &self.z);
        }
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
        self.counters.steps += 1;
        Ok(())
    }

    fn vec3(&self, i: usize) -> [f64; 3] {
        [self.x[i], self.x[i + 1], self.x[i + 2]]
    }
}

impl<M: ParticleDae> Backend for IndexOneParticles<M> {
    fn name(&self) -> String {
        format!("index-1 rk4 steps/frame={}", self.steps_per_frame)
    }
    fn n_particles(&self) -> usize {
        self.model.n_particles()
    }
    fn time(&self) -> f64 {
        self.t
    }
    fn advance_to(&mut self, t: f64) -> Result<(), BackendError> {
        let span = t - self.t;
        let n = ((span * 60.0 * self.steps_per_frame as f64) - 1e-9)
            .ceil()
            .max(1.0) as u64;
        let h = span / n as f64;
        for _ in 0..n {
            self.step(h)?;
        }
        self.t = t;
        if let Some(i) = self.x.iter().position(|v| !v.is_finite()) {
            return Err(self.fail(
                t,
                format!("state {} is not finite", self.model.state_name(i)),
            ));
        }
        Ok(())
    }
    fn positions(&self, out: &mut [[f64; 3]]) {
        for (k, p) in out.iter_mut().enumerate() {
            *p = self.vec3(self.model.state_slots(k).0);
        }
    }
    fn velocities(&self, out: &mut [[f64; 3]]) {
        for (k, v) in out.iter_mut().enumerate() {
            *v = self.vec3(self.model.state_slots(k).1);
        }
    }
    fn particle(&self, k: usize) -> Kinematics {
        let mut f = vec![0.0; self.x.len()];
        self.model.rhs(self.t, &self.x, &self.z, &mut f);
        let (p, v) = self.model.state_slots(k);
        Kinematics {
            pos: self.vec3(p),
            vel: self.vec3(v),
            acc: [f[v], f[v + 1], f[v + 2]],
            jerk: [0.0; 3],
        }
    }
    fn set_pin(&mut self, k: usize, pin: Option<Pin>) -> Result<(), BackendError> {
        let t = self.t;
        self.model
            .set_pin(k, pin)
            .map_err(|e| self.fail(t, e.to_string()))
    }
    fn counters(&self) -> Counters {
        self.counters
    }
}
