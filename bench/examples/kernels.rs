//! Where the generated family models' extra cost is: one evaluation of each per-step
//! function (`rhs`, `sliding`, `jacobian`, `beta`) of the generated model of a scene
//! (`dae_bench::generated_chain`, `generated_grid`: the `.dae` family compiled by
//! `dae_file!`, behind `FamilyParticles`) against the hand-written
//! `dae_particles::ParticleModel` of the same system, both through the runtime's `Model`
//! trait, at the scene's initial point with every tension 1.
//!
//! ```text
//! cargo run --release -p dae-bench --example kernels
//! ```
//!
//! Chains of 100, 1,000 and 10,000 links (C1, end-mass ratio 1e2) and cloths of 16 x 16,
//! 32 x 32 and 64 x 64 (C3 (a)). Times are the best of 5 batches of at least 20 ms
//! each, one core; the ratios, measured in one run, are what to read (the benchmark's
//! DBSMC runs on the generated models cost 1.46x those on the hand-written model, median
//! of 26 complete runs). The last column is the sum of the four, weighted as a DBSMC step
//! calls them (7 `rhs`, 3 `sliding`, 2 `jacobian`, 2 `beta`: the calls per step of the
//! ramped design on the heavy 100-link chain at eps = 1e-4, counted with callgrind
//! (6.9, 3.4, 1.9, 1.9), rounded).

use std::hint::black_box;

use dae_bench::{best_time, generated_chain, generated_grid};
use dae_particles::{FAR_EDGE_SLACK, GridPins, ParticleModel, System};
use dae_runtime::Model;

/// Seconds per evaluation of rhs, sliding, jacobian and beta at the initial point.
fn times(m: &dyn Model) -> [f64; 4] {
    let (n, k) = (m.n_states(), m.n_constraints());
    let mut x = vec![0.0; n];
    m.initial_state(&mut x);
    let z = vec![1.0; k];
    let mu = vec![0.1; k];
    let nw: usize = m.indices().iter().sum();
    let (mut dx, mut w, mut s, mut ah) = (vec![0.0; n], vec![0.0; nw], vec![0.0; k], vec![0.0; k]);
    let mut j = vec![0.0; m.jacobian_pattern().len()];
    let mut b = vec![0.0; k];
    [
        best_time(|| m.rhs(0.1, black_box(&x), &z, &mut dx)),
        best_time(|| m.sliding(0.1, black_box(&x), &z, &mu, &mut w, &mut s, &mut ah)),
        best_time(|| m.jacobian(0.1, black_box(&x), &z, &mut j)),
        best_time(|| m.beta(0.1, black_box(&x), &z, &mut b)),
    ]
}

/// Calls per DBSMC step (rhs, sliding, jacobian, beta); see the module docs.
const PER_STEP: [f64; 4] = [7.0, 3.0, 2.0, 2.0];

fn row(scene: &str, links: usize, hand: &dyn Model, generated: &dyn Model) {
    let (h, g) = (times(hand), times(generated));
    let cell = |i: usize| format!("{:.1} / {:.1} ({:.2})", h[i] * 1e6, g[i] * 1e6, g[i] / h[i]);
    let step = |t: &[f64; 4]| t.iter().zip(PER_STEP).map(|(t, k)| t * k).sum::<f64>();
    println!(
        "| {scene} | {links} | {} | {} | {} | {} | {:.2} |",
        cell(0),
        cell(1),
        cell(2),
        cell(3),
        step(&g) / step(&h)
    );
}

fn main() {
    println!(
        "Microseconds per evaluation, hand-written / generated (ratio); last column: the four weighted as a step calls them, generated / hand-written.\n"
    );
    println!("| scene | links | rhs | sliding | jacobian | beta | per step |");
    println!("|---|---|---|---|---|---|---|");
    let fail = |what: &str, e: String| -> ! {
        eprintln!("kernels: {what}: {e}");
        std::process::exit(1);
    };
    for n in [100, 1000, 10_000] {
        let system: System =
            dae_particles::chain(n, 1e2).unwrap_or_else(|e| fail("chain", e.to_string()));
        let hand = ParticleModel::new(&system).unwrap_or_else(|e| fail("chain", e.to_string()));
        let generated = generated_chain(&system, n, 1e2).unwrap_or_else(|e| fail("chain", e));
        row("C1 r=1e2", n, &hand, &generated);
    }
    for w in [16, 32, 64] {
        let system = dae_particles::grid_with_slack(w, GridPins::Corners, false, FAR_EDGE_SLACK)
            .unwrap_or_else(|e| fail("grid", e.to_string()));
        let hand = ParticleModel::new(&system).unwrap_or_else(|e| fail("grid", e.to_string()));
        let generated = generated_grid(&system, w, GridPins::Corners, false, FAR_EDGE_SLACK)
            .unwrap_or_else(|e| fail("grid", e));
        row(
            &format!("C3 (a) {w} x {w}"),
            system.links().len(),
            &hand,
            &generated,
        );
    }
}
