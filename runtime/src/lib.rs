//! `dae-runtime`: simulation of differential-algebraic models by discretized bounded
//! sliding mode control (DBSMC).
//!
//! A model `x' = f(t, x, z), 0 = g(t, x, z)` of any index is realized as an ODE: `z`
//! becomes a state driven by a control `v = z'` that keeps the sliding variables `s_i`
//! (the constraint residual `w_i` filtered through its derivatives, with time constants
//! `mu_i`) inside boundary layers `|s_i| <= eps_i` that you choose. Steps are explicit
//! and non-iterative; `v` is recomputed only when some `s_i` reaches its layer, so the
//! looser the layer, the fewer the updates. The constraint error that follows is bounded
//! by the layer (docs/method.md).
//!
//! # A model and a run
//!
//! Models are usually written in the `.dae` language and compiled into a Rust type by
//! `dae!` (feature `macros`), or interpreted at run time (feature `families`):
//!
//! ```
//! # #[cfg(feature = "macros")] {
//! use dae_runtime::{Simulator, Trace, dae, design::Online};
//!
//! dae! {
//!     // A planar pendulum of length L: the rod force z keeps the mass on the circle.
//!     model Pendulum {
//!         param m = 1.0, L = 1.0, g = 9.81;
//!         state x = 1.0, y = 0.0, vx = 0.0, vy = 0.0;
//!         alg z = 0.0;
//!         let l = sqrt(x^2 + y^2);
//!         der(x) = vx;
//!         der(y) = vy;
//!         der(vx) = -z * x / (m * l);
//!         der(vy) = -z * y / (m * l) - g;
//!         constraint rod: l = L;
//!     }
//! }
//!
//! // The layer |s| <= 1e-3 over one second: mu, the gains, the law, the step control
//! // and consistent start values, in one call.
//! let model = Pendulum::default();
//! let settings = Online::default().design(&model, &[1e-3], 1.0)?;
//! let mut trace = Trace::new();
//! let summary = Simulator::new(&model, settings)?.run(&mut trace)?;
//! assert!(summary.bound_held());
//! let r = (summary.x[0].powi(2) + summary.x[1].powi(2)).sqrt();
//! assert!((r - 1.0).abs() < 1e-3);
//! # }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`design::Online`] designs from the layers and a time scale (a frame, 1/60 s by
//! default) with no pilot run, gains that follow the drift the run measures; with the
//! values themselves, `Settings::new(eps, mu, gains)` builds the settings, and
//! [`design::auto_design`] designs `mu` and guaranteed fixed gains from pilot runs
//! (docs/method.md, section 5). A model
//! can also be written by hand: implement [`Model`] (its [`ModelInfo`]: name, sizes and names; `f`,
//! the sliding variables, `J_Omega` and `beta`).
//!
//! # Features
//!
//! | feature | what it adds |
//! |---|---|
//! | `macros` | `dae!` and `dae_file!`: a `.dae` model compiled into a Rust type with your crate |
//! | `families` | `family`: family models (chains, hair, cloth: language version 2) sized when they are built, interpreted or generated |
//! | `plot` | `charts`: SVG charts of a recorded run |
//!
//! # Modules
//!
//! * [`Simulator`] runs a [`Model`] under [`Settings`], in one call or in pieces
//!   between which the model may change; it returns a [`Summary`], or a [`SimError`]
//!   that says when, where and by how much.
//! * [`settings`]: the layers and gains, the integrator, the time window and the
//!   control law ([`settings::Law`]: DBSMC with its update rule, gain rule, hold and
//!   in-layer law; the thesis's step-end rule; SPSM).
//! * [`design`]: guaranteed update periods, gains and `mu` from bounds (T 3.14, T 4.4),
//!   and the automatic design from pilot runs.
//! * [`solve`]: the solvers of `J_s` at the updates (dense, sparse direct, linear-time
//!   on trees, approximate inverses checked by the robustness condition T 3.22), the
//!   constraints a singular `J_s` makes redundant ([`solve::Redundancy`]) and the
//!   choice of solving without them ([`solve::RedundantRows`], `Settings::redundant`).
//! * [`trace`]: where samples go (in memory, streamed to CSV, decimated).
//! * [`summary`], [`error`], [`model`]: what a run reports, how it fails, the model
//!   seam. A [`Summary`] prints (`Display`, `summary.to_string()`) as the text `daec
//!   run` shows for the run: a few dozen lines whatever the size of the model.
//!
//! # How a run works
//!
//! `x` is integrated by an error-controlled embedded pair or with a fixed step; `z`
//! follows the exact ramp of the held `v` between updates. With the default law a step
//! ends where some `s_i` reaches its layer moving outward (located on a cubic of `s`
//! and refined on the true `s`), and the control is updated there: `|s_i| / eps_i`
//! stays within `1 + tol` ([`settings::CROSSING_TOL`]) for any step. A layer left after
//! reaching is recorded in [`Summary::bound_loss`] (when, which constraint, how far),
//! and a nearly singular `J_s` is named with it. The long form, with what each
//! algebraic output (`z`, `z_eq`, `z*`) is worth and how to choose a solver, is
//! docs/simulator.md in the repository.
#![warn(missing_docs)]

#[cfg(feature = "macros")]
pub use dae_macros::{dae, dae_file};

#[cfg(feature = "plot")]
pub mod charts;
pub mod design;
pub mod error;
#[cfg(feature = "families")]
pub mod family;
pub mod model;
pub mod settings;
mod sim;
pub mod solve;
pub mod summary;
pub mod trace;

/// `dae-lang` for the code that `dae-codegen` generates for family models (it builds the
/// model's `Construction` from literals). Not an API of this crate.
#[cfg(feature = "families")]
#[doc(hidden)]
pub use dae_lang as __dae_lang;

pub use error::SimError;
pub use model::{Model, ModelInfo};
pub use settings::Settings;
pub use sim::Simulator;
pub use summary::Summary;
pub use trace::Trace;
