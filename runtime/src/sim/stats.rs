//! What a run counts and measures: work, update periods, the window maxima, the values
//! seen before the window, and the record of a lost layer.

use crate::summary::BoundLoss;

/// Per-constraint measurements of one accepted step: the largest `|s_i|` over the step
/// (on the dense output with located crossings, at the end otherwise) and the time
/// spent beyond the bound.
pub(crate) struct StepMeasure {
    /// The step's length.
    pub(crate) h: f64,
    pub(crate) max_s: Vec<f64>,
    pub(crate) time_beyond: Vec<f64>,
}

impl StepMeasure {
    pub(crate) fn new(m: usize) -> Self {
        Self {
            h: 0.0,
            max_s: vec![0.0; m],
            time_beyond: vec![0.0; m],
        }
    }
}

#[derive(Default)]
pub(crate) struct Stats {
    pub(crate) steps: u64,
    pub(crate) rejected: u64,
    pub(crate) cuts: u64,
    /// Steps the progress guard took whole, without locating crossings in them.
    pub(crate) unlocated: u64,
    pub(crate) updates: u64,
    /// Updates of the blocks that asked only (block-local updates).
    pub(crate) block_updates: u64,
    /// Per constraint, the monitored updates its own `s_i` asked for.
    pub(crate) triggered: Vec<u64>,
    pub(crate) reaching_updates: u64,
    pub(crate) steps_since_update: u64,
    pub(crate) reaching_time: Option<f64>,
    pub(crate) stats_from: Option<f64>,
    pub(crate) last_window_update: Option<f64>,
    pub(crate) min_period: f64,
    pub(crate) period_sum: f64,
    pub(crate) periods: u64,
    pub(crate) max_s: Vec<f64>,
    pub(crate) max_w: Vec<f64>,
    /// Over the whole run (reaching phase included).
    pub(crate) seen_s: Vec<f64>,
    pub(crate) seen_w: Vec<f64>,
    pub(crate) violations: u64,
    pub(crate) rhs_evals: u64,
    pub(crate) loss: Loss,
}

impl Stats {
    pub(crate) fn new(m: usize) -> Self {
        Stats {
            triggered: vec![0; m],
            max_s: vec![0.0; m],
            max_w: vec![0.0; m],
            seen_s: vec![0.0; m],
            seen_w: vec![0.0; m],
            min_period: f64::INFINITY,
            loss: Loss::new(m),
            ..Stats::default()
        }
    }
}

/// The layer lost after reaching: `|s_i| > (1 + tol) eps_i`.
#[derive(Default)]
pub(crate) struct Loss {
    first: Option<(f64, usize)>,
    worst: Option<(f64, f64, usize)>,
    left: Vec<bool>,
    steps: u64,
    time: f64,
}

impl Loss {
    fn new(m: usize) -> Self {
        Loss {
            left: vec![false; m],
            ..Loss::default()
        }
    }

    /// Account for one step ending at `t` of length `h` (after reaching): `measure`
    /// holds each variable's largest `|s_i|` over the step and its time beyond the
    /// bound; `bound_i = (1 + tol) eps_i`.
    pub(crate) fn observe(&mut self, t: f64, h: f64, measure: &StepMeasure, eps: &[f64], tol: f64) {
        let mut outside = false;
        for (i, (&s, &e)) in measure.max_s.iter().zip(eps).enumerate() {
            let ratio = s / e;
            // A NaN ratio counts as outside.
            let within = ratio <= 1.0 + tol;
            if !within {
                outside = true;
                if self.first.is_none() {
                    // The step's start plus the time inside before leaving.
                    let left_at = t - h + (h - measure.time_beyond[i].min(h));
                    self.first = Some((left_at, i));
                }
                self.left[i] = true;
                if self.worst.is_none_or(|(r, _, _)| ratio > r) {
                    self.worst = Some((ratio, t, i));
                }
            }
        }
        if outside {
            self.steps += 1;
            self.time += measure
                .time_beyond
                .iter()
                .fold(0.0f64, |a, b| a.max(*b))
                .min(h);
        }
    }

    /// Whether a layer has been left after reaching.
    pub(crate) fn lost(&self) -> bool {
        self.first.is_some()
    }

    pub(crate) fn record(
        &self,
        names: &[String],
        near_singular: Option<crate::summary::NearSingular>,
    ) -> Option<BoundLoss> {
        let (first_time, first) = self.first?;
        let (worst_ratio, worst_time, worst) = self.worst?;
        Some(BoundLoss {
            first_time,
            first_constraint: names[first].clone(),
            worst_ratio,
            worst_time,
            worst_constraint: names[worst].clone(),
            constraints: names
                .iter()
                .zip(&self.left)
                .filter(|(_, l)| **l)
                .map(|(n, _)| n.clone())
                .collect(),
            steps_outside: self.steps,
            time_outside: self.time,
            near_singular,
        })
    }
}
