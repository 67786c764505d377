//! The stability suite's long run (i) outside the suite: the generated double pendulum,
//! DBSMC with `mu = 0.05`, eps = 5e-4, gains `1.5 mu^2 max|beta|` from the scene's
//! pilot (`Scene::dbsmc`), Dormand-Prince, crossings located, over `T` seconds (the
//! pilot covers the same `T`, so the gains depend on it). Prints the settings, the
//! counts, `max |s|` and the bound loss, if any.
//!
//! ```text
//! cargo run --release -p dae-bench --example long_run -- [T]   # T = 1000 by default
//! ```
//!
//! It found the regression of docs/work-precision.md ("Stability"): the layer was lost
//! at 83.7 s at T = 100 (commit 65d2b22 on) and at 0.042 s at T = 1000 (8b98364 on).
//! Fixed, it holds: 613,879 updates at T = 100, 6,110,790 at T = 1000 (2.4 s).

use std::f64::consts::FRAC_PI_2;

use dae_bench::{generated::DoublePendulum, scenes::chain_scene, truth::PlanarChain};
use dae_runtime::{Model, Simulator, trace::NoTrace};

fn main() {
    let t_end: f64 = match std::env::args().nth(1).map(|a| a.parse()) {
        None => 1000.0,
        Some(Ok(t)) if t > 0.0 => t,
        Some(_) => {
            eprintln!("long_run: T must be a positive number of seconds");
            std::process::exit(2);
        }
    };
    let dp = PlanarChain::double_pendulum();
    let dp_dae = DoublePendulum::default();
    let horizontal = [-FRAC_PI_2, -FRAC_PI_2];
    let scene = match chain_scene("double_pendulum", &dp_dae, &dp, &horizontal, t_end) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("long_run: scene: {e}");
            std::process::exit(1);
        }
    };
    let method = scene.dbsmc(5e-4, 0.05, 1.5);
    let Some(settings) = method.runtime_settings(&scene) else {
        eprintln!("long_run: no runtime settings for {method:?}");
        std::process::exit(1);
    };
    println!(
        "T = {t_end} s: mu {:?}, gains {:?}, eps {:?}",
        settings.layers.mu, settings.layers.gains, settings.layers.eps
    );
    let summary =
        Simulator::new(&dp_dae as &dyn Model, settings).and_then(|mut sim| sim.run(&mut NoTrace));
    match summary {
        Ok(s) => {
            println!(
                "{} updates, {} steps, max |s| {:?}",
                s.updates, s.steps, s.max_abs_s
            );
            match s.bound_loss {
                None => println!("layer held"),
                Some(l) => {
                    println!(
                        "layer lost: `{}` at t = {:.6}, worst {:.3} eps (`{}` at t = {:.3}), {} steps outside",
                        l.first_constraint,
                        l.first_time,
                        l.worst_ratio,
                        l.worst_constraint,
                        l.worst_time,
                        l.steps_outside
                    );
                    std::process::exit(3);
                }
            }
        }
        Err(e) => {
            eprintln!("long_run: {e}");
            std::process::exit(1);
        }
    }
}
