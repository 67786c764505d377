//! The control law `v = J_hat^{-1}(-alpha_hat - K sgn(s))`, its buffers, the robustness
//! check (T 3.22) with its gain-raising policy, the rate `s' = J_s v + alpha`, and the
//! algebraic outputs `z_eq` and `z*`.

mod blocks;
mod conditioning;

use super::robust::Robustness;
use crate::model::w_offsets;
use crate::settings::Scope;
use crate::solve::{
    InverseKind, LinearSolver, RedundantRows, SolveError, Solver, SolverChoice, Structure,
};
use crate::{Model, SimError};
pub(crate) use blocks::BlockSet;
use conditioning::probe_vector;

/// Switching function: `sgn` for DBSMC, `sat(s/eps)` for SPSM.
#[derive(Clone, Copy)]
pub(crate) enum Switch {
    Sign,
    Saturation,
}

impl Switch {
    /// `sgn(s)` or `sat(s / eps)`.
    #[inline]
    fn of(self, s: f64, eps: f64) -> f64 {
        match self {
            Switch::Sign => sgn(s),
            Switch::Saturation => (s / eps).clamp(-1.0, 1.0),
        }
    }
}

/// What the law does about robustness (T 3.22) at one update.
#[derive(Clone, Copy)]
pub(crate) struct Check {
    /// Evaluate the condition (needs `beta`).
    pub(crate) evaluate: bool,
    /// Count the failing rows (inside the statistics window).
    pub(crate) count: bool,
    /// Raise the failing rows' gains by this relative margin.
    pub(crate) raise: Option<f64>,
    /// `beta` was already evaluated at this point (located crossings evaluate it at a
    /// cut, and at every step's end for a model without [`Model::omega_rate`]).
    pub(crate) beta_ready: bool,
}

impl Check {
    pub(crate) const OFF: Check = Check {
        evaluate: false,
        count: false,
        raise: None,
        beta_ready: false,
    };
}

/// A raised gain never exceeds this multiple of its configured value: beyond it the
/// approximation is too poor for any gain (the raise would not converge), and the
/// failing rows stay counted.
pub(crate) const GAIN_RAISE_LIMIT: f64 = 1e3;

pub(crate) struct Controller {
    pub(crate) offs: Vec<usize>,
    mu: Vec<f64>,
    /// `mu_i^(r_i - 1)`, the row scaling from `J_Omega` to `J_s`.
    mu_pow: Vec<f64>,
    pub(crate) gains: Vec<f64>,
    gain_limit: Vec<f64>,
    margin: Vec<f64>,
    eps: Vec<f64>,
    exact_alpha: bool,
    pattern: Vec<(usize, usize)>,
    jvals: Vec<f64>,
    /// w-derivatives, sliding variables and cheap alpha_hat at the last `sliding` call.
    pub(crate) w: Vec<f64>,
    pub(crate) s: Vec<f64>,
    ah: Vec<f64>,
    /// `alpha_hat` used by the law, `alpha - alpha_hat`, right-hand side, residual.
    ah_used: Vec<f64>,
    g: Vec<f64>,
    beta: Vec<f64>,
    rhs: Vec<f64>,
    res: Vec<f64>,
    /// The previous `z_eq` correction, warm start of the iterative solvers.
    dz: Vec<f64>,
    pub(crate) solver: Solver,
    factored: bool,
    /// Exact solver for `z* = z - J_Omega^{-1} Omega` at the current state, and its
    /// buffers (the unit row scaling, the right-hand side).
    zsolver: Solver,
    ones: Vec<f64>,
    zrhs: Vec<f64>,
    /// Largest value of a factorisation's least pivot magnitude seen in the run, and the
    /// smallest ratio of a factorisation's least pivot to it, with its time. The least
    /// pivot is compared with its own history, not with the other pivots of the same
    /// factor: a long chain's factor spreads its pivots over a factor `m` from the start
    /// without anything having gone wrong.
    pivot_max: f64,
    pub(crate) min_pivot_ratio: Option<(f64, f64)>,
    /// The largest `|b| / |J_s^{-1} b|` for the fixed `b` of [`Self::solve_measure`]
    /// seen in the run: measured at the run's first factorisation, at every one of a
    /// dense LU's (whose partial pivoting can keep its pivots large while `J_s` nears
    /// singular; one `O(m^2)` solve against the factorisation's `O(m^3)`), and by the
    /// probe at a failure ([`Self::probe_singular`]), each compared with it. Not with
    /// the pivots: the two measure different things (on a healthy 1000-link chain this
    /// one is 2e-7 of the least pivot, on the 64 x 64 cloth 1e-4), so only its own
    /// history says whether `J_s` came near singular.
    solve_max: Option<f64>,
    /// The fixed `b` of the probe ([`probe_vector`]), and the solve's vector (both sized
    /// once).
    probe_b: Vec<f64>,
    probe: Vec<f64>,
    robust: Robustness,
    /// Evaluations at a point other than the current one (see [`Self::s_rate_at`]).
    elsewhere: Elsewhere,
    /// Whether the model gives `Omega`'s rate in one pass ([`Model::omega_rate`]):
    /// assumed until its first call says otherwise.
    model_rate: bool,
    /// `Omega`'s rate from the model, the buffer of [`Self::rate_from_model`].
    omega_rate: Vec<f64>,
    pub(crate) sliding_evals: u64,
    pub(crate) jacobian_evals: u64,
    pub(crate) beta_evals: u64,
    pub(crate) rate_evals: u64,
    pub(crate) gain_raises: u64,
    /// The partition of block-local updates ([`Scope::Blocks`]), and whether block
    /// updates came after the last factorisation of all of `J_s`.
    blocks: Option<BlockSet>,
    global_stale: bool,
}

/// `w`, `s`, `alpha_hat`, `J_Omega` and `beta` at a point other than the current one,
/// kept apart so that the current point's stay valid.
struct Elsewhere {
    w: Vec<f64>,
    s: Vec<f64>,
    ah: Vec<f64>,
    jvals: Vec<f64>,
    beta: Vec<f64>,
}

/// `s' = alpha_hat + mu^(r-1) (J_Omega v + beta)` from evaluated `alpha_hat`, `J_Omega`
/// (values on `pattern`) and `beta`, into `out`.
fn rate(
    pattern: &[(usize, usize)],
    jvals: &[f64],
    beta: &[f64],
    ah: &[f64],
    mu_pow: &[f64],
    v: &[f64],
    out: &mut [f64],
) {
    out.copy_from_slice(beta);
    for (&(i, j), a) in pattern.iter().zip(jvals) {
        out[i] += a * v[j];
    }
    for ((o, d), ah) in out.iter_mut().zip(mu_pow).zip(ah) {
        *o = ah + d * *o;
    }
}

/// `s' = alpha_hat + mu^(r-1) Omega'` from `Omega`'s rate, into `out`.
fn combine_rate(ah: &[f64], mu_pow: &[f64], omega_rate: &[f64], out: &mut [f64]) {
    for (((o, ah), d), r) in out.iter_mut().zip(ah).zip(mu_pow).zip(omega_rate) {
        *o = ah + d * r;
    }
}

fn sgn(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

impl Controller {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new<M: Model + ?Sized>(
        model: &M,
        mu: &[f64],
        gains: &[f64],
        margin: &[f64],
        eps: &[f64],
        exact_alpha: bool,
        solver: SolverChoice,
        redundant: RedundantRows,
        scope: Scope,
    ) -> Result<Self, SimError> {
        let m = model.n_constraints();
        let r = model.indices();
        if r.len() != m || r.contains(&0) {
            return Err(SimError::Settings {
                field: "model",
                reason: format!("indices {r:?} must be {m} values >= 1"),
            });
        }
        let pattern = model.jacobian_pattern().to_vec();
        let bad_pattern = |e: SolveError| SimError::Settings {
            field: "model",
            reason: format!("jacobian pattern: {e}"),
        };
        let structure = Structure::new(m, &pattern).map_err(bad_pattern)?;
        let blocks = match scope {
            Scope::Global => None,
            Scope::Blocks { size } => Some(BlockSet::new(&structure, size).map_err(bad_pattern)?),
        };
        let families = crate::model::constraint_families(model);
        let solver = Solver::new(m, &pattern, solver)
            .map_err(|e| SimError::Settings {
                field: "solver",
                reason: e.to_string(),
            })?
            .redundant_rows(redundant, &pattern, &families)
            .map_err(bad_pattern)?;
        // The same symbolic analysis where the choices agree (it is most of the set-up
        // of a large sparse pattern).
        let zsolver = if solver.choice() == SolverChoice::Auto {
            solver.clone()
        } else {
            Solver::new(m, &pattern, SolverChoice::Auto)
                .and_then(|s| s.redundant_rows(redundant, &pattern, &families))
                .map_err(bad_pattern)?
        };
        let offs = w_offsets(r);
        let mu_pow = mu_powers(model, mu)?;
        let vm = || vec![0.0; m];
        let elsewhere = Elsewhere {
            w: vec![0.0; offs[m]],
            s: vm(),
            ah: vm(),
            jvals: vec![0.0; pattern.len()],
            beta: vm(),
        };
        Ok(Self {
            w: vec![0.0; offs[m]],
            offs,
            mu: mu.to_vec(),
            mu_pow,
            gains: gains.to_vec(),
            gain_limit: gains.iter().map(|k| GAIN_RAISE_LIMIT * k).collect(),
            margin: margin.to_vec(),
            eps: eps.to_vec(),
            exact_alpha,
            jvals: vec![0.0; pattern.len()],
            pattern,
            s: vm(),
            ah: vm(),
            ah_used: vm(),
            g: vm(),
            beta: vm(),
            rhs: vm(),
            res: vm(),
            dz: vm(),
            solver,
            factored: false,
            zsolver,
            ones: vec![1.0; m],
            zrhs: vm(),
            pivot_max: 0.0,
            min_pivot_ratio: None,
            solve_max: None,
            probe_b: probe_vector(m),
            probe: vm(),
            robust: Robustness::new(structure),
            elsewhere,
            model_rate: true,
            omega_rate: vm(),
            sliding_evals: 0,
            jacobian_evals: 0,
            beta_evals: 0,
            rate_evals: 0,
            gain_raises: 0,
            blocks,
            global_stale: false,
        })
    }

    /// New `mu`, its row scaling `mu_pow` ([`mu_powers`]) and configured gains
    /// ([`Simulator::rescale_mu`](super::Simulator::rescale_mu)); `J_s` must be factored
    /// again.
    pub(crate) fn set_mu(&mut self, mu: &[f64], mu_pow: Vec<f64>, gains: &[f64]) {
        // The pivots of `J_s` scale with its rows: the history that the least pivot is
        // compared with scales by the least row factor, so that a smaller `mu` is not
        // taken for a nearly singular `J_Omega`.
        let least = mu_pow
            .iter()
            .zip(&self.mu_pow)
            .map(|(new, old)| new / old)
            .fold(f64::INFINITY, f64::min);
        self.mu.copy_from_slice(mu);
        self.mu_pow = mu_pow;
        if least.is_finite() {
            self.pivot_max *= least;
            if let Some(e) = &mut self.solve_max {
                *e *= least;
            }
        }
        self.gains.copy_from_slice(gains);
        for (l, k) in self.gain_limit.iter_mut().zip(gains) {
            *l = GAIN_RAISE_LIMIT * k;
        }
        self.factored = false;
    }

    /// Reset counters and the configured gains for a new run.
    pub(crate) fn reset(&mut self, gains: &[f64]) {
        self.sliding_evals = 0;
        self.jacobian_evals = 0;
        self.beta_evals = 0;
        self.rate_evals = 0;
        self.gain_raises = 0;
        self.gains.copy_from_slice(gains);
        self.solver.reset_stats();
        self.factored = false;
        self.dz.fill(0.0);
        self.pivot_max = 0.0;
        self.min_pivot_ratio = None;
        self.solve_max = None;
        if let Some(b) = &mut self.blocks {
            b.reset();
        }
        self.global_stale = false;
    }

    /// Evaluate w-derivatives, `s` and the cheap `alpha_hat` at `(t, x, z)`.
    pub(crate) fn sliding<M: Model + ?Sized>(&mut self, model: &M, t: f64, x: &[f64], z: &[f64]) {
        model.sliding(t, x, z, &self.mu, &mut self.w, &mut self.s, &mut self.ah);
        self.sliding_evals += 1;
    }

    /// Constraint residual `w_i` from the last `sliding` call.
    pub(crate) fn residual(&self, i: usize) -> f64 {
        self.w[self.offs[i]]
    }

    /// Evaluate `J_Omega` at `(t, x, z)` and factor `J_s = diag(mu^(r-1)) J_Omega`.
    pub(crate) fn factor<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
    ) -> Result<(), SimError> {
        self.eval_jacobian(model, t, x, z);
        self.factor_current(model, t)
    }

    /// Evaluate `J_Omega` at `(t, x, z)` (kept for a later [`Self::factor_current`],
    /// [`Self::s_rate`] or [`Self::z_star`] at the same point).
    pub(crate) fn eval_jacobian<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
    ) {
        model.jacobian(t, x, z, &mut self.jvals);
        self.jacobian_evals += 1;
    }

    /// Evaluate `beta` at `(t, x, z)`.
    pub(crate) fn eval_beta<M: Model + ?Sized>(&mut self, model: &M, t: f64, x: &[f64], z: &[f64]) {
        model.beta(t, x, z, &mut self.beta);
        self.beta_evals += 1;
    }

    /// Factor `J_s` from the last evaluated `J_Omega`, and follow its conditioning
    /// ([`Self::watch_conditioning`]).
    pub(crate) fn factor_current<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
    ) -> Result<(), SimError> {
        self.factored = false;
        match self.solver.factor(&self.jvals, &self.mu_pow) {
            Ok(()) => {
                self.factored = true;
                self.global_stale = false;
                self.watch_conditioning(t);
                Ok(())
            }
            Err(e) => Err(self.solver_error(model, t, e)),
        }
    }

    /// `s' = alpha_hat + mu^(r-1) (J_Omega v + beta)` from the last `sliding`,
    /// `J_Omega` and `beta` evaluations, into `out`.
    pub(crate) fn s_rate(&self, v: &[f64], out: &mut [f64]) {
        rate(
            &self.pattern,
            &self.jvals,
            &self.beta,
            &self.ah,
            &self.mu_pow,
            v,
            out,
        );
    }

    /// `s' = alpha_hat + mu^(r-1) Omega'` at `(t, x, z)` with the rate `v`, into `out`,
    /// from the last `sliding` call (there) and the model's [`Model::omega_rate`] in one
    /// pass. Returns `false` (`out` untouched) if the model does not provide that rate:
    /// `s'` then needs `J_Omega` and `beta` ([`Self::s_rate`]).
    pub(crate) fn rate_from_model<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
        v: &[f64],
        out: &mut [f64],
    ) -> bool {
        self.model_rate_with(model, (t, x, z), v, false, out)
    }

    /// [`Self::rate_from_model`] with `alpha_hat` of the current point, or with that of
    /// the point of [`Self::s_rate_at`] (`elsewhere`).
    fn model_rate_with<M: Model + ?Sized>(
        &mut self,
        model: &M,
        (t, x, z): (f64, &[f64], &[f64]),
        v: &[f64],
        elsewhere: bool,
        out: &mut [f64],
    ) -> bool {
        if !(self.model_rate && model.omega_rate(t, x, z, v, &mut self.omega_rate)) {
            self.model_rate = false;
            return false;
        }
        self.rate_evals += 1;
        let ah = if elsewhere {
            &self.elsewhere.ah
        } else {
            &self.ah
        };
        combine_rate(ah, &self.mu_pow, &self.omega_rate, out);
        true
    }

    /// Whether the model may give `Omega`'s rate in one pass (until its first call
    /// says it does not): the step's end then needs neither `J_Omega` nor `beta`.
    pub(crate) fn model_rate(&self) -> bool {
        self.model_rate
    }

    /// Whether [`Self::law`] with this `check` evaluates `beta` (if not ready).
    pub(crate) fn law_needs_beta(&self, check: Check) -> bool {
        self.exact_alpha || check.evaluate
    }

    /// `s'` at another point `(t, x, z)` with the rate `v`, into `out`: `sliding` and
    /// `Omega`'s rate (or `J_Omega` and `beta`) evaluated there into buffers of their
    /// own, so that the current point's `s`, `J_Omega` and `beta` stay as they are.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn s_rate_at<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
        v: &[f64],
        out: &mut [f64],
    ) {
        let e = &mut self.elsewhere;
        model.sliding(t, x, z, &self.mu, &mut e.w, &mut e.s, &mut e.ah);
        self.sliding_evals += 1;
        if self.model_rate_with(model, (t, x, z), v, true, out) {
            return;
        }
        let e = &mut self.elsewhere;
        model.jacobian(t, x, z, &mut e.jvals);
        model.beta(t, x, z, &mut e.beta);
        self.jacobian_evals += 1;
        self.beta_evals += 1;
        rate(
            &self.pattern,
            &e.jvals,
            &e.beta,
            &e.ah,
            &self.mu_pow,
            v,
            out,
        );
    }

    /// `z* = z - J_Omega^{-1} Omega(t, x, z)` with `Omega_i = w_i^(r_i - 1)` from the
    /// last `sliding` call and `J_Omega` from the last evaluation (both at the current
    /// point): one exact factorisation and solve. NaN where `J_Omega` is singular.
    pub(crate) fn z_star(&mut self, z: &[f64], out: &mut [f64]) {
        if self.zsolver.factor(&self.jvals, &self.ones).is_err() {
            out.fill(f64::NAN);
            return;
        }
        for (i, r) in self.zrhs.iter_mut().enumerate() {
            *r = self.w[self.offs[i + 1] - 1];
        }
        self.zsolver.solve(&mut self.zrhs);
        for ((o, zi), d) in out.iter_mut().zip(z).zip(&self.zrhs) {
            *o = zi - d;
        }
    }

    /// `Omega_i = w_i^(r_i - 1)` from the last `sliding` call, into `out`.
    pub(crate) fn omega(&self, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.w[self.offs[i + 1] - 1];
        }
    }

    /// Move `z` so that `Omega` returns to `before`: `z -= J_Omega^{-1} (Omega - before)`
    /// with `Omega` from the last `sliding` call and `J_Omega` from the last evaluation
    /// (both at the current point, after a change of the model). Exact when `Omega` is
    /// affine in `z` (particle models: tensions enter the accelerations linearly), a
    /// Newton step otherwise.
    pub(crate) fn carry_omega<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        before: &[f64],
        z: &mut [f64],
    ) -> Result<(), SimError> {
        if let Err(e) = self.zsolver.factor(&self.jvals, &self.ones) {
            return Err(self.solver_error(model, t, e));
        }
        for (i, r) in self.zrhs.iter_mut().enumerate() {
            *r = self.w[self.offs[i + 1] - 1] - before[i];
        }
        self.zsolver.solve(&mut self.zrhs);
        for (zi, d) in z.iter_mut().zip(&self.zrhs) {
            *zi -= d;
        }
        Ok(())
    }

    fn solver_error<M: Model + ?Sized>(&self, model: &M, t: f64, e: SolveError) -> SimError {
        let name = |i: usize| format!("`{}`", model.constraint_name(i));
        let reason = match e {
            SolveError::Singular { constraints } => {
                return SimError::SingularJacobian {
                    t,
                    names: constraints
                        .iter()
                        .map(|&i| model.constraint_name(i).to_string())
                        .collect(),
                    constraints,
                };
            }
            SolveError::Breakdown { row } => format!(
                "no usable diagonal pivot at constraint {} although J_s is not singular; this solver eliminates without row exchanges: use --solver dense",
                name(row)
            ),
            SolveError::NotSymmetric { row, col } => format!(
                "J_Omega is not symmetric at constraints {} and {}: cg needs a symmetric J_Omega; use gauss-seidel, ilu0 or an exact solver",
                name(row),
                name(col)
            ),
            SolveError::NonFinite { row } => {
                format!(
                    "J_Omega has a non-finite entry in the row of constraint {}",
                    name(row)
                )
            }
            SolveError::Pattern(p) => p,
        };
        SimError::SolverFailed {
            t,
            solver: self.solver.name().to_string(),
            reason,
        }
    }

    /// The control `v` at `(t, x, z)`, using `s`/`alpha_hat` from the last `sliding` call
    /// and the factors from the last `factor` call. Evaluates `beta` when the exact
    /// alpha is used or the robustness condition is evaluated; returns the number of
    /// rows failing (T 3.22) when counted (0 otherwise).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn law<M: Model + ?Sized>(
        &mut self,
        model: &M,
        t: f64,
        x: &[f64],
        z: &[f64],
        switch: Switch,
        check: Check,
        v: &mut [f64],
    ) -> u64 {
        let m = self.s.len();
        if self.law_needs_beta(check) && !check.beta_ready {
            model.beta(t, x, z, &mut self.beta);
            self.beta_evals += 1;
        }
        let kind = self.solver.inverse();
        if !check.evaluate || (kind == InverseKind::Exact && check.raise.is_none()) {
            // The common paths: one pass for the right-hand side (and, with an exact
            // solver, the condition k_i > |alpha_i - alpha_hat_i| + k_i^c), one solve.
            let mut failures = 0;
            for i in 0..m {
                let (rhs, holds) = self.law_row(i, switch);
                if check.evaluate && !holds {
                    failures += 1;
                }
                self.rhs[i] = rhs;
            }
            self.solver.solve_from(&self.rhs, v);
            return if check.count { failures } else { 0 };
        }
        for i in 0..m {
            let exact_part = self.mu_pow[i] * self.beta[i];
            if self.exact_alpha {
                self.ah_used[i] = self.ah[i] + exact_part;
                self.g[i] = 0.0;
            } else {
                self.ah_used[i] = self.ah[i];
                self.g[i] = exact_part;
            }
        }
        let mut failures = 0;
        if kind != InverseKind::Approximate {
            self.robust.evaluate(
                kind,
                &self.jvals,
                &self.mu_pow,
                &self.g,
                &self.ah_used,
                &self.gains,
                &self.margin,
                &self.res,
            );
            failures = self.robust.failures(&self.gains);
            if let (Some(margin), true) = (check.raise, failures > 0) {
                self.gain_raises += if kind == InverseKind::Diagonal {
                    self.robust.raise_jacobi(
                        &self.jvals,
                        &self.mu_pow,
                        &self.margin,
                        &mut self.gains,
                        margin,
                        &self.gain_limit,
                    )
                } else {
                    self.robust.raise_rows(&mut self.gains, margin)
                };
                cap(&mut self.gains, &self.gain_limit);
            }
        }
        self.solve_law(switch, v);
        if kind == InverseKind::Approximate {
            self.residual_of(v);
            self.robust.evaluate(
                kind,
                &self.jvals,
                &self.mu_pow,
                &self.g,
                &self.ah_used,
                &self.gains,
                &self.margin,
                &self.res,
            );
            failures = self.robust.failures(&self.gains);
            if let (Some(margin), true) = (check.raise, failures > 0) {
                self.gain_raises += self.robust.raise_rows(&mut self.gains, margin);
                cap(&mut self.gains, &self.gain_limit);
                // The raised gains change the right-hand side: solve again, warm.
                self.solve_law(switch, v);
            }
        }
        if check.count { failures } else { 0 }
    }

    /// Row `i` of the law's right-hand side, `-alpha_hat_i - k_i sw(s_i)` (with the
    /// exact alpha, `alpha_hat_i` includes `mu_i^(r_i-1) beta_i`), and whether the row
    /// holds the robustness condition `k_i > |alpha_i - alpha_hat_i| + k_i^c` for an
    /// exact solver (a NaN `beta` fails it).
    #[inline]
    fn law_row(&self, i: usize, switch: Switch) -> (f64, bool) {
        let exact_part = self.mu_pow[i] * self.beta[i];
        let (ah, g) = if self.exact_alpha {
            (self.ah[i] + exact_part, 0.0)
        } else {
            (self.ah[i], exact_part)
        };
        let holds = self.gains[i] > g.abs() + self.margin[i];
        (
            -ah - self.gains[i] * switch.of(self.s[i], self.eps[i]),
            holds,
        )
    }

    /// `x = J_s^{-1} b` with the factorisation of the last update.
    pub(crate) fn solve_factored(&mut self, b: &[f64], x: &mut [f64]) {
        self.solver.solve_from(b, x);
    }

    /// `v = J_hat^{-1}(-alpha_hat - K sw(s))`, warm-started from the previous `v`.
    fn solve_law(&mut self, switch: Switch, v: &mut [f64]) {
        for i in 0..self.s.len() {
            self.rhs[i] = -self.ah_used[i] - self.gains[i] * switch.of(self.s[i], self.eps[i]);
        }
        self.solver.solve_from(&self.rhs, v);
    }

    /// `res = rhs - J_s v`.
    fn residual_of(&mut self, v: &[f64]) {
        crate::solve::mul_js(&self.pattern, &self.jvals, &self.mu_pow, v, &mut self.res);
        for (r, b) in self.res.iter_mut().zip(&self.rhs) {
            *r = b - *r;
        }
    }

    /// `z_eq = z - J_hat^{-1} s` with the last factors and the last `s`.
    pub(crate) fn z_eq(&mut self, z: &[f64], out: &mut [f64]) {
        if !self.factored {
            out.copy_from_slice(z);
            return;
        }
        self.solver.solve_from(&self.s, &mut self.dz);
        for ((o, zi), d) in out.iter_mut().zip(z).zip(&self.dz) {
            *o = zi - d;
        }
    }
}

fn cap(gains: &mut [f64], limit: &[f64]) {
    for (k, l) in gains.iter_mut().zip(limit) {
        *k = k.min(*l);
    }
}

/// `mu_i^(r_i - 1)` for every constraint of `model`, the row scaling from `J_Omega` to
/// `J_s`; an error naming the first constraint whose scale overflows or underflows.
pub(crate) fn mu_powers<M: Model + ?Sized>(model: &M, mu: &[f64]) -> Result<Vec<f64>, SimError> {
    let r = model.indices();
    let mu_pow: Vec<f64> = r
        .iter()
        .zip(mu)
        .map(|(&ri, &mi)| mi.powi(ri as i32 - 1))
        .collect();
    match (0..mu_pow.len()).find(|&i| !(mu_pow[i].is_finite() && mu_pow[i] > 0.0)) {
        Some(i) => Err(SimError::Settings {
            field: "mu",
            reason: format!(
                "{:e} for constraint `{}` of index {}: mu^(r-1) = {:e} is not a usable scale (overflow or underflow)",
                mu[i],
                model.constraint_name(i),
                r[i],
                mu_pow[i]
            ),
        }),
        None => Ok(mu_pow),
    }
}
