//! The dense output of a sliding variable over one step and the crossings it shows.
//!
//! Between two control updates `s_i` is smooth, and at both ends of a step the
//! simulator knows `s_i` and its exact rate `s_i' = (J_s v + alpha)_i`. The cubic
//! Hermite through those four numbers ([`Cubic`]) is split at its extrema into monotone
//! pieces; on each piece, in order, a layer boundary `|s_i| = L_i` can only be crossed
//! once, so the first outward crossing of the step (also one that leaves and re-enters
//! the layer within the step) is found exactly on the cubic by bisection. The
//! simulator then refines it on the true `s` (see `sim::events`).

/// `p(theta) = a0 + a1 theta + a2 theta^2 + a3 theta^3` on `theta` in `[0, 1]`.
///
/// Most variables stay well inside their layers over most steps, and for them the
/// extrema (a square root and a few divisions per variable and step: 7 % of the cycles
/// of a heavy 10-link chain's run, `perf record`) say nothing the bound [`Cubic::hull`]
/// does not: a cubic built with [`Cubic::bounded`] finds them only when asked
/// ([`Cubic::resolve`]), and every query answers from the bound where the bound settles
/// it, exactly as the extrema would.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cubic {
    a: [f64; 4],
    /// An upper bound of `|p|` on `[0, 1]`, above every value the extrema or an
    /// evaluation can give in floating point.
    hull: f64,
    /// `0`, the extrema inside `(0, 1)`, `1`, and how many (`0` until found); the
    /// values there.
    breaks: [f64; 4],
    n_breaks: usize,
    vals: [f64; 4],
}

/// What ends a step for one sliding variable.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Watch {
    /// The layer half-width `L > 0` whose outward crossing is an event.
    pub(crate) level: f64,
    /// Contracting layers: the sign of `s` at the last update of a variable that was
    /// outside then; reaching `s = 0` from that side is an event.
    pub(crate) surface_from: Option<f64>,
}

impl Cubic {
    /// The Hermite cubic with `p(0) = s0`, `p(1) = s1`, `p'(0) = h ds0`, `p'(1) = h ds1`
    /// (`ds` are rates in time, `h` the step length), its extrema found.
    pub(crate) fn hermite(s0: f64, ds0: f64, s1: f64, ds1: f64, h: f64) -> Self {
        let mut c = Self::bounded(s0, ds0, s1, ds1, h);
        c.resolve();
        c
    }

    /// The same cubic with its bound only; the extrema are found when a query needs them
    /// (or by [`Cubic::resolve`], once).
    pub(crate) fn bounded(s0: f64, ds0: f64, s1: f64, ds1: f64, h: f64) -> Self {
        let (d0, d1) = (h * ds0, h * ds1);
        let a = [
            s0,
            d0,
            3.0 * (s1 - s0) - 2.0 * d0 - d1,
            2.0 * (s0 - s1) + d0 + d1,
        ];
        // The cubic lies in the convex hull of its Bernstein coefficients `s0`,
        // `s0 + d0 / 3`, `s1 - d1 / 3`, `s1`. The margin covers the roundings of those,
        // of `a` and of evaluating `a` by Horner's rule: each a few ulps of
        // `sum |a_k| <= 6 (|s0| + |s1| + |d0| + |d1|)`.
        let (b1, b2) = (s0 + d0 / 3.0, s1 - d1 / 3.0);
        let size = s0.abs() + s1.abs() + d0.abs() + d1.abs();
        let hull = s0.abs().max(s1.abs()).max(b1.abs()).max(b2.abs()) + 128.0 * f64::EPSILON * size;
        Cubic {
            a,
            hull,
            breaks: [0.0; 4],
            n_breaks: 0,
            vals: [0.0; 4],
        }
    }

    /// Find and keep the extrema (for a cubic that will be asked more than once).
    pub(crate) fn resolve(&mut self) {
        if self.n_breaks == 0 {
            (self.breaks, self.n_breaks, self.vals) = self.shape();
        }
    }

    /// An upper bound of `|p|` on `[0, 1]` ([`Cubic::max_abs`] never exceeds it).
    pub(crate) fn hull(&self) -> f64 {
        self.hull
    }

    /// The breaks ([`Cubic::breaks`]), how many, and the values there: kept, or found
    /// now.
    fn shape(&self) -> ([f64; 4], usize, [f64; 4]) {
        if self.n_breaks > 0 {
            return (self.breaks, self.n_breaks, self.vals);
        }
        let (breaks, n) = extrema(&self.a);
        let mut vals = [0.0; 4];
        for (v, &t) in vals.iter_mut().zip(&breaks).take(n) {
            *v = eval(&self.a, t);
        }
        (breaks, n, vals)
    }

    pub(crate) fn eval(&self, t: f64) -> f64 {
        eval(&self.a, t)
    }

    fn slope(&self, t: f64) -> f64 {
        let a = &self.a;
        a[1] + t * (2.0 * a[2] + t * 3.0 * a[3])
    }

    /// `0`, the extrema inside `(0, 1)` in increasing order, `1`; and how many.
    pub(crate) fn breaks(&self) -> ([f64; 4], usize) {
        let (b, n, _) = self.shape();
        (b, n)
    }

    /// The monotone piece `[b_k, b_k+1]` between the cubic's breaks (its ends and
    /// extrema) that holds `theta`.
    pub(crate) fn piece(&self, theta: f64) -> (f64, f64) {
        let (b, n) = self.breaks();
        let k = (1..n - 1).rev().find(|&k| b[k] <= theta).unwrap_or(0);
        (b[k], b[k + 1])
    }

    /// The root of `p = level` in `[lo, hi]` where `p - level` changes sign from `lo` to
    /// `hi` (a monotone piece): Newton steps, bisection whenever a step would leave the
    /// bracket, to the last bits.
    fn root(&self, level: f64, mut lo: f64, mut hi: f64) -> f64 {
        let below_lo = self.eval(lo) < level;
        let mut t = 0.5 * (lo + hi);
        for _ in 0..64 {
            let r = self.eval(t) - level;
            if r == 0.0 {
                return t;
            }
            if (r < 0.0) == below_lo {
                lo = t;
            } else {
                hi = t;
            }
            let newton = t - r / self.slope(t);
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (next - t).abs() <= 4.0 * f64::EPSILON * t.abs().max(1e-300) || hi <= lo {
                return next;
            }
            t = next;
        }
        t
    }

    /// The first `theta` in `(0, 1]` at which this variable asks for an update: an
    /// outward crossing of `|p| = level` (or the start of an outward motion outside the
    /// layer, at an extremum), or, with `surface_from`, the arrival at `p = 0`. An event
    /// at `theta = 0` is never returned (the end-of-step check of the previous step
    /// handles the start point, and a variable already moving outward at an update,
    /// because its gain is too small, must not stop the integration).
    pub(crate) fn first_event(&self, watch: Watch) -> Option<f64> {
        let l = watch.level;
        if watch.surface_from.is_none() && self.hull < l {
            return None;
        }
        let (b, n, v) = self.shape();
        if watch.surface_from.is_none() && v[..n].iter().all(|p| p.abs() < l) {
            // Inside the layer all along (the extrema and the ends bound the cubic).
            return None;
        }
        for k in 0..n - 1 {
            let (ta, tb) = (b[k], b[k + 1]);
            let (pa, pb) = (v[k], v[k + 1]);
            let mut hit = None;
            if pb > pa {
                if pa >= l {
                    hit = Some(ta);
                } else if pb >= l {
                    hit = Some(self.root(l, ta, tb));
                }
                if let Some(-1.0) = watch.surface_from {
                    if pa < 0.0 && pb >= 0.0 {
                        let r = self.root(0.0, ta, tb);
                        hit = Some(hit.map_or(r, |h: f64| h.min(r)));
                    }
                }
            } else if pb < pa {
                if pa <= -l {
                    hit = Some(ta);
                } else if pb <= -l {
                    hit = Some(self.root(-l, ta, tb));
                }
                if let Some(1.0) = watch.surface_from {
                    if pa > 0.0 && pb <= 0.0 {
                        let r = self.root(0.0, ta, tb);
                        hit = Some(hit.map_or(r, |h: f64| h.min(r)));
                    }
                }
            }
            match hit {
                Some(t) if t > 0.0 => return Some(t),
                _ => {}
            }
        }
        None
    }

    /// Largest `|p|` on `[0, 1]`.
    pub(crate) fn max_abs(&self) -> f64 {
        let (_, n, v) = self.shape();
        largest_abs(&v[..n])
    }

    /// Whether `|p| <= level` on all of `[0, 1]` ([`Cubic::max_abs`]` <= level`).
    pub(crate) fn within(&self, level: f64) -> bool {
        self.hull <= level || self.max_abs() <= level
    }

    /// [`Cubic::max_abs`] where it exceeds `floor`, and otherwise some value at most
    /// `floor` (the bound): for a measurement that only a larger value would change.
    pub(crate) fn max_abs_above(&self, floor: f64) -> f64 {
        if self.hull <= floor {
            self.hull
        } else {
            self.max_abs()
        }
    }

    /// Largest `|p|` on `[from, 1]`.
    pub(crate) fn max_abs_from(&self, from: f64) -> f64 {
        let (b, n, v) = self.shape();
        (0..n)
            .filter(|&k| b[k] > from)
            .fold(self.eval(from).abs(), |m, k| m.max(v[k].abs()))
    }

    /// Measure of `{theta in [0, 1] : |p(theta)| > level}`.
    pub(crate) fn time_beyond(&self, level: f64) -> f64 {
        if self.hull <= level {
            return 0.0;
        }
        let (b, n, vals) = self.shape();
        if largest_abs(&vals[..n]) <= level {
            return 0.0;
        }
        let mut total = 0.0;
        for k in 0..n - 1 {
            let (ta, tb) = (b[k], b[k + 1]);
            for sign in [1.0, -1.0] {
                // On a monotone piece, {sign p > level} is an interval at one end.
                let (qa, qb) = (sign * vals[k], sign * vals[k + 1]);
                total += match (qa > level, qb > level) {
                    (true, true) => tb - ta,
                    (false, false) => 0.0,
                    (true, false) => self.root(sign * level, ta, tb) - ta,
                    (false, true) => tb - self.root(sign * level, ta, tb),
                };
            }
        }
        total
    }

    /// The side of `target` (`+1` above, `-1` below) the cubic comes from when it
    /// reaches it at the event `theta`: against its motion there. Not the side of the
    /// step's start: a step that starts on the level itself (after an update there)
    /// may start a rounding error beyond it, and a grazing `s` that turns inside and
    /// comes back to the same level would then have its bracket turned around (the
    /// root search walks to the step's end, and the excursion beyond the level is
    /// accepted uncut).
    pub(crate) fn side_before(&self, theta: f64, target: f64) -> f64 {
        let rate = self.slope(theta);
        if rate != 0.0 {
            -rate.signum()
        } else {
            // A tangency: only the start can tell.
            (self.eval(0.0) - target).signum()
        }
    }

    /// Rate of change in `theta` at `t` (for Newton steps on the true `s`).
    pub(crate) fn rate(&self, t: f64) -> f64 {
        self.slope(t)
    }
}

/// Largest `|p|` over the values at the breaks (which bound the cubic).
fn largest_abs(vals: &[f64]) -> f64 {
    vals.iter().fold(0.0f64, |m, p| m.max(p.abs()))
}

/// The cubic with coefficients `a` at `t` (Horner).
fn eval(a: &[f64; 4], t: f64) -> f64 {
    a[0] + t * (a[1] + t * (a[2] + t * a[3]))
}

/// `0`, the extrema of the cubic with coefficients `a` inside `(0, 1)` in increasing
/// order, `1`; and how many.
fn extrema(a: &[f64; 4]) -> ([f64; 4], usize) {
    let mut out = [0.0, 1.0, 1.0, 1.0];
    let mut n = 1;
    // p' = 3 a3 t^2 + 2 a2 t + a1.
    let (qa, qb, qc) = (3.0 * a[3], 2.0 * a[2], a[1]);
    let mut roots = [f64::NAN; 2];
    let scale = qa.abs().max(qb.abs()).max(qc.abs());
    if scale > 0.0 {
        if qa.abs() <= 1e-14 * scale {
            if qb != 0.0 {
                roots[0] = -qc / qb;
            }
        } else {
            let disc = qb * qb - 4.0 * qa * qc;
            if disc >= 0.0 {
                // The numerically stable pair of roots.
                let sign = if qb >= 0.0 { 1.0 } else { -1.0 };
                let q = -0.5 * (qb + sign * disc.sqrt());
                roots[0] = q / qa;
                if q != 0.0 {
                    roots[1] = qc / q;
                }
            }
        }
    }
    if roots[0] > roots[1] {
        roots.swap(0, 1);
    }
    for r in roots {
        if r > 0.0 && r < 1.0 && r > out[n - 1] {
            out[n] = r;
            n += 1;
        }
    }
    out[n] = 1.0;
    (out, n + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_poly(f: impl Fn(f64) -> f64, df: impl Fn(f64) -> f64) -> Cubic {
        Cubic::hermite(f(0.0), df(0.0), f(1.0), df(1.0), 1.0)
    }

    #[test]
    fn hermite_reproduces_a_cubic_and_its_extrema() {
        // p = (t - 0.2)(t - 0.5)(t - 0.9) * 10: extrema at the roots of p'.
        let f = |t: f64| 10.0 * (t - 0.2) * (t - 0.5) * (t - 0.9);
        let df =
            |t: f64| 10.0 * ((t - 0.5) * (t - 0.9) + (t - 0.2) * (t - 0.9) + (t - 0.2) * (t - 0.5));
        let c = from_poly(f, df);
        for t in [0.0, 0.3, 0.77, 1.0] {
            assert!((c.eval(t) - f(t)).abs() < 1e-12);
        }
        let (b, n) = c.breaks();
        assert_eq!(n, 4);
        for &t in &b[1..3] {
            assert!(df(t).abs() < 1e-10, "{t}");
        }
        assert!(b[1] < b[2]);
    }

    #[test]
    fn first_outward_crossing_and_an_excursion_that_returns() {
        // Linear from 0 to 2: crosses 1 at 0.5.
        let c = Cubic::hermite(0.0, 2.0, 2.0, 2.0, 1.0);
        let w = Watch {
            level: 1.0,
            surface_from: None,
        };
        assert!((c.first_event(w).unwrap() - 0.5).abs() < 1e-15);
        // Leaves the layer [-1, 1] and comes back within the step: p = 5 t (1 - t),
        // max 1.25 at 0.5; crosses 1 at t = (1 - sqrt(0.2)) / 2.
        let c = from_poly(|t| 5.0 * t * (1.0 - t), |t| 5.0 - 10.0 * t);
        let expect = (1.0 - 0.2f64.sqrt()) / 2.0;
        assert!((c.first_event(w).unwrap() - expect).abs() < 1e-14);
        // Inward motion from outside ends inside: no event.
        let c = Cubic::hermite(1.5, -2.0, -0.5, -2.0, 1.0);
        assert_eq!(c.first_event(w), None);
        // Moving outward from the start (a gain too small): no event at 0, nor later.
        let c = Cubic::hermite(1.2, 1.0, 2.2, 1.0, 1.0);
        assert_eq!(c.first_event(w), None);
        // Outside, moving in, turning back outside at t = 0.5: event at the turn.
        let c = from_poly(|t| 2.0 + (t - 0.5) * (t - 0.5), |t| 2.0 * (t - 0.5));
        assert!((c.first_event(w).unwrap() - 0.5).abs() < 1e-9);
        // Negative side.
        let c = Cubic::hermite(0.5, -3.0, -2.5, -3.0, 1.0);
        assert!((c.first_event(w).unwrap() - 0.5).abs() < 1e-15);
    }

    #[test]
    fn reaching_the_surface_from_the_side_of_the_last_update() {
        let c = Cubic::hermite(3.0, -4.0, -1.0, -4.0, 1.0);
        let w = Watch {
            level: 3.5,
            surface_from: Some(1.0),
        };
        assert!((c.first_event(w).unwrap() - 0.75).abs() < 1e-15);
        // From the other side nothing happens.
        let w = Watch {
            level: 3.5,
            surface_from: Some(-1.0),
        };
        assert_eq!(c.first_event(w), None);
    }

    #[test]
    fn a_grazing_return_to_the_level_it_started_a_rounding_error_beyond_comes_from_inside() {
        // The C4 W=8 step that left its layer: an update at s = -1 (the located level,
        // reached 2.6e-10 beyond it), s turns inside and comes back out past -1.
        let (l, h) = (1.0, 0.2896);
        let c = Cubic::hermite(-l - 2.6e-10, 8.95, -1.28, -11.57, h);
        let w = Watch {
            level: l,
            surface_from: None,
        };
        let theta = c.first_event(w).unwrap();
        assert!((c.eval(theta) + l).abs() < 1e-12 && theta > 0.5, "{theta}");
        // Before the event the variable is inside (above -1), whatever the start says.
        assert_eq!(c.side_before(theta, -l), 1.0);
        assert_eq!((c.eval(0.0) + l).signum(), -1.0);
        // The upper level, and the surface reached from above.
        let up = Cubic::hermite(l + 1e-12, -3.0, 1.4, 4.0, 1.0);
        let t_up = up.first_event(w).unwrap();
        assert_eq!(up.side_before(t_up, l), -1.0);
        let down = Cubic::hermite(3.0, -4.0, -1.0, -4.0, 1.0);
        assert_eq!(down.side_before(0.75, 0.0), 1.0);
    }

    #[test]
    fn the_crossing_is_looked_for_on_the_monotone_piece_of_its_event() {
        // The C1 N=10 r=1e4 step (fixed gains, steps of mu / 64) that cut itself ever
        // shorter: it starts 1.08e-4 of the level beyond it, moves inside by 5.6e-5,
        // turns out through the level and comes back. Within the crossing tolerance the
        // start is a root too; the piece of the event excludes it.
        let (l, h) = (1e-3, 2.277e-5);
        let c = Cubic::hermite(-1.000108e-3, 1.332, 1.462963e-4, 211.3, h);
        let w = Watch {
            level: l,
            surface_from: None,
        };
        let theta = c.first_event(w).unwrap();
        let (lo, hi) = c.piece(theta);
        let (b, n) = c.breaks();
        assert_eq!(n, 4);
        assert_eq!((lo, hi), (b[1], b[2]));
        assert!(lo > 0.01 && lo < theta && theta < hi, "{lo} {theta} {hi}");
        assert!(c.eval(lo) > -l && c.eval(hi) < -l);
        // The ends of the cubic are their own pieces' ends.
        assert_eq!(c.piece(0.0), (0.0, b[1]));
        assert_eq!(c.piece(1.0), (b[2], 1.0));
    }

    #[test]
    fn largest_value_after_a_point_sees_an_excursion_that_comes_back() {
        // p = 1 - t + 3 t^2 - 2 t^3: an outward motion starts at its minimum (0.90
        // near 0.21), goes out to 1.10 near 0.79 and comes back to 1 by the end.
        let c = Cubic::hermite(1.0, -1.0, 1.0, -1.0, 1.0);
        let (b, _) = c.breaks();
        let (first, peak) = (b[1], b[2]);
        assert!(c.eval(peak) > c.eval(first));
        let m = c.max_abs_from(first);
        assert_eq!(m, c.eval(peak).abs());
        assert!(m > c.eval(first).abs() + 0.05 && m > c.eval(1.0).abs() + 0.05);
        // From beyond the peak only the end and the way there count.
        assert_eq!(
            c.max_abs_from(0.99),
            c.eval(0.99).abs().max(c.eval(1.0).abs())
        );
    }

    #[test]
    fn the_bound_answers_every_query_as_the_extrema_do() {
        // Random cubics, many of them near a level of 1 and some exactly on it at an
        // end, queried through the bound alone and with their extrema found.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut skipped = 0;
        for k in 0..20_000 {
            let mut v = [0.0; 4];
            for x in &mut v {
                *x = 2.4 * uniform() - 1.2;
            }
            if k % 5 == 0 {
                v[2] = 1.0f64.copysign(v[2]);
            }
            let h = [1.0, 1e-3, 0.37][k % 3];
            let (s0, ds0, s1, ds1) = (v[0], v[1] / h, v[2], v[3] / h);
            let lazy = Cubic::bounded(s0, ds0, s1, ds1, h);
            let exact = Cubic::hermite(s0, ds0, s1, ds1, h);
            assert!(lazy.hull() >= exact.max_abs(), "{v:?}");
            for level in [0.5, 0.999, 1.0, 1.2, 2.0] {
                let w = Watch {
                    level,
                    surface_from: None,
                };
                assert_eq!(lazy.first_event(w), exact.first_event(w), "{v:?} {level}");
                assert_eq!(lazy.within(level), exact.max_abs() <= level);
                assert_eq!(lazy.time_beyond(level), exact.time_beyond(level));
                // Above the floor the exact maximum; at or below it, a value that a
                // running maximum of at least the floor ignores.
                let m = lazy.max_abs_above(level);
                if exact.max_abs() > level || m > level {
                    assert_eq!(m, exact.max_abs(), "{v:?} {level}");
                } else {
                    skipped += 1;
                }
            }
        }
        // The bound settles most of the queries below the larger levels.
        assert!(skipped > 20_000, "{skipped}");
    }

    #[test]
    fn max_and_time_beyond_a_level() {
        let c = from_poly(|t| 5.0 * t * (1.0 - t), |t| 5.0 - 10.0 * t);
        assert!((c.max_abs() - 1.25).abs() < 1e-12);
        // |p| > 1 on ((1 - sqrt 0.2)/2, (1 + sqrt 0.2)/2).
        assert!((c.time_beyond(1.0) - 0.2f64.sqrt()).abs() < 1e-12);
        let line = Cubic::hermite(-2.0, 4.0, 2.0, 4.0, 1.0);
        assert!((line.time_beyond(1.0) - 0.5).abs() < 1e-12);
        assert_eq!(line.max_abs(), 2.0);
    }
}
