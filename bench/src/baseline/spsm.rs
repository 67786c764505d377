//! Baseline (b): SPSM (the runtime's `Law::Spsm`) and the search for the largest
//! step a method survives.

use dae_runtime::{Model, Summary};

use super::{BaselineError, ZSolver};

/// Whether a DBSMC or SPSM run "holds": it reached the layers (all `|s_i| <= eps_i`
/// at some step end), and afterwards every `|s_i|` stayed within `2 eps_i` (the
/// runtime's window statistics), with all values finite (a non-finite run is an error
/// before a summary exists).
pub fn spsm_stable(summary: &Summary, eps: &[f64]) -> bool {
    summary.reaching_time.is_some()
        && summary.max_abs_s.as_ref().is_some_and(|max| {
            max.iter()
                .zip(eps)
                .all(|(s, e)| s.is_finite() && *s <= 2.0 * e)
        })
}

/// Result of [`largest_stable_step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSearch {
    /// Largest step found stable (`None`: even the smallest tried failed).
    pub stable: Option<f64>,
    /// Smallest step found unstable (`None`: even the largest tried held).
    pub unstable: Option<f64>,
    /// Number of trial runs.
    pub trials: usize,
}

/// Bisect (geometrically) for the largest step `h` in `[h_min, h_max]` for which
/// `trial(h)` holds, with `iters` bisection steps after checking both ends. Assumes
/// stability is monotone in `h` (it usually is; where it is not, the result is one
/// stable and one unstable step `ratio` apart, not the global boundary).
pub fn largest_stable_step(
    mut trial: impl FnMut(f64) -> bool,
    h_min: f64,
    h_max: f64,
    iters: usize,
) -> StepSearch {
    if trial(h_max) {
        return StepSearch {
            stable: Some(h_max),
            unstable: None,
            trials: 1,
        };
    }
    if !trial(h_min) {
        return StepSearch {
            stable: None,
            unstable: Some(h_min),
            trials: 2,
        };
    }
    let (mut lo, mut hi) = (h_min, h_max);
    for _ in 0..iters {
        let mid = (lo * hi).sqrt();
        if trial(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    StepSearch {
        stable: Some(lo),
        unstable: Some(hi),
        trials: 2 + iters,
    }
}

/// The algebraic unknowns consistent with `(t, x)`: `z` with `s(t, x, z) = 0` for the
/// given `mu` (for a state with `w = w' = ... = 0` this is `Omega = 0`, independent of
/// `mu`), by Newton from `z_guess`.
pub fn consistent_alg<M: Model + ?Sized>(
    model: &M,
    t: f64,
    x: &[f64],
    mu: &[f64],
    z_guess: &[f64],
) -> Result<Vec<f64>, BaselineError> {
    let mut solver = ZSolver::new(model, mu, 1e-13)?;
    let mut z = z_guess.to_vec();
    solver.solve(model, t, x, &mut z)?;
    Ok(z)
}
