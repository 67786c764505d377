//! Locating the first event of the sliding variables inside a step and cutting the
//! step there: apart from [`step`](super::step), which integrates the step and cuts
//! it where this file says.
//!
//! With located crossings a step ends at the first event of any sliding variable
//! (see [`crossing`](super::crossing)): the cubic of `s_i` over the trial step finds
//! it; Newton iterations on the true `s` along the integrator's dense output of `x`
//! (`z` on its exact ramp) refine it to within a quarter of the crossing tolerance;
//! the step is cut there (the embedded pairs take their dense output as the new state,
//! the fixed-step integrators integrate again to the cut); and the cubic is rebuilt on
//! the shortened step from the exact end values, which must show the event at its end
//! (within the tolerance) and no earlier one, or the step is cut again.

use super::Simulator;
use super::crossing::{Cubic, Watch};
use crate::Model;

/// Most cuts of one step while locating a crossing: the rebuilt cubic agrees with the
/// true `s` to the tolerance after one or two; the rest is a guard against a model
/// whose `s` is not smooth within a step.
const MAX_CUTS: usize = 8;
/// Newton iterations on the true `s` per cut.
const MAX_NEWTON: usize = 8;

/// The event a cut is aimed at: a sliding variable, the `theta` of the event on the
/// cubic, and the value of `s` to reach (`None` for the start of an outward motion at
/// an extremum, which is taken from the cubic).
struct Event {
    i: usize,
    theta: f64,
    target: Option<f64>,
}

impl<M: Model> Simulator<M> {
    /// The watch of each sliding variable for the current phase.
    ///
    /// A variable that starts the step on its boundary and still moving outward was
    /// just updated with a gain too small for the crossing condition; it is watched at
    /// `(1 + tol)` times its current `|s|`, so that it gets a fresh control each time it
    /// moves out by that fraction (as the step-end rule's update after every step did)
    /// instead of running away for a whole long step, or stalling the integration with
    /// events at the step's start.
    pub(super) fn watch(&self, i: usize) -> Watch {
        let mut w = if self.steady() {
            Watch {
                level: self.set.layers.eps[i],
                surface_from: None,
            }
        } else {
            Watch {
                level: self.eps_k[i],
                surface_from: self.outside_k[i].then_some(self.sgn_k[i]),
            }
        };
        let tol = self.crossing_tol();
        let (s0, ds0) = (self.s0[i], self.ds0[i]);
        if s0.abs() >= w.level * (1.0 - tol) && s0 * ds0 > 0.0 {
            w.level = w.level.max(s0.abs()) * (1.0 + tol);
        }
        w
    }

    /// The cubics of every `s_i` over the current step `[t0, t0 + h]`, from `s` and `s'`
    /// at both ends, into `self.cubics`. The extrema are found only for the cubics whose
    /// bound reaches their watch level or the step's measurement floor
    /// ([`Self::measure_floor`]); for the others the bound answers every query of the
    /// step as the extrema would.
    fn build_cubics(&mut self, h: f64) {
        for i in 0..self.cubics.len() {
            let mut c = Cubic::bounded(self.s0[i], self.ds0[i], self.ctl.s[i], self.ds[i], h);
            let watch = self.watches[i];
            let quiet = if watch.surface_from.is_some() {
                0.0
            } else {
                watch.level.min(self.measure_floor(i))
            };
            // (A NaN bound settles nothing.)
            let settled = c.hull() < quiet;
            if !settled {
                c.resolve();
            }
            self.cubics[i] = c;
        }
    }

    /// The largest `|s_i|` over a step that would change nothing the run measures: the
    /// largest seen so far, the window's (once it is open) and the bound's. A step whose
    /// `|s_i|` stays below it needs no exact maximum.
    fn measure_floor(&self, i: usize) -> f64 {
        let st = &self.stats;
        // Just inside the bound, so that `max / eps <= 1 + tol` holds after rounding.
        let bound = (1.0 + self.set.bound_tol) * self.set.layers.eps[i] * (1.0 - 1e-12);
        let floor = st.seen_s[i].min(bound);
        if st.stats_from.is_some() {
            floor.min(st.max_s[i])
        } else {
            floor
        }
    }

    /// Cut the step just taken from `t0` at the first event inside it (monitoring
    /// only), and measure the accepted step on the cubic of each `s_i`.
    pub(super) fn locate(&mut self, t0: f64) {
        let tol = self.crossing_tol();
        self.build_cubics(self.pt.t - t0);
        if self.stalled() {
            // Two steps in a row made (almost) no progress: this one is not cut, and
            // the control is updated at its end, as the step-end rule does.
            self.run.force_update = true;
            self.stats.unlocated += 1;
        } else if self.set.law.monitors() {
            let mut cut = false;
            for _ in 0..MAX_CUTS {
                let h = self.pt.t - t0;
                let Some(ev) = self.first_event() else {
                    break;
                };
                let c = self.cubics[ev.i];
                // The tolerance is relative to the layer (to eps for the surface).
                let scale = match ev.target {
                    Some(0.0) => self.set.layers.eps[ev.i],
                    _ => self.watches[ev.i].level,
                };
                // The event is the step's end (within the tolerance): for a level, when
                // nothing of the cubic goes beyond it by more than that (the end's value
                // alone would pass a dip beyond the level that comes back to it by the
                // end, as `s` does when the drift turns twice within a step); and no
                // other variable leaves its watch within the step (a later crossing
                // of another variable is not the first event, but it is inside the step).
                // For the start of an outward motion, likewise: the end near the event's
                // value, and nothing further out between them.
                let at_end = match ev.target {
                    Some(level) if level != 0.0 => c.max_abs() <= level.abs() + tol * scale,
                    Some(_) => (c.eval(1.0) - c.eval(ev.theta)).abs() <= tol * scale,
                    None => {
                        let p = c.eval(ev.theta);
                        (c.eval(1.0) - p).abs() <= tol * scale
                            && c.max_abs_from(ev.theta) <= p.abs() + tol * scale
                    }
                } && self.others_within(ev.i, tol);
                if at_end {
                    break;
                }
                // A cubic fitted over a step too long for it can show an event the
                // true `s` does not reach (the refinement then finds no root and would
                // walk to the step's end, and an earlier event of another variable,
                // hidden behind this one, be missed): the step is cut at the cubic's
                // event instead, and the shorter step looked at again.
                let theta = self.refine(t0, h, &ev, &c, tol * scale).unwrap_or(ev.theta);
                self.cut(t0, t0 + theta * h);
                cut = true;
                self.build_cubics(self.pt.t - t0);
                // An outward motion that starts at an extremum (outside the layer, or on
                // its boundary where the rate's sign is lost in rounding) asks for an
                // update at the cut whatever the end-of-step test says; so does a cut
                // too short to be a step, or the integration would stall there.
                if ev.target.is_none() || theta * h <= 1e-9 * h.max(f64::MIN_POSITIVE) {
                    self.run.force_update = true;
                }
            }
            if cut {
                self.stats.cuts += 1;
            }
        }
        let h = self.pt.t - t0;
        let bound = 1.0 + self.set.bound_tol;
        for (i, c) in self.cubics.iter().enumerate() {
            self.measure.max_s[i] = c.max_abs_above(self.measure_floor(i));
            self.measure.time_beyond[i] = c.time_beyond(bound * self.set.layers.eps[i]) * h;
        }
    }

    /// Whether every sliding variable but `skip` stays within its watch level (to the
    /// tolerance `tol` of it) on the current step's cubic.
    fn others_within(&self, skip: usize, tol: f64) -> bool {
        self.cubics
            .iter()
            .enumerate()
            .all(|(i, c)| i == skip || c.within(self.watches[i].level * (1.0 + tol)))
    }

    /// The earliest event of all sliding variables on the current step.
    fn first_event(&self) -> Option<Event> {
        let mut best: Option<Event> = None;
        for (i, (c, &watch)) in self.cubics.iter().zip(&self.watches).enumerate() {
            let Some(theta) = c.first_event(watch) else {
                continue;
            };
            if best.as_ref().is_some_and(|b| theta >= b.theta) {
                continue;
            }
            let p = c.eval(theta);
            let target = if watch.surface_from.is_some() && p.abs() < 0.5 * watch.level {
                Some(0.0)
            } else if (p.abs() - watch.level).abs() <= 1e-9 * watch.level {
                Some(watch.level.copysign(p))
            } else {
                // An outward motion starting at an extremum outside the layer.
                None
            };
            best = Some(Event { i, theta, target });
        }
        best
    }

    /// Newton iterations for `s_i(theta) = target` on the true `s` along the dense
    /// output (slope from the cubic, bisection when a step leaves the bracket), until
    /// within a quarter of `tol_abs`; `None` when they do not get there.
    fn refine(&mut self, t0: f64, h: f64, ev: &Event, c: &Cubic, tol_abs: f64) -> Option<f64> {
        let Some(target) = ev.target else {
            return Some(ev.theta);
        };
        let mut theta = ev.theta;
        // The crossing is on the cubic's monotone piece that holds the event: a root
        // elsewhere on the true `s` is another crossing of the level (a step that
        // starts on the level, within the tolerance beyond it, and moves inside before it
        // turns outward has one at its start: cut there, it would end where it began,
        // and the next step the same, without end).
        let (mut lo, mut hi) = c.piece(ev.theta);
        let start_side = c.side_before(ev.theta, target);
        for _ in 0..MAX_NEWTON {
            let r = self.s_along(t0, h, theta, ev.i) - target;
            if r.abs() <= 0.25 * tol_abs {
                return Some(theta);
            }
            // Before the event the variable is still on the side it started from.
            if r.signum() == start_side {
                lo = theta;
            } else {
                hi = theta;
            }
            let mut next = theta - r / c.rate(theta);
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            theta = next;
        }
        let r = self.s_along(t0, h, theta, ev.i) - target;
        (r.abs() <= 0.25 * tol_abs).then_some(theta)
    }
}
