//! Cost against size: the same first frames of a chain and a cloth at every size.

use std::path::Path;
use std::time::Duration;

use dae_bench::{
    particle_bench::MethodSpec, particle_bench::ParticleRecord, particle_bench::ParticleScene,
    particle_bench::c1, particle_bench::c3_with_slack, particle_bench::cheapest,
    particle_bench::parallel_map, particle_bench::particle_pilot,
    particle_bench::run_particle_method, particle_bench::scene_title,
    particle_bench::timed_repeatedly,
};
use dae_particles::GridPins;
use dae_runtime::{settings::Integrator, solve::SolverChoice};

use super::{Options, bisect_small_steps, print};

/// Frames every size of the size sweep runs: the same part of the motion at every size.
const SWEEP_FRAMES: u64 = 12;

/// The budget of one run of the size sweep: large enough that every size completes its
/// [`SWEEP_FRAMES`] (a run stopped early would cover other frames than the others). 120 s
/// was, while the budget was checked only between frames; since it holds inside a frame,
/// the held 64 x 64 cloth (about 10 s per frame, 22 s at most) ran out of it in its 12th.
const SWEEP_BUDGET: Duration = Duration::from_secs(300);

/// Cost against size: chains C1 r=1 (N = 10, 100, 1000) and cloth C3 (a) (W = 8, 16,
/// 32, 64), every method at one setting over the same first [`SWEEP_FRAMES`] frames of
/// its scene, as rows of the CSV (variant `... first 0.2 s`); the exponent of the mean
/// cost per frame fitted over the sizes, and the counts that explain it. Returns the
/// tables' section and draws `cost_vs_size.svg`.
pub fn size_sweep(records: &mut Vec<ParticleRecord>, pictures: &Path, o: &Options) -> String {
    let e = |x: dae_particles::SystemError| x.to_string();
    let families: [(&str, Vec<Result<ParticleScene, String>>); 2] = [
        (
            "chains C1 r=1",
            [10, 100, 1000].map(|n| c1(n, 1.0).map_err(e)).to_vec(),
        ),
        (
            "cloth C3 (a)",
            [8, 16, 32, 64]
                .map(|w| c3_with_slack(w, GridPins::Corners, false, o.slack).map_err(e))
                .to_vec(),
        ),
    ];
    let mut specs: Vec<MethodSpec> = Vec::new();
    specs.extend([64, 256, 1024].map(MethodSpec::XpbdSubsteps));
    specs.extend([64, 256, 1024].map(MethodSpec::XpbdColoured));
    specs.extend([4, 16, 64].map(MethodSpec::Vbd));
    specs.extend([4, 16, 64].map(MethodSpec::Avbd));
    specs.extend([4, 16, 64].map(MethodSpec::AvbdTuned));
    // One setting of the index-1 method: at 256 steps per frame it fitted the same
    // exponents (0.97 on chains, 1.31 on cloth against 1.32, run of f5e06e2) and was
    // the sweep's longest job (52 s, 45 of them the 64 x 64 cloth).
    specs.push(MethodSpec::IndexOne(64));
    // The pilot-based design (`--studies`), from a pilot of the same frames.
    if o.studies {
        specs.push(MethodSpec::Dbsmc {
            eps: 1e-2,
            solver: SolverChoice::Auto,
            integrator: Integrator::DormandPrince,
        });
    }
    specs.extend([4.0, 32.0].map(|gain| MethodSpec::DbsmcRelaxed { eps: 1e-2, gain }));
    specs.extend([4.0, 32.0].map(|gain| MethodSpec::DbsmcRamped { eps: 1e-2, gain }));
    specs.push(MethodSpec::DbsmcRampGenerated {
        eps: 1e-2,
        gain: 4.0,
    });
    let mut md = format!(
        "\n## Cost against size (every size over its first {SWEEP_FRAMES} frames)\n\n\
         Mean cost per frame (ms) at each size, control updates per frame (DBSMC), and the\n\
         exponent of cost against links fitted over the sizes whose run completed the frames.\n\
         A setting that left its s-layer or its budget at a smaller size is not run at the larger ones.\n\n\
         | family | method | setting | sizes (links) | ms / frame | updates / frame | s-layer lost | exponent |\n|---|---|---|---|---|---|---|---|\n"
    );
    let mut lines = Vec::new();
    let mut hold = String::from(
        "\nThe cheapest of those settings holding worst strain 1e-2 over the frames, at each size, and the exponent of its cost \
         (XPBD's substeps bisected between the grid's last k that did not hold it and its first that did, to within a sixteenth):\n\n\
         | family | method | sizes (links) | setting (ms / frame) | exponent |\n|---|---|---|---|---|\n",
    );
    for (family, scenes) in families {
        let mut scenes: Vec<ParticleScene> = match scenes.into_iter().collect() {
            Ok(s) => s,
            Err(err) => {
                md += &format!("| {family} | - | - | scene: {err} | | | | |\n");
                continue;
            }
        };
        for sc in &mut scenes {
            sc.duration = SWEEP_FRAMES as f64 * dae_particles::FRAME;
            sc.variant = format!("{} first {:.1} s", sc.variant, sc.duration);
            sc.conservative = false;
        }
        println!("size sweep: {family}");
        // Pilots only for the pilot-based design.
        let bounds: Vec<_> = parallel_map(scenes.len(), o.jobs, |i| {
            o.studies
                .then(|| particle_pilot(&scenes[i], 64, SWEEP_BUDGET).ok())
                .flatten()
                .map(|(b, _)| b)
        });
        // Runs go in size order and, once one is skipped, so are all larger sizes: the
        // columns line up with the scenes.
        let sizes: Vec<String> = scenes.iter().map(|sc| sc.size().to_string()).collect();
        let kept: Vec<&MethodSpec> = specs.iter().filter(|spec| o.keeps(spec)).collect();
        // One job per setting, its sizes in order (a size is run only if the smaller
        // ones held); the settings side by side on the workers.
        let chains = parallel_map(kept.len(), o.jobs, |j| {
            let spec = kept[j];
            let mut runs: Vec<ParticleRecord> = Vec::new();
            let mut not_run = 0;
            for (sc, b) in scenes.iter().zip(&bounds) {
                // A setting that left its layer or its budget at a smaller size is not run
                // at the larger ones: its cost there says nothing about a bound that holds,
                // and a lost layer on a big cloth can take minutes per frame.
                if let Some(prev) = runs
                    .last()
                    .filter(|r| !r.complete() || r.counters.layer_lost_at().is_some())
                {
                    println!(
                        "  {family}: {:22} {:16} size {}: not run (left its {} at {} links)",
                        spec.method(),
                        spec.knob(),
                        sc.size(),
                        if prev.complete() { "layer" } else { "budget" },
                        prev.size
                    );
                    not_run += 1;
                    continue;
                }
                let r = timed_repeatedly(|| {
                    run_particle_method(sc, spec, b.as_ref(), SWEEP_BUDGET, None, None)
                });
                print(&r);
                runs.push(r);
            }
            (runs, not_run)
        });
        for (spec, (runs, not_run)) in kept.into_iter().zip(chains) {
            let points: Vec<(f64, f64)> = runs
                .iter()
                .filter(|r| r.complete())
                .map(|r| (r.size as f64, r.ms_mean))
                .collect();
            let exp = dae_bench::particle_bench::fitted_exponent(&points);
            let col = |f: &dyn Fn(&ParticleRecord) -> String| {
                runs.iter()
                    .map(f)
                    .chain(std::iter::repeat_n("not run".to_string(), not_run))
                    .collect::<Vec<_>>()
                    .join(" / ")
            };
            let is_dbsmc = spec.method().starts_with("dbsmc");
            md += &format!(
                "| {family} | {} | {} | {} | {} | {} | {} | {} |\n",
                spec.method(),
                spec.knob(),
                sizes.join(" / "),
                col(&|r| if r.complete() {
                    format!("{:.3}", r.ms_mean)
                } else {
                    r.status.chars().take(40).collect()
                }),
                if is_dbsmc {
                    col(&|r| {
                        format!(
                            "{:.0}",
                            r.counters.updates() as f64 / r.frames.max(1) as f64
                        )
                    })
                } else {
                    "-".into()
                },
                if is_dbsmc {
                    col(&|r| {
                        r.counters.layer_lost_at().map_or("-".into(), |t| {
                            let ratio = r.counters.layer_worst_ratio().unwrap_or(f64::NAN);
                            if ratio < 100.0 {
                                format!("{t:.3} s (max {ratio:.2} eps)")
                            } else {
                                format!("{t:.3} s (max {ratio:.1e} eps)")
                            }
                        })
                    })
                } else {
                    "-".into()
                },
                exp.map_or("-".into(), |p| format!("{p:.2}")),
            );
            let label = format!("{family} {} {}", spec.method(), spec.knob());
            let label = match exp {
                Some(p) => format!("{label} (exponent {p:.2})"),
                None => label,
            };
            lines.push(dae_bench::particle_bench::Line { label, points });
            records.extend(runs);
        }
        records.extend(bisect_xpbd(&scenes, records, o));
        for method in [
            "xpbd-substeps",
            "xpbd-coloured",
            "vbd",
            "avbd",
            "avbd-tuned",
            "index1-rk4",
            "dbsmc-dp",
            "dbsmc-relaxed",
            "dbsmc-ramp",
            "dbsmc-ramp-generated",
        ] {
            let best: Vec<Option<&ParticleRecord>> = scenes
                .iter()
                .map(|sc| cheapest(records, &sc.title(), method, 1e-2))
                .collect();
            let points: Vec<(f64, f64)> = best
                .iter()
                .flatten()
                .map(|r| (r.size as f64, r.ms_mean))
                .collect();
            // An exponent only where every size holds: a gap would fit other sizes.
            let exp = if points.len() == scenes.len() {
                dae_bench::particle_bench::fitted_exponent(&points)
            } else {
                None
            };
            let settings: Vec<String> = best
                .iter()
                .map(|r| r.map_or("none".into(), |r| format!("{} ({:.3})", r.knob, r.ms_mean)))
                .collect();
            hold += &format!(
                "| {family} | {method} | {} | {} | {} |\n",
                sizes.join(" / "),
                settings.join(" / "),
                exp.map_or("-".into(), |p| format!("{p:.2}"))
            );
        }
    }
    md += &hold;
    if let Err(e) = dae_bench::particle_bench::loglog(
        &pictures.join("cost_vs_size.svg"),
        &format!("mean cost per frame against links (first {SWEEP_FRAMES} frames, fixed settings)"),
        "links",
        "ms per frame",
        &lines,
    ) {
        println!("chart cost vs size: {e}");
    }
    md
}

/// The worst strain the sweep's cheapest-setting table and target 2 read.
const SWEEP_LEVEL: f64 = 1e-2;

/// XPBD's substeps at each size, bisected for [`SWEEP_LEVEL`] over the sweep's frames as
/// the whole scenes are for every level (`super::bisect_small_steps`): the grid of `k` by
/// 4x can put XPBD's cheapest holding setting up to 4x too high, and target 2 reads
/// XPBD's cost on the 64 x 64 cloth from here. The runs made, for the CSV and the tables
/// (not the chart, whose lines are one setting at every size).
fn bisect_xpbd(
    scenes: &[ParticleScene],
    records: &[ParticleRecord],
    o: &Options,
) -> Vec<ParticleRecord> {
    // Each scene with each sweep order, and the sweep's runs of it.
    let mut jobs: Vec<(&ParticleScene, MethodSpec, Vec<ParticleRecord>)> = Vec::new();
    for sc in scenes {
        for first in [MethodSpec::XpbdSubsteps(1), MethodSpec::XpbdColoured(1)] {
            if !o.keeps(&first) {
                continue;
            }
            let runs = records
                .iter()
                .filter(|r| scene_title(r) == sc.title() && r.method == first.method())
                .cloned()
                .collect();
            jobs.push((sc, first, runs));
        }
    }
    parallel_map(jobs.len(), o.jobs, |j| {
        let (sc, first, runs) = &jobs[j];
        bisect_small_steps(first, runs, &[SWEEP_LEVEL], |spec| {
            let r =
                timed_repeatedly(|| run_particle_method(sc, spec, None, SWEEP_BUDGET, None, None));
            print(&r);
            r
        })
    })
    .into_iter()
    .flatten()
    .collect()
}
