//! Global against block-local control updates (`dae_runtime::settings::Scope`) on the
//! chains, hair and cloths of the particle benchmark, whole scenes: the frame-tied design
//! (`dbsmc-relaxed`) with its gains fixed at the floor `c eps / mu`, with crossings
//! located (Dormand-Prince, the step cut at each) and checked at the step ends (RK4 with
//! a step of `0.2 eps_i / k_i`), each with every row updated at every event and with
//! only the blocks of the rows that asked. The cost per frame against the size, and
//! whether the strain and the `s`-layer held.
//!
//! ```text
//! cargo run --release -p dae-bench --example update_scope [-- [--pilot] [--block N] [--only TEXT] EPS C BUDGET]
//! ```
//!
//! `--pilot` runs the pilot design instead (`dbsmc`: sufficient gains from an index-1
//! pilot of the scene, RK4 at `0.2 min eps_i / k_i`, the exact alpha; `C` unused).
//! `EPS` (default 1e-2), `C` (default 8), `BUDGET` the wall-clock seconds of one run
//! (default 120), `--block N` the most rows in a block (default 16), `--only TEXT`
//! keeps the scenes whose title contains `TEXT`. One run at a time (one core is the
//! metric).

use std::time::Duration;

use dae_bench::{
    particle_bench::MethodSpec, particle_bench::ParticleRecord, particle_bench::ParticleScene,
    particle_bench::c1, particle_bench::c2, particle_bench::c3, particle_bench::dbsmc_settings,
    particle_bench::drive_scene, particle_bench::particle_pilot, particle_bench::run_relaxed_with,
};
use dae_particles::{Dbsmc as DbsmcBackend, FRAME, GridPins, ParticleModel};
use dae_runtime::Settings;
use dae_runtime::settings::{
    Dbsmc as DbsmcLaw, GainRule, InLayer, Integrator, Law, Scope, StepEnd, Update,
};
use dae_runtime::solve::SolverChoice;

#[derive(Clone, Copy)]
enum Crossing {
    Located,
    StepEnd,
}

/// Monitoring with attracting surfaces over `scope`.
fn monitor(scope: Scope) -> Update {
    Update::Monitor {
        reaching: Default::default(),
        scope,
    }
}

fn with_law(settings: Settings, crossing: Crossing, scope: Scope) -> Settings {
    let update = monitor(scope);
    match crossing {
        Crossing::Located => settings.law(
            DbsmcLaw::default()
                .update(update)
                .gains(GainRule::Fixed)
                .in_layer(InLayer::Saturate),
        ),
        Crossing::StepEnd => {
            // A step of a fifth of the shortest time a row takes to cross its layer
            // at its gain, dividing the frame.
            let shortest = settings
                .layers
                .eps
                .iter()
                .zip(&settings.layers.gains)
                .map(|(e, k)| 0.2 * e / k)
                .fold(f64::INFINITY, f64::min);
            let per_frame = (FRAME / shortest.min(FRAME)).ceil();
            settings
                .integrator(Integrator::Rk4)
                .step(FRAME / per_frame)
                .law(Law::StepEnd(StepEnd {
                    update,
                    raise: None,
                    in_layer: InLayer::Saturate,
                }))
        }
    }
}

/// The pilot design ([`dbsmc_settings`]: sufficient gains from an index-1 pilot, RK4
/// at `0.2 min eps_i / k_i`) with crossings located or checked at the step ends.
fn pilot_run(
    scene: &ParticleScene,
    eps: f64,
    crossing: Crossing,
    scope: Scope,
    budget: Duration,
) -> Result<ParticleRecord, String> {
    let (bounds, _) = particle_pilot(scene, 64, budget)?;
    let model = ParticleModel::new(&scene.system).map_err(|e| e.to_string())?;
    let (settings, _) = dbsmc_settings(&model, &bounds, eps, SolverChoice::Auto)?;
    let update = monitor(scope);
    let settings = match crossing {
        Crossing::Located => settings.law(DbsmcLaw::default().update(update)),
        Crossing::StepEnd => settings.law(StepEnd {
            update,
            raise: None,
            in_layer: InLayer::Sign,
        }),
    };
    let spec = MethodSpec::Dbsmc {
        eps,
        solver: SolverChoice::Auto,
        integrator: Integrator::Rk4,
    };
    let backend = DbsmcBackend::new(model, settings, "pilot design")
        .map_err(|e| e.to_string())?
        .keep_going_after_bound_loss();
    Ok(drive_scene(scene, &spec, backend, budget, None, None))
}

fn row(scene: &ParticleScene, label: &str, r: &ParticleRecord) -> String {
    let frames = r.frames.max(1) as f64;
    let s = r.counters.sliding.unwrap_or_default();
    let lost = match (s.layer_lost_at, s.layer_worst_ratio) {
        (Some(t), Some(q)) => format!("{t:.3} s, {q:.3} eps"),
        _ => "-".into(),
    };
    let (block_solves, global) = match s.blocks {
        Some(b) => (
            format!("{:.1}", b.block_solves as f64 / frames),
            b.global_updates.to_string(),
        ),
        None => ("-".into(), "all".into()),
    };
    format!(
        "| {} | {label} | {:.3e} | {lost} | {:.3} | {:.1} | {block_solves} | {global} | {:.1} | {:.1} | {}/{} {} |",
        scene.title(),
        r.worst_strain,
        r.ms_mean,
        s.updates as f64 / frames,
        r.counters.steps as f64 / frames,
        s.steps_cut as f64 / frames,
        r.frames,
        r.frames_total,
        r.status.chars().take(30).collect::<String>(),
    )
}

fn main() {
    let mut block = 16usize;
    let mut only: Option<String> = None;
    let mut pilot = false;
    let mut rest = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--block" => match args.next().and_then(|v| v.parse().ok()) {
                Some(n) if n >= 1 => block = n,
                _ => {
                    eprintln!("update_scope: --block takes a number >= 1");
                    std::process::exit(2);
                }
            },
            "--only" => only = args.next(),
            "--pilot" => pilot = true,
            _ => rest.push(a),
        }
    }
    let number = |i: usize, default: f64| -> f64 {
        match rest.get(i).map(|v| v.parse::<f64>()) {
            None => default,
            Some(Ok(v)) if v.is_finite() && v > 0.0 => v,
            Some(_) => {
                eprintln!("update_scope: `{}` is not a positive number", rest[i]);
                std::process::exit(2);
            }
        }
    };
    let (eps, gain) = (number(0, 1e-2), number(1, 8.0));
    let budget = Duration::from_secs_f64(number(2, 120.0));
    let scenes = (|| -> Result<Vec<ParticleScene>, dae_particles::SystemError> {
        Ok(vec![
            c1(10, 1.0)?,
            c1(100, 1.0)?,
            c1(1000, 1.0)?,
            c2(10, 32)?,
            c2(100, 32)?,
            c3(16, GridPins::Corners, false)?,
            c3(32, GridPins::Corners, false)?,
            c3(64, GridPins::Corners, false)?,
        ])
    })();
    let scenes = match scenes {
        Ok(s) => s,
        Err(e) => {
            eprintln!("update_scope: {e}");
            std::process::exit(1);
        }
    };
    println!(
        "eps = {eps:e}, gains {gain} eps / mu, blocks of at most {block} rows, budget {budget:?} per run\n"
    );
    println!(
        "| scene | crossings, scope | worst strain | layer lost | ms / frame | updates / frame | block solves / frame | global updates | steps / frame | steps cut / frame | frames |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for scene in scenes
        .iter()
        .filter(|s| only.as_ref().is_none_or(|t| s.title().contains(t.as_str())))
    {
        for (crossing, cname) in [
            (Crossing::Located, "located"),
            (Crossing::StepEnd, "step end"),
        ] {
            for (scope, sname) in [
                (Scope::Global, "global".to_string()),
                (Scope::Blocks { size: block }, format!("blocks:{block}")),
            ] {
                let r = if pilot {
                    match pilot_run(scene, eps, crossing, scope, budget) {
                        Ok(r) => r,
                        Err(e) => {
                            eprintln!("update_scope: {}: {e}", scene.title());
                            continue;
                        }
                    }
                } else {
                    run_relaxed_with(scene, eps, gain, budget, |s| with_law(s, crossing, scope))
                };
                let line = row(scene, &format!("{cname}, {sname}"), &r);
                eprintln!("{line}");
                println!("{line}");
            }
        }
    }
}
