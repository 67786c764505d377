//! The hair of `S` strands (scene C2, 32 links per strand), whole 5 s scenes: one DBSMC
//! simulator over the whole head against one per strand (`dae_particles::Components`,
//! the default of the benchmark's DBSMC runs), the latter on 1 and 2 threads. The
//! design is the benchmark's `dbsmc-ramp` (frame-tied, `v` ramped against the drift)
//! at one `eps` and floor gain `c`; the table gives the cost per frame, the updates and
//! steps per frame (summed over the parts), the worst strain against `eps`, and the
//! exponent of the cost per frame in `S` fitted over the sizes that ran whole.
//!
//! ```text
//! cargo run --release -p dae-bench --example parts_apart [-- EPS C BUDGET S1,S2,... [ONE_UP_TO]]
//! ```
//!
//! `EPS` (default 1e-2), `C` (default 4), `BUDGET` the wall-clock seconds of one run
//! (default 300), the strand counts (default 10,30,100,300,1000), and the largest
//! strand count run with one simulator (default 100: its cost grows as `S^2`). One
//! run at a time: one core is the metric, the second thread is the parallel row.

use std::time::Duration;

use dae_bench::particle_bench::{
    MethodSpec, ParticleRecord, ParticleScene, c2, drive_scene, fitted_exponent, kept_both, ramped,
    relaxed_settings,
};
use dae_particles::{BackendError, Components, Dbsmc, ParticleModel, System};

/// The benchmark's `dbsmc-ramp` backend on `system`, going on after a lost layer.
fn dbsmc(system: &System, eps: f64, c: f64) -> Result<Dbsmc<ParticleModel>, BackendError> {
    let model = ParticleModel::new(system).map_err(|e| BackendError {
        method: "dbsmc-ramp".into(),
        t: 0.0,
        reason: e.to_string(),
        deadline: false,
    })?;
    let settings = ramped(relaxed_settings(&model, eps, c));
    Ok(Dbsmc::new(model, settings, "dbsmc-ramp")?.keep_going_after_bound_loss())
}

fn run(
    scene: &ParticleScene,
    eps: f64,
    c: f64,
    budget: Duration,
    threads: Option<usize>,
) -> ParticleRecord {
    let spec = MethodSpec::DbsmcRamped { eps, gain: c };
    let failed = |e: BackendError| ParticleRecord {
        status: format!("failed: {e}"),
        ..ParticleRecord::default()
    };
    match threads {
        None => match dbsmc(&scene.system, eps, c) {
            Ok(b) => drive_scene(scene, &spec, b, budget, None, None),
            Err(e) => failed(e),
        },
        Some(n) => match Components::new(&scene.system, |part, _| dbsmc(&part.system, eps, c)) {
            Ok(b) => drive_scene(scene, &spec, b.threads(n), budget, None, None),
            Err(e) => failed(e),
        },
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |i: usize, default: f64| {
        args.get(i)
            .map(|a| a.parse::<f64>().expect("a number"))
            .unwrap_or(default)
    };
    let (eps, c, budget) = (num(0, 1e-2), num(1, 4.0), num(2, 300.0));
    let sizes: Vec<usize> = args
        .get(3)
        .map(|a| {
            a.split(',')
                .map(|s| s.parse().expect("a strand count"))
                .collect()
        })
        .unwrap_or_else(|| vec![10, 30, 100, 300, 1000]);
    let one_up_to = num(4, 100.0) as usize;
    let budget = Duration::from_secs_f64(budget);
    println!(
        "| strands | links | simulators | threads | ms / frame mean (max) | updates / frame | steps / frame | worst strain / eps | frames | status |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut fits: Vec<(&str, Vec<(f64, f64)>)> = vec![
        ("one", Vec::new()),
        ("one per strand, 1 thread", Vec::new()),
        ("one per strand, 2 threads", Vec::new()),
    ];
    for &s in &sizes {
        let scene = match c2(s, 32) {
            Ok(scene) => scene,
            Err(e) => {
                eprintln!("parts_apart: {e}");
                std::process::exit(2);
            }
        };
        let runs: Vec<(usize, Option<usize>)> = [(0, None), (1, Some(1)), (2, Some(2))]
            .into_iter()
            .filter(|&(_, t)| t.is_some() || s <= one_up_to)
            .collect();
        for (row, threads) in runs {
            let r = run(&scene, eps, c, budget, threads);
            let frames = r.frames.max(1) as f64;
            let sims = if threads.is_some() { s } else { 1 };
            println!(
                "| {s} | {} | {sims} | {} | {:.3} ({:.3}) | {:.0} | {:.0} | {:.3} | {}/{} | {} |",
                32 * s,
                threads.unwrap_or(1),
                r.ms_mean,
                r.ms_max,
                r.counters.updates() as f64 / frames,
                r.counters.steps as f64 / frames,
                r.worst_strain / eps,
                r.frames,
                r.frames_total,
                r.status
            );
            if r.complete() && r.frames == r.frames_total && kept_both(&r) {
                fits[row].1.push((s as f64, r.ms_mean));
            } else {
                eprintln!("parts_apart: S = {s}, {}: {}", fits[row].0, r.status);
            }
        }
    }
    println!();
    for (name, points) in &fits {
        if let Some(e) = fitted_exponent(points) {
            println!(
                "{name}: cost per frame ~ S^{e:.2} over S = {:?}",
                points.iter().map(|p| p.0 as usize).collect::<Vec<_>>()
            );
        }
    }
}
