//! The relaxed DBSMC design (`dbsmc-relaxed`, docs/particles.md) on the five runs of the
//! particle benchmark where its gains, held fixed at the frame-tied floor `c eps / mu`,
//! once left their `s`-layer (before the runtime's located crossings were fixed): with
//! fixed gains at the runtime's default Dormand-Prince tolerance (`TOLERANCE_PER_EPS =
//! 0.01` of the smallest layer), at a tolerance 100 times tighter, and with steps of at
//! most 1/4 and 1/16 of the design's longest (`mu / 2`); with the gains following the
//! drift of `s'` (`Settings::follow_drift`) up to the gain that sweeps the layer, at
//! safety 1 and 2; and with them following it only as far as grazing returns `mu / 8`
//! apart need (`Settings::graze`, the benchmark's design), with `v` held or ramping
//! against the drift between updates (`Settings::ramp_against_drift`); and the design,
//! held and ramped, with the method's `sgn(s)` in the law instead of the design's
//! saturation `sat(s / eps)` inside the layer (`Settings::saturate_in_layer`; every
//! other row saturates). Which keep the layer, and at what cost per frame?
//!
//! ```text
//! cargo run --release -p dae-bench --example relaxed_design
//! ```

use std::time::Duration;

use dae_bench::{
    particle_bench::ParticleScene, particle_bench::RELAXED_DRIFT_SAFETY, particle_bench::c1,
    particle_bench::c3, particle_bench::ramped, particle_bench::run_relaxed_with,
};
use dae_particles::GridPins;
use dae_runtime::Settings;
use dae_runtime::settings::{GainRule, InLayer};

/// Budget of one run (wall clock).
const BUDGET: Duration = Duration::from_secs(30);

/// How a run's steps are controlled.
#[derive(Clone, Copy)]
enum Control {
    /// Fixed gains, the runtime's default state tolerance.
    Fixed,
    /// Fixed gains, a state tolerance of this fraction of the smallest layer.
    State(f64),
    /// Fixed gains, steps of at most this fraction of the design's longest.
    Shorter(f64),
    /// Gains following the drift of `s'` with this safety factor, up to the gain that
    /// sweeps the layer.
    Follow(f64),
    /// The benchmark's design: gains following the drift only as far as grazing
    /// returns `RELAXED_GRAZE_PER_MU * mu` apart need.
    Graze,
    /// The benchmark's design with `v` ramping against the drift between updates.
    GrazeRamp,
    /// The benchmark's design, held or ramped (`true`), with `sgn(s)` in the law
    /// instead of the saturation inside the layer.
    GrazeSign(bool),
}

impl Control {
    fn label(self) -> String {
        match self {
            Control::Fixed => "fixed gains".into(),
            Control::State(f) => format!("fixed gains, tolerance {f:e}"),
            Control::Shorter(f) => format!("fixed gains, max step x {f}"),
            Control::Follow(f) => format!("gains sweep the layer against the drift, safety {f}"),
            Control::Graze => "gains graze the layer against the drift (design)".into(),
            Control::GrazeRamp => "design, v ramps against the drift".into(),
            Control::GrazeSign(false) => "design with sgn(s) inside the layer".into(),
            Control::GrazeSign(true) => {
                "design with sgn(s) inside the layer, v ramps against the drift".into()
            }
        }
    }
}

fn run(scene: &ParticleScene, eps: f64, gain: f64, control: Control) -> String {
    let r = run_relaxed_with(scene, eps, gain, BUDGET, |settings| {
        let design = settings.clone();
        let settings = with_gains(settings, GainRule::Fixed);
        match control {
            Control::Graze => design,
            Control::GrazeRamp => ramped(design),
            Control::GrazeSign(ramp) => {
                let mut sign = design;
                sign.dbsmc_mut().expect("a DBSMC design").in_layer = InLayer::Sign;
                if ramp { ramped(sign) } else { sign }
            }
            Control::Fixed => settings,
            Control::State(f) => {
                let smallest = settings
                    .layers
                    .eps
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                settings.tolerance(f * smallest, f * smallest)
            }
            Control::Shorter(f) => {
                let h = settings.integration.max_step * f;
                settings.max_step(h)
            }
            Control::Follow(f) => with_gains(
                settings,
                GainRule::FollowDrift {
                    safety: f,
                    graze: None,
                    raise: None,
                },
            ),
        }
    });
    let frames = r.frames.max(1) as f64;
    let lost = match (r.counters.layer_lost_at(), r.counters.layer_worst_ratio()) {
        (Some(t), Some(q)) if q < 1e3 => format!("{t:.3} s, {q:.3} eps"),
        (Some(t), Some(q)) => format!("{t:.3} s, {q:.2e} eps"),
        _ => "-".into(),
    };
    format!(
        "| {} | {eps:e} | {gain} | {} | {:.2e} | {lost} | {:.2} | {:.0} | {:.0} | {}/{} {} |",
        scene.title(),
        control.label(),
        r.worst_strain,
        r.ms_mean,
        r.counters.updates() as f64 / frames,
        r.counters.steps as f64 / frames,
        r.frames,
        r.frames_total,
        r.status.chars().take(40).collect::<String>(),
    )
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
            eprintln!("relaxed_design: {e}");
            std::process::exit(1);
        }
    };
    println!(
        "| scene | eps | c | gains, step control (tolerance / smallest eps_i) | worst strain | s-layer left (max \\|s\\|/eps) | ms / frame | updates / frame | steps / frame | frames |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (scene, eps, gain) in &scenes {
        for control in [
            Control::Fixed,
            Control::State(1e-4),
            Control::Shorter(0.25),
            Control::Shorter(0.0625),
            Control::Follow(RELAXED_DRIFT_SAFETY),
            Control::Follow(2.0 * RELAXED_DRIFT_SAFETY),
            Control::Graze,
            Control::GrazeRamp,
            Control::GrazeSign(false),
            Control::GrazeSign(true),
        ] {
            println!("{}", run(scene, *eps, *gain, control));
        }
    }
}

/// The design's settings with other gains.
fn with_gains(mut settings: Settings, gains: GainRule) -> Settings {
    settings.dbsmc_mut().expect("a DBSMC design").gains = gains;
    settings
}
