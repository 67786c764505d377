//! `--every H`: a run cut at `t = H, 2H, ..` and sampled there only, as a co-simulation
//! importer runs an FMU from one communication point to the next.

use dae_runtime::trace::{Layout, Sample, Sink};
use dae_runtime::{Model, SimError, Simulator, Summary};
use std::io;

/// A sink that passes on only the samples on the grid `t = k H` (all of them without a
/// grid); the first and the last are passed on anyway.
pub(super) struct OnGrid<S> {
    pub(super) inner: S,
    every: Option<f64>,
}

impl<S> OnGrid<S> {
    pub(super) fn new(inner: S, every: Option<f64>) -> Self {
        OnGrid { inner, every }
    }
}

/// Whether `t` is a multiple of `h` (to the rounding of `k h`).
fn on_grid(t: f64, h: f64) -> bool {
    let k = (t / h).round();
    (t - k * h).abs() <= 1e-9 * h.max(t.abs() * 1e-6)
}

impl<S: Sink> Sink for OnGrid<S> {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        self.inner.begin(layout)
    }
    fn wants(&self, step: u64, t: f64) -> bool {
        self.every.is_none_or(|h| on_grid(t, h)) && self.inner.wants(step, t)
    }
    fn algebraic_outputs(&self) -> bool {
        self.inner.algebraic_outputs()
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        self.inner.record(s)
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        self.inner.update(t)
    }
    fn finish(&mut self) -> io::Result<()> {
        self.inner.finish()
    }
}

/// The run of `sim` over its window, cut at every multiple of `h` (or in one piece).
pub(super) fn run<M: Model, S: Sink>(
    sim: &mut Simulator<M>,
    h: Option<f64>,
    sink: &mut S,
) -> Result<Summary, SimError> {
    let Some(h) = h else { return sim.run(sink) };
    let (t0, t_end) = (sim.settings().window.t_start, sim.settings().window.t_end);
    sim.start(sink)?;
    // Each cut where an importer puts it: the points are `t0 + k h`, and each step goes
    // from the last point by the difference to the next (`fmi2DoStep(t, next - t)`), so
    // the cut is `t + (next - t)`, which can differ from `next` in the last bit.
    let mut t = t0;
    for k in 1u64.. {
        let next = t0 + k as f64 * h;
        if next >= t_end - 1e-9 * h {
            break;
        }
        sim.advance_to(t + (next - t), sink)?;
        t = next;
    }
    sim.advance_to(t_end, sink)?;
    sim.finish(sink)
}

#[cfg(test)]
mod tests {
    use super::on_grid;

    #[test]
    fn grid_points_are_told_from_the_points_between() {
        let h = 1.0 / 60.0;
        let mut t = 0.0;
        for _ in 0..600 {
            t += h;
            assert!(on_grid(t, h), "{t}");
            assert!(!on_grid(t + 0.3 * h, h), "{t}");
        }
    }
}
