//! Per-step evaluation cost of interpreted family models through the runtime's `Model`
//! trait: one `rhs`, one `sliding`, one `jacobian` (the values of `J_Omega`) and one
//! `beta`, on `chain.dae` at N = 10^3, 10^4, 10^5 links (with the exponent of a
//! least-squares fit of log time against log links) and on `cloth.dae` at W = 16, 32, 64.
//!
//! ```text
//! cargo run --release -p dae-runtime --features families --example family_model_eval
//! ```
//!
//! Each figure is the best of several repetitions (a repetition runs the four functions
//! enough times to take about 0.2 s), per evaluation of all four.

use std::time::Instant;

use dae_runtime::family::{FamilyInstance, Interpreter, Spec};
use dae_runtime::{Model, model::w_offsets};

fn model(file: &str, size: (&str, i64)) -> FamilyInstance<Interpreter> {
    let path = format!("{}/../examples/models/{file}", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).expect("the example model");
    let c = dae_lang::compile_source(&src)
        .expect("the example compiles")
        .remove(0);
    let spec = Spec {
        sizes: vec![(size.0.into(), size.1)],
        ..Spec::default()
    };
    FamilyInstance::interpreted(Interpreter::new(c), &spec).expect("the model builds")
}

/// Seconds per step (rhs + sliding + jacobian + beta) and per function.
fn per_step(m: &FamilyInstance<Interpreter>) -> (f64, [f64; 4]) {
    let (n, k) = (m.n_states(), m.n_constraints());
    let mut x = vec![0.0; n];
    m.initial_state(&mut x);
    // A point off the initial one: every particle moved a little, tensions nonzero.
    for (i, v) in x.iter_mut().enumerate() {
        *v += 1e-3 * ((i * 7919) % 13) as f64 / 13.0;
    }
    let z: Vec<f64> = (0..k).map(|i| 0.1 + (i % 5) as f64 * 0.01).collect();
    let mu = vec![0.05; k];
    let mut dx = vec![0.0; n];
    let mut w = vec![0.0; w_offsets(m.indices())[k]];
    let (mut s, mut ah, mut beta) = (vec![0.0; k], vec![0.0; k], vec![0.0; k]);
    let mut j = vec![0.0; m.jacobian_pattern().len()];
    let mut fns: [Box<dyn FnMut(f64)>; 4] = [
        Box::new(|t| m.rhs(t, &x, &z, &mut dx)),
        Box::new(|t| m.sliding(t, &x, &z, &mu, &mut w, &mut s, &mut ah)),
        Box::new(|t| m.jacobian(t, &x, &z, &mut j)),
        Box::new(|t| m.beta(t, &x, &z, &mut beta)),
    ];
    let mut best = [f64::INFINITY; 4];
    for (f, b) in fns.iter_mut().zip(&mut best) {
        f(0.0);
        // Calibrate: about 0.05 s per repetition.
        let t0 = Instant::now();
        f(1e-6);
        let once = t0.elapsed().as_secs_f64().max(1e-7);
        let reps = ((0.05 / once) as usize).clamp(1, 100_000);
        for _ in 0..4 {
            let t0 = Instant::now();
            for r in 0..reps {
                f(r as f64 * 1e-9);
            }
            *b = b.min(t0.elapsed().as_secs_f64() / reps as f64);
        }
    }
    (best.iter().sum(), best)
}

/// Least-squares slope of log(y) against log(x).
fn exponent(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// A measured size: its label, its number of links, the step and per-function times.
type Row = (String, usize, (f64, [f64; 4]));

fn table(title: &str, rows: &[Row]) {
    println!("\n{title}");
    println!(
        "{:<10} {:>8} {:>12} {:>12} {:>12} {:>12} {:>12} {:>10}",
        "size", "links", "step [us]", "rhs", "sliding", "jacobian", "beta", "ns/link"
    );
    for (size, links, (total, f)) in rows {
        println!(
            "{:<10} {:>8} {:>12.1} {:>12.1} {:>12.1} {:>12.1} {:>12.1} {:>10.1}",
            size,
            links,
            total * 1e6,
            f[0] * 1e6,
            f[1] * 1e6,
            f[2] * 1e6,
            f[3] * 1e6,
            total * 1e9 / *links as f64
        );
    }
}

fn main() {
    let mut chain = Vec::new();
    for n in [1_000, 10_000, 100_000] {
        let m = model("chain.dae", ("N", n));
        chain.push((format!("N = {n}"), m.n_constraints(), per_step(&m)));
    }
    table(
        "chain.dae (interpreter, per step: rhs + sliding + jacobian + beta)",
        &chain,
    );
    let pts: Vec<(f64, f64)> = chain.iter().map(|r| (r.1 as f64, r.2.0)).collect();
    println!(
        "fitted exponent (time ~ links^p), N = 10^3 .. 10^5: p = {:.3}",
        exponent(&pts)
    );
    let mut cloth = Vec::new();
    for w in [16, 32, 64] {
        let m = model("cloth.dae", ("W", w));
        cloth.push((format!("W = {w}"), m.n_constraints(), per_step(&m)));
    }
    table("cloth.dae (interpreter, per step)", &cloth);
    let pts: Vec<(f64, f64)> = cloth.iter().map(|r| (r.1 as f64, r.2.0)).collect();
    println!("fitted exponent, W = 16 .. 64: p = {:.3}", exponent(&pts));
}
