//! `dae-bench`: speed against accuracy for DAE simulation methods, generic over any
//! [`dae_runtime::Model`].
//!
//! # What is here
//!
//! * **Baselines** DBSMC is compared with, each over any `M: Model`:
//!   * (a) [`IndexOneRk4`]: RK4 on `x' = f(t, x, z)` with `z` solved at every stage from
//!     `s(x, z) = 0` (Newton with `J_s = diag(mu^(r-1)) J_Omega`, [`ZSolver`]): the
//!     index-1 reduction with Baumgarte-like stabilisation, poles at `-1/mu`;
//!   * (b) SPSM, the runtime's `Law::Spsm`, with [`spsm_stable`] (reached the layers,
//!     then `|s_i| <= 2 eps_i`, finite) and the step search [`largest_stable_step`];
//!   * (c) `bdf_index1` (feature `bdf`, off by default: diffsol and faer are slow to
//!     compile): the `diffsol` crate's variable-order BDF on the same index-1
//!     form, at a chosen tolerance.
//! * **Truth** ([`PlanarChain`], [`reference()`]): planar N-link pendulum chains in minimal
//!   coordinates, equations derived by Lagrange (see the `PlanarChain` docs), integrated
//!   by an adaptive Gragg-Bulirsch-Stoer extrapolation ([`Extrapolation`], order 16) to
//!   `1e-13`, self-checked against a run at a 100 times looser tolerance and by energy,
//!   and mapped to Cartesian coordinates.
//! * **Generated models** ([`DoublePendulum`], [`DoublePendulum3D`], [`Chain5`],
//!   [`Chain3`]): `dae_runtime::dae_file!` on `examples/models/*.dae`; every scene runs
//!   on these. [`chain_scene`] builds a consistent scene for a planar Cartesian chain,
//!   [`embedded_chain_scene`] with [`vertical_plane_map`] for the 3-D pendulum moving
//!   in a vertical plane.
//! * **Independent oracle** [`PlanarChainDae`]: a hand-written Cartesian chain model,
//!   checked against finite differences; the tests compare the generated chains'
//!   `f`, `w` derivatives, `J_Omega` and `beta` with it at random points.
//! * **Particle Jacobians** ([`Particles`]): `J_Omega = -G M^-1 G^T` built by hand for
//!   chains (straight or bent, heavy end), square cloth and random particle trees, the
//!   test and benchmark matrices of the runtime's `J_s` solvers
//!   (`cargo run --release -p dae-bench --example solvers` times every solver at 10^2,
//!   10^3 and 10^4 links with fitted exponents).
//! * **Particle scenes** ([`ParticleScene`], [`c1`] ... [`c4`], [`MethodSpec`],
//!   [`run_particle_method`], [`ParticleRecord`], [`write_particles_csv`]): the scenes of
//!   docs/particles.md through the `dae_particles::Backend` seam, with the baselines
//!   [`Xpbd`] (zero compliance, substeps or iterations) and [`IndexOneParticles`] (RK4,
//!   exact solve at every stage), the DBSMC design from an index-1 pilot
//!   ([`particle_pilot`], [`dbsmc_settings`]), a method's settings run as a series
//!   ([`run_series`]: XPBD's and the index-1 method's costlier settings are left out once
//!   one ran out of its budget or held the tightest level), charts and pictures;
//!   `cargo run --release -p dae-bench --example particles` regenerates
//!   `docs/results/particles.csv` and everything beside it.
//! * **Scenes from generated family models** ([`FamilyParticles`], [`generated_chain`],
//!   [`generated_strands`], [`generated_grid`]): C1 on `examples/models/chain.dae`, C2 on
//!   `bench/models/c2_hair.dae`, C3 and C4 on `bench/models/c3_cloth.dae`, compiled by
//!   `dae_file!`, sized at run time and run by the DBSMC backend as the particle model of
//!   the scene (method `dbsmc-generated`); pins, grabs and releases become the models'
//!   parameter `free[p]` and input `pin[p]` (its position and three derivatives).
//! * **Work-precision harness** ([`Scene`], [`Method`], [`run_method`], [`Record`],
//!   [`write_csv`], [`chart`]): one run per knob value, position error at `t_end`
//!   against the truth, max `|w|`, best-of-N wall time, `J_s` solves, `f` evaluations.
//! * **Stability suite** ([`stability_row`], [`largest_step_row`], [`Envelope`],
//!   [`judge`], [`write_table`]): long runs with a streaming, windowed envelope of the
//!   constraint error, and the verdict table.
//!
//! Scenes start from their own consistent `(x0, z0)` through the runtime's
//! [`Settings::initial`](dae_runtime::Settings::initial) and the baselines' `initial`.
//!
//! # Regenerating the figures
//!
//! `cargo run --release -p dae-bench --features bdf --example work_precision [-- DIR]`
//! writes `work_precision.csv`, `<scene>_position.svg`, `<scene>_constraint.svg`,
//! `<scene>_position_jsolves.svg`, `<scene>_position_fevals.svg` and `stability.md` into
//! `DIR` (default `docs/results/` of the workspace), in about 25 s on two cores once
//! built. `cargo bench -p dae-bench --features bdf --bench step` times one step of each
//! method. The feature `bdf` (off by default, slow to compile) enables baseline (c).
//!
//! # Example
//!
//! ```
//! use dae_bench::{DoublePendulum, Method, PlanarChain, chain_scene, run_method};
//!
//! let chain = PlanarChain::double_pendulum();
//! let model = DoublePendulum::default();
//! // Both links horizontal at rest, 0.5 s.
//! let h = -std::f64::consts::FRAC_PI_2;
//! let scene = chain_scene("dp", &model, &chain, &[h, h], 0.5)?;
//! let r = run_method(&scene, &Method::IndexOne { mu: 0.05, step: 1e-3 }, 1);
//! assert!(r.ok && r.pos_err < 1e-8 && r.max_w < 1e-8);
//! let d = run_method(&scene, &scene.dbsmc(1e-3, 0.05, 1.5), 1);
//! assert!(d.ok && d.max_w < 2e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

mod baseline;
mod generated;
mod harness;
mod particle_bench;
mod particle_methods;
mod particles;
mod scenes;
mod stability;
mod standin;
mod timing;
mod truth;

pub use baseline::*;
pub use generated::{Chain3, Chain5, DoublePendulum, DoublePendulum3D};
pub use harness::{
    BDF_MISSING, CostAxis, DbsmcStep, DesignedBounds, ErrorAxis, Method, Record, Scene, chart,
    designed_bounds, pilot_beta_bound, run_method, step_rule, write_csv,
};
pub use particle_bench::{
    CSV_COLUMNS, Capture, Draws, FrameObserver, FrameTied, Grab, Line, MAX_TIMINGS, MethodSpec,
    NUDGES, NotRun, PILOT_SAFETY, ParticleRecord, ParticleScene, RELAXED_DRIFT_SAFETY,
    RELAXED_GRAZE_PER_MU, RELAXED_MU_PER_FRAME, RELAXED_STEP_PER_MU, RELAXED_TOLERANCE_PER_EPS,
    RETIME_BELOW_MS, STRAIN_LEVELS, SceneDraws, SceneShape, Spread, bisect_least_holding,
    bound_held, c1, c2, c3, c3_with_slack, c4, c4_with_slack, capture_frame, cheapest,
    cheapest_table, dbsmc_runs_table, dbsmc_settings, default_workers, drive_scene, ends_series,
    fitted_exponent, frame_tied_draws, heavy_chain_choices, holding_brackets, index_one, kept_both,
    left_a_guarantee, loglog, parallel_map, parse_workers, particle_pilot, ramped, ratio_chart,
    relaxed_settings, relaxed_settings_at, run_particle_method, run_relaxed_at, run_relaxed_with,
    run_series, scene_groups, scene_of_spec, scene_title, stability_table, strain_chart,
    strain_colour, targets_section, timed_repeatedly, write_particles_csv, write_pictures,
};
pub use particle_methods::{
    ChainKernels, ClothKernels, FamilyParticles, HairKernels, IndexOneParticles, PilotBounds,
    SweepOrder, Xpbd, generated_chain, generated_grid, generated_strands,
};
pub use particles::{Lcg, Particles};
pub use scenes::{SceneError, TRUTH_TOL, chain_scene, embedded_chain_scene, vertical_plane_map};
pub use stability::{
    DRIFT_FLOOR, DRIFT_GROWTH, Envelope, StabilityRow, Verdict, envelope_run, judge,
    largest_step_row, stability_row, with_step, write_table,
};
pub use standin::{MAX_LINKS, PlanarChainDae};
pub use timing::best_time;
pub use truth::{
    ChainWork, Extrapolation, PlanarChain, Reference, TruthError, TruthStats, reference,
};
