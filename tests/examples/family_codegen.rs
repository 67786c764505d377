//! The cost of the generated code of family models, printed as tables (issue 10):
//!
//! 1. the family chain5 (`chain5_family.dae`, generated kernels) against the scalar
//!    generated chain5 (`chain5_planar.dae`), per evaluation of each `Model` function,
//!    and per link at N = 1000 (target: family <= 1.5x scalar per link);
//! 2. the generated chain (`chain.dae`) against the interpreter (`Program::eval`, the
//!    runtime's `Interpreter` back end) at N = 10^4, per function (target: interpreter
//!    <= 3x generated);
//! 3. one evaluation of every per-step function (rhs, sliding, jacobian, beta) of the
//!    generated and of the interpreted chain (both through the `Model` trait) at
//!    N = 10^3, 10^4, 10^5, with the fitted exponents of time against N (target <= 1.05);
//! 4. the compiler on `cloth.dae` (check, derive, emit) at two default sizes, and the
//!    number of lines of its generated code (targets: under 50 ms, under 2,000 lines).
//!
//! Run with the optimised test profile (the one the tests use):
//! `cargo run --profile test -p dae-tests --example family_codegen`.
//! Times are the best of 5 batches of at least 50 ms each.

use std::hint::black_box;
use std::time::Instant;

use dae_lang::family::{Instance, Spec, Values};
use dae_runtime::Model;
use dae_runtime::family::{FamilyInstance, Interpreter, Kernels};

mod generated {
    dae_runtime::dae_file!("../examples/models/chain.dae");
    dae_runtime::dae_file!("../examples/models/chain5_family.dae");
    dae_runtime::dae_file!("../examples/models/chain5_planar.dae");
}

/// Seconds per call of `f`: the best of 5 batches of at least 50 ms.
fn time(mut f: impl FnMut()) -> f64 {
    let mut reps = 1u64;
    loop {
        let t = Instant::now();
        for _ in 0..reps {
            f();
        }
        if t.elapsed().as_secs_f64() >= 0.05 {
            break;
        }
        reps *= 2;
    }
    (0..5)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                f();
            }
            t.elapsed().as_secs_f64() / reps as f64
        })
        .fold(f64::INFINITY, f64::min)
}

/// Least-squares slope of log(time) against log(size).
fn exponent(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

fn source(file: &str) -> String {
    std::fs::read_to_string(dae_tests::models_dir().join(file)).expect("example model")
}

/// Times of rhs, sliding, jacobian, beta of a model through the `Model` trait, at its
/// initial point with tensions 1.
fn model_times(m: &dyn Model) -> [f64; 4] {
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
        time(|| m.rhs(0.1, black_box(&x), &z, &mut dx)),
        time(|| m.sliding(0.1, black_box(&x), &z, &mu, &mut w, &mut s, &mut ah)),
        time(|| m.jacobian(0.1, black_box(&x), &z, &mut j)),
        time(|| m.beta(0.1, black_box(&x), &z, &mut b)),
    ]
}

/// Times of the four kernels of a back end on an instance (no `Model` layer).
fn kernel_times<K: Kernels>(k: &K, inst: &Instance) -> [f64; 4] {
    let l = &inst.layout;
    let mut scratch = k.scratch(inst);
    let algs = vec![1.0; l.n_algs];
    // `z' = 0`: the rate program gives `beta`, as `Model::beta` runs it.
    let rates = vec![0.0; l.n_algs];
    let mu = vec![0.1; l.n_rows];
    let v = Values {
        params: &inst.params,
        states: &inst.states,
        algs: &algs,
        alg_rates: &rates,
        mu: &mu,
        inputs: &inst.inputs,
        t: 0.1,
    };
    let (mut dx, mut w, mut s, mut ah) = (
        vec![0.0; l.n_states],
        vec![0.0; l.n_w],
        vec![0.0; l.n_rows],
        vec![0.0; l.n_rows],
    );
    let mut j = vec![0.0; inst.jacobian.entries.len()];
    let mut b = vec![0.0; l.n_rows];
    [
        time(|| k.rhs(inst, black_box(&v), &mut scratch, &mut dx)),
        time(|| k.sliding(inst, black_box(&v), &mut scratch, &mut w, &mut s, &mut ah)),
        time(|| k.jacobian(inst, black_box(&v), &mut scratch, &mut j)),
        time(|| k.omega_rate(inst, black_box(&v), &mut scratch, &mut b)),
    ]
}

const NAMES: [&str; 4] = ["rhs", "sliding", "jacobian", "beta"];

fn interpreter(file: &str) -> Interpreter {
    let model = dae_lang::compile_source(&source(file))
        .expect("compiles")
        .remove(0);
    Interpreter::new(model)
}

fn sized(n: i64) -> Spec {
    Spec {
        sizes: vec![("N".into(), n)],
        ..Spec::default()
    }
}

fn main() {
    // 1. Family chain5 against scalar chain5.
    let scalar = generated::Chain5::default();
    let family = generated::Chain5Family::new(&Spec::default()).expect("chain5 family");
    let (ts, tf) = (model_times(&scalar), model_times(&family));
    let tk = kernel_times(family.kernels(), family.instance());
    println!("1. chain5: generated family against generated scalar, ns per evaluation");
    println!("| function | scalar | family (Model) | ratio | family (kernels) | ratio |");
    println!("|---|---|---|---|---|---|");
    for i in 0..4 {
        println!(
            "| {} | {:.0} | {:.0} | {:.2} | {:.0} | {:.2} |",
            NAMES[i],
            ts[i] * 1e9,
            tf[i] * 1e9,
            tf[i] / ts[i],
            tk[i] * 1e9,
            tk[i] / ts[i]
        );
    }
    let (ss, sf, sk) = (
        ts.iter().sum::<f64>(),
        tf.iter().sum::<f64>(),
        tk.iter().sum::<f64>(),
    );
    println!(
        "| all four | {:.0} | {:.0} | {:.2} | {:.0} | {:.2} |",
        ss * 1e9,
        sf * 1e9,
        sf / ss,
        sk * 1e9,
        sk / ss
    );
    // Per link: the same family model at N = 1000 (fixed costs spread over the links)
    // against the scalar chain5's 5 links.
    let big = generated::Chain5Family::new(&sized(1000)).expect("chain5 family");
    let tb: f64 = model_times(&big).iter().sum();
    println!(
        "per link, all four: scalar chain5 {:.1} ns, family chain5 at N = 1000 {:.1} ns (ratio {:.2})\n",
        ss * 1e9 / 5.0,
        tb * 1e9 / 1000.0,
        tb / 1000.0 / (ss / 5.0)
    );

    // 2. Generated against interpreted chain at N = 10^4.
    let gen_chain = generated::Chain::new(&sized(10_000)).expect("chain");
    let inst = gen_chain.instance();
    let tg = kernel_times(gen_chain.kernels(), inst);
    let ti = kernel_times(&interpreter("chain.dae"), inst);
    println!(
        "2. chain N = 10^4: interpreter (Program::eval) against generated kernels, us per evaluation"
    );
    println!("| function | generated | interpreter | ratio |");
    println!("|---|---|---|---|");
    for i in 0..4 {
        println!(
            "| {} | {:.1} | {:.1} | {:.2} |",
            NAMES[i],
            tg[i] * 1e6,
            ti[i] * 1e6,
            ti[i] / tg[i]
        );
    }
    let (sg, si) = (tg.iter().sum::<f64>(), ti.iter().sum::<f64>());
    println!(
        "| all four | {:.1} | {:.1} | {:.2} |\n",
        sg * 1e6,
        si * 1e6,
        si / sg
    );

    // 3. Scaling of the generated and of the interpreted chain.
    println!(
        "3. chain: rhs + sliding + jacobian + beta through the Model trait, generated and interpreted"
    );
    println!(
        "| N | generated: us per step | ns per link | (rhs / sliding / jacobian / beta, us) | interpreter: us per step | ns per link | (rhs / sliding / jacobian / beta, us) |"
    );
    println!("|---|---|---|---|---|---|---|");
    let (mut gen_points, mut int_points) = (Vec::new(), Vec::new());
    let us = |t: [f64; 4]| {
        t.iter()
            .map(|v| format!("{:.1}", v * 1e6))
            .collect::<Vec<_>>()
            .join(" / ")
    };
    for n in [1_000i64, 10_000, 100_000] {
        let g = generated::Chain::new(&sized(n)).expect("chain");
        let tg = model_times(&g);
        drop(g);
        let i = FamilyInstance::interpreted(interpreter("chain.dae"), &sized(n)).expect("chain");
        let ti = model_times(&i);
        let (sg, si) = (tg.iter().sum::<f64>(), ti.iter().sum::<f64>());
        println!(
            "| {n} | {:.1} | {:.1} | {} | {:.1} | {:.1} | {} |",
            sg * 1e6,
            sg * 1e9 / n as f64,
            us(tg),
            si * 1e6,
            si * 1e9 / n as f64,
            us(ti)
        );
        gen_points.push((n as f64, sg));
        int_points.push((n as f64, si));
    }
    println!(
        "fitted exponent (least squares on log-log, N = 10^3 .. 10^5): generated {:.3}, interpreter {:.3}\n",
        exponent(&gen_points),
        exponent(&int_points)
    );

    // 4. The compiler on the cloth, at two default sizes.
    println!("4. cloth.dae: compiler stages, ms (best of 5), and the generated code");
    println!(
        "| default W | check | derive (analysis + text) | emit (compile + formatted Rust) | lines |"
    );
    println!("|---|---|---|---|---|");
    let cloth = source("cloth.dae");
    assert!(
        cloth.contains("size W = 32;"),
        "cloth.dae changed: update this benchmark"
    );
    for w in [32, 320] {
        let src = cloth.replace("size W = 32;", &format!("size W = {w};"));
        let check = time(|| {
            black_box(dae_lang::check_source(black_box(&src)).expect("checks"));
        });
        let derive = time(|| {
            for (_, a) in dae_lang::analyze_source(black_box(&src)).expect("analyses") {
                black_box(a.derive_text());
            }
        });
        let mut lines = 0;
        let emit = time(|| {
            let models = dae_lang::compile_source(black_box(&src)).expect("compiles");
            lines = dae_codegen::emit_rust(&models[0]).lines().count();
        });
        println!(
            "| {w} | {:.2} | {:.2} | {:.2} | {lines} |",
            check * 1e3,
            derive * 1e3,
            emit * 1e3
        );
    }
}
