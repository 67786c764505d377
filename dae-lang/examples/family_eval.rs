//! Measures what the compiler does with family models, as a table:
//!
//! * the cost of `check` + `analyze` (+ compile) + the template text of each family
//!   example (the same for any sizes: nothing here reads them);
//! * `Program::eval` (the vectorised interpreter) of the chain's four programs per link
//!   at 10^2 .. 10^5 links, with the fitted exponent of the time per call against the
//!   number of links.
//!
//! `cargo run --release -p dae-lang --example family_eval`

use std::time::Instant;

use dae_lang::family::{Scratch, Spec, Values, construct};
use dae_lang::{AnalysisOptions, analyze, compile};

fn models_dir() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples/models")
}

/// The median of `reps` timings of `f`, in seconds.
fn median(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[reps / 2]
}

fn main() {
    println!(
        "| model | check + analyze + compile | + template text | text lines | program instructions (rhs / sliding / jacobian / beta) |"
    );
    println!("|---|---|---|---|---|");
    for stem in [
        "chain",
        "hair",
        "cloth",
        "chain5_family",
        "double_pendulum_family",
    ] {
        let src = std::fs::read_to_string(models_dir().join(format!("{stem}.dae"))).unwrap();
        let analyse = || {
            let m = dae_lang::check_source(&src).unwrap();
            analyze(&m[0], &AnalysisOptions::default()).unwrap()
        };
        let t = median(11, || {
            analyse();
        });
        let tt = median(11, || {
            analyse().derive_text();
        });
        let a = analyse();
        let c = compile(&a);
        let f = &c.programs;
        let ops: Vec<String> = f
            .programs()
            .iter()
            .map(|(_, p)| p.op_count().to_string())
            .collect();
        println!(
            "| {stem} | {:.1} ms | {:.1} ms | {} | {} |",
            t * 1e3,
            tt * 1e3,
            a.derive_text().lines().count(),
            ops.join(" / ")
        );
    }
    let src = std::fs::read_to_string(models_dir().join("chain.dae")).unwrap();
    let m = dae_lang::check_source(&src).unwrap();
    let c = compile(&analyze(&m[0], &AnalysisOptions::default()).unwrap());
    let f = &c.programs;
    println!();
    println!("| links | rhs | sliding | jacobian | rate | all four, per link |");
    println!("|---|---|---|---|---|---|");
    let mut points = Vec::new();
    for n in [100i64, 1_000, 10_000, 100_000] {
        let spec = Spec {
            sizes: vec![("N".into(), n)],
            ..Spec::default()
        };
        let inst = construct(&f.construction, &spec).unwrap();
        let l = &inst.layout;
        let z: Vec<f64> = (0..l.n_algs).map(|k| 0.1 + 0.001 * k as f64).collect();
        let mu = vec![0.05; l.n_rows];
        let x = Values {
            params: &inst.params,
            states: &inst.states,
            algs: &z,
            alg_rates: &z,
            mu: &mu,
            inputs: &inst.inputs,
            t: 0.0,
        };
        let reps = (2_000_000 / n as usize).clamp(5, 2000);
        let mut times = Vec::new();
        for (name, p) in f.programs() {
            let mut scratch = Scratch::new(p, &inst);
            let lens: Vec<usize> = match name {
                "rhs" => vec![l.n_states],
                "sliding" => vec![l.n_w, l.n_rows, l.n_rows],
                "jacobian" => vec![inst.jacobian.entries.len()],
                _ => vec![l.n_rows],
            };
            let mut outs: Vec<Vec<f64>> = lens.iter().map(|&k| vec![0.0; k]).collect();
            let t = median(reps, || {
                let mut refs: Vec<&mut [f64]> = outs.iter_mut().map(|v| v.as_mut_slice()).collect();
                p.eval(&inst, &x, &mut scratch, &mut refs);
            });
            times.push(t);
        }
        let total: f64 = times.iter().sum();
        points.push((n as f64, total));
        println!(
            "| {n} | {:.1} µs | {:.1} µs | {:.1} µs | {:.1} µs | {:.0} ns |",
            times[0] * 1e6,
            times[1] * 1e6,
            times[2] * 1e6,
            times[3] * 1e6,
            total / n as f64 * 1e9
        );
    }
    let (a, b) = (points[1], points[3]);
    let exponent = (b.1 / a.1).ln() / (b.0 / a.0).ln();
    println!("\nfitted exponent of the time per call, 10^3 to 10^5 links: {exponent:.3}");
}
