//! `mu` that follows the motion: a search, frame by frame, for the `mu` at which a run
//! costs least ([`Dbsmc::adapt_mu`](crate::Dbsmc::adapt_mu)).
//!
//! Why a search and not a rule: `mu` pulls two ways. The drift of `s'` between updates
//! grows with `mu`, so the updates a frame needs grow with it; the longest step, tied
//! to `mu`, sets the steps where the updates are few. Which wins depends on the scene
//! and changes during it: on light and medium 100-link chains the whole scene costs
//! 3x less at `mu` = 1/32 of the frame than at 1/4, on the 100-link chain with an end
//! 10^4 times heavier 2.3x less at 1/2, and over the first calm frames of every scene
//! the large `mu` is the cheaper (measured by `mu_sweep`: docs/particles.md says where the
//! measurements are). The counts of each frame say which way the cost went after a move.
//!
//! The search dithers and follows the slope it measures (extremum seeking): `mu`
//! alternates between two values a `step` apart, `window` frames at each, and after
//! three windows (sides `a`, `b`, `a`) the work per frame at side `a`, taken as the mean
//! of its two windows, is compared with side `b`'s. The mean of the windows before and
//! after cancels a work that rises or falls steadily with the motion (a chain that
//! whips harder each frame), which a comparison of two windows in a row would take for
//! the effect of `mu`. The pair then moves one `step` towards the cheaper side, and the
//! next three windows measure again. The work is counted (right-hand side evaluations
//! and factorisations), not timed, so that a run is the same on any machine.

/// How `mu` is searched for during a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveMu {
    /// Frames per trial of one `mu` (at least 1).
    pub window: u32,
    /// Factor of one move of `mu` (above 1).
    pub step: f64,
    /// Bounds of `mu` as multiples of the one the run started with.
    pub min_scale: f64,
    /// Upper bound, likewise.
    pub max_scale: f64,
}

impl Default for AdaptiveMu {
    /// Windows of 4 frames, `mu` dithered by a factor 2 and moved by 2 (a move every
    /// 0.2 s at most), between 1/16 and 2 times the start's: with the frame-tied
    /// design's `mu` of a quarter frame, from 1/64 to 1/2 of the frame, the range of
    /// `mu_sweep`'s best values.
    fn default() -> Self {
        Self {
            window: 4,
            step: 2.0,
            min_scale: 1.0 / 16.0,
            max_scale: 2.0,
        }
    }
}

impl AdaptiveMu {
    /// Whether the fields make a search (`window >= 1`, `step > 1`, `0 < min_scale <= 1
    /// <= max_scale`, all finite): an error message naming the field otherwise.
    pub fn check(&self) -> Result<(), String> {
        if self.window == 0 {
            return Err("mu search: window must be at least one frame".into());
        }
        if !(self.step.is_finite() && self.step > 1.0) {
            return Err(format!(
                "mu search: step {} must be a finite factor above 1",
                self.step
            ));
        }
        if !(self.min_scale > 0.0 && self.min_scale <= 1.0) {
            return Err(format!(
                "mu search: min_scale {} must be in (0, 1]",
                self.min_scale
            ));
        }
        if !(self.max_scale.is_finite() && self.max_scale >= 1.0) {
            return Err(format!(
                "mu search: max_scale {} must be finite and at least 1",
                self.max_scale
            ));
        }
        if self.max_scale < self.step * self.min_scale * (1.0 - 1e-9) {
            return Err(format!(
                "mu search: max_scale / min_scale = {} leaves no room for two values a step {} apart",
                self.max_scale / self.min_scale,
                self.step
            ));
        }
        Ok(())
    }
}

/// The state of a search during a run.
#[derive(Clone, Debug)]
pub(crate) struct Searcher {
    how: AdaptiveMu,
    /// The geometric middle of the two dithered values, as a multiple of the start's
    /// `mu`: they are `low * step` and `low`, with `low = middle / sqrt(step)`.
    low: f64,
    /// Whether `mu` is at the upper of the two values now.
    upper: bool,
    frames: u32,
    work: u64,
    /// Work per frame of the windows at the present pair, oldest first.
    rates: Vec<f64>,
    /// Moves asked for, and of those refused by the simulator.
    asked: u64,
    refused: u64,
}

impl Searcher {
    /// A search whose first window is the start's `mu` as the upper of the pair: the
    /// second tries `mu / step` (the frame-tied design starts from a `mu` that the calm
    /// first frames favour, and the scenes that whip favour a smaller one). Where
    /// `min_scale` leaves no room below the start, the start is the lower of the pair
    /// and the second window tries `mu * step`.
    pub(crate) fn new(how: AdaptiveMu) -> Self {
        let below = 1.0 / how.step >= how.min_scale * (1.0 - 1e-9);
        Self {
            how,
            low: if below { 1.0 / how.step } else { 1.0 },
            upper: below,
            frames: 0,
            work: 0,
            rates: Vec::with_capacity(3),
            asked: 0,
            refused: 0,
        }
    }

    /// `mu` now, as a multiple of the start's.
    pub(crate) fn scale(&self) -> f64 {
        self.scale_of(self.upper)
    }

    /// The moves made so far, and those refused.
    pub(crate) fn moves(&self) -> (u64, u64) {
        (self.asked - self.refused, self.refused)
    }

    /// After a frame that cost `work`: the factor to move `mu` by, at the end of a
    /// window (none where the pair moved to put the other side where `mu` is).
    pub(crate) fn after_frame(&mut self, work: u64) -> Option<f64> {
        self.frames += 1;
        self.work += work;
        if self.frames < self.how.window {
            return None;
        }
        let rate = self.work as f64 / f64::from(self.frames);
        self.frames = 0;
        self.work = 0;
        self.rates.push(rate);
        let before = self.scale();
        if let [a0, b, a1] = self.rates[..] {
            // Side `a` (where `mu` is now) against side `b`, a steady trend cancelled;
            // a tie moves nothing.
            let a = 0.5 * (a0 + a1);
            if a != b {
                let up = self.upper == (a < b);
                let step = if up {
                    self.how.step
                } else {
                    1.0 / self.how.step
                };
                // Relative slack: the pair is a product of moves and meets its bounds
                // only up to rounding.
                let slack = 1.0 + 1e-9;
                let low = self.low * step;
                if low * slack >= self.how.min_scale
                    && low * self.how.step <= self.how.max_scale * slack
                {
                    self.low = low;
                }
            }
            self.rates.clear();
        }
        self.upper = !self.upper;
        let factor = self.scale() / before;
        let asks = (factor - 1.0).abs() > 1e-9;
        self.asked += u64::from(asks);
        asks.then_some(factor)
    }

    /// The move asked for by [`Self::after_frame`] was refused: `mu` stays where it
    /// was, and the search starts its measurement again from there.
    pub(crate) fn refused(&mut self, factor: f64) {
        self.refused += 1;
        let now = self.scale() / factor;
        self.upper = (now - self.low * self.how.step).abs() < (now - self.low).abs();
        if (now / self.scale_of(self.upper) - 1.0).abs() > 1e-9 {
            // Not one of the pair any more (a refused move of the pair): make it the
            // upper one.
            self.low = now / self.how.step;
            self.upper = true;
        }
        self.rates.clear();
    }

    fn scale_of(&self, upper: bool) -> f64 {
        if upper {
            self.low * self.how.step
        } else {
            self.low
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn how(window: u32) -> AdaptiveMu {
        AdaptiveMu {
            window,
            step: 2.0,
            min_scale: 0.125,
            max_scale: 2.0,
        }
    }

    /// Drive a search with windows of one frame against a cost per frame of `mu` and
    /// the frame's number, and return the scales it visited, one per frame.
    fn visits(cost: impl Fn(f64, usize) -> f64, frames: usize) -> Vec<f64> {
        let mut s = Searcher::new(how(1));
        (0..frames)
            .map(|k| {
                s.after_frame(cost(s.scale(), k) as u64);
                s.scale()
            })
            .collect()
    }

    #[test]
    fn the_search_dithers_once_per_window_and_moves_towards_the_cheaper_side() {
        let mut s = Searcher::new(how(2));
        assert_eq!(s.scale(), 1.0);
        assert_eq!(s.after_frame(10), None);
        assert_eq!(s.after_frame(10), Some(0.5), "tries the smaller mu first");
        for _ in 0..2 {
            s.after_frame(6);
        }
        assert_eq!(s.scale(), 1.0, "dithers back");
        s.after_frame(10);
        // Side 1.0 cost 10 twice, side 0.5 cost 6: the pair moves down to (0.25, 0.5),
        // and the next window is at its other side.
        assert_eq!(s.after_frame(10), Some(0.25));
        assert_eq!(s.scale(), 0.25);
        // The other way: side 1.0 cheaper than 0.5. The pair moves up to (1, 2), whose
        // lower side is the mu in use: no move, and the next window tries 2.
        let mut s = Searcher::new(how(1));
        assert_eq!(s.after_frame(10), Some(0.5));
        assert_eq!(s.after_frame(20), Some(2.0));
        assert_eq!(s.after_frame(10), None);
        assert_eq!(s.scale(), 1.0);
        assert_eq!(s.after_frame(10), Some(2.0));
    }

    #[test]
    fn a_cost_that_rises_with_the_motion_does_not_move_the_search() {
        // The work grows by 10 per frame whatever mu is, and mu costs nothing: the
        // trend cancels, and the pair stays where it starts.
        let v = visits(|_, k| 100.0 + 10.0 * k as f64, 30);
        assert!(v.iter().all(|&s| s == 1.0 || s == 0.5), "{v:?}");
        // Two windows in a row would have read the trend as the effect of mu: at every
        // second window the side just measured looks dearer.
    }

    #[test]
    fn the_search_settles_around_the_cheapest_mu_and_stays_within_its_bounds() {
        // Least at 0.25, under a rising trend.
        let cost =
            |scale: f64, k: usize| 100.0 * (scale.log2() + 2.0).abs() + 50.0 + 5.0 * k as f64;
        let v = visits(cost, 60);
        assert!(v.iter().all(|&s| (0.125..=2.0).contains(&s)), "{v:?}");
        assert!(v[12..].iter().all(|&s| (0.125..=0.5).contains(&s)), "{v:?}");
        // A cost that falls towards a bound: the pair reaches it and stays.
        let v = visits(|scale, _| 100.0 * scale, 30);
        assert_eq!(&v[24..], &[0.125, 0.25, 0.125, 0.25, 0.125, 0.25], "{v:?}");
        let v = visits(|scale, _| 100.0 / scale, 30);
        assert!(v[12..].iter().all(|&s| s == 1.0 || s == 2.0), "{v:?}");
    }

    #[test]
    fn a_search_that_may_not_shrink_below_the_start_tries_a_larger_mu_first() {
        let mut s = Searcher::new(AdaptiveMu {
            min_scale: 1.0,
            ..how(1)
        });
        assert_eq!(s.scale(), 1.0);
        assert_eq!(s.after_frame(10), Some(2.0));
        // Cheaper above: the pair cannot move past max_scale = 2, so it dithers.
        for _ in 0..6 {
            s.after_frame(if s.scale() > 1.0 { 5 } else { 10 });
            assert!((1.0..=2.0).contains(&s.scale()), "{}", s.scale());
        }
    }

    #[test]
    fn a_refused_move_leaves_the_search_at_the_mu_the_run_kept() {
        let mut s = Searcher::new(how(1));
        let f = s.after_frame(10).unwrap();
        assert_eq!(f, 0.5);
        s.refused(f);
        assert_eq!(s.scale(), 1.0);
        // Measures again from there: the next window dithers to 0.5.
        assert_eq!(s.after_frame(10), Some(0.5));
        // A refused move of the pair: the kept mu becomes the pair's upper side.
        let mut s = Searcher::new(how(1));
        for w in [10, 5] {
            let f = s.after_frame(w).unwrap();
            assert!(f != 1.0);
        }
        let f = s.after_frame(10).unwrap();
        assert_eq!(s.scale(), 0.25);
        s.refused(f);
        assert_eq!(s.scale(), 1.0);
        assert_eq!(s.after_frame(1), Some(0.5));
    }

    #[test]
    fn a_search_that_cannot_search_is_refused_with_its_field() {
        let ok = AdaptiveMu::default();
        assert!(ok.check().is_ok());
        for (bad, field) in [
            (AdaptiveMu { window: 0, ..ok }, "window"),
            (AdaptiveMu { step: 1.0, ..ok }, "step"),
            (
                AdaptiveMu {
                    step: f64::NAN,
                    ..ok
                },
                "step",
            ),
            (
                AdaptiveMu {
                    min_scale: 0.0,
                    ..ok
                },
                "min_scale",
            ),
            (
                AdaptiveMu {
                    min_scale: 2.0,
                    ..ok
                },
                "min_scale",
            ),
            (
                AdaptiveMu {
                    max_scale: 0.5,
                    ..ok
                },
                "max_scale",
            ),
            (
                AdaptiveMu {
                    max_scale: f64::INFINITY,
                    ..ok
                },
                "max_scale",
            ),
            (
                AdaptiveMu {
                    min_scale: 1.0,
                    max_scale: 1.5,
                    ..ok
                },
                "no room",
            ),
        ] {
            let e = bad.check().unwrap_err();
            assert!(e.contains(field), "{e}");
        }
    }
}
