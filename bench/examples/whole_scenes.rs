//! The relaxed DBSMC design (`dbsmc-relaxed`, gains following the drift) through the
//! whole 5 s of every scene of the particle benchmark at one setting, without the
//! benchmark's 6 s budget per run: where the benchmark stops the large scenes after a
//! few frames, this says whether the strain bound and the `s`-layer hold to the end
//! (issue 13's first target), and at what cost per frame.
//!
//! ```text
//! cargo run --release -p dae-bench --example whole_scenes [-- [--ramp | --adapt | --generated] [--jobs N] [--pictures DIR [--beside CSV]] EPS C BUDGET [TEXT]]
//! ```
//!
//! `--ramp` runs the design with `v` ramped against the drift between updates
//! (`dbsmc-ramp`, `Settings::ramp_against_drift`) instead of held; `--generated` runs
//! it ramped on the scenes' generated family models (`dbsmc-ramp-generated`); `--adapt`
//! runs it ramped with `mu` searched for during the run (`dbsmc-adapt`,
//! `dae_particles::AdaptiveMu`).
//! `EPS` (default 1e-2), `C` (the floor gain `c eps / mu`, default 8) and `BUDGET`, the
//! wall-clock seconds one scene may take (default 120; the harness stops a run that
//! has spent it, or a tenth of it while its projected total is over it, and the table
//! says how many frames it ran). A scene that stops at the budget counts as not shown.
//! `TEXT` keeps the scenes whose title contains it. The column "links asking" counts
//! the links whose own `s_i` asked for at least one update (`Summary::triggered_updates`).
//! The scenes run one per core at a time (`--jobs N` runs N at a time, 1 for one at a
//! time); each scene's run is one thread's, and the table lists them in order when all
//! have ended (a line on stderr as each ends).
//!
//! `--pictures DIR` draws each scene that ran whole with its strain and its layer kept
//! (`<scene>_<method>_t{0.00,1.00,2.50,5.00}.png` and `<scene>_<method>.gif`, every
//! fifth frame, links coloured by strain relative to `EPS`, as the benchmark's
//! pictures): the benchmark's 6 s budget stops every DBSMC run on the hair and the
//! cloths after a few frames, so its own pictures of those scenes are XPBD's only. A
//! scene stopped by the budget, or that left a bound, is not drawn (the table says which).
//! `--beside CSV` (a benchmark's `particles.csv`, e.g. `docs/results/particles.csv`)
//! draws, as the benchmark does, the methods side by side at the same worst strain: next
//! to DBSMC the cheapest settings of XPBD by colour, VBD, AVBD and AVBD tuned that held
//! `EPS` over the whole scene in CSV, run again here (one after the other, each within
//! `BUDGET`), into `<scene>_side_by_side.gif` (the benchmark's name: run this after the
//! benchmark, whose own GIF of the scene it replaces) instead of `<scene>_<method>.gif`.

use std::path::PathBuf;
use std::time::Duration;

use dae_bench::{
    particle_bench::Capture, particle_bench::MethodSpec, particle_bench::Panel,
    particle_bench::ParticleRecord, particle_bench::ParticleScene, particle_bench::c1,
    particle_bench::c2, particle_bench::c3, particle_bench::c4, particle_bench::capture_frame,
    particle_bench::cheapest, particle_bench::default_workers, particle_bench::left_a_guarantee,
    particle_bench::parallel_map, particle_bench::records_from_csv,
    particle_bench::run_particle_method, particle_bench::write_side_by_side,
    particle_bench::write_stills,
};
use dae_particles::GridPins;

fn scenes() -> Result<Vec<ParticleScene>, String> {
    let e = |x: dae_particles::SystemError| x.to_string();
    let mut v = Vec::new();
    for n in [10, 100] {
        for r in [1.0, 1e2, 1e4] {
            v.push(c1(n, r).map_err(e)?);
        }
    }
    v.push(c1(1000, 1.0).map_err(e)?);
    v.push(c2(100, 32).map_err(e)?);
    for pins in [GridPins::Corners, GridPins::Edge, GridPins::CornersHeavy] {
        v.push(c3(32, pins, false).map_err(e)?);
    }
    v.push(c3(64, GridPins::Corners, false).map_err(e)?);
    v.push(c4(8).map_err(e)?);
    v.push(c4(32).map_err(e)?);
    Ok(v)
}

/// The panels beside DBSMC's in a scene's side-by-side GIF: the cheapest settings of XPBD
/// by colour, VBD, AVBD and AVBD tuned that held `level` over the whole scene in the
/// benchmark's CSV `csv`, each run again with its frames captured (within `budget`).
fn peers(
    scene: &ParticleScene,
    records: &[ParticleRecord],
    level: f64,
    budget: Duration,
) -> Vec<Panel> {
    let mut panels = Vec::new();
    for method in ["xpbd-coloured", "vbd", "avbd", "avbd-tuned"] {
        let Some(knob) = cheapest(records, &scene.title(), method, level).map(|r| &r.knob) else {
            eprintln!(
                "  {}: no {method} setting held {level:e} in the CSV",
                scene.title()
            );
            continue;
        };
        let Some(k) = knob.strip_prefix("k=").and_then(|k| k.parse::<u32>().ok()) else {
            eprintln!("  {}: {method} {knob}: not a k=N knob", scene.title());
            continue;
        };
        let spec = match method {
            "vbd" => MethodSpec::Vbd(k),
            "avbd" => MethodSpec::Avbd(k),
            "avbd-tuned" => MethodSpec::AvbdTuned(k),
            _ => MethodSpec::XpbdColoured(k),
        };
        let mut capture: Capture = Vec::new();
        let mut keep = |f: u64, p: &[[f64; 3]]| capture_frame(&mut capture, f, p);
        let r = run_particle_method(scene, &spec, None, budget, None, Some(&mut keep));
        eprintln!(
            "  beside: {} {}: {} ({}/{} frames, worst strain {:.3e}, {:.3} ms/frame)",
            spec.method(),
            spec.knob(),
            r.status,
            r.frames,
            r.frames_total,
            r.worst_strain,
            r.ms_mean
        );
        panels.push(Panel {
            method: format!("{} {}", spec.method(), spec.knob()),
            capture,
        });
    }
    panels
}

fn main() {
    let mut ramp = false;
    let mut generated = false;
    let mut adapt = false;
    let mut jobs = default_workers();
    let mut pictures: Option<PathBuf> = None;
    let mut beside: Option<Vec<ParticleRecord>> = None;
    let mut args: Vec<String> = Vec::new();
    let mut given = std::env::args();
    while let Some(a) = given.next() {
        match a.as_str() {
            "--ramp" => ramp = true,
            "--generated" => generated = true,
            "--adapt" => adapt = true,
            "--jobs" => {
                jobs = dae_bench::particle_bench::parse_workers(given.next().as_deref())
                    .unwrap_or_else(|e| {
                        eprintln!("whole_scenes: {e}");
                        std::process::exit(2);
                    });
            }
            "--pictures" => match given.next() {
                Some(dir) => pictures = Some(PathBuf::from(dir)),
                None => {
                    eprintln!("whole_scenes: --pictures needs a folder");
                    std::process::exit(2);
                }
            },
            "--beside" => match given.next().map(|f| {
                let read = std::fs::read_to_string(&f).map_err(|e| e.to_string());
                (read.and_then(|csv| records_from_csv(&csv)), f)
            }) {
                Some((Ok(records), _)) => beside = Some(records),
                Some((Err(e), f)) => {
                    eprintln!("whole_scenes: {f}: {e}");
                    std::process::exit(1);
                }
                None => {
                    eprintln!("whole_scenes: --beside needs a benchmark CSV");
                    std::process::exit(2);
                }
            },
            _ => args.push(a),
        }
    }
    if beside.is_some() && pictures.is_none() {
        eprintln!("whole_scenes: --beside draws pictures: it needs --pictures DIR");
        std::process::exit(2);
    }
    if let Some(dir) = &pictures
        && let Err(e) = std::fs::create_dir_all(dir)
    {
        eprintln!("whole_scenes: {}: {e}", dir.display());
        std::process::exit(1);
    }
    let arg = |i: usize, default: f64| -> f64 {
        match args.get(i) {
            None => default,
            Some(a) => a.parse().unwrap_or_else(|_| {
                eprintln!(
                    "whole_scenes: `{a}` is not a number (usage: whole_scenes [--ramp | --adapt | --generated] [--jobs N] [--pictures DIR [--beside CSV]] [EPS C BUDGET [TEXT]])"
                );
                std::process::exit(2);
            }),
        }
    };
    let (eps, gain) = (arg(1, 1e-2), arg(2, 8.0));
    let budget = Duration::from_secs_f64(arg(3, 120.0));
    let only = args.get(4);
    let mut scenes = scenes().unwrap_or_else(|e| {
        eprintln!("whole_scenes: {e}");
        std::process::exit(1);
    });
    scenes.retain(|s| only.as_ref().is_none_or(|t| s.title().contains(t.as_str())));
    let spec = if generated {
        MethodSpec::DbsmcRampGenerated { eps, gain }
    } else if adapt {
        MethodSpec::DbsmcAdaptive { eps, gain }
    } else if ramp {
        MethodSpec::DbsmcRamped { eps, gain }
    } else {
        MethodSpec::DbsmcRelaxed { eps, gain }
    };
    println!(
        "| scene | links | worst strain / eps | s-layer left (max \\|s\\|/eps) | ms / frame mean (max) | updates / frame | links asking | frames | status |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let runs = parallel_map(scenes.len(), jobs, |i| {
        let scene = &scenes[i];
        // Every fifth frame, only when pictures are asked for (the hair's 61 frames are
        // about 5 MB).
        let mut capture: Capture = Vec::new();
        let mut keep = |f: u64, p: &[[f64; 3]]| capture_frame(&mut capture, f, p);
        let observe: Option<dae_bench::particle_bench::FrameObserver<'_>> = pictures
            .as_ref()
            .map(|_| &mut keep as dae_bench::particle_bench::FrameObserver<'_>);
        let r = run_particle_method(scene, &spec, None, budget, None, observe);
        eprintln!(
            "{}: {} ({}/{} frames)",
            scene.title(),
            r.status,
            r.frames,
            r.frames_total
        );
        let mut picture_error = None;
        if let Some(dir) = &pictures {
            let stem = format!("{}_{}", scene.stem(), spec.method());
            if r.complete() && !left_a_guarantee(&r) {
                let panel = Panel {
                    method: format!("{} {}", spec.method(), spec.knob()),
                    capture,
                };
                let marks = dae_bench::particle_bench::Marks::of(scene);
                let links = scene.system.links();
                let mut panels = vec![panel];
                let mut gif_stem = stem.clone();
                if let Some(records) = &beside {
                    panels.extend(peers(scene, records, eps, budget));
                    gif_stem = format!("{}_side_by_side", scene.stem());
                }
                let drawn = write_stills(dir, &stem, links, &marks, &panels[0], eps).and_then(
                    |mut files| {
                        files.extend(write_side_by_side(
                            dir, &gif_stem, links, &marks, &panels, eps,
                        )?);
                        Ok(files)
                    },
                );
                match drawn {
                    Ok(files) => eprintln!("  pictures: {}", files.join(", ")),
                    Err(e) => picture_error = Some(format!("pictures {stem}: {e}")),
                }
            } else {
                eprintln!("  pictures {stem}: not drawn (the run is not whole, or left a bound)");
            }
        }
        (r, picture_error)
    });
    let (mut lost, mut short) = (0, 0);
    let mut picture_errors = Vec::new();
    for (scene, (r, picture_error)) in scenes.iter().zip(runs) {
        picture_errors.extend(picture_error);
        let layer = match (r.counters.layer_lost_at(), r.counters.layer_worst_ratio()) {
            (Some(t), Some(q)) => format!("{t:.3} s, {q:.3} eps"),
            _ => "-".into(),
        };
        if left_a_guarantee(&r) {
            lost += 1;
        } else if !r.complete() {
            short += 1;
        }
        println!(
            "| {} | {} | {:.3} | {layer} | {:.3} ({:.3}) | {:.0} | {} | {}/{} | {} |",
            scene.title(),
            scene.size(),
            r.worst_strain / eps,
            r.ms_mean,
            r.ms_max,
            r.counters.updates() as f64 / r.frames.max(1) as f64,
            r.counters.links_asking(),
            r.frames,
            r.frames_total,
            r.status
                .chars()
                .take(60)
                .collect::<String>()
                .replace('|', "/"),
        );
    }
    println!(
        "\n{} of {} scenes held the strain within 1.05 eps and kept the s-layer to the end, \
         {short} held them until the budget stopped them, {lost} lost one ({} {}).",
        scenes.len() - lost - short,
        scenes.len(),
        spec.method(),
        spec.knob()
    );
    for e in &picture_errors {
        eprintln!("whole_scenes: {e}");
    }
    if lost > 0 || !picture_errors.is_empty() {
        std::process::exit(1);
    }
}
