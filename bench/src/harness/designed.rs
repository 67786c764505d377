//! DBSMC designed with the runtime's toolkit: one `auto_design` pilot per scene for the
//! bounds `|beta_i|` and `M_i`, then per layer `eps` the pure `design` (maximise the
//! guaranteed period over `mu_i` with relaxed gains `k_i = mu_i^(r-1) |beta_i|`).

use dae_runtime::settings::StepEnd;
use dae_runtime::{
    Model, Settings, design::AutoDesignOptions, design::GainChoice, design::LayerBound,
    design::MuSearch, design::auto_design, design::design, design::pilot_specs,
};

use super::{DbsmcStep, Method, Scene, step_rule};

/// The pilot bounds of a scene, from which [`DesignedBounds::dbsmc`] designs DBSMC for
/// any layer.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignedBounds {
    /// Constraint indices.
    pub indices: Vec<usize>,
    /// Largest `|beta_i|` over the pilot passes.
    pub beta_abs: Vec<f64>,
    /// Largest drift bound `M_i` over the pilot passes.
    pub m: Vec<f64>,
}

/// Run the runtime's `auto_design` (two pilot passes, relaxed gains, general layer
/// bound) on `scene` at the layer `eps_pilot`, starting from `mu = 0.05` and the scene's
/// [`Scene::gains`] with factor 1.5, the DBSMC step rule of [`Scene::dbsmc`] with
/// `h_max`; return the largest bounds the pilots measured.
pub fn designed_bounds<M: Model + ?Sized>(
    scene: &Scene<'_, M>,
    eps_pilot: f64,
    h_max: f64,
) -> Result<DesignedBounds, String> {
    let m = scene.model.n_constraints();
    let gains = scene.gains(0.05, 1.5);
    let step = step_rule(eps_pilot, &gains, h_max);
    // The pilot as before located crossings (RK4, the step rule, step-end crossings):
    // dense samples in every interval for the drift bound M.
    let pilot = Settings::new(vec![eps_pilot; m], vec![0.05; m], gains)
        .step(step)
        .law(StepEnd::default())
        .t_end(scene.t_end)
        .check_robustness(false)
        .initial(scene.x0.clone(), scene.z0.clone());
    let auto = auto_design(
        scene.model,
        &vec![eps_pilot; m],
        &pilot,
        &AutoDesignOptions::default(),
    )
    .map_err(|e| e.to_string())?;
    let (mut beta_abs, mut drift) = (vec![0.0f64; m], vec![0.0f64; m]);
    for pass in &auto.passes {
        for i in 0..m {
            beta_abs[i] = beta_abs[i].max(pass.pilot.estimate.beta_abs[i]);
            drift[i] = drift[i].max(pass.pilot.estimate.m[i]);
        }
    }
    Ok(DesignedBounds {
        indices: scene.model.indices().to_vec(),
        beta_abs,
        m: drift,
    })
}

impl DesignedBounds {
    /// [`Method::DbsmcDesigned`] at layer `eps`: `mu_i`, `k_i` from the runtime's
    /// `design` (relaxed gains, general layer bound, default `mu` search), integrated as
    /// `step` says; with `None`, the step rule of before located crossings
    /// (`h = 0.2 eps / max k_i` clamped to `[1e-6, h_max]`, step-end crossings).
    pub fn dbsmc(&self, eps: f64, step: Option<DbsmcStep>, h_max: f64) -> Result<Method, String> {
        let est = dae_runtime::design::PilotEstimate {
            beta_abs: self.beta_abs.clone(),
            m: self.m.clone(),
            intervals: 0,
            samples: 0,
        };
        let eps_v = vec![eps; self.indices.len()];
        let specs = pilot_specs(&self.indices, &eps_v, &est, LayerBound::General)
            .map_err(|e| e.to_string())?;
        let d =
            design(&specs, GainChoice::Relaxed, &MuSearch::default()).map_err(|e| e.to_string())?;
        let gains: Vec<f64> = d.constraints.iter().map(|c| c.k).collect();
        let step = step.unwrap_or_else(|| DbsmcStep::StepEnd(step_rule(eps, &gains, h_max)));
        Ok(Method::DbsmcDesigned {
            eps,
            mu: d.constraints.iter().map(|c| c.mu).collect(),
            gains,
            step,
        })
    }
}
