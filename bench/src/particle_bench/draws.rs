//! A frame-tied DBSMC setting over nine draws: its longest step moved by -4 % ... +4 %.
//!
//! On a chaotic scene (the chains with heavy ends) any change of the step pattern leads
//! the trajectory elsewhere, and the counts and cost of one run are one draw among many:
//! the heavy 10-link chain's target-3 ratio read 0.89, 1.05 and 1.23 in three full runs of
//! the same design. Nine runs whose longest step differs by at most 4 % give the median
//! and the range of what the design costs there; `count_spread` prints them for any scene,
//! and the benchmark reads target 3 from them.

use std::time::Duration;

use dae_particles::AdaptiveMu;

use super::report::left_a_guarantee;
use super::run::{MethodSpec, ParticleRecord, RELAXED_MU_PER_FRAME, run_relaxed_at};
use super::scenes::ParticleScene;

/// The longest step's distances from the design's, as factors.
pub const NUDGES: [f64; 9] = [0.96, 0.97, 0.98, 0.99, 1.0, 1.01, 1.02, 1.03, 1.04];

/// What a frame-tied design does with `v` between updates, and with `mu`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameTied {
    /// `v` held (`dbsmc-relaxed`).
    Held,
    /// `v` ramped against the drift (`dbsmc-ramp`).
    Ramp,
    /// Ramped, `mu` searched for during the run (`dbsmc-adapt`).
    Adapt,
}

impl FrameTied {
    /// The design, layer and gain of a frame-tied setting on the hand-written model;
    /// `None` for any other method.
    pub fn of(spec: &MethodSpec) -> Option<(FrameTied, f64, f64)> {
        match *spec {
            MethodSpec::DbsmcRelaxed { eps, gain } => Some((FrameTied::Held, eps, gain)),
            MethodSpec::DbsmcRamped { eps, gain } => Some((FrameTied::Ramp, eps, gain)),
            MethodSpec::DbsmcAdaptive { eps, gain } => Some((FrameTied::Adapt, eps, gain)),
            _ => None,
        }
    }
}

/// The median, least and largest of nine draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    /// The fifth of the nine, sorted.
    pub median: f64,
    /// The least.
    pub min: f64,
    /// The largest.
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (not empty).
    pub fn of(mut values: Vec<f64>) -> Spread {
        values.sort_by(f64::total_cmp);
        Spread {
            median: values[values.len() / 2],
            min: values[0],
            max: values[values.len() - 1],
        }
    }
}

/// Nine draws of one setting on one scene.
#[derive(Clone, Debug)]
pub struct Draws {
    /// Mean wall time per frame (ms), one timing per draw.
    pub ms: Spread,
    /// Control updates per frame.
    pub updates: Spread,
    /// Steps per frame.
    pub steps: Spread,
    /// The updates per frame at the design's own longest step (the benchmark's draw).
    pub updates_at_design: f64,
    /// The largest worst strain over the draws (relative).
    pub worst_strain: f64,
    /// Draws that left their strain bound or `s`-layer.
    pub left: usize,
    /// Draws that did not run the whole scene (their budget stopped them).
    pub incomplete: usize,
}

/// The frame-tied `design` at layer `eps` and gain `gain` on `scene`, nine times, with
/// the longest step `per_mu * mu` moved by each of [`NUDGES`] (the benchmark's design
/// is `per_mu = 1/2`), each draw within `budget`.
pub fn frame_tied_draws(
    scene: &ParticleScene,
    design: FrameTied,
    eps: f64,
    gain: f64,
    per_mu: f64,
    budget: Duration,
) -> Draws {
    let runs: Vec<_> = NUDGES
        .iter()
        .map(|nudge| {
            let search = (design == FrameTied::Adapt).then(AdaptiveMu::default);
            run_relaxed_at(
                scene,
                eps,
                gain,
                RELAXED_MU_PER_FRAME,
                search,
                budget,
                |s| {
                    let s = if design == FrameTied::Held {
                        s
                    } else {
                        super::ramped(s)
                    };
                    let mu = s.layers.mu[0];
                    s.max_step(per_mu * nudge * mu)
                },
            )
        })
        .collect();
    let per_frame = |r: &ParticleRecord, count: u64| count as f64 / r.frames.max(1) as f64;
    let of = |f: &dyn Fn(&ParticleRecord) -> f64| Spread::of(runs.iter().map(f).collect());
    Draws {
        ms: of(&|r| r.ms_mean),
        updates: of(&|r| per_frame(r, r.counters.updates())),
        steps: of(&|r| per_frame(r, r.counters.steps)),
        updates_at_design: {
            let r = &runs[NUDGES.len() / 2];
            per_frame(r, r.counters.updates())
        },
        // A run without a finite worst strain did not complete, and counts there.
        worst_strain: runs.iter().map(|r| r.worst_strain).fold(0.0, f64::max),
        left: runs.iter().filter(|r| left_a_guarantee(r)).count(),
        incomplete: runs.iter().filter(|r| !r.complete()).count(),
    }
}
