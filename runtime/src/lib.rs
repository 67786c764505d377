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
//! * **Control update.** `v = J_s^{-1}(-alpha_hat - K sgn(s))` with
//!   `J_s = diag(mu_i^(r_i-1)) J_Omega` assembled from [`Model::jacobian_pattern`] and
//!   [`Model::jacobian`] and LU-factored once per update (partial pivoting, in a
//!   preallocated buffer); a singular `J_s` is [`SimError::SingularJacobian`] naming the
//!   constraints and the time. `alpha_hat` is the cheap one from [`Model::sliding`] or the
//!   exact `alpha_hat + mu^(r-1) beta` ([`AlphaChoice`]).
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
//! adds one [`Model::jacobian`], one `m x m` LU, one solve and, with the exact alpha or
//! robustness counting ([`Settings::check_robustness`]), one [`Model::beta`]. Each
//! recorded sample adds one triangular solve for `z_eq`.
//!
//! Checking only `|s_i| >= eps_i` (without "moving outward") would re-trigger on the step
//! right after every update, while `s_i` is still outside but already turning back, and
//! collapse the period to one step.
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
mod model;

#[cfg(feature = "plot")]
pub use charts::{
    ChartError, ErrorSeries, RunCharts, SlidingSeries, YScale, plot_errors, plot_periods, plot_run,
    plot_sliding,
};
pub use design::{
    AutoDesign, AutoDesignOptions, ConstraintDesign, ConstraintSpec, Design, DesignError,
    DesignPass, GainChoice, LayerBound, MAX_INDEX, MuChoice, MuSearch, PilotError, PilotEstimate,
    PilotEstimator, PilotRun, PilotRunError, auto_design, c_r, design, design_at, optimise_mu,
    pilot_run, pilot_specs, reachable_bound, robust_gain, sufficient_gain, t_min,
};
pub use model::{Model, w_offsets};

// The simulator: settings, control law, integration, traces, summary, errors.
mod error;
mod settings;
mod sim;
mod summary;
mod trace;

pub use error::{Quantity, SimError};
pub use settings::{AlphaChoice, Initial, Integrator, Policy, Reaching, Settings};
pub use sim::Simulator;
pub use summary::Summary;
pub use trace::{CsvSink, Decimate, Layout, NoTrace, Sample, Sink, Tee, Trace};
