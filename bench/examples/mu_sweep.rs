//! How the frame-tied design's cost depends on `mu`: the ramped design (`dbsmc-ramp`,
//! `dae_bench::particle_bench::relaxed_settings_at` with `v` ramped against the drift) through one whole
//! scene at several `mu`, each a fraction of the 1/60 s frame. The benchmark runs the
//! design at `mu` = a quarter of the frame only (`RELAXED_MU_PER_FRAME`).
//!
//! ```text
//! cargo run --release -p dae-bench --example mu_sweep [-- [--held] SCENE EPS C BUDGET [MU ...]]
//! ```
//!
//! `SCENE` is `c1:N:RATIO` or `c3:W` (default `c1:100:1e2`, the medium 100-link chain of
//! target 3), `EPS` the strain bound (1e-3), `C` the floor gain (4), `BUDGET` the wall
//! seconds one run may take (60), and the `MU` are fractions of the frame (default
//! 1/4, 1/8, 1/16, 1/32 and 1/64, written `0.25` or `1/4`). `mu` sets two things that
//! pull apart: the drift of `s'` between updates grows with `mu^2` (so the updates per
//! frame, about `sqrt(drift / eps)`, with `mu`), and the longest step is `mu / 2` (so the
//! steps per frame grow as `mu` shrinks). The runs go one per core at a time, each one
//! thread's; the exit status is 1 if any run left its layer or its strain bound.
//! `--held` holds `v` between updates (the benchmark's `dbsmc-relaxed`) instead of
//! ramping it, and a `MU` of `search` (or `search:1/8`) searches for `mu` during the run
//! from a quarter of the frame (or the fraction given; `dae_particles::AdaptiveMu`).

use std::time::Duration;

use dae_bench::{
    particle_bench::RELAXED_MU_PER_FRAME, particle_bench::default_workers,
    particle_bench::left_a_guarantee, particle_bench::parallel_map, particle_bench::run_relaxed_at,
    particle_bench::scene_of_spec,
};
use dae_particles::AdaptiveMu;

/// One run's `mu`: a fixed fraction of the frame, or searched for from a start.
#[derive(Clone, Copy)]
enum Mu {
    Fixed(f64),
    Search(f64),
}

/// `0.25`, `1/4`, `search` (from a quarter of the frame) or `search:1/8`.
fn mu_of(s: &str) -> Result<Mu, String> {
    match s.strip_prefix("search") {
        Some("") => Ok(Mu::Search(RELAXED_MU_PER_FRAME)),
        Some(rest) => match rest.strip_prefix(':') {
            Some(start) => fraction(start).map(Mu::Search),
            None => Err(format!("`{s}` is not `search` or `search:FRACTION`")),
        },
        None => fraction(s).map(Mu::Fixed),
    }
}

/// `0.25` or `1/4`.
fn fraction(s: &str) -> Result<f64, String> {
    let bad = || format!("`{s}` is not a fraction of the frame (0.25 or 1/4)");
    let value = match s.split_once('/') {
        Some((a, b)) => {
            let (a, b): (f64, f64) = (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
            a / b
        }
        None => s.parse().map_err(|_| bad())?,
    };
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(bad())
    }
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    // `--held`: `v` held between updates (`dbsmc-relaxed`) instead of ramped.
    let held = args.iter().any(|a| a == "--held");
    args.retain(|a| a != "--held");
    let get = |i: usize, d: &str| args.get(i).cloned().unwrap_or_else(|| d.to_string());
    let parsed = scene_of_spec(&get(0, "c1:100:1e2")).and_then(|scene| {
        let eps: f64 = get(1, "1e-3").parse().map_err(|_| "EPS is not a number")?;
        let gain: f64 = get(2, "4").parse().map_err(|_| "C is not a number")?;
        let budget: f64 = get(3, "60").parse().map_err(|_| "BUDGET is not a number")?;
        let mus: Vec<Mu> = if args.len() > 4 {
            args[4..]
                .iter()
                .map(|s| mu_of(s))
                .collect::<Result<_, _>>()?
        } else {
            [0.25, 0.125, 0.0625, 0.03125, 0.015625]
                .map(Mu::Fixed)
                .to_vec()
        };
        Ok((scene, eps, gain, budget, mus))
    });
    let (scene, eps, gain, budget, mus) = parsed.unwrap_or_else(|e| {
        eprintln!("mu_sweep: {e} (usage: mu_sweep [--held] [SCENE EPS C BUDGET [MU ...]])");
        std::process::exit(2);
    });
    println!(
        "{}, eps = {eps:e}, c = {gain}, v {}, {budget} s per run\n",
        scene.title(),
        if held { "held" } else { "ramped" }
    );
    println!(
        "| mu / frame | ms / frame | updates / frame | steps / frame | worst strain / eps | frames | left a bound |"
    );
    println!("|---|---|---|---|---|---|---|");
    let runs = parallel_map(mus.len(), default_workers(), |i| {
        let (start, search) = match mus[i] {
            Mu::Fixed(f) => (f, None),
            Mu::Search(f) => (f, Some(AdaptiveMu::default())),
        };
        run_relaxed_at(
            &scene,
            eps,
            gain,
            start,
            search,
            Duration::from_secs_f64(budget),
            |s| {
                if held {
                    s
                } else {
                    dae_bench::particle_bench::ramped(s)
                }
            },
        )
    });
    let mut lost = false;
    for (mu, r) in mus.iter().zip(&runs) {
        let f = r.frames.max(1) as f64;
        let left = left_a_guarantee(r);
        lost |= left;
        let label = match mu {
            Mu::Fixed(f) => format!("1/{:.0}", 1.0 / f),
            Mu::Search(f) => format!("searched from 1/{:.0}", 1.0 / f),
        };
        println!(
            "| {label} | {:.3} | {:.1} | {:.1} | {:.3} | {}/{} {} | {} |",
            r.ms_mean,
            r.counters.updates() as f64 / f,
            r.counters.steps as f64 / f,
            r.worst_strain / eps,
            r.frames,
            r.frames_total,
            r.status,
            if left {
                r.counters
                    .layer_lost_at()
                    .map_or("strain".into(), |t| format!("layer at {t:.3} s"))
            } else {
                "-".into()
            },
        );
    }
    if lost {
        std::process::exit(1);
    }
}
