//! The particle benchmark (docs/particles.md): scenes C1-C4, DBSMC against XPBD (small
//! steps and iterations) and the index-1 method, every run a row of
//! `docs/results/particles.csv`, charts, tables and pictures beside it.
//!
//! ```text
//! cargo run --release -p dae-bench --example particles [-- --large] [--budget SECS] [--only TEXT] [DIR]
//! ```
//!
//! `--large` adds C1 at N = 1,000 (end-mass ratios 1e2, 1e4) and 10,000, C2 1,000 x 32,
//! C3 (b), (c) at W = 64 and (a) at W = 128. `--budget` is the wall-clock budget of one
//! run (default 6 s): a run whose projected time exceeds it stops after a tenth of it
//! and is recorded as `budget` with the frames it ran (its cost per frame is measured,
//! its worst strain covers those frames only; runs on the small C4, W = 8, get at least
//! 30 s so that they reach the grab and the release). `--only`
//! keeps the scenes whose title contains TEXT. DIR defaults to `docs/results`.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use dae_bench::{
    Capture, MethodSpec, ParticleRecord, ParticleScene, bound_held, c1, c2, c3, c4, cheapest,
    cheapest_table, drive_scene, index_one, particle_pilot, ratio_chart, run_particle_method,
    size_line, stability_table, strain_chart, write_particles_csv, write_pictures,
};
use dae_particles::GridPins;
use dae_runtime::{Integrator, SolverChoice};

/// The least budget of a run on the small C4 (W = 8), whose point is the grab at 1 s
/// and the release at 2.5 s.
const SMALL_C4_BUDGET: Duration = Duration::from_secs(30);

struct Options {
    large: bool,
    budget: Duration,
    only: Option<String>,
    dir: PathBuf,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        large: false,
        budget: Duration::from_secs(6),
        only: None,
        dir: Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/results"),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--large" => o.large = true,
            "--budget" => {
                let v = args.next().ok_or("--budget needs a number of seconds")?;
                let s: f64 = v
                    .parse()
                    .map_err(|_| format!("--budget {v}: not a number"))?;
                o.budget = Duration::from_secs_f64(s);
            }
            "--only" => o.only = Some(args.next().ok_or("--only needs a text")?),
            d if !d.starts_with('-') => o.dir = PathBuf::from(d),
            other => return Err(format!("unknown option {other}")),
        }
    }
    Ok(o)
}

fn scenes(large: bool) -> Result<Vec<ParticleScene>, String> {
    let e = |x: dae_particles::SystemError| x.to_string();
    let mut v = Vec::new();
    let chains: &[usize] = if large {
        &[10, 100, 1000, 10000]
    } else {
        &[10, 100]
    };
    for &n in chains {
        for r in [1.0, 1e2, 1e4] {
            v.push(c1(n, r).map_err(e)?);
        }
    }
    if !large {
        v.push(c1(1000, 1.0).map_err(e)?);
    }
    v.push(c2(100, 32).map_err(e)?);
    if large {
        v.push(c2(1000, 32).map_err(e)?);
    }
    for pins in [GridPins::Corners, GridPins::Edge, GridPins::CornersHeavy] {
        v.push(c3(32, pins, false).map_err(e)?);
    }
    v.push(c3(32, GridPins::Corners, true).map_err(e)?);
    v.push(c3(64, GridPins::Corners, false).map_err(e)?);
    if large {
        v.push(c3(64, GridPins::Edge, false).map_err(e)?);
        v.push(c3(64, GridPins::CornersHeavy, false).map_err(e)?);
        v.push(c3(128, GridPins::Corners, false).map_err(e)?);
    }
    // A small C4 whose DBSMC runs reach the grab (1 s) and the release (2.5 s) within
    // the budget, and the scene's size, whose runs may stop before.
    v.push(c4(8).map_err(e)?);
    v.push(c4(32).map_err(e)?);
    Ok(v)
}

/// The settings swept per method, cheapest first.
fn sweeps() -> Vec<Vec<MethodSpec>> {
    vec![
        [1, 4, 16, 64, 256, 1024]
            .map(MethodSpec::XpbdSubsteps)
            .to_vec(),
        [4, 16, 64, 256].map(MethodSpec::XpbdIterations).to_vec(),
        [4, 16, 64, 256].map(MethodSpec::IndexOne).to_vec(),
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::Dbsmc {
                eps,
                solver: SolverChoice::Auto,
                integrator: Integrator::Rk4,
            })
            .to_vec(),
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::Dbsmc {
                eps,
                solver: SolverChoice::Auto,
                integrator: Integrator::Euler,
            })
            .to_vec(),
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::Dbsmc {
                eps,
                solver: SolverChoice::Auto,
                integrator: Integrator::DormandPrince,
            })
            .to_vec(),
        // The scene's generated family model (chain.dae, c2_hair.dae, c3_cloth.dae).
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::DbsmcGenerated {
                eps,
                integrator: Integrator::Rk4,
            })
            .to_vec(),
    ]
}

/// The tracked particle's position at t = 1 s from the index-1 method at
/// `steps_per_frame`.
fn position_at_1s(scene: &ParticleScene, steps_per_frame: u32) -> Option<[f64; 3]> {
    let mut short = scene.clone();
    short.duration = 1.0;
    let backend = index_one(&short, steps_per_frame).ok()?;
    let mut at = None;
    let mut obs = |f: u64, p: &[[f64; 3]]| {
        if f == 60 {
            at = Some(p[scene.tracked]);
        }
    };
    let r = drive_scene(
        &short,
        &MethodSpec::IndexOne(steps_per_frame),
        backend,
        Duration::from_secs(600),
        None,
        Some(&mut obs),
    );
    if r.complete() { at } else { None }
}

fn print(r: &ParticleRecord) {
    println!(
        "  {:22} {:16} worst {:9.3e}  ms/frame {:9.3} (max {:9.3})  frames {:3}/{}  {}",
        r.method,
        r.knob,
        r.worst_strain,
        r.ms_mean,
        r.ms_max,
        r.frames,
        r.frames_total,
        r.status.chars().take(90).collect::<String>()
    );
}

fn main() {
    let o = match options() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("particles: {e}");
            std::process::exit(2);
        }
    };
    let pictures = o.dir.join("particles");
    if let Err(e) = std::fs::create_dir_all(&pictures) {
        eprintln!("particles: {}: {e}", pictures.display());
        std::process::exit(1);
    }
    let clock = Instant::now();
    let mut records: Vec<ParticleRecord> = Vec::new();
    let mut notes: Vec<String> = Vec::new();
    let all = match scenes(o.large) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("particles: {e}");
            std::process::exit(1);
        }
    };
    for scene in all.iter().filter(|s| {
        o.only
            .as_ref()
            .is_none_or(|t| s.title().contains(t.as_str()))
    }) {
        println!("{} ({} links)", scene.title(), scene.size());
        // The reference (N <= 100) and its own error: the index-1 method at two steps.
        let mut reference = None;
        if scene.id == "C1" && scene.size() <= 100 {
            let (a, b) = (position_at_1s(scene, 512), position_at_1s(scene, 1024));
            if let (Some(a), Some(b)) = (a, b) {
                let self_err = dae_particles::distance(a, b);
                notes.push(format!("{}: reference (index-1, 1024 steps/frame) at t = 1 s differs by {self_err:.2e} m from 512 steps/frame", scene.title()));
                reference = Some(b);
            }
        }
        // Pilot bounds for the DBSMC design: the index-1 method, finer until it runs.
        let mut bounds = None;
        let mut pilot_note = String::from("no pilot ran");
        for spf in [64, 256, 1024] {
            match particle_pilot(scene, spf, o.budget * 3) {
                Ok((b, r)) => {
                    pilot_note = format!(
                        "pilot index-1 {} steps/frame over {}/{} frames",
                        spf, r.frames, r.frames_total
                    );
                    bounds = Some(b);
                    break;
                }
                Err(e) => pilot_note = format!("pilot failed: {e}"),
            }
        }
        notes.push(format!("{}: {pilot_note}", scene.title()));
        println!("  {pilot_note}");
        // The small C4 is there to show the grab and the release: its runs get at least
        // SMALL_C4_BUDGET so that those that cost up to about 100 ms per frame get there.
        let budget = if scene.id == "C4" && scene.size() < 1000 {
            o.budget.max(SMALL_C4_BUDGET)
        } else {
            o.budget
        };
        for sweep in sweeps() {
            for spec in sweep {
                let mut r = run_particle_method(
                    scene,
                    &spec,
                    bounds.as_ref(),
                    budget,
                    reference.as_ref(),
                    None,
                );
                if matches!(
                    spec,
                    MethodSpec::Dbsmc { .. } | MethodSpec::DbsmcGenerated { .. }
                ) && bounds.is_none()
                {
                    r.status = format!("failed: {pilot_note}");
                }
                print(&r);
                records.push(r);
            }
        }
        // Pictures: DBSMC at the loosest layer that ran through within its bound, else the cheapest
        // complete index-1 or XPBD run; and XPBD small steps at k = 16 for contrast.
        let title = scene.title();
        let dbsmc = records
            .iter()
            .filter(|r| {
                format!("{} {}", r.scene, r.variant) == title
                    && r.method == "dbsmc"
                    && r.complete()
                    && bound_held(r) == Some(true)
            })
            .map(|r| r.eps.unwrap_or(1e-2))
            .fold(None, |a: Option<f64>, e| Some(a.map_or(e, |a| a.max(e))));
        let mut shots: Vec<(MethodSpec, f64)> = Vec::new();
        if let Some(eps) = dbsmc {
            shots.push((
                MethodSpec::Dbsmc {
                    eps,
                    solver: SolverChoice::Auto,
                    integrator: Integrator::Rk4,
                },
                eps,
            ));
        } else if let Some(r) = cheapest(&records, &title, "index1-rk4", 1e-2) {
            let spf: u32 = r
                .knob
                .trim_start_matches("steps/frame=")
                .parse()
                .unwrap_or(64);
            shots.push((MethodSpec::IndexOne(spf), 1e-2));
        }
        shots.push((MethodSpec::XpbdSubsteps(16), 1e-2));
        for (spec, scale) in shots {
            let mut capture: Capture = Vec::new();
            let mut obs = |f: u64, p: &[[f64; 3]]| {
                if f % 5 == 0 {
                    capture.push((f, p.to_vec()));
                }
            };
            let r = run_particle_method(
                scene,
                &spec,
                bounds.as_ref(),
                Duration::from_secs(600),
                reference.as_ref(),
                Some(&mut obs),
            );
            let stem = format!("{}_{}", scene.stem(), spec.method());
            match write_pictures(
                &pictures,
                &stem,
                scene.system.links(),
                &capture,
                &[0, 60, 150, 300],
                83,
                scale,
            ) {
                Ok(files) => println!("  pictures {} ({}): {}", stem, r.status, files.join(", ")),
                Err(e) => println!("  pictures {stem}: {e}"),
            }
        }
    }
    let methods: Vec<String> = [
        "dbsmc",
        "dbsmc-euler",
        "dbsmc-dp",
        "dbsmc-generated",
        "index1-rk4",
        "xpbd-substeps",
        "xpbd-iterations",
    ]
    .map(String::from)
    .to_vec();
    let csv = o.dir.join("particles.csv");
    if let Err(e) = std::fs::File::create(&csv)
        .and_then(|f| write_particles_csv(&records, std::io::BufWriter::new(f)))
    {
        eprintln!("particles: {}: {e}", csv.display());
        std::process::exit(1);
    }
    let mut md = String::from(
        "# Particle benchmark: tables\n\nGenerated by `cargo run --release -p dae-bench --example particles`.\n\n## Cheapest setting holding a worst strain (complete runs)\n\n",
    );
    md += &cheapest_table(&records, &methods);
    md += "\n## Stability\n\n";
    md += &stability_table(&records);
    // Charts.
    let mut titles: Vec<String> = Vec::new();
    for r in &records {
        let t = format!("{} {}", r.scene, r.variant);
        if !titles.contains(&t) {
            titles.push(t);
        }
    }
    for t in &titles {
        let stem = records
            .iter()
            .find(|r| &format!("{} {}", r.scene, r.variant) == t)
            .map(|r| {
                let mut s = format!("{}_{}", r.scene, r.variant).to_lowercase();
                s.retain(|c| c.is_ascii_alphanumeric() || c == '_' || c == ' ');
                s.replace(' ', "_")
            });
        if let Some(stem) = stem {
            if let Err(e) = strain_chart(
                &records,
                t,
                &methods,
                &pictures.join(format!("{stem}_strain.svg")),
            ) {
                println!("chart {t}: {e}");
            }
        }
    }
    md += "\n## Cost against size (fitted exponents of mean cost per frame against links)\n\n| family | method | setting | exponent |\n|---|---|---|---|\n";
    let chains: Vec<String> = titles
        .iter()
        .filter(|t| t.starts_with("C1") && t.ends_with("r=1"))
        .cloned()
        .collect();
    let cloth: Vec<String> = titles
        .iter()
        .filter(|t| t.starts_with("C3") && t.ends_with("(a)"))
        .cloned()
        .collect();
    let mut lines = Vec::new();
    for (family, ts) in [("chains C1 r=1", &chains), ("cloth C3 (a)", &cloth)] {
        for (m, k) in [
            ("dbsmc", "eps=1e-2"),
            ("dbsmc", "eps=1e-3"),
            ("dbsmc-euler", "eps=1e-2"),
            ("dbsmc-dp", "eps=1e-2"),
            ("dbsmc-dp", "eps=1e-3"),
            ("dbsmc-generated", "eps=1e-2"),
            ("index1-rk4", "steps/frame=64"),
            ("xpbd-substeps", "k=64"),
            ("xpbd-iterations", "n=64"),
        ] {
            let (line, exp) = size_line(&records, ts, m, k, &format!("{family} {m} {k}"));
            md += &format!(
                "| {family} | {m} | {k} | {} |\n",
                exp.map_or("-".into(), |p| format!("{p:.2}"))
            );
            lines.push(line);
        }
    }
    if let Err(e) = dae_bench::loglog(
        &pictures.join("cost_vs_size.svg"),
        "mean cost per frame against links (fixed settings)",
        "links",
        "ms per frame",
        &lines,
    ) {
        println!("chart cost vs size: {e}");
    }
    for n in [10, 100, 1000] {
        if let Err(e) = ratio_chart(
            &records,
            n,
            1e-3,
            &methods,
            &pictures.join(format!("c1_n{n}_hold_1e-3_vs_ratio.svg")),
        ) {
            println!("chart ratio N={n}: {e}");
        }
    }
    md += "\n## Notes\n\n";
    for n in &notes {
        md += &format!("- {n}\n");
    }
    if let Err(e) = std::fs::write(o.dir.join("particles_tables.md"), &md) {
        eprintln!("particles: tables: {e}");
        std::process::exit(1);
    }
    println!(
        "{} runs in {:.0} s; wrote {} and {}",
        records.len(),
        clock.elapsed().as_secs_f64(),
        csv.display(),
        o.dir.join("particles_tables.md").display()
    );
}
