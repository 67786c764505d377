//! `dae-runtime`: simulation of DAE models by discretized bounded sliding mode control.
//!
//! A model `x' = f(t, x, z), 0 = g(t, x, z)` (the [`Model`] trait, usually generated from
//! a `.dae` model by `dae!`) is realized as an ODE by making `z` a state driven by a control
//! `v = z'` that keeps the sliding variables `s_i` (combinations of the constraint
//! residual `w_i` and its derivatives) inside boundary layers `|s_i| <= eps_i`.
//!
//! # What the simulator does
//!
//! * **State.** `x` is integrated with a fixed step `h` ([`Integrator::Euler`] or
//!   [`Integrator::Rk4`]). `z` is held by a zero-order hold of `v`: between updates
//!   `z(t) = z_b + v (t - t_b)` exactly, also inside the RK4 stages.
//! * **Control update.** `v = J_hat^{-1}(-alpha_hat - K sgn(s))` with
//!   `J_s = diag(mu_i^(r_i-1)) J_Omega` from [`Model::jacobian_pattern`] and
//!   [`Model::jacobian`], factored once per update by the solver of
//!   [`Settings::solver`] (exact by default, `J_hat = J_s`; see *Solving with `J_s`*
//!   below); a singular `J_s` is [`SimError::SingularJacobian`] naming the dependent
//!   constraints and the time. `alpha_hat` is the cheap one from [`Model::sliding`] or
//!   the exact `alpha_hat + mu^(r-1) beta` ([`AlphaChoice`]).
//! * **When to update** ([`Policy`]): monitoring (after every step, as soon as some
//!   `|s_i| >= eps_i` while moving outward), a fixed period, or SPSM (`sat(s/eps)` and `v`
//!   recomputed at every stage, the continuous baseline).
//! * **Reaching phase** ([`Reaching`]): attracting surfaces or contracting layers while
//!   the initial `s` is outside the layers; [`Settings::reaching_limit`] bounds its
//!   duration ([`SimError::ReachingTimeout`]).
//! * **`z_eq`.** `z` itself is a ramp that oscillates around the algebraic solution with
//!   an amplitude set by the gains. The value to trust is
//!   `z_eq = z - J_s^{-1} s(x, z)` (with the `J_s` factored at the last update): the `z`
//!   that puts the state on `s = 0`, exact when `Omega` is affine in `z`. It is reported
//!   in every trace sample and in the [`Summary`].
//!
//! # How crossings are located, and what it costs
//!
//! Boundary crossings are detected once per step, at the step's end: an update happens
//! at the end of the first step after which `|s_i| >= eps_i` and `s_i` moved outward
//! over that step (`s_i (s_i - s_i,prev) > 0`: the derivative `s_i'` is estimated by the
//! finite difference over the step, which needs no model call and includes the part
//! `mu^(r-1) beta` that the cheap `alpha_hat` neglects). The crossing is not
//! interpolated back into the step, so `s_i` can overshoot its layer by at most one step
//! of motion, `|s_i'| h`; choose `h` so that this is small against `eps_i`. The cost per
//! step is one [`Model::sliding`] evaluation plus `f` (1 for Euler, 4 for RK4); an update
//! adds one [`Model::jacobian`], one factorisation, one solve and, with the exact alpha
//! or robustness counting ([`Settings::check_robustness`]), one [`Model::beta`]. Each
//! recorded sample adds one solve for `z_eq`.
//!
//! Checking only `|s_i| >= eps_i` (without "moving outward") would re-trigger on the step
//! right after every update, while `s_i` is still outside but already turning back, and
//! collapse the period to one step.
//!
//! # Solving with `J_s`
//!
//! Every solve with `J_s` (the simulator, the design toolkit's
//! [`approximate_inverse_gains`], the baselines of `dae-bench`) goes through one seam,
//! the [`LinearSolver`] trait, implemented by [`Solver`]: built once per pattern (the
//! symbolic analysis), [`factor`](LinearSolver::factor)ed with the values of
//! `J_Omega` and the row scaling `mu_i^(r_i-1)` at each update, then applied to any
//! number of right-hand sides. The solvers ([`SolverChoice`], `daec run --solver`):
//!
//! | choice | what | cost per update | memory |
//! |---|---|---|---|
//! | `dense` | LU with partial pivoting | `O(m^3)` | `m^2` |
//! | `sparse` | ordering + elimination tree once; multifrontal `LDL^T` for symmetric values, up-looking `LU` with diagonal pivots otherwise | `O(flops of the factor)` | `O(nnz(L))` |
//! | `tree` | elimination along a forest (chains, hair strands) | `O(m)` | `O(m)` |
//! | `jacobi` | `J_hat = diag(J_s)` | `O(m)` | `O(nnz)` |
//! | `gauss-seidel:K` | `K` forward sweeps, warm-started | `O(K nnz)` | `O(nnz)` |
//! | `cg:K` | `K` Jacobi-preconditioned CG iterations, warm-started (symmetric `J_Omega`) | `O(K nnz)` | `O(nnz)` |
//! | `ilu0` | incomplete LU without fill | `O(nnz * row length)` | `O(nnz)` |
//!
//! **How to choose.** [`SolverChoice::Auto`] (the default) stays exact: dense LU up
//! to [`DENSE_MAX`] constraints (or for a pattern denser than a quarter), the forest
//! elimination when the graph of the pattern's off-diagonal entries has no cycle, the
//! sparse solver otherwise. The sparse solver's
//! ordering is a perfect elimination ordering (maximum cardinality search) when that
//! graph is chordal, which the link graph of any particle tree is (the links at a
//! particle form a clique, two cliques share at most one link): branching hair is then
//! factored with no fill, in time linear in the entries. Other graphs (cloth) get
//! minimum degree. The sparse and tree solvers pivot on the diagonal (no row
//! exchanges): right for particle systems, where `J_Omega = -G M^-1 G^T` is negative
//! definite, and diagnosed otherwise ([`SimError::SolverFailed`] says to use `dense`
//! when a diagonal pivot vanishes on a nonsingular `J_s`). The approximate inverses
//! are never chosen automatically: they change the dynamics and need the gains of the
//! next section. Measured costs: `cargo run --release -p dae-bench --example solvers`
//! (64 x 64 cloth, 8,064 links: about 3 ms exact, 0.1–0.5 ms approximate).
//!
//! **Why our own sparse solver.** Measured on the 64 x 64 cloth (one core): faer 0.24's
//! supernodal `LL^T` factors in 2.8 ms (solve 0.17 ms) but costs 1 min 46 s of cold
//! compilation (2 min 6 s CPU); nalgebra-sparse 0.12's `CscCholesky` adds about 15 s
//! to nalgebra's cold build but has no fill-reducing ordering (50 ms per refactor on the
//! cloth in link order, a million factor entries); this module adds about 2 s to the
//! crate's build and factors in 2.5 ms (solve 0.26 ms).
//!
//! # Robustness with an approximate `J_hat` (T 3.22)
//!
//! With `E = J_s J_hat^{-1}`, `D = E K` and `gamma = alpha - E alpha_hat`, the
//! crossing condition holds for every sign pattern when each row satisfies
//! `D_ii > |gamma_i| + sum_{j != i} |D_ij| + k_i^c` (`k^c`:
//! [`Settings::crossing_margin`]). With [`Settings::check_robustness`] (on by default)
//! it is evaluated at every update in the statistics window and the failing rows are
//! counted ([`Summary::robustness_violations`], [`SolverSummary`]):
//!
//! * exact solvers (`E = I`): `k_i > |alpha_i - alpha_hat_i| + k_i^c`, exactly;
//! * `jacobi` (`E = J_s diag(J_s)^{-1}`, unit diagonal): formed row by row from the
//!   pattern in `O(nnz)`, exactly;
//! * iterations and `ilu0`: `E` is not formed. The computed `v` satisfies
//!   `J_s v = b - r` (residual `r`, one multiplication by `J_s`), so at the update
//!   `s' = (alpha - alpha_hat) - K sgn(s) - r`, and `k_i > |alpha_i - alpha_hat_i| +
//!   |r_i| + k_i^c` guarantees the crossing of row `i` for this update's sign pattern:
//!   an upper bound of what (T 3.22) asks, exact for the held `v`.
//!
//! [`Settings::raise_gains`] turns the count into a policy: each failing row's gain is
//! raised to `(1 + margin)` times its requirement before `v` is computed (the Jacobi
//! rows in passes, which converge to the least gains when the coupling's spectral
//! radius is below one, see there). A straight chain solved with `jacobi` is the case
//! in point: its `J_Omega` is only weakly diagonally dominant, so with equal gains every
//! interior row fails by equality, and raised (unequal) gains restore the condition. To
//! design for an approximation beforehand: [`approximate_inverse_gain`] (from a row's
//! dominance margin), [`approximate_inverse_gains`] (least gains for a coupling `E`,
//! e.g. [`jacobi_coupling`]).
//!
//! **`z` and `z_eq` with an approximate inverse.** `z` is still the held ramp: it
//! oscillates around the algebraic solution `z*` with an amplitude set by the gains, so
//! raised gains widen it. `z_eq = z - J_hat^{-1} s` is one quasi-Newton step towards the
//! `z` on `s = 0`: for `Omega` affine in `z`, `z_eq - z* = (I - J_hat^{-1} J_s)(z - z*)`,
//! so it improves on `z` only as far as `J_hat` is good (`|I - J_hat^{-1} J_s| < 1`;
//! for `jacobi` on a weakly dominant chain barely). The iterative solvers warm-start
//! each `z_eq` solve from the previous correction, so along a run their `z_eq`
//! accumulates iterations while `s` changes slowly. Where the algebraic outputs matter,
//! record with an exact solver or more iterations.
//!
//! # Recording
//!
//! Samples go to a [`Sink`]: a [`Trace`] in memory, a [`CsvSink`] that streams, either
//! wrapped in [`Decimate`] to keep every k-th step or a minimum time spacing, two of them
//! at once with [`Tee`] (an `Option` of a sink is a sink that may be absent). Update
//! times are always recorded. A failed run leaves the sink with everything up to the
//! failure.
//!
//! # Example
//!
//! ```
//! use dae_runtime::{Model, Settings, Simulator, Trace};
//!
//! /// x' = z - x, 0 = x - sin t (index 2): exact x = sin t, z = sin t + cos t.
//! struct Tracking;
//! impl Model for Tracking {
//!     fn name(&self) -> &str { "tracking" }
//!     fn n_states(&self) -> usize { 1 }
//!     fn n_constraints(&self) -> usize { 1 }
//!     fn n_params(&self) -> usize { 0 }
//!     fn state_name(&self, _: usize) -> &str { "x" }
//!     fn alg_name(&self, _: usize) -> &str { "z" }
//!     fn constraint_name(&self, _: usize) -> &str { "track" }
//!     fn param_name(&self, _: usize) -> &str { "" }
//!     fn indices(&self) -> &[usize] { &[2] }
//!     fn param(&self, _: usize) -> f64 { 0.0 }
//!     fn set_param(&mut self, _: usize, _: f64) {}
//!     fn initial_state(&self, x: &mut [f64]) { x[0] = 0.0 }
//!     fn initial_alg(&self, z: &mut [f64]) { z[0] = 1.0 }
//!     fn rhs(&self, _: f64, x: &[f64], z: &[f64], dx: &mut [f64]) { dx[0] = z[0] - x[0] }
//!     fn sliding(&self, t: f64, x: &[f64], z: &[f64], mu: &[f64],
//!                w: &mut [f64], s: &mut [f64], ah: &mut [f64]) {
//!         w[0] = x[0] - t.sin();
//!         w[1] = z[0] - x[0] - t.cos();
//!         s[0] = mu[0] * w[1] + w[0];
//!         ah[0] = w[1];
//!     }
//!     fn jacobian_pattern(&self) -> &[(usize, usize)] { &[(0, 0)] }
//!     fn jacobian(&self, _: f64, _: &[f64], _: &[f64], j: &mut [f64]) { j[0] = 1.0 }
//!     fn beta(&self, t: f64, x: &[f64], z: &[f64], b: &mut [f64]) {
//!         b[0] = -(z[0] - x[0]) + t.sin();
//!     }
//! }
//!
//! let settings = Settings::new(vec![1e-3], vec![0.05], vec![0.1]).step(1e-3).t_end(2.0);
//! let mut trace = Trace::new();
//! let summary = Simulator::new(&Tracking, settings)?.run(&mut trace)?;
//! let t = summary.t_end;
//! assert!((summary.x[0] - t.sin()).abs() < 2e-3);
//! assert!((summary.z_eq[0] - (t.sin() + t.cos())).abs() < 0.05);
//! # Ok::<(), dae_runtime::SimError>(())
//! ```
#![warn(missing_docs)]

#[cfg(feature = "macros")]
pub use dae_macros::{dae, dae_file};

#[cfg(feature = "plot")]
mod charts;
mod design;
#[cfg(feature = "families")]
pub mod family;
/// `dae-lang` for the code that `dae-codegen` generates for family models (it builds the
/// model's `Construction` from literals). Not an API of this crate.
#[cfg(feature = "families")]
#[doc(hidden)]
pub use dae_lang as __dae_lang;
mod model;

#[cfg(feature = "plot")]
pub use charts::{
    ChartError, ErrorSeries, RunCharts, SlidingSeries, YScale, plot_errors, plot_periods, plot_run,
    plot_sliding,
};
pub use design::{
    AutoDesign, AutoDesignOptions, ConstraintDesign, ConstraintSpec, Design, DesignError,
    DesignPass, GainChoice, LayerBound, MAX_INDEX, MuChoice, MuSearch, PilotError, PilotEstimate,
    PilotEstimator, PilotRun, PilotRunError, approximate_inverse_gain, approximate_inverse_gains,
    auto_design, c_r, design, design_at, jacobi_coupling, optimise_mu, pilot_run, pilot_specs,
    reachable_bound, robust_gain, sufficient_gain, t_min,
};
pub use model::{Model, w_offsets};

// The simulator: settings, control law, integration, traces, summary, errors.
mod error;
mod settings;
mod sim;
mod solve;
mod summary;
mod trace;

pub use error::{Quantity, SimError};
pub use settings::{AlphaChoice, Initial, Integrator, Policy, Reaching, Settings};
pub use sim::Simulator;
pub use solve::{
    DENSE_MAX, InverseKind, LinearSolver, SolveError, Solver, SolverChoice, SolverStats, mul_js,
};
pub use summary::{SolverSummary, Summary};
pub use trace::{CsvSink, Decimate, Layout, NoTrace, Sample, Sink, Tee, Trace};
