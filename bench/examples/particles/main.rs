//! The particle benchmark (docs/particles.md): scenes C1-C7, DBSMC against XPBD (small
//! steps with the links in the system's order, `xpbd-substeps`, or by colour,
//! `xpbd-coloured`; and one step of n iterations), Vertex Block Descent (`vbd`) and
//! Augmented VBD (`avbd`), k substeps of 10 iterations each, and the index-1 method,
//! every run a row of `docs/results/particles.csv`, charts, tables and pictures beside
//! it.
//!
//! ```text
//! cargo run --release -p dae-bench --example particles [-- --large] [--studies] [--jobs N] [--budget SECS] [--only TEXT] [--method TEXT] [--slack S] [--pictures-from CSV] [DIR]
//! ```
//!
//! `--large` adds C1 at N = 1,000 (end-mass ratios 1e2, 1e4) and 10,000, C2 1,000 x 32,
//! C3 (b), (c) at W = 64 and (a) at W = 128. `--studies` adds the pilot-based DBSMC design
//! (the one the frame-tied design replaced: `dbsmc` with RK4, `dbsmc-euler`, `dbsmc-dp`,
//! and `dbsmc-generated` on the generated models), each scene's pilot run and, in the size
//! sweep, `dbsmc-dp`. The settings of XPBD and the index-1 method run as a series,
//! cheapest first, until one runs out of its budget or holds 1e-4 over the whole scene:
//! the costlier ones are not run, and the tables' notes name them. Every DBSMC setting
//! runs (each eps is a bound to check). On every scene, XPBD's small steps (and the
//! substeps of VBD and AVBD) are bisected
//! between the grid's last failing and first holding k of each level, to within a
//! sixteenth (the grid, by 2x on the chains and 4x on the others, would put the cheapest
//! setting up to 2x or 4x too high; the third target compares DBSMC with XPBD tuned to a
//! worst strain), and in the size sweep at every size for worst strain 1e-2 over its
//! frames (the second target reads XPBD's cost on the 64 x 64 cloth there). On each
//! chain of the third target, the cheapest DBSMC setting holding 1e-3 runs nine times
//! more with its longest step moved by -4 % ... +4 % (`frame_tied_draws`): a heavy chain
//! is chaotic, and the target reads the median of the nine. `--budget`
//! is the wall-clock budget of one
//! run (default 6 s): a run whose projected time exceeds it stops after a tenth of it
//! and is recorded as `budget` with the frames it ran (its cost per frame is measured,
//! its worst strain covers those frames only; runs on the small C4, W = 8, get at least
//! 30 s so that they reach the grab and the release). `--only`
//! keeps the scenes whose title contains TEXT (`size` selects the size sweep),
//! `--method` the settings whose method and knob (`dbsmc-ramp eps=1e-3 c=4`,
//! `xpbd-substeps k=1024`) contain TEXT (a run filtered so draws no pictures). DIR defaults
//! to `docs/results`, or to `target/particles-filtered` for a filtered run, so that
//! reproducing one figure does not overwrite the committed full results. `--slack S`
//! gives the cloths with two pinned corners (C3 (a), (c), C4 and the size sweep's) a far
//! edge `S` longer than the 1 m between the corners instead of `FAR_EDGE_SLACK` (2 %),
//! names it in their variants, and counts as a filter. `--jobs N` runs N runs at a
//! time (default: one per core; `--jobs 1` runs one at a time): every run is one
//! thread's from its start to its end, and the CSV, tables and charts are the same
//! whatever N, but for the wall times (docs/particles.md measures what the second run
//! beside costs each).
//!
//! `--pictures-from CSV` runs no sweep: it reads the runs of an earlier benchmark's CSV
//! (`docs/results/particles.csv`), chooses each scene's pictures from them as the
//! benchmark does and draws them into `DIR/particles/` (the kept scenes' PNG stills and
//! `<scene>_side_by_side.gif`; nothing else is written). The pictures' runs are run
//! again, so they are those of the CSV where the code is the CSV's.

mod sweep;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use dae_bench::{
    particle_bench::Capture, particle_bench::FrameTied, particle_bench::Marks,
    particle_bench::MethodSpec, particle_bench::Panel, particle_bench::ParticleRecord,
    particle_bench::ParticleScene, particle_bench::RELAXED_STEP_PER_MU,
    particle_bench::STRAIN_LEVELS, particle_bench::SceneDraws,
    particle_bench::bisect_least_holding, particle_bench::c1, particle_bench::c2,
    particle_bench::c3_with_slack, particle_bench::c4_with_slack, particle_bench::c5,
    particle_bench::c6, particle_bench::c7, particle_bench::capture_frame,
    particle_bench::cheapest, particle_bench::cheapest_table, particle_bench::drive_scene,
    particle_bench::frame_tied_draws, particle_bench::heavy_chain_choices,
    particle_bench::holding_brackets, particle_bench::index_one, particle_bench::kept_both,
    particle_bench::parallel_map, particle_bench::particle_pilot, particle_bench::ratio_chart,
    particle_bench::records_from_csv, particle_bench::run_particle_method,
    particle_bench::run_series, particle_bench::scene_groups, particle_bench::scene_title,
    particle_bench::stability_table, particle_bench::strain_chart,
    particle_bench::timed_repeatedly, particle_bench::write_particles_csv,
    particle_bench::write_side_by_side, particle_bench::write_stills,
    particle_methods::PilotBounds,
};
use dae_particles::{FAR_EDGE_SLACK, GridPins};
use dae_runtime::{settings::Integrator, solve::SolverChoice};

/// The least budget of a run on the small C4 (W = 8), whose point is the grab at 1 s
/// and the release at 2.5 s.
const SMALL_C4_BUDGET: Duration = Duration::from_secs(30);

struct Options {
    large: bool,
    /// Whether the pilot-based design runs too (`--studies`).
    studies: bool,
    /// Runs at a time.
    jobs: usize,
    budget: Duration,
    only: Option<String>,
    method: Option<String>,
    /// The far edge's slack of the cloths with two pinned corners.
    slack: f64,
    /// Draw the pictures only, choosing their runs from this benchmark CSV
    /// (`--pictures-from`) instead of running the sweeps.
    pictures_from: Option<PathBuf>,
    dir: PathBuf,
}

impl Options {
    /// Whether `spec` is among the settings `--method` keeps.
    fn keeps(&self, spec: &MethodSpec) -> bool {
        self.method
            .as_ref()
            .is_none_or(|t| format!("{} {}", spec.method(), spec.knob()).contains(t.as_str()))
    }

    fn filtered(&self) -> bool {
        self.only.is_some() || self.method.is_some() || self.slack != FAR_EDGE_SLACK
    }
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        large: false,
        studies: false,
        jobs: dae_bench::particle_bench::default_workers(),
        budget: Duration::from_secs(6),
        only: None,
        method: None,
        slack: FAR_EDGE_SLACK,
        pictures_from: None,
        dir: Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/results"),
    };
    let mut dir = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--large" => o.large = true,
            "--studies" => o.studies = true,
            "--budget" => {
                let v = args.next().ok_or("--budget needs a number of seconds")?;
                let s: f64 = v
                    .parse()
                    .map_err(|_| format!("--budget {v}: not a number"))?;
                o.budget = Duration::from_secs_f64(s);
            }
            "--jobs" => o.jobs = dae_bench::particle_bench::parse_workers(args.next().as_deref())?,
            "--only" => o.only = Some(args.next().ok_or("--only needs a text")?),
            "--method" => o.method = Some(args.next().ok_or("--method needs a text")?),
            "--slack" => {
                let v = args.next().ok_or("--slack needs a number")?;
                o.slack = v
                    .parse()
                    .map_err(|_| format!("--slack {v}: not a number"))?;
            }
            "--pictures-from" => {
                o.pictures_from = Some(PathBuf::from(
                    args.next().ok_or("--pictures-from needs a benchmark CSV")?,
                ));
            }
            d if !d.starts_with('-') => dir = Some(PathBuf::from(d)),
            other => return Err(format!("unknown option {other}")),
        }
    }
    o.dir = match dir {
        Some(d) => d,
        None if o.filtered() => {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/particles-filtered")
        }
        None => o.dir,
    };
    Ok(o)
}

fn scenes(large: bool, slack: f64) -> Result<Vec<ParticleScene>, String> {
    let c3 = |w, pins, shear| c3_with_slack(w, pins, shear, slack);
    let c4 = |w| c4_with_slack(w, slack);
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
    // The heavy-end scenes of the block-descent papers.
    v.push(c5().map_err(e)?);
    v.push(c6().map_err(e)?);
    v.push(c7().map_err(e)?);
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

/// The settings swept per method, as series cheapest first (one per method, one per
/// gain floor of the frame-tied design; see [`run_series`]). XPBD's substeps go up by 4x, or by 2x
/// up to 8192 on the chains (`fine_k`), where issue 13's third target compares DBSMC
/// with XPBD tuned to a worst strain: a 4x grid can miss the cheapest holding setting
/// by up to 4x in cost.
/// The pilot-based design runs only in `studies`.
fn sweeps(fine_k: bool, studies: bool) -> Vec<Vec<MethodSpec>> {
    let ks: Vec<u32> = if fine_k {
        (0..14).map(|p| 1 << p).collect()
    } else {
        (0..7).map(|p| 1 << (2 * p)).collect()
    };
    // The pilot-based design with one integrator, at the three eps.
    let pilot_based = |integrator| {
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::Dbsmc {
                eps,
                solver: SolverChoice::Auto,
                integrator,
            })
            .to_vec()
    };
    let mut sweeps = vec![
        ks.iter().copied().map(MethodSpec::XpbdSubsteps).collect(),
        ks.iter().copied().map(MethodSpec::XpbdColoured).collect(),
        [4, 16, 64, 256].map(MethodSpec::XpbdIterations).to_vec(),
        [4, 16, 64, 256, 1024].map(MethodSpec::IndexOne).to_vec(),
        ks.iter().copied().map(MethodSpec::Vbd).collect(),
        ks.iter().copied().map(MethodSpec::Avbd).collect(),
        ks.iter().copied().map(MethodSpec::AvbdTuned).collect(),
    ];
    if studies {
        sweeps.extend(
            [
                Integrator::Rk4,
                Integrator::Euler,
                Integrator::DormandPrince,
            ]
            .map(pilot_based),
        );
    }
    // The frame-tied design without a pilot, at three floors of the gains: one
    // series per floor, the eps tighter along it.
    for gain in [4.0, 8.0, 32.0] {
        sweeps.push(
            [1e-2, 1e-3, 1e-4]
                .map(|eps| MethodSpec::DbsmcRelaxed { eps, gain })
                .to_vec(),
        );
    }
    // The same design with `v` ramped against the drift between updates, and with
    // `mu` searched for during the run besides.
    sweeps.push(
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::DbsmcRamped { eps, gain: 4.0 })
            .to_vec(),
    );
    sweeps.push(
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::DbsmcAdaptive { eps, gain: 4.0 })
            .to_vec(),
    );
    // The scene's generated family model (chain.dae, c2_hair.dae, c3_cloth.dae), with
    // the pilot-based design.
    if studies {
        sweeps.push(
            [1e-2, 1e-3, 1e-4]
                .map(|eps| MethodSpec::DbsmcGenerated {
                    eps,
                    integrator: Integrator::Rk4,
                })
                .to_vec(),
        );
    }
    // The generated model with the frame-tied design, `v` ramped.
    sweeps.push(
        [1e-2, 1e-3, 1e-4]
            .map(|eps| MethodSpec::DbsmcRampGenerated { eps, gain: 4.0 })
            .to_vec(),
    );
    sweeps
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
        "  {:34} {:22} {:16} worst {:9.3e}  ms/frame {:9.3} (max {:9.3})  frames {:3}/{}  {}",
        scene_title(r),
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

/// What a scene's runs share: the reference position (C1, N <= 100) and the pilot
/// bounds of the pilot-based designs, with the notes that say how they were found.
struct Prepared {
    reference: Option<[f64; 3]>,
    bounds: Option<PilotBounds>,
    pilot_note: String,
    notes: Vec<String>,
}

fn prepare(scene: &ParticleScene, o: &Options) -> Prepared {
    let mut notes = Vec::new();
    // The reference (N <= 100) and its own error: the index-1 method at two steps.
    let mut reference = None;
    if scene.is_chain() && scene.size() <= 100 {
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
    let pilot_needed = sweeps(false, o.studies)
        .iter()
        .flatten()
        .any(|spec| o.keeps(spec) && needs_pilot(spec));
    for spf in [64, 256, 1024].into_iter().filter(|_| pilot_needed) {
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
    if pilot_needed {
        notes.push(format!("{}: {pilot_note}", scene.title()));
        println!("{} ({} links): {pilot_note}", scene.title(), scene.size());
    }
    Prepared {
        reference,
        bounds,
        pilot_note,
        notes,
    }
}

fn needs_pilot(spec: &MethodSpec) -> bool {
    matches!(
        spec,
        MethodSpec::Dbsmc { .. } | MethodSpec::DbsmcGenerated { .. }
    )
}

/// XPBD's small steps tuned to a worst strain (issue 13's third target compares DBSMC
/// with them on the chains; the cheapest-setting table on every scene): the grid of k by
/// 2x (4x on the cloths, the hair and the grabs) can put the least holding k up to 2x (4x)
/// too high, so between the grid's last failing and first holding k of each level
/// bisection runs more settings (`dae_bench::particle_bench::bisect_least_holding`, to within a
/// sixteenth). `first` is the series' first setting (its method); `runs` its records;
/// `levels` the worst strains to bisect for (the size sweep asks for 1e-2 only).
fn bisect_small_steps(
    first: &MethodSpec,
    runs: &[ParticleRecord],
    levels: &[f64],
    mut run: impl FnMut(&MethodSpec) -> ParticleRecord,
) -> Vec<ParticleRecord> {
    let make: fn(u32) -> MethodSpec = match first {
        MethodSpec::XpbdSubsteps(_) => MethodSpec::XpbdSubsteps,
        MethodSpec::XpbdColoured(_) => MethodSpec::XpbdColoured,
        MethodSpec::Vbd(_) => MethodSpec::Vbd,
        MethodSpec::Avbd(_) => MethodSpec::Avbd,
        MethodSpec::AvbdTuned(_) => MethodSpec::AvbdTuned,
        _ => return Vec::new(),
    };
    // A k asked for by two levels runs once.
    let mut made: Vec<(u32, ParticleRecord)> = Vec::new();
    let brackets = holding_brackets(runs).into_iter();
    for (level, fail, hold) in brackets.filter(|(level, _, _)| levels.contains(level)) {
        bisect_least_holding(fail, hold, level, |k| {
            if let Some((_, r)) = made.iter().find(|(m, _)| *m == k) {
                return r.clone();
            }
            let r = run(&make(k));
            made.push((k, r.clone()));
            r
        });
    }
    made.into_iter().map(|(_, r)| r).collect()
}

/// The wall-clock budget of one run on `scene`. The small C4 is there to show the grab
/// and the release: its runs get at least SMALL_C4_BUDGET so that those that cost up to
/// about 100 ms per frame get there.
fn run_budget(scene: &ParticleScene, o: &Options) -> Duration {
    if scene.id == "C4" && scene.size() < 1000 {
        o.budget.max(SMALL_C4_BUDGET)
    } else {
        o.budget
    }
}

/// Target 3's DBSMC settings (the cheapest frame-tied run holding 1e-3 on each heavy
/// chain), nine draws each at the benchmark's longest step moved by -4 % ... +4 %
/// (`frame_tied_draws`), the chains in parallel. A chosen setting of another design
/// (the pilot-based ones of `--studies`) keeps its one run.
fn target_three_draws(
    kept: &[&ParticleScene],
    records: &[ParticleRecord],
    o: &Options,
) -> Vec<SceneDraws> {
    let specs: Vec<MethodSpec> = sweeps(true, o.studies).into_iter().flatten().collect();
    let chosen: Vec<(&ParticleScene, &ParticleRecord, (FrameTied, f64, f64))> =
        heavy_chain_choices(records)
            .into_iter()
            .filter_map(|(title, r)| {
                let scene = kept.iter().find(|s| s.title() == title)?;
                let spec = specs
                    .iter()
                    .find(|s| s.method() == r.method && s.knob() == r.knob)?;
                Some((*scene, r, FrameTied::of(spec)?))
            })
            .collect();
    parallel_map(chosen.len(), o.jobs, |i| {
        let (scene, r, (design, eps, gain)) = chosen[i];
        SceneDraws {
            title: scene.title(),
            method: r.method.clone(),
            knob: r.knob.clone(),
            draws: frame_tied_draws(
                scene,
                design,
                eps,
                gain,
                RELAXED_STEP_PER_MU,
                run_budget(scene, o),
            ),
        }
    })
}

/// One run of the benchmark's sweep on a prepared scene.
fn run(scene: &ParticleScene, prep: &Prepared, spec: &MethodSpec, o: &Options) -> ParticleRecord {
    let budget = run_budget(scene, o);
    let mut r = timed_repeatedly(|| {
        run_particle_method(
            scene,
            spec,
            prep.bounds.as_ref(),
            budget,
            prep.reference.as_ref(),
            None,
        )
    });
    if needs_pilot(spec) && prep.bounds.is_none() {
        r.status = format!("failed: {}", prep.pilot_note);
    }
    print(&r);
    r
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
    let all = match scenes(o.large, o.slack) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("particles: {e}");
            std::process::exit(1);
        }
    };
    let kept: Vec<&ParticleScene> = all
        .iter()
        .filter(|s| {
            o.only
                .as_ref()
                .is_none_or(|t| s.title().contains(t.as_str()))
        })
        .collect();
    let prepared = parallel_map(kept.len(), o.jobs, |i| prepare(kept[i], &o));
    if let Some(csv) = &o.pictures_from {
        let records = match std::fs::read_to_string(csv)
            .map_err(|e| e.to_string())
            .and_then(|text| records_from_csv(&text))
        {
            Ok(r) => r,
            Err(e) => {
                eprintln!("particles: {}: {e}", csv.display());
                std::process::exit(1);
            }
        };
        parallel_map(kept.len(), o.jobs, |i| {
            draw_pictures(kept[i], &prepared[i], &records, &pictures)
        });
        println!(
            "{:.0} s: pictures of {} scenes from the {} runs of {}",
            clock.elapsed().as_secs_f64(),
            kept.len(),
            records.len(),
            csv.display()
        );
        return;
    }
    println!(
        "{:.0} s: references and pilots of {} scenes, {} at a time",
        clock.elapsed().as_secs_f64(),
        kept.len(),
        o.jobs
    );
    for p in &prepared {
        notes.extend(p.notes.iter().cloned());
    }
    // Every series of every scene (a method's settings, cheapest first), in the
    // scenes' and the sweeps' order. A series runs on one worker until a run ends it
    // (`run_series`: a run of XPBD or the index-1 method out of its budget, or holding
    // the tightest level whole; a DBSMC series runs every eps). The small C4's series,
    // whose runs have the longest budget, are handed out first, so that none of them is
    // the last to end.
    let opts = &o;
    let series: Vec<(usize, Vec<MethodSpec>)> = kept
        .iter()
        .enumerate()
        .flat_map(|(i, scene)| {
            sweeps(scene.is_chain(), opts.studies)
                .into_iter()
                .filter_map(move |sweep| {
                    let kept: Vec<MethodSpec> = sweep
                        .into_iter()
                        .filter(|s| {
                            opts.keeps(s) && (scene.has_generated_model() || !s.generated())
                        })
                        .collect();
                    (!kept.is_empty()).then_some((i, kept))
                })
        })
        .collect();
    let mut order: Vec<usize> = (0..series.len()).collect();
    order.sort_by_key(|&j| std::cmp::Reverse(run_budget(kept[series[j].0], &o)));
    let ran = parallel_map(order.len(), o.jobs, |k| {
        let (i, specs) = &series[order[k]];
        let (scene, prep) = (kept[*i], &prepared[*i]);
        let (mut runs, left) =
            run_series(specs, MethodSpec::knob, |spec| run(scene, prep, spec, &o));
        runs.extend(bisect_small_steps(
            &specs[0],
            &runs,
            &STRAIN_LEVELS,
            |spec| run(scene, prep, spec, &o),
        ));
        (runs, left)
    });
    // Back in the series' order.
    let mut ran: Vec<(usize, _)> = order.into_iter().zip(ran).collect();
    ran.sort_by_key(|&(j, _)| j);
    let mut not_run = 0;
    for ((i, specs), (_, (runs, left))) in series.iter().zip(ran) {
        records.extend(runs);
        if let Some(left) = left {
            not_run += left.knobs.len();
            let note = format!(
                "{}: {} {} not run: {}",
                kept[*i].title(),
                specs[0].method(),
                left.knobs.join(", "),
                left.reason
            );
            println!("  {note}");
            notes.push(note);
        }
    }
    println!(
        "{:.0} s: {} runs ({not_run} costlier settings not run)",
        clock.elapsed().as_secs_f64(),
        records.len()
    );
    // The pictures' runs are chosen among all methods: none for a run filtered by
    // method.
    if o.method.is_none() {
        parallel_map(kept.len(), o.jobs, |i| {
            draw_pictures(kept[i], &prepared[i], &records, &pictures)
        });
        println!("{:.0} s: pictures", clock.elapsed().as_secs_f64());
    }
    let methods: Vec<String> = [
        "dbsmc",
        "dbsmc-euler",
        "dbsmc-dp",
        "dbsmc-generated",
        "dbsmc-relaxed",
        "dbsmc-ramp",
        "dbsmc-adapt",
        "dbsmc-ramp-generated",
        "index1-rk4",
        "xpbd-substeps",
        "xpbd-coloured",
        "xpbd-iterations",
        "vbd",
        "avbd",
        "avbd-tuned",
    ]
    .map(String::from)
    .to_vec();
    let mut md = String::from(
        "# Particle benchmark: tables\n\nGenerated by `cargo run --release -p dae-bench --example particles`.\n\n## Cheapest setting holding a worst strain (complete runs)\n\n\
         The cheapest setting whose run held the worst strain over the whole scene (and, for \
         DBSMC, its `s`-layer). Where no run of a method did, `not whole: ...` names the \
         cheapest run that held it over the first frames, as many as its 6 s budget allowed \
         (the rest of the scene unknown: a calm start says little about the rest), and `none` \
         says that no run held it even so.\n\n",
    );
    md += &cheapest_table(&records, &methods);
    md += "\n## DBSMC runs\n\n";
    md += &dae_bench::particle_bench::dbsmc_runs_table(&records);
    md += "\n## Stability\n\n";
    md += &stability_table(&records);
    // Charts.
    for (t, runs) in scene_groups(&records) {
        let mut stem = format!("{}_{}", runs[0].scene, runs[0].variant).to_lowercase();
        stem.retain(|c| c.is_ascii_alphanumeric() || c == '_' || c == ' ');
        let stem = stem.replace(' ', "_");
        if let Err(e) = strain_chart(
            &runs,
            &t,
            &methods,
            &pictures.join(format!("{stem}_strain.svg")),
        ) {
            println!("chart {t}: {e}");
        }
    }
    if o.only.as_ref().is_none_or(|t| "size".contains(t.as_str())) {
        md += &sweep::size_sweep(&mut records, &pictures, &o);
        println!("{:.0} s: size sweep", clock.elapsed().as_secs_f64());
    }
    // After the size sweep: its runs are rows of the CSV too.
    let csv = o.dir.join("particles.csv");
    if let Err(e) = std::fs::File::create(&csv)
        .and_then(|f| write_particles_csv(&records, std::io::BufWriter::new(f)))
    {
        eprintln!("particles: {}: {e}", csv.display());
        std::process::exit(1);
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
    let draws = target_three_draws(&kept, &records, &o);
    println!(
        "{:.0} s: nine draws of target 3's DBSMC settings on {} chains",
        clock.elapsed().as_secs_f64(),
        draws.len()
    );
    md += &dae_bench::particle_bench::peers_section(&records);
    md += &dae_bench::particle_bench::targets_section(&records, &draws);
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

/// Pictures of `scene`: the DBSMC run (hand-written model, RK4, Dormand-Prince or the
/// frame-tied design) at the loosest eps that ran through holding its strain and its
/// s-layer, the cheapest of those; else the cheapest complete index-1 run; and the
/// cheapest settings of XPBD by colour, VBD and AVBD that held the same worst strain
/// (or 1e-2) over the whole scene: each one's PNG stills, and one GIF of all side by
/// side (`<scene>_side_by_side.gif`).
fn draw_pictures(
    scene: &ParticleScene,
    prep: &Prepared,
    records: &[ParticleRecord],
    pictures: &Path,
) {
    let title = scene.title();
    let dbsmc = sweeps(false, true)
        .into_iter()
        .flatten()
        .filter(|spec| {
            matches!(spec, MethodSpec::DbsmcRelaxed { .. })
                || matches!(spec, MethodSpec::Dbsmc { integrator, .. } if *integrator != Integrator::Euler)
        })
        .filter_map(|spec| {
            let r = records.iter().find(|r| {
                scene_title(r) == title
                    && r.method == spec.method()
                    && r.knob == spec.knob()
            })?;
            (r.complete() && kept_both(r)).then(|| (r.eps.unwrap_or(1e-2), r.ms_mean, spec))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    let mut shots: Vec<(MethodSpec, f64)> = Vec::new();
    if let Some((eps, _, spec)) = dbsmc {
        shots.push((spec, eps));
    } else if let Some(r) = cheapest(records, &title, "index1-rk4", 1e-2) {
        let spf: u32 = r
            .knob
            .trim_start_matches("steps/frame=")
            .parse()
            .unwrap_or(64);
        shots.push((MethodSpec::IndexOne(spf), 1e-2));
    }
    // The peers at the same worst strain: each one's cheapest setting that held the
    // bound of the first shot over the whole scene (or 1e-2 where none held that).
    let bound = shots.first().map_or(1e-2, |s| s.1);
    let make = |method: &str, k: u32| match method {
        "vbd" => MethodSpec::Vbd(k),
        "avbd" => MethodSpec::Avbd(k),
        "avbd-tuned" => MethodSpec::AvbdTuned(k),
        _ => MethodSpec::XpbdColoured(k),
    };
    for method in ["xpbd-coloured", "vbd", "avbd", "avbd-tuned"] {
        let held = [bound, 1e-2]
            .into_iter()
            .find_map(|level| Some((cheapest(records, &title, method, level)?, level)));
        let k = held
            .and_then(|(r, level)| Some((r.knob.strip_prefix("k=")?.parse::<u32>().ok()?, level)));
        if let Some((k, level)) = k {
            shots.push((make(method, k), level));
        }
    }
    let marks = Marks::of(scene);
    let links = scene.system.links();
    let mut panels: Vec<Panel> = Vec::new();
    for (spec, scale) in shots {
        let mut capture: Capture = Vec::new();
        let mut obs = |f: u64, p: &[[f64; 3]]| capture_frame(&mut capture, f, p);
        let r = run_particle_method(
            scene,
            &spec,
            prep.bounds.as_ref(),
            Duration::from_secs(600),
            prep.reference.as_ref(),
            Some(&mut obs),
        );
        let stem = format!("{}_{}", scene.stem(), spec.method());
        let panel = Panel {
            method: format!("{} {}", spec.method(), spec.knob()),
            capture,
        };
        match write_stills(pictures, &stem, links, &marks, &panel, scale) {
            Ok(files) => println!("  pictures {} ({}): {}", stem, r.status, files.join(", ")),
            Err(e) => println!("  pictures {stem}: {e}"),
        }
        panels.push(panel);
    }
    let stem = format!("{}_side_by_side", scene.stem());
    match write_side_by_side(pictures, &stem, links, &marks, &panels, bound) {
        Ok(files) => println!("  pictures {stem}: {}", files.join(", ")),
        Err(e) => println!("  pictures {stem}: {e}"),
    }
}
