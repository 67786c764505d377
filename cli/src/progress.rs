//! The progress of a long `daec run` on a terminal: a bar on stderr with the time
//! reached of `--t-end`, the control updates so far and an estimate of the time left,
//! redrawn a few times a second. Silent (no bar at all) when stderr is not a terminal
//! or with `--json`; it never writes to stdout.
//!
//! [`Progress`] wraps the run's trace sink: the simulator asks every sink whether it
//! wants each step's sample ([`Sink::wants`]), which is where the bar learns the time;
//! it asks for nothing itself, so what is recorded is what the inner sink wants. The
//! clock is read only every `stride` steps, a stride that adapts to about one reading
//! per redraw interval, so a step costs a counter comparison.

use dae_runtime::trace::{Layout, Sample, Sink};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::cell::Cell;
use std::io::{self, IsTerminal};
use std::time::{Duration, Instant};

/// Positions of the bar (time fractions are drawn to a thousandth).
const BAR_LEN: u64 = 1000;

/// Time between redraws of the bar.
const REDRAW: Duration = Duration::from_millis(200);

/// Whether progress is shown: stderr is a terminal and the output is not JSON.
pub(crate) fn enabled() -> bool {
    std::io::stderr().is_terminal() && !crate::failure::json()
}

/// The part of `[t_start, t_end]` reached at `t`, in `0..=1`.
pub(crate) fn fraction(t: f64, t_start: f64, t_end: f64) -> f64 {
    let span = t_end - t_start;
    if span.is_nan() || span <= 0.0 || !t.is_finite() {
        return 0.0;
    }
    ((t - t_start) / span).clamp(0.0, 1.0)
}

/// The wall time left if the rest goes at the pace so far (`None` before any
/// progress).
pub(crate) fn time_left(elapsed: Duration, fraction: f64) -> Option<Duration> {
    (fraction > 0.0 && fraction.is_finite()).then(|| {
        let left = elapsed.as_secs_f64() * (1.0 - fraction.min(1.0)) / fraction;
        Duration::from_secs_f64(left.min(1e9))
    })
}

/// `3 min 20 s`, `12 s`, `1 h 05 min`.
fn duration_text(d: Duration) -> String {
    let s = d.as_secs();
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

/// The text beside the bar: `t = 1.25 of 10, 340 updates, about 12 s left`.
pub(crate) fn message(t: f64, t_end: f64, updates: u64, left: Option<Duration>) -> String {
    let left = left.map_or("estimating the time left".to_string(), |d| {
        format!("about {} left", duration_text(d))
    });
    format!(
        "t = {} of {}, {updates} update{}, {left}",
        crate::messages::number((t * 1e4).round() / 1e4),
        crate::messages::number(t_end),
        if updates == 1 { "" } else { "s" }
    )
}

/// What the bar is updated from, read at most every `stride` steps.
struct Clock {
    started: Instant,
    last_draw: Instant,
    last_step: u64,
    next_check: u64,
    stride: u64,
}

/// A trace sink that shows the run's progress (see the module documentation) and
/// passes everything on to `inner`.
pub(crate) struct Progress<S> {
    inner: S,
    bar: Option<ProgressBar>,
    t_start: f64,
    t_end: f64,
    updates: Cell<u64>,
    clock: Cell<Option<Clock>>,
}

impl<S: Sink> Progress<S> {
    /// A sink showing the progress of a run over `[t_start, t_end]` when `show`.
    pub(crate) fn new(inner: S, t_start: f64, t_end: f64, show: bool) -> Self {
        let bar = show.then(|| {
            let bar =
                ProgressBar::with_draw_target(Some(BAR_LEN), ProgressDrawTarget::stderr_with_hz(5));
            if let Ok(style) = ProgressStyle::with_template("{bar:20} {percent:>3}% {wide_msg}") {
                bar.set_style(style);
            }
            bar.set_message(message(t_start, t_end, 0, None));
            bar
        });
        Progress {
            inner,
            bar,
            t_start,
            t_end,
            updates: Cell::new(0),
            clock: Cell::new(None),
        }
    }

    /// The wrapped sink.
    pub(crate) fn inner_mut(&mut self) -> &mut S {
        &mut self.inner
    }

    /// Removes the bar from the terminal (before the summary or an error is printed).
    pub(crate) fn clear(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }

    /// Called at every step: reads the clock every `stride` steps and redraws when
    /// [`REDRAW`] has passed.
    fn tick(&self, step: u64, t: f64) {
        let Some(bar) = &self.bar else { return };
        let now = Instant::now;
        let mut clock = self.clock.take().unwrap_or_else(|| {
            let t0 = now();
            Clock {
                started: t0,
                last_draw: t0,
                last_step: step,
                next_check: step,
                stride: 1,
            }
        });
        if step >= clock.next_check {
            let at = now();
            let since = at.duration_since(clock.last_draw);
            if since >= REDRAW {
                // About four clock readings per redraw at the pace of the last interval.
                let steps = step.saturating_sub(clock.last_step);
                let per_interval = steps as f64 * REDRAW.as_secs_f64() / since.as_secs_f64();
                clock.stride = ((per_interval / 4.0) as u64).clamp(1, 1 << 20);
                clock.last_draw = at;
                clock.last_step = step;
                let f = fraction(t, self.t_start, self.t_end);
                bar.set_position((f * BAR_LEN as f64) as u64);
                let left = time_left(at.duration_since(clock.started), f);
                bar.set_message(message(t, self.t_end, self.updates.get(), left));
            }
            clock.next_check = step + clock.stride;
        }
        self.clock.set(Some(clock));
    }
}

impl<S> Drop for Progress<S> {
    fn drop(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl<S: Sink> Sink for Progress<S> {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        self.inner.begin(layout)
    }
    fn wants(&self, step: u64, t: f64) -> bool {
        self.tick(step, t);
        self.inner.wants(step, t)
    }
    fn algebraic_outputs(&self) -> bool {
        self.inner.algebraic_outputs()
    }
    fn record(&mut self, sample: &Sample<'_>) -> io::Result<()> {
        self.inner.record(sample)
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        self.updates.set(self.updates.get() + 1);
        self.inner.update(t)
    }
    fn finish(&mut self) -> io::Result<()> {
        self.clear();
        self.inner.finish()
    }
}

/// A spinner with `text` on stderr while something without steps runs (the pilot runs
/// of the automatic design); `None` when progress is not shown. Dropping it clears it.
pub(crate) fn spinner(text: &'static str) -> Option<Spinner> {
    enabled().then(|| {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr_with_hz(5));
        if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
            bar.set_style(style);
        }
        bar.set_message(text);
        bar.enable_steady_tick(Duration::from_millis(200));
        Spinner(bar)
    })
}

/// See [`spinner`].
pub(crate) struct Spinner(ProgressBar);

impl Drop for Spinner {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dae_runtime::trace::NoTrace;

    #[test]
    fn the_fraction_is_the_time_reached_within_the_window() {
        assert_eq!(fraction(0.0, 0.0, 10.0), 0.0);
        assert_eq!(fraction(2.5, 0.0, 10.0), 0.25);
        assert_eq!(fraction(3.0, 1.0, 5.0), 0.5);
        assert_eq!(fraction(11.0, 0.0, 10.0), 1.0);
        assert_eq!(fraction(f64::NAN, 0.0, 10.0), 0.0);
        assert_eq!(fraction(1.0, 0.0, 0.0), 0.0);
    }

    #[test]
    fn the_time_left_goes_at_the_pace_so_far() {
        assert_eq!(time_left(Duration::from_secs(10), 0.0), None);
        assert_eq!(
            time_left(Duration::from_secs(10), 0.25),
            Some(Duration::from_secs(30))
        );
        assert_eq!(
            time_left(Duration::from_secs(10), 1.0),
            Some(Duration::ZERO)
        );
    }

    #[test]
    fn the_message_says_time_updates_and_time_left() {
        assert_eq!(
            message(1.25, 10.0, 340, Some(Duration::from_secs(12))),
            "t = 1.25 of 10, 340 updates, about 12 s left"
        );
        assert_eq!(
            message(0.0, 2.0, 1, None),
            "t = 0 of 2, 1 update, estimating the time left"
        );
        assert_eq!(duration_text(Duration::from_secs(200)), "3 min 20 s");
        assert_eq!(duration_text(Duration::from_secs(3900)), "1 h 05 min");
    }

    #[test]
    fn a_silent_progress_passes_everything_on_and_counts_updates() {
        let mut p = Progress::new(NoTrace, 0.0, 1.0, false);
        assert!(p.bar.is_none());
        assert!(!p.wants(5, 0.5));
        assert!(!p.algebraic_outputs());
        p.update(0.1).unwrap();
        p.update(0.2).unwrap();
        assert_eq!(p.updates.get(), 2);
        // Nothing is read or drawn without a bar.
        assert!(p.clock.take().is_none());
    }

    #[test]
    fn a_shown_progress_reads_the_clock_only_every_stride_steps() {
        let p = Progress::new(NoTrace, 0.0, 1.0, true);
        // Drawn into a hidden target: the bar logic runs, nothing is written.
        if let Some(bar) = &p.bar {
            bar.set_draw_target(ProgressDrawTarget::hidden());
        }
        p.tick(0, 0.0);
        let c = p.clock.take().unwrap();
        assert_eq!((c.next_check, c.stride), (1, 1));
        // A redraw interval passed after 1000 steps: about 250 steps between readings.
        p.clock.set(Some(Clock {
            last_draw: c.last_draw - REDRAW,
            ..c
        }));
        p.tick(1000, 0.5);
        let c = p.clock.take().unwrap();
        assert!((100..=260).contains(&c.stride), "{}", c.stride);
        assert_eq!(c.next_check, 1000 + c.stride);
        assert_eq!(p.bar.as_ref().unwrap().position(), 500);
    }
}
