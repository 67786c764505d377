//! `mu` searched for during a run ([`AdaptiveMu`]); the search itself is
//! [`MuSearcher`](crate::design::MuSearcher).

use serde::{Deserialize, Serialize};

/// How `mu` is searched for during a run: every `mu_i` is scaled by one common factor,
/// dithered between two values a `step` apart, `window` frames of `frame` seconds at
/// each, and moved towards the one whose frames cost less work (right-hand side
/// evaluations and factorisations, counted, not timed). The search and why it is a
/// search are described at [`MuSearcher`](crate::design::MuSearcher).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AdaptiveMu {
    /// The length of one frame in seconds (the time between two looks at the work).
    pub frame: f64,
    /// Frames per trial of one `mu` (at least 1).
    pub window: u32,
    /// Factor of one move of `mu` (above 1).
    pub step: f64,
    /// Bounds of `mu` as multiples of the one the run started with.
    pub min_scale: f64,
    /// Upper bound, likewise.
    pub max_scale: f64,
    /// Leave a larger `mu` at once when a frame costs more than `surge` times the last
    /// window's work per frame (at least 1; `None`: only the windows' comparison moves
    /// `mu`). See [`MuSearcher`](crate::design::MuSearcher).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surge: Option<f64>,
}

impl Default for AdaptiveMu {
    /// Frames of 1/60 s, windows of 4 frames, `mu` dithered by a factor 2 and moved by 2
    /// (a move every 0.2 s at most), between 1/16 and 2 times the start's: with the
    /// frame-tied design's `mu` of a quarter frame, from 1/64 to 1/2 of the frame, the
    /// range of the particle scenes' best values (docs/particles.md).
    fn default() -> Self {
        Self {
            frame: 1.0 / 60.0,
            window: 4,
            step: 2.0,
            min_scale: 1.0 / 16.0,
            max_scale: 2.0,
            surge: None,
        }
    }
}

impl AdaptiveMu {
    /// The search of [`design::Online`](crate::design::Online) for a model of any kind:
    /// the default's windows of 4 frames of `frame` seconds, `mu` dithered and moved by
    /// `sqrt(2)`, from 1/16 to 64 times the start's `mu` (a slow motion at a loose layer is
    /// cheapest at a `mu` many times the frame-tied one: the 3-D double pendulum at `eps =
    /// 0.2` at 16-64 times it), and a larger `mu` left at once where a frame costs more
    /// than 4 times the last window's frames. Both bound what the trials cost where the
    /// cost is steep in `mu`: on hair whose motion quickens after calm frames (20 strands
    /// of 32 links, 2 s at `eps = 1e-3`), dithered by 2 without the surge rule the run
    /// cost 6.3x the `mu` kept, by 2 with it 2.4x, by `sqrt(2)` with it 1.3x (`daec run`,
    /// docs/cli.md).
    pub fn wide(frame: f64) -> Self {
        Self {
            frame,
            max_scale: 64.0,
            surge: Some(4.0),
            step: std::f64::consts::SQRT_2,
            ..Self::default()
        }
    }

    /// Whether the fields make a search (`frame > 0`, `window >= 1`, `step > 1`,
    /// `0 < min_scale <= 1 <= max_scale`, room for two values a step apart, all
    /// finite): an error message naming the field otherwise.
    pub fn check(&self) -> Result<(), String> {
        if !(self.frame.is_finite() && self.frame > 0.0) {
            return Err(format!(
                "mu search: frame {} must be finite and > 0",
                self.frame
            ));
        }
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
        if let Some(surge) = self.surge {
            if !(surge.is_finite() && surge >= 1.0) {
                return Err(format!(
                    "mu search: surge {surge} must be a finite factor of at least 1"
                ));
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_search_that_cannot_search_is_refused_with_its_field() {
        let ok = AdaptiveMu::default();
        assert!(ok.check().is_ok());
        for (bad, field) in [
            (
                AdaptiveMu {
                    surge: Some(0.5),
                    ..ok
                },
                "surge",
            ),
            (AdaptiveMu { frame: 0.0, ..ok }, "frame"),
            (
                AdaptiveMu {
                    frame: f64::NAN,
                    ..ok
                },
                "frame",
            ),
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

    #[test]
    fn the_wide_search_reaches_64_times_the_start() {
        let w = AdaptiveMu::wide(0.25);
        assert!(w.check().is_ok());
        assert_eq!((w.frame, w.max_scale), (0.25, 64.0));
    }
}
