//! `mu` that follows the motion: a search, frame by frame, for the `mu` at which a run
//! costs least ([`AdaptiveMu`]; the simulator runs it when
//! [`Layers::adapt_mu`](crate::settings::Layers::adapt_mu) is set, and
//! `dae_particles::Dbsmc::adapt_mu` at the frames of a scene).
//!
//! Why a search and not a rule: `mu` pulls two ways. The drift of `s'` between updates
//! grows with `mu`, so the updates a frame needs grow with it; the longest step, tied
//! to `mu`, sets the steps where the updates are few. Which wins depends on the scene
//! and changes during it: on light and medium 100-link chains the whole scene costs
//! 3x less at `mu` = 1/32 of the frame than at 1/4, on the 100-link chain with an end
//! 10^4 times heavier 2.3x less at 1/2, and over the first calm frames of every scene
//! the large `mu` is the cheaper (measured by dae-bench's `mu_sweep`, docs/particles.md). The counts of each frame say which way the cost went after a move.
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

use crate::settings::AdaptiveMu;

/// The state of a search during a run: fed the work of each frame, it says when to
/// move `mu` and by which factor.
#[derive(Clone, Debug)]
pub struct MuSearcher {
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
    /// Work per frame of the last window, for [`AdaptiveMu::surge`].
    last_rate: Option<f64>,
    surges: u64,
}

impl MuSearcher {
    /// A search whose first window is the start's `mu` as the upper of the pair: the
    /// second tries `mu / step` (the frame-tied design starts from a `mu` that the calm
    /// first frames favour, and the scenes that whip favour a smaller one). Where
    /// `min_scale` leaves no room below the start, the start is the lower of the pair
    /// and the second window tries `mu * step`.
    pub fn new(how: AdaptiveMu) -> Self {
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
            last_rate: None,
            surges: 0,
        }
    }

    /// `mu` now, as a multiple of the start's.
    pub fn scale(&self) -> f64 {
        self.scale_of(self.upper)
    }

    /// The moves made so far, and those refused.
    pub fn moves(&self) -> (u64, u64) {
        (self.asked - self.refused, self.refused)
    }

    /// After a frame that cost `work`: the factor to move `mu` by, at the end of a
    /// window (none where the pair moved to put the other side where `mu` is).
    pub fn after_frame(&mut self, work: u64) -> Option<f64> {
        if let Some(factor) = self.surged(work) {
            return Some(factor);
        }
        self.frames += 1;
        self.work += work;
        if self.frames < self.how.window {
            return None;
        }
        let rate = self.work as f64 / f64::from(self.frames);
        self.frames = 0;
        self.work = 0;
        self.rates.push(rate);
        self.last_rate = Some(rate);
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
    pub fn refused(&mut self, factor: f64) {
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

    /// [`AdaptiveMu::surge`]: a frame above `surge` times the last window's work per
    /// frame while `mu` is above the start's moves `mu` down by one step at once (to no
    /// less than the start's), and the search measures again from there. The trials of a
    /// larger `mu` that a calm motion favours can cost many times more once the motion
    /// quickens, and three windows are too slow to leave them.
    fn surged(&mut self, work: u64) -> Option<f64> {
        let surge = self.how.surge?;
        let base = self.last_rate?;
        let now = self.scale();
        if (work as f64) <= surge * base || now <= 1.0 + 1e-9 {
            return None;
        }
        let to = (now / self.how.step).max(1.0);
        self.low = to / self.how.step;
        self.upper = true;
        if self.low < self.how.min_scale * (1.0 - 1e-9) {
            self.low = to;
            self.upper = false;
        }
        self.frames = 0;
        self.work = 0;
        self.rates.clear();
        self.last_rate = None;
        self.asked += 1;
        self.surges += 1;
        Some(self.scale() / now)
    }

    /// Moves made by [`AdaptiveMu::surge`] (counted in [`Self::moves`] too).
    pub fn surges(&self) -> u64 {
        self.surges
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
            frame: 1.0 / 60.0,
            window,
            step: 2.0,
            min_scale: 0.125,
            max_scale: 2.0,
            surge: None,
        }
    }

    /// Drive a search with windows of one frame against a cost per frame of `mu` and
    /// the frame's number, and return the scales it visited, one per frame.
    fn visits(cost: impl Fn(f64, usize) -> f64, frames: usize) -> Vec<f64> {
        let mut s = MuSearcher::new(how(1));
        (0..frames)
            .map(|k| {
                s.after_frame(cost(s.scale(), k) as u64);
                s.scale()
            })
            .collect()
    }

    #[test]
    fn the_search_dithers_once_per_window_and_moves_towards_the_cheaper_side() {
        let mut s = MuSearcher::new(how(2));
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
        let mut s = MuSearcher::new(how(1));
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
        let mut s = MuSearcher::new(AdaptiveMu {
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
        let mut s = MuSearcher::new(how(1));
        let f = s.after_frame(10).unwrap();
        assert_eq!(f, 0.5);
        s.refused(f);
        assert_eq!(s.scale(), 1.0);
        // Measures again from there: the next window dithers to 0.5.
        assert_eq!(s.after_frame(10), Some(0.5));
        // A refused move of the pair: the kept mu becomes the pair's upper side.
        let mut s = MuSearcher::new(how(1));
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
    fn a_surge_above_the_start_steps_mu_down_at_once_and_never_below_the_start() {
        let mut s = MuSearcher::new(AdaptiveMu {
            surge: Some(4.0),
            min_scale: 0.125,
            max_scale: 64.0,
            ..how(1)
        });
        // Larger mu cheaper: the search climbs to 4 (pairs move up every third window).
        let mut guard = 0;
        while s.scale() < 4.0 {
            s.after_frame((100.0 / s.scale()) as u64);
            guard += 1;
            assert!(guard < 100, "never reached 4: {}", s.scale());
        }
        let windows = s.moves().0;
        // A frame at ten times the last window's work (at most 50, at scale 2 or 4):
        // down by one step at once.
        assert_eq!(s.after_frame(500), Some(0.5));
        assert_eq!(s.scale(), 2.0);
        assert_eq!((s.moves().0, s.surges()), (windows + 1, 1));
        // The next frame has no window to compare with: no surge, it measures again.
        assert_eq!(s.after_frame(1000), Some(0.5), "dithers to the lower side");
        assert_eq!(s.scale(), 1.0);
        // At the start's mu (or below it) a surge moves nothing.
        let mut at_start = MuSearcher::new(AdaptiveMu {
            surge: Some(4.0),
            ..how(1)
        });
        at_start.after_frame(10);
        assert_eq!(at_start.scale(), 0.5);
        assert_eq!(
            at_start.after_frame(1000),
            Some(2.0),
            "the window's dither only"
        );
        assert_eq!(at_start.surges(), 0);
    }
}
