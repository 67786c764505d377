//! The bookkeeping the substepping position-based methods (XPBD, VBD, AVBD) share: how
//! a frame is cut into substeps, the kinematics a particle reports, and the checks of
//! the `Backend` seam.

use dae_particles::{BackendError, Kinematics};

/// The substeps that cover `span` seconds at `substeps` per frame of 1/60 s: as many
/// of `1/(60 k)` s as fit (at least one), as `(count, length)`.
pub(crate) fn split(span: f64, substeps: u32) -> (u64, f64) {
    let n = ((span * 60.0 * substeps as f64) - 1e-9).ceil().max(1.0) as u64;
    (n, span / n as f64)
}

/// Particle `k`'s kinematics: its position and velocity, the acceleration over the
/// last substep (`h_last`, zero before the first) and no jerk.
pub(crate) fn kinematics(
    k: usize,
    x: &[[f64; 3]],
    v: &[[f64; 3]],
    v_prev: &[[f64; 3]],
    h_last: f64,
) -> Kinematics {
    let mut acc = [0.0; 3];
    if h_last > 0.0 {
        for (i, a) in acc.iter_mut().enumerate() {
            *a = (v[k][i] - v_prev[k][i]) / h_last;
        }
    }
    Kinematics {
        pos: x[k],
        vel: v[k],
        acc,
        jerk: [0.0; 3],
    }
}

/// An error naming the first particle whose position is not finite at `t`.
pub(crate) fn check_finite(method: String, t: f64, x: &[[f64; 3]]) -> Result<(), BackendError> {
    match x.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        Some(k) => Err(BackendError {
            method,
            t,
            reason: format!("particle {k} has a non-finite position"),
            deadline: false,
        }),
        None => Ok(()),
    }
}

/// An error unless particle `k` is one of `n`.
pub(crate) fn check_particle(
    method: String,
    t: f64,
    k: usize,
    n: usize,
) -> Result<(), BackendError> {
    if k < n {
        return Ok(());
    }
    Err(BackendError {
        method,
        t,
        reason: format!("particle {k} does not exist"),
        deadline: false,
    })
}
