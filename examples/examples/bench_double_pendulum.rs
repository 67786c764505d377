//! Timing of the 3-D double pendulum on GENERATED code, and of the same scene on the
//! interpreter: `cargo run --release --example bench_double_pendulum`.
//!
//! Prints ns per model call, ns per RK4 step (v held; includes the per-step `sliding`
//! evaluation and checks), ns per control update (Jacobian, 2 x 2 LU, solve, with and
//! without the `beta` evaluation of robustness counting), the wall time of the whole
//! 10 s chapter-5 scene at h = 1e-4, and the interpreter's time for the same scene.
//! Every figure is the best of several repetitions.

use dae_runtime::settings::{Dbsmc, Update};
use std::hint::black_box;
use std::time::Instant;

use dae_examples::chapter5::{self, DoublePendulum3D};
use dae_runtime::{Model, Settings, Simulator, Summary, trace::NoTrace};

const REPS: usize = 7;

fn best_of(model: &dyn Model, settings: &Settings) -> Summary {
    let mut best: Option<Summary> = None;
    for _ in 0..REPS {
        let s = Simulator::new(model, settings.clone())
            .unwrap()
            .run(&mut NoTrace)
            .unwrap();
        if best.as_ref().is_none_or(|b| s.wall_time < b.wall_time) {
            best = Some(black_box(s));
        }
    }
    best.unwrap()
}

/// Best-of-REPS ns per call of `f`, called `n` times per repetition.
fn ns_per_call(n: usize, mut f: impl FnMut(usize)) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..REPS {
        let t = Instant::now();
        for i in 0..n {
            f(i);
        }
        best = best.min(t.elapsed().as_secs_f64() / n as f64 * 1e9);
    }
    best
}

fn model_calls(model: &dyn Model, label: &str) {
    let mut x = vec![0.0; 12];
    model.initial_state(&mut x);
    x[2] = 0.3; // off the axis, so nothing is trivially zero
    let z = [1.2, 0.7];
    let mu = chapter5::THESIS_MU;
    let (mut dx, mut w, mut s, mut ah, mut j, mut b) = (
        vec![0.0; 12],
        vec![0.0; 6],
        [0.0; 2],
        [0.0; 2],
        vec![0.0; 4],
        [0.0; 2],
    );
    let n = 200_000;
    let rhs = ns_per_call(n, |i| {
        model.rhs(black_box(i as f64 * 1e-9), black_box(&x), &z, &mut dx)
    });
    let sl = ns_per_call(n, |i| {
        model.sliding(
            black_box(i as f64 * 1e-9),
            black_box(&x),
            &z,
            &mu,
            &mut w,
            &mut s,
            &mut ah,
        )
    });
    let jac = ns_per_call(n, |i| {
        model.jacobian(black_box(i as f64 * 1e-9), black_box(&x), &z, &mut j)
    });
    let beta = ns_per_call(n, |i| {
        model.beta(black_box(i as f64 * 1e-9), black_box(&x), &z, &mut b)
    });
    black_box((&dx, &w, &j, &b));
    println!("{label:<12} {rhs:>10.1} {sl:>10.1} {jac:>10.1} {beta:>10.1}");
}

fn main() {
    let generated = DoublePendulum3D::default();
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/double_pendulum_3d.dae"
    ))
    .expect("model file");
    let interpreted = daec::interpret_source(&src)
        .expect("the model compiles")
        .remove(0);

    println!("ns per model call (best of {REPS})");
    println!(
        "{:<12} {:>10} {:>10} {:>10} {:>10}",
        "", "rhs f", "sliding", "J_Omega", "beta"
    );
    model_calls(&generated, "generated");
    model_calls(&interpreted, "interpreted");

    let scene = chapter5::monitored(chapter5::T_END, 1.0);
    println!("\nsimulator, generated code (h = 1e-4, RK4)");
    // One update in 2 s: the cost of steps alone.
    let rare = best_of(
        &generated,
        &scene
            .clone()
            .law(Dbsmc::default().update(Update::Fixed { period: 1e9 }))
            .t_end(2.0),
    );
    let step_ns = rare.wall_time / rare.steps as f64 * 1e9;
    println!(
        "  {:<52} {step_ns:>8.1}",
        "ns per RK4 step (4 f + 1 sliding + checks)"
    );
    for check in [false, true] {
        let every = best_of(
            &generated,
            &scene
                .clone()
                .law(Dbsmc::default().update(Update::Fixed {
                    period: chapter5::STEP,
                }))
                .t_end(2.0)
                .check_robustness(check),
        );
        let upd_ns = (every.wall_time / every.steps as f64 * 1e9 - step_ns).max(0.0);
        let what = if check {
            "ns per control update (J, LU, solve, beta)"
        } else {
            "ns per control update (J, LU, solve)"
        };
        println!("  {what:<52} {upd_ns:>8.1}");
    }
    let g = best_of(&generated, &scene);
    println!(
        "  whole 10 s scene, monitored: {:.2} ms ({} steps, {} updates)",
        g.wall_time * 1e3,
        g.steps,
        g.updates
    );
    let i = best_of(&interpreted, &scene);
    println!(
        "  whole 10 s scene, interpreted: {:.2} ms ({} updates) = {:.1} x the generated code",
        i.wall_time * 1e3,
        i.updates,
        i.wall_time / g.wall_time
    );
    let quiet = scene.clone().check_robustness(false);
    let gq = best_of(&generated, &quiet);
    let iq = best_of(&interpreted, &quiet);
    println!(
        "  same without robustness counting: generated {:.2} ms, interpreted {:.2} ms ({:.1} x)",
        gq.wall_time * 1e3,
        iq.wall_time * 1e3,
        iq.wall_time / gq.wall_time
    );
}
