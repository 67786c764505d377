//! Baseline (c): an implicit variable-order BDF reference (the `diffsol` crate) on the
//! index-1 form `x' = f(t, x, z(t, x))`, with `z(t, x)` from baseline (a)'s Newton solve
//! of `s(t, x, z) = 0` at every right-hand-side evaluation.
//!
//! The BDF Newton iteration needs Jacobian-vector products of that right-hand side;
//! they are one-sided finite differences along the direction (the reduced `f` is only
//! available through the solve, so there is nothing analytic to hand over).

use std::cell::{Cell, RefCell};
use std::time::Instant;

use dae_runtime::{Model, settings::Initial};
use diffsol::{NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod, OdeSolverStopReason, Vector};

use super::index1::start;
use super::{BaselineError, Observer, ZSolver};

/// Settings of [`bdf_index1`].
#[derive(Debug, Clone, PartialEq)]
pub struct BdfSettings {
    /// Stabilisation time constants of the index-1 form (as in baseline (a)).
    pub mu: Vec<f64>,
    /// Relative tolerance of the BDF error control.
    pub rtol: f64,
    /// Absolute tolerance of the BDF error control.
    pub atol: f64,
    /// Start time.
    pub t_start: f64,
    /// End time.
    pub t_end: f64,
    /// Start here instead of the model's initial state and guess.
    pub initial: Option<Initial>,
}

/// What a BDF run did.
#[derive(Debug, Clone, PartialEq)]
pub struct BdfSummary {
    /// Accepted BDF steps.
    pub steps: u64,
    /// Evaluations of `f` (right-hand side and finite-difference Jacobian products).
    pub rhs_evals: u64,
    /// `J_s` factorisations and solves in the `z` Newton solves.
    pub j_solves: u64,
    /// BDF linear-solver setups (`n x n` Jacobian factorisations).
    pub lin_setups: u64,
    /// Largest `|w_i|` at the accepted steps.
    pub max_abs_w: Vec<f64>,
    /// Final time.
    pub t_end: f64,
    /// Final states.
    pub x: Vec<f64>,
    /// Final algebraic unknowns.
    pub z: Vec<f64>,
    /// Wall-clock seconds.
    pub wall_time: f64,
}

struct Reduced<'a, M: Model + ?Sized> {
    model: &'a M,
    zs: RefCell<(ZSolver, Vec<f64>)>,
    failure: RefCell<Option<BaselineError>>,
    rhs_evals: Cell<u64>,
    /// Scratch `(x + delta v, f(x))` for the Jacobian-vector products.
    jvp: RefCell<(Vec<f64>, Vec<f64>)>,
}

impl<M: Model + ?Sized> Reduced<'_, M> {
    fn eval(&self, t: f64, x: &[f64], out: &mut [f64]) {
        let mut guard = self.zs.borrow_mut();
        let (zs, z) = &mut *guard;
        match zs.solve(self.model, t, x, z) {
            Ok(_) => {
                self.model.rhs(t, x, z, out);
                self.rhs_evals.set(self.rhs_evals.get() + 1);
            }
            Err(e) => {
                // The solver sees NaN and fails its step; the cause is reported after.
                self.failure.borrow_mut().get_or_insert(e);
                out.fill(f64::NAN);
            }
        }
    }
}

/// Integrate the index-1 form of `model` from its initial state and guess with
/// `diffsol`'s BDF and nalgebra's dense LU; if given, call `observe(t, x, w)` after
/// every accepted step.
pub fn bdf_index1<M: Model + ?Sized>(
    model: &M,
    settings: &BdfSettings,
    mut observe: Option<Observer<'_>>,
) -> Result<BdfSummary, BaselineError> {
    let clock = Instant::now();
    let (n, m) = (model.n_states(), model.n_constraints());
    let mut x0 = vec![0.0; n];
    let mut z0 = vec![0.0; m];
    start(model, settings.initial.as_ref(), &mut x0, &mut z0)?;
    let red = Reduced {
        model,
        zs: RefCell::new((ZSolver::new(model, &settings.mu, 1e-13)?, z0)),
        failure: RefCell::new(None),
        rhs_evals: Cell::new(0),
        jvp: RefCell::new((vec![0.0; n], vec![0.0; n])),
    };
    let fail = |what: String| BaselineError::Settings(format!("diffsol: {what}"));
    let t0 = settings.t_start;
    let problem = OdeBuilder::<NalgebraMat<f64>>::new()
        .t0(t0)
        .rtol(settings.rtol)
        .atol([settings.atol])
        .rhs_implicit(
            |x: &[f64], _p: &[f64], t: f64, y: &mut [f64]| red.eval(t, x, y),
            |x: &[f64], _p: &[f64], t: f64, v: &[f64], y: &mut [f64]| {
                let vn = v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
                if vn == 0.0 {
                    y.fill(0.0);
                    return;
                }
                let xn = x.iter().fold(0.0f64, |a, b| a.max(b.abs()));
                let delta = f64::EPSILON.sqrt() * (1.0 + xn) / vn;
                let mut scratch = red.jvp.borrow_mut();
                let (xp, f0) = &mut *scratch;
                for ((p, a), b) in xp.iter_mut().zip(x).zip(v) {
                    *p = a + delta * b;
                }
                red.eval(t, x, f0);
                red.eval(t, xp, y);
                for (yi, f) in y.iter_mut().zip(f0.iter()) {
                    *yi = (*yi - f) / delta;
                }
            },
        )
        .init(
            move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&x0),
            n,
        )
        .build()
        .map_err(|e| fail(e.to_string()))?;
    let mut solver = problem.bdf::<NalgebraLU<f64>>().map_err(|e| {
        red.failure
            .borrow()
            .clone()
            .unwrap_or_else(|| fail(e.to_string()))
    })?;
    solver
        .set_stop_time(settings.t_end)
        .map_err(|e| fail(e.to_string()))?;
    let mut w = vec![0.0; sum_w(model)];
    let (mut s, mut ah) = (vec![0.0; m], vec![0.0; m]);
    let offs = dae_runtime::model::w_offsets(model.indices());
    let mut max_w = vec![0.0f64; m];
    let mut x = vec![0.0; n];
    loop {
        let reason = solver.step().map_err(|e| {
            red.failure
                .borrow()
                .clone()
                .unwrap_or_else(|| fail(format!("{e} at t = {}", solver.state().t)))
        })?;
        let state = solver.state();
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = state.y.get_index(i);
        }
        let t = state.t;
        {
            let guard = red.zs.borrow();
            model.sliding(t, &x, &guard.1, &settings.mu, &mut w, &mut s, &mut ah);
        }
        for i in 0..m {
            max_w[i] = max_w[i].max(w[offs[i]].abs());
            s[i] = w[offs[i]];
        }
        if let Some(obs) = observe.as_mut() {
            obs(t, &x, &s[..m]);
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(BaselineError::NonFinite { t });
        }
        if matches!(reason, OdeSolverStopReason::TstopReached) {
            break;
        }
    }
    let state = solver.state();
    let x = state.y.clone_as_vec();
    let t_end = state.t;
    let stats = solver.get_statistics().clone();
    let mut guard = red.zs.borrow_mut();
    let (zs, z) = &mut *guard;
    zs.solve(model, t_end, &x, z)?;
    Ok(BdfSummary {
        steps: stats.number_of_steps as u64,
        rhs_evals: red.rhs_evals.get(),
        j_solves: zs.j_solves,
        lin_setups: stats.number_of_linear_solver_setups as u64,
        max_abs_w: max_w,
        t_end,
        x,
        z: z.clone(),
        wall_time: clock.elapsed().as_secs_f64(),
    })
}

fn sum_w<M: Model + ?Sized>(model: &M) -> usize {
    model.indices().iter().sum()
}
