//! Scenes on the DEVELOPMENT STAND-IN chains: the truth in minimal coordinates mapped
//! onto the Cartesian DAE. When generated models replace the stand-in, only the state
//! layout (`[x_k, y_k, vx_k, vy_k]` per particle) has to match.

use dae_runtime::Model;

use crate::baseline::{BaselineError, consistent_alg};
use crate::harness::{Scene, pilot_beta_bound};
use crate::truth::{PlanarChain, TruthError, reference};

/// Why a scene could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The reference integration failed.
    #[error("truth: {0}")]
    Truth(#[from] TruthError),
    /// The consistent `z0` or the pilot run failed.
    #[error("baseline: {0}")]
    Baseline(#[from] BaselineError),
}

/// Tolerance of the reference solutions.
pub const TRUTH_TOL: f64 = 1e-13;

/// A scene for a Cartesian chain model (`[x_k, y_k, vx_k, vy_k]` per particle) of
/// `chain`, starting at the angles `theta0` at rest, ending at `t_end`: consistent
/// `x0` from the angles, consistent `z0` by Newton on `s = 0`, the truth by
/// [`reference()`], the `|beta|` bound by a pilot run of baseline (a) with `h = 1e-3`,
/// `mu = 0.05`.
pub fn chain_scene<'a, M: Model + ?Sized>(
    name: &str,
    model: &'a M,
    chain: &PlanarChain,
    theta0: &[f64],
    t_end: f64,
) -> Result<Scene<'a, M>, SceneError> {
    let n = chain.links();
    if theta0.len() != n || model.n_states() != 4 * n || model.n_constraints() != n {
        return Err(TruthError::InvalidChain(format!(
            "{} angles for {n} links and a model with {} states and {} constraints \
             (need one angle per link, 4 states per particle, one constraint per link)",
            theta0.len(),
            model.n_states(),
            model.n_constraints()
        ))
        .into());
    }
    let mut y0 = theta0.to_vec();
    y0.extend(std::iter::repeat_n(0.0, n));
    let x0 = chain.cartesian(&y0);
    let mu = vec![0.05; n];
    let z0 = consistent_alg(model, 0.0, &x0, &mu, &vec![0.0; n])?;
    let truth = reference(chain, &y0, t_end, TRUTH_TOL)?;
    let beta_bound = pilot_beta_bound(model, &x0, &z0, t_end, 0.05, 1e-3)?;
    Ok(Scene {
        name: name.to_string(),
        model,
        x0,
        z0,
        t_end,
        compare: (0..n).flat_map(|k| [4 * k, 4 * k + 1]).collect(),
        truth: truth.positions,
        beta_bound,
    })
}
