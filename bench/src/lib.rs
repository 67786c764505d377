//! `dae-bench`: speed against accuracy for DAE simulation methods, generic over any
//! [`dae_runtime::Model`].
//!
//! # What is here
//!
//! * **Baselines** DBSMC is compared with, each over any `M: Model`:
//!   * (a) [`IndexOneRk4`](baseline::IndexOneRk4): RK4 on `x' = f(t, x, z)` with `z` solved at every stage from
//!     `s(x, z) = 0` (Newton with `J_s = diag(mu^(r-1)) J_Omega`, [`ZSolver`](baseline::ZSolver)): the
//!     index-1 reduction with Baumgarte-like stabilisation, poles at `-1/mu`;
//!   * (b) SPSM, the runtime's `Law::Spsm`, with [`spsm_stable`](baseline::spsm_stable) (reached the layers,
//!     then `|s_i| <= 2 eps_i`, finite) and the step search [`largest_stable_step`](baseline::largest_stable_step);
//!   * (c) `bdf_index1` (feature `bdf`, off by default: diffsol and faer are slow to
//!     compile): the `diffsol` crate's variable-order BDF on the same index-1
//!     form, at a chosen tolerance.
//! * **Truth** ([`PlanarChain`](truth::PlanarChain), [`reference()`](truth::reference)): planar N-link pendulum chains in minimal
//!   coordinates, equations derived by Lagrange (see the `PlanarChain` docs), integrated
//!   by an adaptive Gragg-Bulirsch-Stoer extrapolation ([`Extrapolation`](truth::Extrapolation), order 16) to
//!   `1e-13`, self-checked against a run at a 100 times looser tolerance and by energy,
//!   and mapped to Cartesian coordinates.
//! * **Generated models** ([`DoublePendulum`](generated::DoublePendulum), [`DoublePendulum3D`](generated::DoublePendulum3D), [`Chain5`](generated::Chain5),
//!   [`Chain3`](generated::Chain3)): `dae_runtime::dae_file!` on `examples/models/*.dae`; every scene runs
//!   on these. [`chain_scene`](scenes::chain_scene) builds a consistent scene for a planar Cartesian chain,
//!   [`embedded_chain_scene`](scenes::embedded_chain_scene) with [`vertical_plane_map`](scenes::vertical_plane_map) for the 3-D pendulum moving
//!   in a vertical plane.
//! * **Independent oracle** [`PlanarChainDae`](standin::PlanarChainDae): a hand-written Cartesian chain model,
//!   checked against finite differences; the tests compare the generated chains'
//!   `f`, `w` derivatives, `J_Omega` and `beta` with it at random points.
//! * **Particle Jacobians** ([`Particles`](particles::Particles)): `J_Omega = -G M^-1 G^T` built by hand for
//!   chains (straight or bent, heavy end), square cloth and random particle trees, the
//!   test and benchmark matrices of the runtime's `J_s` solvers
//!   (`cargo run --release -p dae-bench --example solvers` times every solver at 10^2,
//!   10^3 and 10^4 links with fitted exponents).
//! * **Particle scenes** ([`ParticleScene`](particle_bench::ParticleScene), [`c1`](particle_bench::c1) ... [`c7`](particle_bench::c7), [`MethodSpec`](particle_bench::MethodSpec),
//!   [`run_particle_method`](particle_bench::run_particle_method), [`ParticleRecord`](particle_bench::ParticleRecord), [`write_particles_csv`](particle_bench::write_particles_csv)): the scenes of
//!   docs/particles.md through the `dae_particles::Backend` seam, with the baselines
//!   [`Xpbd`](particle_methods::Xpbd) (zero compliance, substeps or iterations),
//!   [`Vbd`](particle_methods::Vbd) and [`Avbd`](particle_methods::Avbd) (vertex block
//!   descent on stiff springs, and with hard links) and [`IndexOneParticles`](particle_methods::IndexOneParticles) (RK4,
//!   exact solve at every stage), the DBSMC design from an index-1 pilot
//!   ([`particle_pilot`](particle_bench::particle_pilot), [`dbsmc_settings`](particle_bench::dbsmc_settings)), a method's settings run as a series
//!   ([`run_series`](particle_bench::run_series): XPBD's and the index-1 method's costlier settings are left out once
//!   one ran out of its budget or held the tightest level), charts and pictures;
//!   `cargo run --release -p dae-bench --example particles` regenerates
//!   `docs/results/particles.csv` and everything beside it.
//! * **Scenes from generated family models** ([`generated_chain`](particle_methods::generated_chain),
//!   [`generated_strands`](particle_methods::generated_strands), [`generated_grid`](particle_methods::generated_grid)): C1 on `examples/models/chain.dae`, C2 on
//!   `bench/models/c2_hair.dae`, C3 and C4 on `bench/models/c3_cloth.dae`, compiled by
//!   `dae_file!`, sized at run time and run by the DBSMC backend as the particle model of
//!   the scene behind [`dae_particles::FamilyParticles`] (method `dbsmc-generated`); pins, grabs and releases become the models'
//!   parameter `free[p]` and input `pin[p]` (its position and three derivatives).
//! * **Work-precision harness** ([`Scene`](harness::Scene), [`Method`](harness::Method), [`run_method`](harness::run_method), [`Record`](harness::Record),
//!   [`write_csv`](harness::write_csv), [`chart`](harness::chart)): one run per knob value, position error at `t_end`
//!   against the truth, max `|w|`, best-of-N wall time, `J_s` solves, `f` evaluations.
//! * **Stability suite** ([`stability_row`](stability::stability_row), [`largest_step_row`](stability::largest_step_row), [`Envelope`](stability::Envelope),
//!   [`judge`](stability::judge), [`write_table`](stability::write_table)): long runs with a streaming, windowed envelope of the
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
//! use dae_bench::generated::DoublePendulum;
//! use dae_bench::harness::{Method, run_method};
//! use dae_bench::scenes::chain_scene;
//! use dae_bench::truth::PlanarChain;
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

pub mod baseline;
pub mod generated;
pub mod harness;
pub mod particle_bench;
pub mod particle_methods;
pub mod particles;
pub mod scenes;
pub mod stability;
pub mod standin;
pub mod timing;
pub mod truth;
