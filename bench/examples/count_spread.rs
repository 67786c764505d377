//! How much one run's counts say: the frame-tied design (`dae_bench::particle_bench::relaxed_settings`)
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

use dae_bench::{
    particle_bench::FrameTied, particle_bench::RELAXED_STEP_PER_MU,
    particle_bench::frame_tied_draws, particle_bench::scene_of_spec,
};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |i: usize, d: &str| args.get(i).cloned().unwrap_or_else(|| d.to_string());
    let parsed = scene_of_spec(&get(0, "c1:10:1e4")).and_then(|s| {
        let eps: f64 = get(1, "1e-3").parse().map_err(|_| "EPS is not a number")?;
        let gain: f64 = get(2, "4").parse().map_err(|_| "C is not a number")?;
        let design = match get(3, "ramp").as_str() {
            "ramp" => FrameTied::Ramp,
            "held" => FrameTied::Held,
            "adapt" => FrameTied::Adapt,
            other => return Err(format!("`{other}`: held, ramp or adapt")),
        };
        Ok((s, eps, gain, design))
    });
    let (scene, eps, gain, design) = parsed.unwrap_or_else(|e| {
        eprintln!("count_spread: {e} (usage: count_spread [SCENE EPS C held|ramp|adapt])");
        std::process::exit(2);
    });
    println!(
        "{}, eps = {eps:e}, c = {gain}, {} (the benchmark's longest step: mu / {})\n",
        scene.title(),
        match design {
            FrameTied::Held => "v held",
            FrameTied::Ramp => "v ramped",
            FrameTied::Adapt => "v ramped, mu searched for from a quarter frame",
        },
        1.0 / RELAXED_STEP_PER_MU
    );
    println!(
        "| longest step | updates / frame: at exactly this step; median [min, max] of the 9 | steps / frame, median [min, max] | ms / frame, median [min, max] (one timing each) | layer or strain left |"
    );
    println!("|---|---|---|---|---|");
    let mut lost_any = false;
    for per_mu in [0.25, 0.5, 1.0] {
        let d = frame_tied_draws(&scene, design, eps, gain, per_mu, Duration::from_secs(600));
        lost_any |= d.left > 0;
        println!(
            "| mu / {} | {:.1}: {:.1} [{:.1}, {:.1}] | {:.1} [{:.1}, {:.1}] | {:.3} [{:.3}, {:.3}] | {} of 9{} |",
            1.0 / per_mu,
            d.updates_at_design,
            d.updates.median,
            d.updates.min,
            d.updates.max,
            d.steps.median,
            d.steps.min,
            d.steps.max,
            d.ms.median,
            d.ms.min,
            d.ms.max,
            d.left,
            if d.incomplete > 0 {
                format!(" ({} incomplete)", d.incomplete)
            } else {
                String::new()
            }
        );
    }
    if lost_any {
        std::process::exit(1);
    }
}
