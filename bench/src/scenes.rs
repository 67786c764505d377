//! Scenes: the truth of a planar chain in minimal coordinates mapped onto a Cartesian
//! DAE model (generated from `examples/models/`, or the stand-in), planar or embedded
//! in a vertical plane of a 3-D model.

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

/// A scene for a Cartesian chain model (`[x_k, y_k, vx_k, vy_k]` per particle, e.g. the
/// generated [`DoublePendulum`](crate::generated::DoublePendulum) and [`Chain5`](crate::generated::Chain5)) of
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
    let map: Vec<usize> = (0..4 * chain.links()).collect();
    embedded_chain_scene(name, model, chain, theta0, t_end, &map)
}

/// Where the planar chain's Cartesian state lies in a 3-D model whose states are all
/// positions `(x, y, z)` per particle, then all velocities (the layout of the generated
/// [`DoublePendulum3D`](crate::generated::DoublePendulum3D)): the chain moves in the vertical
/// `x`-`z` plane, planar `x -> x`, planar `y -> z` (gravity along `-y` in the plane,
/// along `-z` in 3-D); the out-of-plane `y` and its velocity stay 0.
pub fn vertical_plane_map(links: usize) -> Vec<usize> {
    let vel = 3 * links;
    (0..links)
        .flat_map(|k| [3 * k, 3 * k + 2, vel + 3 * k, vel + 3 * k + 2])
        .collect()
}

/// [`chain_scene`] for a model with another state layout: `map[i]` is the model state
/// holding the planar chain's Cartesian state `i` (`[x_k, y_k, vx_k, vy_k]` per
/// particle, see [`PlanarChain::cartesian`]); the model's other states start at 0. The
/// truth of the compared positions is the planar one (valid when the model restricted
/// to the mapped states is the planar chain, e.g. [`vertical_plane_map`]).
pub fn embedded_chain_scene<'a, M: Model + ?Sized>(
    name: &str,
    model: &'a M,
    chain: &PlanarChain,
    theta0: &[f64],
    t_end: f64,
    map: &[usize],
) -> Result<Scene<'a, M>, SceneError> {
    let n = chain.links();
    let ns = model.n_states();
    let mut distinct = map.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    if theta0.len() != n
        || model.n_constraints() != n
        || map.len() != 4 * n
        || distinct.len() != map.len()
        || map.iter().any(|&i| i >= ns)
    {
        return Err(TruthError::InvalidChain(format!(
            "{} angles for {n} links and a model with {ns} states and {} constraints, \
             state map {map:?} (need one angle per link, one constraint per link, \
             4 distinct model states per particle)",
            theta0.len(),
            model.n_constraints()
        ))
        .into());
    }
    let mut y0 = theta0.to_vec();
    y0.extend(std::iter::repeat_n(0.0, n));
    let mut x0 = vec![0.0; ns];
    for (&i, v) in map.iter().zip(chain.cartesian(&y0)) {
        x0[i] = v;
    }
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
        compare: (0..n).flat_map(|k| [map[4 * k], map[4 * k + 1]]).collect(),
        truth: truth.positions,
        beta_bound,
    })
}
