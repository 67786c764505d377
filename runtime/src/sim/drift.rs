//! Gains that follow the drift of `s'` ([`Settings::follow_drift`](crate::Settings::follow_drift)).
//!
//! Between two updates `v` is held, so `s_i'` leaves its value right after the update
//! (`-k_i sgn(s_i)` with exact `alpha`) only through the motion of the state. If it
//! drifts at the rate `D_i`, the sweep from one side of the layer reaches the other
//! (`2 eps_i`) before `s_i'` turns when `k_i^2 >= 4 eps_i D_i`; a smaller gain lets `s_i`
//! turn back a depth `k_i^2 / (2 D_i)` inside the side it started from, grazing it, and
//! the next update comes from the same side after `2 k_i / D_i`.

/// How much of the drift estimate is kept from one update to the next: a drift that
/// fell is forgotten over a few updates, one that rose counts at once.
pub(crate) const DRIFT_MEMORY: f64 = 0.5;

/// The drift estimate after an interval whose measured drift of `s_i'` was `measured`
/// (`prev`: the estimate before it), and the gain it asks for: at least `configured`,
/// and `safety * 2 sqrt(eps D)`. A non-finite measurement keeps the estimate.
pub(crate) fn follow(
    configured: f64,
    eps: f64,
    safety: f64,
    prev: f64,
    measured: f64,
) -> (f64, f64) {
    let drift = if measured.is_finite() {
        measured.max(DRIFT_MEMORY * prev)
    } else {
        prev
    };
    (drift, configured.max(safety * 2.0 * (eps * drift).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gain_sweeps_the_layer_against_the_drift_and_never_falls_below_the_configured() {
        // k = 2 sqrt(eps D): the sweep k t - D t^2 / 2 at the turn t = k / D is 2 eps.
        let (d, k) = follow(0.1, 1e-3, 1.0, 0.0, 400.0);
        assert_eq!(d, 400.0);
        assert!((k - 2.0 * (1e-3f64 * 400.0).sqrt()).abs() < 1e-15);
        let turn = k / d;
        assert!((k * turn - 0.5 * d * turn * turn - 2e-3).abs() < 1e-15);
        assert_eq!(follow(0.1, 1e-3, 1.0, 0.0, 1.0).1, 0.1);
        assert_eq!(follow(0.1, 1e-3, 3.0, 0.0, 400.0).1, 3.0 * k);
    }

    #[test]
    fn a_falling_drift_is_forgotten_by_halves_and_a_rising_one_counts_at_once() {
        assert_eq!(follow(0.0, 1.0, 1.0, 400.0, 10.0).0, 200.0);
        assert_eq!(follow(0.0, 1.0, 1.0, 400.0, 300.0).0, 300.0);
        assert_eq!(follow(0.0, 1.0, 1.0, 400.0, 900.0).0, 900.0);
        assert_eq!(follow(0.0, 1.0, 1.0, 400.0, f64::NAN).0, 400.0);
        assert_eq!(follow(0.0, 1.0, 1.0, 400.0, f64::INFINITY).0, 400.0);
    }
}
