//! The frame-tied DBSMC design (`dbsmc-relaxed`, docs/particles.md) at the runtime's
//! default Dormand-Prince tolerance (`TOLERANCE_PER_EPS = 0.01` of the smallest layer),
//! at a tolerance 100 times tighter, and with steps of at most 1/4 and 1/16 of the
//! design's longest (`mu / 4`), on the runs of the particle benchmark that left their
//! `s`-layer: does the layer loss come from the integration (then it goes away as the
//! steps shrink) or from the assumed drift (then it does not)?
//!
//! ```text
//! cargo run --release -p dae-bench --example relaxed_tolerance
//! ```

use std::time::Duration;

use dae_bench::{MethodSpec, ParticleScene, c1, c3, drive_scene, relaxed_settings};
use dae_particles::{Dbsmc, GridPins, ParticleDae, ParticleModel};
use dae_runtime::Model;

/// Budget of one run (wall clock).
const BUDGET: Duration = Duration::from_secs(30);

/// How a run's steps are controlled.
#[derive(Clone, Copy)]
enum Control {
    /// The runtime's default state tolerance.
    Default,
    /// A state tolerance of this fraction of the smallest layer.
    State(f64),
    /// Steps of at most this fraction of the design's longest.
    Shorter(f64),
}

impl Control {
    fn label(self) -> String {
        match self {
            Control::Default => "state 1e-2 (default)".into(),
            Control::State(f) => format!("state {f:e}"),
            Control::Shorter(f) => format!("state 1e-2, max step x {f}"),
        }
    }
}

fn run(scene: &ParticleScene, eps: f64, gain: f64, control: Control) -> Result<String, String> {
    let spec = MethodSpec::DbsmcRelaxed { eps, gain };
    let model = ParticleModel::new(&scene.system).map_err(|e| e.to_string())?;
    let smallest = (0..model.n_constraints())
        .map(|i| eps * model.rest_length(i))
        .fold(f64::INFINITY, f64::min);
    let mut settings = relaxed_settings(&model, eps, gain);
    match control {
        Control::Default => {}
        Control::State(f) => settings = settings.tolerance(f * smallest, f * smallest),
        Control::Shorter(f) => {
            let h = settings.max_step * f;
            settings = settings.max_step(h)
        }
    }
    let backend = Dbsmc::new(model, settings, "relaxed")
        .map_err(|e| e.to_string())?
        .keep_going_after_bound_loss();
    let r = drive_scene(scene, &spec, backend, BUDGET, None, None);
    let frames = r.frames.max(1) as f64;
    let lost = match (r.counters.layer_lost_at, r.counters.layer_worst_ratio) {
        (Some(t), Some(q)) if q < 1e3 => format!("{t:.3} s, {q:.3} eps"),
        (Some(t), Some(q)) => format!("{t:.3} s, {q:.2e} eps"),
        _ => "-".into(),
    };
    Ok(format!(
        "| {} | {eps:e} | {gain} | {} | {:.2e} | {lost} | {:.2} | {:.0} | {:.0} | {}/{} {} |",
        scene.title(),
        control.label(),
        r.worst_strain,
        r.ms_mean,
        r.counters.updates as f64 / frames,
        r.counters.steps as f64 / frames,
        r.frames,
        r.frames_total,
        r.status.chars().take(40).collect::<String>(),
    ))
}

fn main() {
    let scenes = (|| -> Result<Vec<(ParticleScene, f64, f64)>, String> {
        let e = |x: dae_particles::SystemError| x.to_string();
        let mut cloth = c3(16, GridPins::Corners, false).map_err(e)?;
        cloth.duration = 1.0;
        Ok(vec![
            (c1(100, 1e4).map_err(e)?, 1e-3, 32.0),
            (c1(10, 1e4).map_err(e)?, 1e-2, 8.0),
            (c1(10, 1.0).map_err(e)?, 1e-4, 8.0),
            (c1(100, 1.0).map_err(e)?, 1e-3, 8.0),
            (cloth, 1e-2, 8.0),
        ])
    })();
    let scenes = match scenes {
        Ok(s) => s,
        Err(e) => {
            eprintln!("relaxed_tolerance: {e}");
            std::process::exit(1);
        }
    };
    println!(
        "| scene | eps | c | step control (state: tolerance / smallest eps_i) | worst strain | s-layer left (max \\|s\\|/eps) | ms / frame | updates / frame | steps / frame | frames |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (scene, eps, gain) in &scenes {
        for control in [
            Control::Default,
            Control::State(1e-4),
            Control::Shorter(0.25),
            Control::Shorter(0.0625),
        ] {
            match run(scene, *eps, *gain, control) {
                Ok(line) => println!("{line}"),
                Err(e) => println!("| {} | {eps:e} | {gain} | failed: {e} |", scene.title()),
            }
        }
    }
}
