//! How much one run's counts say: the frame-tied design (`dae_bench::relaxed_settings`)
//! run on one scene with its longest step moved by -4 % ... +4 % around `mu / 4`, `mu / 2`
//! and `mu`, and the spread of the control updates and steps per frame it makes.
//!
//! On a chaotic scene (the chains with heavy ends) any change of the step pattern leads
//! the trajectory elsewhere, and the counts of one run are one draw among many: a
//! comparison of two settings there needs several draws each. The layer is checked in
//! every run (a run that left it is counted, not hidden), and the exit status is 1 if
//! any did. The wall time per frame is timed once per run: compare it on a quiet machine.
//!
//! ```text
//! cargo run --release -p dae-bench --example count_spread [-- SCENE EPS C held|ramp|adapt]
//! ```
//!
//! `SCENE` is `c1:N:RATIO` (C1, `N` links, end-mass ratio `RATIO`) or `c3:W` (C3 (a),
//! `W` x `W`); the defaults run the heavy 10-link chain (`c1:10:1e4`) at eps = 1e-3,
//! `c = 4`, `v` ramped. `adapt` ramps `v` and searches for `mu` during the run from a
//! quarter of the frame (the benchmark's `dbsmc-adapt`; the longest step follows `mu`,
//! so its nudge stays).

use std::time::Duration;

use dae_bench::{RELAXED_MU_PER_FRAME, left_a_guarantee, run_relaxed_at, scene_of_spec};
use dae_particles::AdaptiveMu;

/// What the design does with `v` between updates, and with `mu`.
#[derive(Clone, Copy, PartialEq)]
enum Design {
    /// `v` held (`dbsmc-relaxed`).
    Held,
    /// `v` ramped against the drift (`dbsmc-ramp`).
    Ramp,
    /// Ramped, `mu` searched for during the run (`dbsmc-adapt`).
    Adapt,
}

/// The longest step's distances from the design's, as factors.
const NUDGES: [f64; 9] = [0.96, 0.97, 0.98, 0.99, 1.0, 1.01, 1.02, 1.03, 1.04];

/// One draw: its counts and cost per frame, whether it left its layer or its strain
/// bound, and whether it ran the whole scene.
struct Draw {
    updates: f64,
    steps: f64,
    ms: f64,
    left: bool,
    complete: bool,
}

/// The median, least and largest of `values` (nine draws).
fn spread(mut values: Vec<f64>) -> (f64, f64, f64) {
    values.sort_by(f64::total_cmp);
    (
        values[values.len() / 2],
        values[0],
        values[values.len() - 1],
    )
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |i: usize, d: &str| args.get(i).cloned().unwrap_or_else(|| d.to_string());
    let parsed = scene_of_spec(&get(0, "c1:10:1e4")).and_then(|s| {
        let eps: f64 = get(1, "1e-3").parse().map_err(|_| "EPS is not a number")?;
        let gain: f64 = get(2, "4").parse().map_err(|_| "C is not a number")?;
        let design = match get(3, "ramp").as_str() {
            "ramp" => Design::Ramp,
            "held" => Design::Held,
            "adapt" => Design::Adapt,
            other => return Err(format!("`{other}`: held, ramp or adapt")),
        };
        Ok((s, eps, gain, design))
    });
    let (scene, eps, gain, design) = parsed.unwrap_or_else(|e| {
        eprintln!("count_spread: {e} (usage: count_spread [SCENE EPS C held|ramp|adapt])");
        std::process::exit(2);
    });
    println!(
        "{}, eps = {eps:e}, c = {gain}, {}\n",
        scene.title(),
        match design {
            Design::Held => "v held",
            Design::Ramp => "v ramped",
            Design::Adapt => "v ramped, mu searched for from a quarter frame",
        }
    );
    println!(
        "| longest step | updates / frame: at exactly this step; median [min, max] of the 9 | steps / frame, median [min, max] | ms / frame, median [min, max] (one timing each) | layer or strain left |"
    );
    println!("|---|---|---|---|---|");
    let mut lost_any = false;
    for per_mu in [0.25, 0.5, 1.0] {
        let draws: Vec<Draw> = NUDGES
            .iter()
            .map(|nudge| {
                let search = (design == Design::Adapt).then(AdaptiveMu::default);
                let budget = Duration::from_secs(600);
                let r = run_relaxed_at(
                    &scene,
                    eps,
                    gain,
                    RELAXED_MU_PER_FRAME,
                    search,
                    budget,
                    |s| {
                        let s = if design == Design::Held {
                            s
                        } else {
                            s.ramp_against_drift()
                        };
                        let mu = s.mu[0];
                        s.max_step(per_mu * nudge * mu)
                    },
                );
                let f = r.frames.max(1) as f64;
                Draw {
                    updates: r.counters.updates as f64 / f,
                    steps: r.counters.steps as f64 / f,
                    ms: r.ms_mean,
                    left: left_a_guarantee(&r),
                    complete: r.complete(),
                }
            })
            .collect();
        let at_design = draws[NUDGES.len() / 2].updates;
        let of = |f: fn(&Draw) -> f64| spread(draws.iter().map(f).collect());
        let (upd, steps, ms) = (of(|d| d.updates), of(|d| d.steps), of(|d| d.ms));
        let lost = draws.iter().filter(|d| d.left).count();
        let short = draws.iter().filter(|d| !d.complete).count();
        lost_any |= lost > 0;
        println!(
            "| mu / {} | {at_design:.1}: {:.1} [{:.1}, {:.1}] | {:.1} [{:.1}, {:.1}] | {:.3} [{:.3}, {:.3}] | {lost} of 9{} |",
            1.0 / per_mu,
            upd.0,
            upd.1,
            upd.2,
            steps.0,
            steps.1,
            steps.2,
            ms.0,
            ms.1,
            ms.2,
            if short > 0 {
                format!(" ({short} incomplete)")
            } else {
                String::new()
            }
        );
    }
    if lost_any {
        std::process::exit(1);
    }
}
