//! Consistent algebraic start values: the `z` at which every constraint's highest
//! w-derivative vanishes, so that a run starts on its sliding surfaces as far as `z`
//! can put it there.
//!
//! Constraint `i` of index `r_i` sees the algebraic unknowns first in its `(r_i - 1)`-th
//! w-derivative `Omega_i = w_i^(r_i - 1)(t, x, z)`, and `dOmega/dz = J_Omega` (docs/method.md
//! section 2). Given `x`, the `z` with `Omega(t, x, z) = 0` is the one the motion is
//! consistent with: the link tensions of a chain at rest, the reaction of a rail. A model
//! that starts from `z = 0` (as most are written) starts instead far from its surfaces,
//! with `s_i = mu_i^(r_i - 1) Omega_i` to be removed by a reaching phase, and a pilot run
//! that measures that phase rather than the motion. Mechanical models are linear in `z`,
//! so one Newton step solves them exactly; the iteration below allows a nonlinear
//! dependence too.

use crate::Model;
use crate::model::w_offsets;
use crate::solve::{LinearSolver, RedundantRows, SolveError, Solver, SolverChoice};

/// Most Newton iterations of [`consistent_start`].
pub const MAX_NEWTON: usize = 20;

/// The consistent algebraic values found by [`consistent_start`], and how far the given
/// ones were from consistency.
#[derive(Debug, Clone, PartialEq)]
pub struct ConsistentStart {
    /// The algebraic start values, one per constraint.
    pub z0: Vec<f64>,
    /// Newton iterations taken (0: the given values were consistent already).
    pub iterations: usize,
    /// `max_i |Omega_i|` at the given values.
    pub residual_before: f64,
    /// `max_i |Omega_i|` at [`z0`](Self::z0).
    pub residual_after: f64,
    /// The constraint of the largest `|Omega_i|` at the given values.
    pub worst_before: usize,
}

/// Why no consistent algebraic values were found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StartError {
    /// `J_Omega` is singular at the start: these constraints do not determine their
    /// algebraic unknowns there.
    #[error(
        "J_Omega is singular at the start (constraints {constraints:?} are dependent): the algebraic unknowns are not determined there"
    )]
    Singular {
        /// The dependent rows.
        constraints: Vec<usize>,
    },
    /// `Omega`, `J_Omega` or a Newton step is NaN or infinite.
    #[error("non-finite value in constraint {constraint} at iteration {iteration}")]
    NonFinite {
        /// The constraint.
        constraint: usize,
        /// The Newton iteration (0: at the given values).
        iteration: usize,
    },
    /// Newton's iteration did not converge.
    #[error(
        "no consistent values after {iterations} Newton iterations: max |Omega| = {residual:e} (constraint {constraint})"
    )]
    NotConverged {
        /// Iterations taken.
        iterations: usize,
        /// `max_i |Omega_i|` at the end.
        residual: f64,
        /// Where it is largest.
        constraint: usize,
    },
    /// The lengths do not fit the model, or its pattern is malformed.
    #[error("{0}")]
    Mismatch(String),
}

/// The algebraic values `z0` that make every constraint's highest w-derivative vanish at
/// `(t, x)`, by Newton's method from `z`: `z <- z - J_Omega^{-1} Omega(t, x, z)`, with the
/// exact solver [`SolverChoice::Auto`] picks for the pattern. A step that does not reduce
/// `max |Omega|` is halved (at most 30 times). Converged when a step changes no `z_j` by
/// more than `1e-12 (1 + |z_j|)` or `Omega` is exactly zero.
///
/// Only `z` changes: `x` is taken as given, so where `x` itself violates a constraint
/// (`w_i != 0`), `z0` makes the error's highest derivative zero and the reaching phase
/// removes the rest.
///
/// ```
/// use dae_runtime::design::consistent_start;
/// use dae_runtime::model::ModelInfo;
/// use dae_runtime::Model;
/// // x' = z with the index-1 constraint x + z = 1: consistent z = 1 - x.
/// struct Relax(ModelInfo);
/// impl Model for Relax {
///     fn info(&self) -> &ModelInfo { &self.0 }
///     fn param(&self, _: usize) -> f64 { 0.0 }
///     fn set_param(&mut self, _: usize, _: f64) {}
///     fn initial_state(&self, x: &mut [f64]) { x[0] = 0.25 }
///     fn initial_alg(&self, z: &mut [f64]) { z[0] = 0.0 }
///     fn rhs(&self, _: f64, _: &[f64], z: &[f64], dx: &mut [f64]) { dx[0] = z[0] }
///     fn sliding(&self, _: f64, x: &[f64], z: &[f64], _: &[f64], w: &mut [f64],
///                s: &mut [f64], a: &mut [f64]) {
///         w[0] = x[0] + z[0] - 1.0; s[0] = w[0]; a[0] = 0.0;
///     }
///     fn jacobian_pattern(&self) -> &[(usize, usize)] { &[(0, 0)] }
///     fn jacobian(&self, _: f64, _: &[f64], _: &[f64], j: &mut [f64]) { j[0] = 1.0 }
///     fn beta(&self, _: f64, _: &[f64], z: &[f64], b: &mut [f64]) { b[0] = z[0] }
/// }
/// let info = ModelInfo::new("Relax", &["x"], &["z"], &["c"], &[], &[1]);
/// let start = consistent_start(&Relax(info), 0.0, &[0.25], &[0.0]).unwrap();
/// assert!((start.z0[0] - 0.75).abs() < 1e-15);
/// assert_eq!(start.iterations, 1);
/// ```
pub fn consistent_start<M: Model + ?Sized>(
    model: &M,
    t: f64,
    x: &[f64],
    z: &[f64],
) -> Result<ConsistentStart, StartError> {
    consistent_start_with(model, t, x, z, RedundantRows::Refuse)
}

/// [`consistent_start`] where a singular `J_Omega` does what `rows` says: with
/// [`RedundantRows::Drop`], each Newton step leaves the algebraic unknowns of the
/// constraints the others imply where they are and solves for the rest (the implied
/// residuals then vanish with the others when the constraints are dependent as
/// functions; when they do not, Newton does not converge and says so).
pub fn consistent_start_with<M: Model + ?Sized>(
    model: &M,
    t: f64,
    x: &[f64],
    z: &[f64],
    rows: RedundantRows,
) -> Result<ConsistentStart, StartError> {
    let (n, m) = (model.n_states(), model.n_constraints());
    if x.len() != n || z.len() != m {
        return Err(StartError::Mismatch(format!(
            "the model has {n} states and {m} algebraic unknowns, given {} and {}",
            x.len(),
            z.len()
        )));
    }
    let mut newton = Newton::new(model, t, x, rows)?;
    let mut z = z.to_vec();
    let (mut residual, worst_before) = newton.residual(&z, 0)?;
    let residual_before = residual;
    let mut step = vec![0.0; m];
    let mut trial = vec![0.0; m];
    for iteration in 1..=MAX_NEWTON {
        if residual == 0.0 {
            return Ok(newton.done(z, iteration - 1, residual_before, worst_before, 0.0));
        }
        newton.step(&z, &mut step, iteration)?;
        // Halve a step that does not reduce the residual (a nonlinear dependence).
        let mut scale = 1.0;
        let mut accepted = None;
        for _ in 0..30 {
            for ((t, z), d) in trial.iter_mut().zip(&z).zip(&step) {
                *t = z - scale * d;
            }
            let (r, _) = newton.residual(&trial, iteration)?;
            if r < residual || r == 0.0 {
                accepted = Some(r);
                break;
            }
            scale *= 0.5;
        }
        let small = step
            .iter()
            .zip(&z)
            .all(|(d, z)| (scale * d).abs() <= 1e-12 * (1.0 + z.abs()));
        match accepted {
            Some(r) => {
                std::mem::swap(&mut z, &mut trial);
                residual = r;
                if small {
                    return Ok(newton.done(z, iteration, residual_before, worst_before, r));
                }
            }
            // No step reduces |Omega|: at its floor (rounding) if the step was tiny.
            None if small => {
                return Ok(newton.done(z, iteration - 1, residual_before, worst_before, residual));
            }
            None => break,
        }
    }
    let (residual, constraint) = newton.residual(&z, MAX_NEWTON)?;
    Err(StartError::NotConverged {
        iterations: MAX_NEWTON,
        residual,
        constraint,
    })
}

/// The buffers of the iteration.
struct Newton<'a, M: Model + ?Sized> {
    model: &'a M,
    t: f64,
    x: &'a [f64],
    /// Where `Omega_i` sits in the w-derivatives.
    top: Vec<usize>,
    w: Vec<f64>,
    s: Vec<f64>,
    alpha: Vec<f64>,
    mu: Vec<f64>,
    jvals: Vec<f64>,
    ones: Vec<f64>,
    solver: Solver,
}

impl<'a, M: Model + ?Sized> Newton<'a, M> {
    fn new(model: &'a M, t: f64, x: &'a [f64], rows: RedundantRows) -> Result<Self, StartError> {
        let m = model.n_constraints();
        let offsets = w_offsets(model.indices());
        let pattern = model.jacobian_pattern();
        let families = crate::model::constraint_families(model);
        let solver = Solver::new(m, pattern, SolverChoice::Auto)
            .and_then(|s| s.redundant_rows(rows, pattern, &families))
            .map_err(|e| StartError::Mismatch(format!("the pattern of J_Omega: {e}")))?;
        Ok(Newton {
            model,
            t,
            x,
            top: (0..m).map(|i| offsets[i + 1] - 1).collect(),
            w: vec![0.0; offsets[m]],
            s: vec![0.0; m],
            alpha: vec![0.0; m],
            mu: vec![1.0; m],
            jvals: vec![0.0; pattern.len()],
            ones: vec![1.0; m],
            solver,
        })
    }

    /// `max_i |Omega_i(z)|` and its constraint; `Omega` stays in `self.s`.
    fn residual(&mut self, z: &[f64], iteration: usize) -> Result<(f64, usize), StartError> {
        self.model.sliding(
            self.t,
            self.x,
            z,
            &self.mu,
            &mut self.w,
            &mut self.s,
            &mut self.alpha,
        );
        let (mut worst, mut at) = (0.0f64, 0);
        for (i, &k) in self.top.iter().enumerate() {
            let o = self.w[k];
            if !o.is_finite() {
                return Err(StartError::NonFinite {
                    constraint: i,
                    iteration,
                });
            }
            self.s[i] = o;
            if o.abs() > worst {
                (worst, at) = (o.abs(), i);
            }
        }
        Ok((worst, at))
    }

    /// The Newton step `J_Omega^{-1} Omega` at `z` into `step`. `self.s` holds `Omega(z)`:
    /// the last point [`residual`](Self::residual) evaluated is always the current `z`
    /// (the start, or the trial just accepted).
    fn step(&mut self, z: &[f64], step: &mut [f64], iteration: usize) -> Result<(), StartError> {
        self.model.jacobian(self.t, self.x, z, &mut self.jvals);
        self.solver
            .factor(&self.jvals, &self.ones)
            .map_err(|e| match e {
                SolveError::Singular { constraints } => StartError::Singular { constraints },
                SolveError::NonFinite { row } => StartError::NonFinite {
                    constraint: row,
                    iteration,
                },
                e => StartError::Mismatch(format!("J_Omega at the start: {e}")),
            })?;
        self.solver.solve_from(&self.s, step);
        match step.iter().position(|d| !d.is_finite()) {
            Some(j) => Err(StartError::NonFinite {
                constraint: j,
                iteration,
            }),
            None => Ok(()),
        }
    }

    fn done(
        &self,
        z0: Vec<f64>,
        iterations: usize,
        residual_before: f64,
        worst_before: usize,
        residual_after: f64,
    ) -> ConsistentStart {
        ConsistentStart {
            z0,
            iterations,
            residual_before,
            residual_after,
            worst_before,
        }
    }
}
