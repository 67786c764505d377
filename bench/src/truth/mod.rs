//! The truth: planar pendulum chains in minimal coordinates, integrated to near
//! round-off by adaptive extrapolation, mapped to Cartesian coordinates.

mod chain;
mod extrapolation;

pub use chain::{ChainWork, PlanarChain};
pub use extrapolation::{Extrapolation, TruthError, TruthStats};

/// A reference solution of a chain at one time.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// Time of the solution.
    pub t: f64,
    /// `[theta, omega]` at `t`.
    pub angles: Vec<f64>,
    /// Cartesian state (per particle `[x, y, vx, vy]`) at `t`.
    pub cartesian: Vec<f64>,
    /// Positions `[x_0, y_0, x_1, y_1, ...]` at `t`.
    pub positions: Vec<f64>,
    /// Largest position difference against a second run at a 100 times looser
    /// tolerance: an upper estimate of the reference's own position error.
    pub error_estimate: f64,
    /// Relative energy change over the run, `|E(t) - E(0)| / max(|E(0)|, 1)`.
    pub energy_drift: f64,
}

/// Integrate `chain` from angles and angular velocities `y0 = [theta, omega]` at time
/// 0 to `t_end` with [`Extrapolation`] at `rtol = atol = tol`, check it against a run at
/// `100 tol`, and map it to Cartesian coordinates.
pub fn reference(
    chain: &PlanarChain,
    y0: &[f64],
    t_end: f64,
    tol: f64,
) -> Result<Reference, TruthError> {
    if y0.len() != 2 * chain.links() {
        return Err(TruthError::InvalidChain(format!(
            "{} initial values for {} links (need angles then angular velocities)",
            y0.len(),
            chain.links()
        )));
    }
    let run = |tol: f64| -> Result<Vec<f64>, TruthError> {
        let mut work = ChainWork::new(chain.links());
        let mut y = y0.to_vec();
        let ex = Extrapolation {
            rtol: tol,
            atol: tol,
            ..Extrapolation::default()
        };
        ex.integrate(
            |_, y, dy| chain.derivative(y, &mut work, dy),
            0.0,
            &mut y,
            t_end,
        )?;
        Ok(y)
    };
    let y = run(tol)?;
    let loose = run(100.0 * tol)?;
    let positions = chain.positions(&y);
    let error_estimate = positions
        .iter()
        .zip(chain.positions(&loose))
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let e0 = chain.energy(y0);
    Ok(Reference {
        t: t_end,
        cartesian: chain.cartesian(&y),
        positions,
        error_estimate,
        energy_drift: (chain.energy(&y) - e0).abs() / e0.abs().max(1.0),
        angles: y,
    })
}
