//! What a layer `eps` gives in position, tension and energy: the online design
//! (`dae_runtime::design::Online`, what `daec run --t-end T --eps E` uses) on planar
//! pendulum chains, against the truth in minimal coordinates (`dae_bench::truth`,
//! integrated to 1e-13 by extrapolation), sampled at ten times of each run.
//!
//! `cargo run --release -p dae-bench --example eps_accuracy`
//!
//! Columns, each the largest over the samples: `|w|` the constraint error (m), `pos` the
//! position error (m), `z` the tension error of the simulator's `z` relative to the
//! largest true tension, `z*` the same for the tensions consistent with the simulated
//! state (`design::consistent_start`), `energy` the change of `T + V` over the run
//! relative to `sum m_k g L` (the truth conserves it to 1e-12).

use std::time::Instant;

use dae_bench::generated::{Chain5, DoublePendulum};
use dae_bench::scenes::chain_scene;
use dae_bench::truth::{PlanarChain, reference};
use dae_runtime::design::{Online, consistent_start};
use dae_runtime::trace::NoTrace;
use dae_runtime::{Model, Simulator};

/// Samples per run.
const SAMPLES: usize = 10;
/// Truth tolerance.
const TRUTH_TOL: f64 = 1e-13;

/// Total energy of a planar Cartesian chain state (`[x, y, vx, vy]` per particle).
fn energy(chain: &PlanarChain, masses: &[f64], x: &[f64]) -> f64 {
    (0..chain.links())
        .map(|k| {
            let p = &x[4 * k..4 * k + 4];
            0.5 * masses[k] * (p[2] * p[2] + p[3] * p[3]) + masses[k] * 9.8 * p[1]
        })
        .sum()
}

struct Row {
    w: f64,
    pos: f64,
    z: f64,
    z_star: f64,
    energy: f64,
    updates: u64,
    wall: f64,
}

fn measure<M: Model>(
    model: &M,
    chain: &PlanarChain,
    masses: &[f64],
    lengths: &[f64],
    theta0: &[f64],
    t_end: f64,
    eps: f64,
) -> Result<Row, Box<dyn std::error::Error>> {
    let scene = chain_scene("accuracy", model, chain, theta0, t_end)?;
    let n = chain.links();
    let y0: Vec<f64> = theta0.iter().copied().chain(vec![0.0; n]).collect();
    let settings = Online::default()
        .settings(vec![eps; n])?
        .t_end(t_end)
        .initial(scene.x0.clone(), scene.z0.clone());
    let scale: f64 = masses.iter().sum::<f64>() * 9.8 * lengths.iter().sum::<f64>();
    let e0 = energy(chain, masses, &scene.x0);
    let mut sim = Simulator::new(model, settings)?;
    sim.start(&mut NoTrace)?;
    let mut row = Row {
        w: 0.0,
        pos: 0.0,
        z: 0.0,
        z_star: 0.0,
        energy: 0.0,
        updates: 0,
        wall: 0.0,
    };
    let mut wall = 0.0;
    for k in 1..=SAMPLES {
        let t = t_end * k as f64 / SAMPLES as f64;
        let lap = Instant::now();
        sim.advance_to(t, &mut NoTrace)?;
        wall += lap.elapsed().as_secs_f64();
        let truth = reference(chain, &y0, t, TRUTH_TOL)?;
        let x = sim.state();
        let positions: Vec<f64> = (0..n).flat_map(|k| [x[4 * k], x[4 * k + 1]]).collect();
        row.pos = positions
            .iter()
            .zip(&truth.positions)
            .fold(row.pos, |m, (a, b)| m.max((a - b).abs()));
        let mut prev = [0.0, 0.0];
        for k in 0..n {
            let (dx, dy) = (x[4 * k] - prev[0], x[4 * k + 1] - prev[1]);
            row.w = row.w.max(((dx * dx + dy * dy).sqrt() - lengths[k]).abs());
            prev = [x[4 * k], x[4 * k + 1]];
        }
        let z_true = chain.tensions(&truth.angles);
        let z_max = z_true.iter().fold(0.0f64, |m, z| m.max(z.abs()));
        let rel = |z: &[f64]| {
            z.iter()
                .zip(&z_true)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs() / z_max))
        };
        row.z = row.z.max(rel(sim.alg()));
        let star = consistent_start(model, t, x, sim.alg())?;
        row.z_star = row.z_star.max(rel(&star.z0));
        row.energy = row
            .energy
            .max((energy(chain, masses, x) - e0).abs() / scale);
    }
    let summary = sim.finish(&mut NoTrace)?;
    if let Some(loss) = summary.bound_loss {
        return Err(format!(
            "`{}` left its layer at t = {:.4}",
            loss.first_constraint, loss.first_time
        )
        .into());
    }
    if !summary.bound_held() {
        return Err("the layers were not reached".into());
    }
    row.updates = summary.updates;
    row.wall = wall;
    Ok(row)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dp = PlanarChain::double_pendulum();
    let chain5 = PlanarChain::new(vec![0.1; 5], vec![0.5; 5], 9.8)?;
    let dp_model = DoublePendulum::default();
    // chain5_planar.dae has one length `L` (1 m by default): the truth's 0.5 m.
    let c5_model = Chain5 {
        L: 0.5,
        ..Chain5::default()
    };
    println!(
        "| scene | eps | max \\|w\\| (m) | position (m) | z (rel.) | z* (rel.) | energy (rel.) | updates | run (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for eps in [1e-1, 1e-2, 1e-3, 1e-4] {
        for (name, result) in [
            (
                "double pendulum, horizontal at rest, 2 s",
                measure(
                    &dp_model,
                    &dp,
                    &[0.1, 0.1],
                    &[2.0, 2.0],
                    &[-std::f64::consts::FRAC_PI_2; 2],
                    2.0,
                    eps,
                ),
            ),
            (
                "5-link chain, 2 s",
                measure(
                    &c5_model,
                    &chain5,
                    &[0.1; 5],
                    &[0.5; 5],
                    &[-1.2, -0.9, -0.6, -0.3, 0.0],
                    2.0,
                    eps,
                ),
            ),
        ] {
            match result {
                Ok(r) => println!(
                    "| {name} | {eps:e} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {} | {:.3} |",
                    r.w, r.pos, r.z, r.z_star, r.energy, r.updates, r.wall
                ),
                Err(e) => println!("| {name} | {eps:e} | failed: {e} |||||||"),
            }
        }
    }
    Ok(())
}
