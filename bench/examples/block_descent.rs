//! VBD and AVBD (`dae_bench::particle_methods::{Vbd, Avbd}`) against coloured XPBD on
//! C1 with a heavy end (`chain(10, 1e2)`, released horizontal) over 5 s: the worst
//! relative strain `|l - L| / L` over the links after each of the 300 frames, and the
//! wall time of the run.
//!
//! ```text
//! cargo run --release -p dae-bench --example block_descent
//! ```
//!
//! The wall times are of one run each: compare them on a quiet machine.

use std::time::Instant;

use dae_bench::particle_methods::{Avbd, SweepOrder, Vbd, Xpbd};
use dae_particles::{Backend, System, chain};

/// Runs `backend` frame by frame to 5 s; the worst strain after a frame, when it
/// happened, and the wall time (s). A failure ends the run and is reported.
fn run(system: &System, mut backend: impl Backend) -> Result<(f64, f64, f64), String> {
    let mut x = vec![[0.0; 3]; system.n_particles()];
    let mut worst = (0.0f64, 0.0);
    let start = Instant::now();
    for f in 1..=300 {
        let t = f as f64 / 60.0;
        backend.advance_to(t).map_err(|e| e.to_string())?;
        backend.positions(&mut x);
        let (s, _) = system.worst_strain(&x);
        if s.is_nan() || s > worst.0 {
            worst = (s, t);
        }
    }
    Ok((worst.0, worst.1, start.elapsed().as_secs_f64()))
}

fn main() {
    let system = chain(10, 1e2).expect("C1");
    let mut rows: Vec<Box<dyn Backend>> = Vec::new();
    for (k, n) in [(1, 10), (4, 10), (16, 4), (64, 1)] {
        rows.push(Box::new(Vbd::new(&system, k, n).expect("vbd")));
    }
    for (k, n) in [(1, 10), (4, 10), (16, 4), (64, 1)] {
        rows.push(Box::new(Avbd::new(&system, k, n).expect("avbd")));
    }
    for k in [16, 64] {
        rows.push(Box::new(
            Xpbd::new(&system, k, 1, SweepOrder::Coloured).expect("xpbd"),
        ));
    }
    println!("chain(10, 1e2), 300 frames of 1/60 s");
    println!(
        "{:<24} {:>12} {:>8} {:>10} {:>12}",
        "method", "worst strain", "at (s)", "wall (s)", "sweeps"
    );
    for backend in rows {
        let name = backend.name();
        let mut b = backend;
        match run(&system, &mut *b) {
            Ok((strain, at, wall)) => println!(
                "{name:<24} {strain:>12.3e} {at:>8.3} {wall:>10.4} {:>12}",
                b.counters().iterations
            ),
            Err(e) => println!("{name:<24} failed: {e}"),
        }
    }
}
