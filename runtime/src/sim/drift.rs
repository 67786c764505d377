//! Gains that follow the drift of `s'` ([`GainRule::FollowDrift`](crate::settings::GainRule::FollowDrift)), and `v` ramped against it
//! ([`Hold::RampAgainstDrift`](crate::settings::Hold::RampAgainstDrift)).
//!
//! Between two updates `v` is held, so `s_i'` leaves its value right after the update
//! (`-k_i sgn(s_i)` with exact `alpha`) only through the motion of the state. If it
//! drifts at the rate `D_i`, the sweep from one side of the layer reaches the other
//! (`2 eps_i`) before `s_i'` turns when `k_i^2 >= 4 eps_i D_i`; a smaller gain lets `s_i`
//! turn back a depth `k_i^2 / (2 D_i)` inside the side it started from, grazing it, and
//! the next update comes from the same side after `2 k_i / D_i`.
//!
//! For one variable alone, the update rate is least at the sweeping gain: below it the
//! returns come every `2 k / D`, above it the crossings every `2 eps / k` or so. With
//! many variables the update that one of them asks for resets all, and a raised gain
//! makes every other variable's next crossing sooner too; on chains with heavy ends
//! the sweeping gains make more updates than the floor gains left grazing
//! (docs/particles.md). The rule's `graze` therefore raises a gain only as far as its
//! grazing returns need to stay a given time apart.

use super::Simulator;
use crate::Model;

/// How much of the drift estimate is kept from one update to the next: a drift that
/// fell is forgotten over a few updates, one that rose counts at once.
pub(crate) const DRIFT_MEMORY: f64 = 0.5;

/// How a gain follows the drift: `safety` on the gain asked for, and the shortest time
/// between grazing returns (`INFINITY`: always the sweeping gain).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Follow {
    pub(crate) safety: f64,
    pub(crate) min_return: f64,
}

/// The drift estimate after an interval whose measured drift of `s_i'` was `measured`
/// (`prev`: the estimate before it), and the gain it asks for: at least `configured`,
/// and `safety` times the smaller of the sweeping gain `2 sqrt(eps D)` and the gain
/// `D T / 2` whose grazing returns come `T = min_return` apart. A non-finite
/// measurement keeps the estimate.
pub(crate) fn follow(
    configured: f64,
    eps: f64,
    how: Follow,
    prev: f64,
    measured: f64,
) -> (f64, f64) {
    let drift = if measured.is_finite() {
        measured.max(DRIFT_MEMORY * prev)
    } else {
        prev
    };
    let sweep = 2.0 * (eps * drift).sqrt();
    let graze = 0.5 * drift * how.min_return;
    (drift, configured.max(how.safety * sweep.min(graze)))
}

impl<M: Model> Simulator<M> {
    /// [`Settings::follow_drift`]: measure the drift of `s'` over the interval that
    /// ends at `t` (`ds` still holds the rate with the old `v`: the settings only allow
    /// it with located crossings) and set the gains.
    pub(super) fn follow_drift(&mut self, t: f64) {
        let Some((safety, graze)) = self.set.law.follows_drift() else {
            return;
        };
        let how = Follow {
            safety,
            min_return: graze.unwrap_or(f64::INFINITY),
        };
        if self.stats.updates == 0 || t <= self.pt.tb {
            return;
        }
        let dt = t - self.pt.tb;
        for i in 0..self.drift.len() {
            let measured = (self.ds[i] - self.ds_b[i]).abs() / dt;
            let (d, k) = follow(
                self.set.layers.gains[i],
                self.set.layers.eps[i],
                how,
                self.drift[i],
                measured,
            );
            self.drift[i] = d;
            self.ctl.gains[i] = k;
        }
    }

    /// The rate of `v` that cancels the drift of `s'` at the update: `s''` by a finite
    /// difference along the flow (`s'` one short step on, evaluated apart from the
    /// point's own `s`, `J_Omega` and `beta`), `va = -J_s^{-1} s''`.
    pub(super) fn ramp_against_drift(&mut self, t: f64) {
        let delta = 1e-6 * self.mu_min;
        self.model
            .rhs(t, &self.pt.x, &self.pt.z, &mut self.scratch.fx);
        self.stats.rhs_evals += 1;
        for ((xs, x), f) in self
            .scratch
            .xs
            .iter_mut()
            .zip(&self.pt.x)
            .zip(&self.scratch.fx)
        {
            *xs = x + delta * f;
        }
        for ((zs, z), v) in self.scratch.zs.iter_mut().zip(&self.pt.z).zip(&self.pt.v) {
            *zs = z + delta * v;
        }
        self.ctl.s_rate_at(
            &self.model,
            t + delta,
            &self.scratch.xs,
            &self.scratch.zs,
            &self.pt.v,
            &mut self.pt.v_now,
        );
        for (n, d) in self.pt.v_now.iter_mut().zip(&self.ds) {
            *n = -(*n - d) / delta;
        }
        self.ctl.solve_factored(&self.pt.v_now, &mut self.pt.va);
        if self.pt.va.iter().any(|a| !a.is_finite()) {
            self.pt.va.fill(0.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SWEEP: Follow = Follow {
        safety: 1.0,
        min_return: f64::INFINITY,
    };

    #[test]
    fn the_gain_sweeps_the_layer_against_the_drift_and_never_falls_below_the_configured() {
        // k = 2 sqrt(eps D): the sweep k t - D t^2 / 2 at the turn t = k / D is 2 eps.
        let (d, k) = follow(0.1, 1e-3, SWEEP, 0.0, 400.0);
        assert_eq!(d, 400.0);
        assert!((k - 2.0 * (1e-3f64 * 400.0).sqrt()).abs() < 1e-15);
        let turn = k / d;
        assert!((k * turn - 0.5 * d * turn * turn - 2e-3).abs() < 1e-15);
        assert_eq!(follow(0.1, 1e-3, SWEEP, 0.0, 1.0).1, 0.1);
        assert_eq!(
            follow(
                0.1,
                1e-3,
                Follow {
                    safety: 3.0,
                    ..SWEEP
                },
                0.0,
                400.0
            )
            .1,
            3.0 * k
        );
    }

    #[test]
    fn a_falling_drift_is_forgotten_by_halves_and_a_rising_one_counts_at_once() {
        assert_eq!(follow(0.0, 1.0, SWEEP, 400.0, 10.0).0, 200.0);
        assert_eq!(follow(0.0, 1.0, SWEEP, 400.0, 300.0).0, 300.0);
        assert_eq!(follow(0.0, 1.0, SWEEP, 400.0, 900.0).0, 900.0);
        assert_eq!(follow(0.0, 1.0, SWEEP, 400.0, f64::NAN).0, 400.0);
        assert_eq!(follow(0.0, 1.0, SWEEP, 400.0, f64::INFINITY).0, 400.0);
    }

    #[test]
    fn a_grazing_gain_is_raised_only_until_its_returns_are_min_return_apart() {
        // Drift 400, eps 1e-3: sweeping gain 2 sqrt(0.4) = 1.26; returns 1e-3 apart
        // need D T / 2 = 0.2, and with s' = -k + D t the return comes at 2 k / D = T.
        let how = Follow {
            safety: 1.0,
            min_return: 1e-3,
        };
        let (d, k) = follow(0.05, 1e-3, how, 0.0, 400.0);
        assert!((k - 0.2).abs() < 1e-15);
        assert!((2.0 * k / d - 1e-3).abs() < 1e-15);
        // Never above the sweeping gain (a longer return would need a crossing), never
        // below the configured one.
        let long = Follow {
            min_return: 1.0,
            ..how
        };
        let sweep = 2.0 * (1e-3f64 * 400.0).sqrt();
        assert!((follow(0.05, 1e-3, long, 0.0, 400.0).1 - sweep).abs() < 1e-15);
        assert_eq!(follow(0.5, 1e-3, how, 0.0, 400.0).1, 0.5);
    }
}
