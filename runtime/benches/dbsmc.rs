//! Timing of the simulator on the hand-written 3-D double pendulum
//! (`cargo bench -p dae-runtime --bench dbsmc`).
//!
//! Reports ns per RK4 step (with `v` held; includes the per-step `sliding` evaluation
//! and checks), ns per control update (Jacobian, 2 x 2 LU, solve; with and without the
//! `beta` evaluation used for robustness counting), and the wall time of the 10 s scene of
//! docs/method.md section 8 at h = 1e-4. Each figure is the best of several repetitions.

#[path = "../tests/simulator/common/pendulum.rs"]
mod pendulum;

use dae_runtime::settings::{Dbsmc, Law, Update};
use std::hint::black_box;

use dae_runtime::{Settings, Simulator, Summary, trace::NoTrace};
use pendulum::Pendulum;

const H: f64 = 1e-4;

fn scene() -> Settings {
    let gains = vec![0.076f64.powi(2) * 1.3e3, 0.066f64.powi(2) * 2.3e3];
    Settings::new(vec![0.2; 2], vec![0.076, 0.066], gains)
        .step(H)
        .settle(1.0)
}

fn best_of(reps: usize, settings: &Settings) -> Summary {
    let p = Pendulum::default();
    let mut best: Option<Summary> = None;
    for _ in 0..reps {
        let s = Simulator::new(&p, settings.clone())
            .unwrap()
            .run(&mut NoTrace)
            .unwrap();
        if best.as_ref().is_none_or(|b| s.wall_time < b.wall_time) {
            best = Some(black_box(s));
        }
    }
    best.unwrap()
}

fn main() {
    let reps = 7;
    // One update in 2 s: the cost of steps alone.
    let rare = best_of(
        reps,
        &scene()
            .law(Dbsmc::default().update(Update::Fixed { period: 1e9 }))
            .t_end(2.0),
    );
    let step_ns = rare.wall_time / rare.steps as f64 * 1e9;
    // An update after every step.
    for check in [false, true] {
        let every = best_of(
            reps,
            &scene()
                .law(Dbsmc::default().update(Update::Fixed { period: H }))
                .t_end(2.0)
                .check_robustness(check),
        );
        let update_ns =
            (every.wall_time - rare.wall_time) / (every.updates - rare.updates) as f64 * 1e9;
        println!(
            "control update{}: {update_ns:.0} ns",
            if check {
                " with beta (robustness counting)"
            } else {
                ""
            }
        );
    }
    println!("RK4 step (v held, incl. sliding eval): {step_ns:.0} ns");
    for (label, settings) in [
        (
            "monitor, cheap alpha, robustness counting",
            scene().t_end(10.0),
        ),
        (
            "monitor, cheap alpha, no counting",
            scene().t_end(10.0).check_robustness(false),
        ),
        (
            "fixed T = 0.005 s",
            scene()
                .t_end(10.0)
                .law(Dbsmc::default().update(Update::Fixed { period: 0.005 })),
        ),
        ("SPSM baseline", scene().t_end(10.0).law(Law::Spsm)),
    ] {
        let s = best_of(reps, &settings);
        println!(
            "10 s scene, {label}: {:.1} ms wall, {} steps, {} updates, {} f evals, min/mean period {:?}/{:?}",
            s.wall_time * 1e3,
            s.steps,
            s.updates,
            s.f_evals,
            s.min_period,
            s.mean_period
        );
    }
}
