//! Cost of the generated code: nanoseconds per evaluation of each `Model` function for
//! the 3-D double pendulum and a planar chain of 5 links, the same functions through the
//! interpreter (`dae_runtime::family::Interpreted`, running the same model's programs), and, printed before the
//! timings, the operation count of the generated code (tape instructions, shared
//! sub-expressions computed once) against the same outputs written as trees; then the
//! cart with a pendulum written with its mass matrix (`examples/models/cart_pendulum.dae`)
//! against the same model with its accelerations written out
//! (`tests/models/cart_pendulum_explicit.dae`).
//!
//! Run with `cargo bench -p dae-tests --bench codegen`.

use std::hint::black_box;

use criterion::Criterion;
use dae_runtime::Model;

mod generated {
    dae_runtime::dae_file!("../examples/models/double_pendulum_3d.dae");
    dae_runtime::dae_file!("../examples/models/chain5_planar.dae");
    dae_runtime::dae_file!("../examples/models/cart_pendulum.dae");
    dae_runtime::dae_file!("models/cart_pendulum_explicit.dae");
}

fn source(file: &str) -> String {
    std::fs::read_to_string(dae_tests::models_dir().join(file)).expect("example model")
}

/// Tape operations against tree operations for each benchmarked function.
fn print_op_counts(label: &str, src: &str) {
    let models = dae_lang::check_source(src).expect("valid model");
    let model = &models[0];
    let analysis =
        dae_lang::analyze(model, &dae_lang::AnalysisOptions::default()).expect("analysable model");
    let compiled = dae_lang::compile(&analysis);
    let sym = analysis.symbolic();
    let cs = &sym.constraints;
    let sliding: Vec<_> = cs
        .iter()
        .flat_map(|c| c.w.iter().copied())
        .chain(cs.iter().map(|c| c.s))
        .chain(cs.iter().map(|c| c.alpha_hat))
        .collect();
    let jacobian: Vec<_> = cs
        .iter()
        .flat_map(|c| c.jacobian_row.iter().map(|(_, id)| *id))
        .collect();
    let rate: Vec<_> = cs.iter().map(|c| c.rate).collect();
    let p = &compiled.programs;
    let rows = [
        ("rhs", &p.rhs, sym.f.clone()),
        ("sliding", &p.sliding, sliding),
        ("jacobian", &p.jacobian, jacobian),
        ("rate", &p.rate, rate),
    ];
    println!("{label}: operation counts (generated code vs expression trees)");
    for (name, program, roots) in rows {
        let tree = sym.arena.tree_op_count(&roots);
        let shared: usize = program.groups.iter().map(|g| g.tape.op_count()).sum();
        println!(
            "  {name:<9} tape {shared:>6}   trees {tree:>10}   ratio {:>8.1}",
            tree as f64 / shared.max(1) as f64
        );
    }
}

/// One model's four hot functions, timed through `&dyn Model`-free generic calls.
fn bench_model<M: Model>(c: &mut Criterion, group: &str, m: &M) {
    let n = m.n_states();
    let k = m.n_constraints();
    let nw: usize = m.indices().iter().sum();
    let mut x = vec![0.0; n];
    let mut z = vec![0.0; k];
    m.initial_state(&mut x);
    m.initial_alg(&mut z);
    // Away from the rest position, so that no term vanishes.
    for (i, v) in x.iter_mut().enumerate() {
        *v += 0.01 * (i as f64 + 1.0).sin();
    }
    for (i, v) in z.iter_mut().enumerate() {
        *v += 0.1 * (i as f64 + 1.0);
    }
    let mu = vec![0.5; k];
    let (mut dx, mut w, mut s, mut ah) = (vec![0.0; n], vec![0.0; nw], vec![0.0; k], vec![0.0; k]);
    let mut jac = vec![0.0; m.jacobian_pattern().len()];
    let mut beta = vec![0.0; k];
    let mut g = c.benchmark_group(group);
    g.bench_function("rhs", |b| {
        b.iter(|| m.rhs(black_box(0.3), black_box(&x), black_box(&z), &mut dx))
    });
    g.bench_function("sliding", |b| {
        b.iter(|| {
            m.sliding(
                black_box(0.3),
                black_box(&x),
                black_box(&z),
                black_box(&mu),
                &mut w,
                &mut s,
                &mut ah,
            )
        })
    });
    g.bench_function("jacobian", |b| {
        b.iter(|| m.jacobian(black_box(0.3), black_box(&x), black_box(&z), &mut jac))
    });
    g.bench_function("beta", |b| {
        b.iter(|| m.beta(black_box(0.3), black_box(&x), black_box(&z), &mut beta))
    });
    g.finish();
}

fn main() {
    let pendulum = source("double_pendulum_3d.dae");
    let chain = source("chain5_planar.dae");
    print_op_counts("double_pendulum_3d", &pendulum);
    print_op_counts("chain5_planar", &chain);

    let mut c = Criterion::default()
        .warm_up_time(std::time::Duration::from_millis(300))
        .measurement_time(std::time::Duration::from_secs(1))
        .configure_from_args();
    bench_model(
        &mut c,
        "pendulum3d/generated",
        &generated::DoublePendulum3D::default(),
    );
    let interp = daec::interpret_source(&pendulum).expect("valid").remove(0);
    bench_model(&mut c, "pendulum3d/interpreted", &interp);
    bench_model(&mut c, "chain5/generated", &generated::Chain5::default());
    let interp = daec::interpret_source(&chain).expect("valid").remove(0);
    bench_model(&mut c, "chain5/interpreted", &interp);
    // A mass matrix against the same model with its accelerations written out.
    bench_model(&mut c, "cart/mass", &generated::CartPendulum::default());
    bench_model(
        &mut c,
        "cart/explicit",
        &generated::CartPendulumExplicit::default(),
    );
    c.final_summary();
}
