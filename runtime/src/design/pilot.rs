//! Estimating `|beta_i|` and `M_i` from a pilot simulation (docs/method.md section 5,
//! pilot estimation). Independent of the simulator: it only sees numbers.

/// Collects samples of a pilot run and estimates the design bounds `|beta_i|` and `M_i`
/// (T 3.5) of every constraint.
///
/// # What to feed
///
/// * After every control update at time `t_b` (and once at the start of the run, or let
///   the first observation play that role): [`mark_update(t_b)`](Self::mark_update),
///   then [`observe`](Self::observe) at `t_b` with the values **after** the update, i.e.
///   evaluated with the new held input `v`. That observation is the reference
///   `w_i^(r_i)(t_b)` of the interval. (If the next observation comes later than `t_b`,
///   it is used as the reference instead.)
/// * After every integration step inside the interval: `observe(t, beta, w_r)`, where
///   - `beta[i]` is `beta_i = dOmega_i/dt + (dOmega_i/dx) f` (T 2.5) at the current state
///     (the model's `beta` evaluation),
///   - `w_r[i]` is the `r_i`-th derivative of constraint `i`,
///     `w_i^(r_i) = Omega_i' = (J_Omega v)_i + beta_i` (T 2.5), evaluated at the current
///     state with the held `v`.
///
/// Then `M_i` is the largest `|w_r[i](t) - w_r[i](t_b)| / (t - t_b)` over all samples
/// with `t > t_b` of all intervals, and `|beta_i|` is the largest `|beta[i]|` seen. The
/// jump of `w^(r)` at an update (the new `v`) is not a drift and is never counted,
/// because every interval is measured from its own reference.
///
/// Feed only the part of the run you want the design to cover: the thesis estimates the
/// bounds from the motion near the surfaces, so a long reaching phase with large `s` may
/// be left out by starting to feed (with a `mark_update`) after it.
#[derive(Debug, Clone)]
pub struct PilotEstimator {
    beta_abs: Vec<f64>,
    m: Vec<f64>,
    reference: Vec<f64>,
    ref_time: f64,
    /// True when the next observation is to become the interval's reference.
    awaiting_reference: bool,
    last_time: f64,
    samples: usize,
    intervals: usize,
    /// Per constraint: number of samples that contributed a drift ratio.
    ratios: Vec<usize>,
}

/// The estimated bounds, one entry per constraint.
#[derive(Debug, Clone, PartialEq)]
pub struct PilotEstimate {
    /// `|beta_i|` (times the safety factor).
    pub beta_abs: Vec<f64>,
    /// `M_i` (times the safety factor).
    pub m: Vec<f64>,
    /// Number of control intervals that contained at least one observation.
    pub intervals: usize,
    /// Number of observations.
    pub samples: usize,
}

/// Why a pilot sample or estimate was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PilotError {
    /// A slice has the wrong length.
    #[error("{what} has {got} entries, expected {expected} (one per constraint)")]
    WrongLength {
        /// `beta` or `w_r`.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The number of constraints.
        expected: usize,
    },
    /// A time or sample value is NaN or infinite.
    #[error("non-finite {what} at t = {t} (constraint {constraint:?})")]
    NonFinite {
        /// `t`, `beta` or `w_r`.
        what: &'static str,
        /// The time of the sample.
        t: f64,
        /// The constraint, if the value belongs to one.
        constraint: Option<usize>,
    },
    /// Time went backwards.
    #[error("time went backwards: {t} after {previous}")]
    TimeWentBack {
        /// The new time.
        t: f64,
        /// The latest time seen before.
        previous: f64,
    },
    /// No sample after an interval's reference, so `M` of this constraint is unknown.
    #[error(
        "no drift data for constraint {constraint}: no interval had two samples at distinct times"
    )]
    NoDriftData {
        /// The constraint.
        constraint: usize,
    },
    /// The estimator was made for zero constraints.
    #[error("the estimator has no constraints")]
    NoConstraints,
    /// The safety factor is below 1 or not finite.
    #[error("safety factor must be finite and at least 1, got {0}")]
    BadSafety(f64),
}

/// Below this fraction of the largest over the constraints, an estimated `M_i` or
/// `|beta_i|` is taken as 0: it is the rounding of an exact zero, not a motion. A
/// constraint at rest (the middle links of a long chain in a short pilot) has `beta_i`
/// and a drift of exactly 0 only while its compiled code cancels equal terms exactly;
/// evaluated in another order (a reciprocal shared by several divisions) they come out
/// as a few units of rounding (3e-14 against hundreds on the chain of
/// `cli/tests/design.rs`), and the design would give that constraint a `mu` of its own
/// instead of listing it as quiet ([`Design::quiet`](super::Design::quiet)).
pub const ROUNDING_FLOOR: f64 = 1e-12;

/// `values` times `safety`, with those at most [`ROUNDING_FLOOR`] of the largest set to 0.
fn above_rounding(values: &[f64], safety: f64) -> Vec<f64> {
    let largest = values.iter().fold(0.0f64, |a, &b| a.max(b));
    values
        .iter()
        .map(|&v| {
            if v <= ROUNDING_FLOOR * largest {
                0.0
            } else {
                v * safety
            }
        })
        .collect()
}

impl PilotEstimator {
    /// An estimator for `constraints` constraints.
    pub fn new(constraints: usize) -> Self {
        PilotEstimator {
            beta_abs: vec![0.0; constraints],
            m: vec![0.0; constraints],
            reference: vec![0.0; constraints],
            ref_time: f64::NEG_INFINITY,
            awaiting_reference: true,
            last_time: f64::NEG_INFINITY,
            samples: 0,
            intervals: 0,
            ratios: vec![0; constraints],
        }
    }

    /// A control update happened at `t`: the next observation starts a new interval.
    pub fn mark_update(&mut self, t: f64) -> Result<(), PilotError> {
        self.check_time(t)?;
        self.awaiting_reference = true;
        self.last_time = t;
        Ok(())
    }

    /// One sample at time `t` (see the type docs for what `beta` and `w_r` are).
    /// The sample is checked completely before anything is recorded.
    pub fn observe(&mut self, t: f64, beta: &[f64], w_r: &[f64]) -> Result<(), PilotError> {
        self.check_time(t)?;
        let n = self.m.len();
        for (what, xs) in [("beta", beta), ("w_r", w_r)] {
            if xs.len() != n {
                return Err(PilotError::WrongLength {
                    what,
                    got: xs.len(),
                    expected: n,
                });
            }
            if let Some(i) = xs.iter().position(|x| !x.is_finite()) {
                return Err(PilotError::NonFinite {
                    what,
                    t,
                    constraint: Some(i),
                });
            }
        }
        self.last_time = t;
        self.samples += 1;
        for (acc, b) in self.beta_abs.iter_mut().zip(beta) {
            *acc = acc.max(b.abs());
        }
        if self.awaiting_reference {
            self.reference.copy_from_slice(w_r);
            self.ref_time = t;
            self.awaiting_reference = false;
            self.intervals += 1;
            return Ok(());
        }
        let dt = t - self.ref_time;
        if dt > 0.0 {
            let per_constraint = self.m.iter_mut().zip(&mut self.ratios).zip(&self.reference);
            for (((m, count), reference), w) in per_constraint.zip(w_r) {
                *m = m.max((w - reference).abs() / dt);
                *count += 1;
            }
        }
        Ok(())
    }

    /// The bounds seen so far, each multiplied by `safety >= 1` (a margin for what the
    /// pilot run did not visit; 1 gives the raw maxima).
    pub fn estimate(&self, safety: f64) -> Result<PilotEstimate, PilotError> {
        if !(safety.is_finite() && safety >= 1.0) {
            return Err(PilotError::BadSafety(safety));
        }
        if self.m.is_empty() {
            return Err(PilotError::NoConstraints);
        }
        if let Some(constraint) = self.ratios.iter().position(|&c| c == 0) {
            return Err(PilotError::NoDriftData { constraint });
        }
        Ok(PilotEstimate {
            beta_abs: above_rounding(&self.beta_abs, safety),
            m: above_rounding(&self.m, safety),
            intervals: self.intervals,
            samples: self.samples,
        })
    }

    fn check_time(&self, t: f64) -> Result<(), PilotError> {
        if !t.is_finite() {
            return Err(PilotError::NonFinite {
                what: "t",
                t,
                constraint: None,
            });
        }
        if t < self.last_time {
            return Err(PilotError::TimeWentBack {
                t,
                previous: self.last_time,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feeds `w_r(t)` and `beta(t)` of two constraints on a uniform grid with updates
    /// every `period`, including the post-update observation at each update time.
    fn run(
        est: &mut PilotEstimator,
        t_end: f64,
        period: f64,
        dt: f64,
        f: impl Fn(usize, f64, f64) -> ([f64; 2], [f64; 2]),
    ) {
        let steps_per = (period / dt).round() as usize;
        let intervals = (t_end / period).round() as usize;
        // Times from one integer grid, so an interval's end is exactly the next start.
        for j in 0..intervals {
            let tb = (j * steps_per) as f64 * dt;
            est.mark_update(tb).unwrap();
            for s in 0..=steps_per {
                let t = (j * steps_per + s) as f64 * dt;
                let (beta, w_r) = f(j, tb, t);
                est.observe(t, &beta, &w_r).unwrap();
            }
        }
    }

    #[test]
    fn piecewise_linear_drift_gives_the_largest_slope_and_ignores_jumps() {
        // Interval j: w_r = c_j + s_j (t - t_b), with jumps c_j of size up to 1e6 at the
        // updates that must not count. Known answer: M = max |s_j|.
        let slopes = [[3.0, -40.0], [-7.5, 12.0], [1.0, 25.0], [0.0, -39.0]];
        let jumps = [[0.0, 1e6], [-5e5, 2.0], [9e5, -1e6], [1.0, 0.0]];
        let mut est = PilotEstimator::new(2);
        run(&mut est, 0.4, 0.1, 0.01, |j, tb, t| {
            let w = [0, 1].map(|i| jumps[j][i] + slopes[j][i] * (t - tb));
            ([-(j as f64), 2.0 * j as f64], w)
        });
        let e = est.estimate(1.0).unwrap();
        assert!((e.m[0] - 7.5).abs() < 1e-6, "{:?}", e.m);
        assert!((e.m[1] - 40.0).abs() < 1e-6, "{:?}", e.m);
        assert_eq!(e.beta_abs, vec![3.0, 6.0]);
        assert_eq!(e.intervals, 4);
        assert_eq!(e.samples, 44);
    }

    #[test]
    fn quadratic_drift_gives_the_chord_slope_at_the_interval_end() {
        // w_r = q (t - t_b)^2: the ratio is q (t - t_b), largest at the last sample of
        // the longest interval, q * period.
        let mut est = PilotEstimator::new(2);
        run(&mut est, 1.0, 0.25, 0.005, |_, tb, t| {
            let d = t - tb;
            ([0.5, -0.25], [100.0 * d * d, -3.0 * d * d])
        });
        let e = est.estimate(1.0).unwrap();
        assert!((e.m[0] - 25.0).abs() < 1e-9, "{:?}", e.m);
        assert!((e.m[1] - 0.75).abs() < 1e-9, "{:?}", e.m);
        assert_eq!(e.beta_abs, vec![0.5, 0.25]);
    }

    #[test]
    fn sine_drift_is_bounded_by_its_lipschitz_constant() {
        // w_r = A sin(omega t) continuous across updates: every chord slope is at most
        // A omega, and with short intervals the largest one approaches it.
        let (a, omega) = (2.0, 30.0);
        let mut est = PilotEstimator::new(2);
        run(&mut est, 1.0, 0.01, 0.0005, |_, _, t| {
            let w = a * (omega * t).sin();
            ([w, 0.0], [w, 0.5 * w])
        });
        let e = est.estimate(1.5).unwrap();
        let lip = a * omega * 1.5;
        assert!(
            e.m[0] <= lip * (1.0 + 1e-12) && e.m[0] > 0.99 * lip,
            "{:?}",
            e.m
        );
        assert!((e.m[1] - 0.5 * e.m[0]).abs() < 1e-9);
        assert!((e.beta_abs[0] - a * 1.5).abs() < 1e-3);
    }

    #[test]
    fn a_bound_at_the_rounding_of_zero_is_zero() {
        // Constraint 1 is at rest: its beta and drift are rounding (1e-14) beside
        // constraint 0's (1e2); constraint 2 moves slowly, but well above rounding.
        let mut est = PilotEstimator::new(3);
        est.observe(0.0, &[100.0, 3e-14, 1e-6], &[0.0, 0.0, 0.0])
            .unwrap();
        est.observe(0.5, &[-120.0, -2e-14, 2e-6], &[50.0, 1e-14, 1e-7])
            .unwrap();
        let e = est.estimate(2.0).unwrap();
        assert_eq!(e.beta_abs, vec![240.0, 0.0, 4e-6]);
        assert_eq!(e.m, vec![200.0, 0.0, 4e-7]);
    }

    #[test]
    fn first_observation_starts_an_interval_without_a_mark() {
        let mut est = PilotEstimator::new(1);
        est.observe(0.0, &[1.0], &[5.0]).unwrap();
        est.observe(0.5, &[-2.0], &[6.0]).unwrap();
        let e = est.estimate(1.0).unwrap();
        assert_eq!(e.m, vec![2.0]);
        assert_eq!(e.beta_abs, vec![2.0]);
    }

    #[test]
    fn bad_samples_are_errors_and_leave_the_state_unchanged() {
        let mut est = PilotEstimator::new(2);
        assert!(matches!(
            est.observe(0.0, &[1.0], &[0.0, 0.0]),
            Err(PilotError::WrongLength {
                what: "beta",
                got: 1,
                expected: 2
            })
        ));
        assert!(matches!(
            est.observe(0.0, &[1.0, 2.0], &[0.0, f64::NAN]),
            Err(PilotError::NonFinite {
                what: "w_r",
                constraint: Some(1),
                ..
            })
        ));
        assert!(matches!(
            est.observe(f64::NAN, &[1.0, 2.0], &[0.0, 0.0]),
            Err(PilotError::NonFinite { what: "t", .. })
        ));
        est.observe(1.0, &[1.0, 2.0], &[0.0, 0.0]).unwrap();
        assert!(matches!(
            est.observe(0.5, &[1.0, 2.0], &[0.0, 0.0]),
            Err(PilotError::TimeWentBack { .. })
        ));
        assert!(matches!(
            est.mark_update(0.9),
            Err(PilotError::TimeWentBack { .. })
        ));
        // Only one good sample: no drift data yet.
        assert_eq!(
            est.estimate(1.0),
            Err(PilotError::NoDriftData { constraint: 0 })
        );
        // The rejected samples did not count.
        est.observe(2.0, &[0.0, 0.0], &[1.0, 4.0]).unwrap();
        let e = est.estimate(1.0).unwrap();
        assert_eq!(e.samples, 2);
        assert_eq!(e.beta_abs, vec![1.0, 2.0]);
        assert_eq!(e.m, vec![1.0, 4.0]);
        assert!(matches!(est.estimate(0.5), Err(PilotError::BadSafety(_))));
        assert!(matches!(
            est.estimate(f64::NAN),
            Err(PilotError::BadSafety(_))
        ));
        assert_eq!(
            PilotEstimator::new(0).estimate(1.0),
            Err(PilotError::NoConstraints)
        );
    }
}
