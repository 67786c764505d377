//! What `daec run` and `daec design` share: the options of the pilot runs and the gain
//! design (`--gains`, `--bound`, `--passes`, `--pilot-mu`, `--pilot-gain`, `--safety`),
//! the automatic design itself, per-constraint values from the command line, and the
//! design as JSON.

use crate::Reported;
use dae_runtime::settings::StepEnd;
use dae_runtime::{
    Model, Settings, design::AutoDesign, design::AutoDesignOptions, design::DesignPass,
    design::GainChoice, design::LayerBound, design::MuChoice, design::auto_design,
    settings::Integrator,
};
use serde_json::json;

/// How the gain follows from `mu` (`--gains`).
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub(crate) enum GainsArg {
    /// `k = k* + mu^(r-1) |beta|`: the crossing guarantee (T 4.4) made robust for the
    /// cheap alpha_hat.
    Sufficient,
    /// `k = mu^(r-1) |beta|`: only what the cheap alpha_hat neglects (the thesis example).
    Relaxed,
}

impl GainsArg {
    pub(crate) fn choice(self) -> GainChoice {
        match self {
            GainsArg::Sufficient => GainChoice::Sufficient,
            GainsArg::Relaxed => GainChoice::Relaxed,
        }
    }
}

/// Which bound enters T_min (`--bound`).
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub(crate) enum BoundArg {
    /// (T 3.14), `c_r = 4 (2^(r-1) - 1)`; any index.
    General,
    /// (T 4.6), the tighter `c_3 = 4 (2 + e^-3)`; index 3 only.
    Index3,
}

impl BoundArg {
    pub(crate) fn layer(self) -> LayerBound {
        match self {
            BoundArg::General => LayerBound::General,
            BoundArg::Index3 => LayerBound::TightIndex3,
        }
    }
}

/// The gain of every constraint in the first pilot when `--pilot-gain` is not given:
/// `2 eps / (100 h)`, so that the layer `|s| <= eps` is crossed in about 100 steps `h`.
pub(crate) fn default_pilot_gain(eps: f64, step: f64) -> f64 {
    2.0 * eps / (100.0 * step)
}

/// The defaults of [`PilotArgs`]' numbers (the online design of `daec run` refuses any
/// other value, which it would leave unused).
pub(crate) const PASSES: usize = 2;
/// See [`PASSES`].
pub(crate) const PILOT_MU: f64 = 0.1;
/// See [`PASSES`].
pub(crate) const SAFETY: f64 = 1.0;
/// See [`PASSES`].
pub(crate) const PILOT_RETRIES: usize = 4;

/// Options of the pilot runs, shared by `daec design FILE` and `daec run --mu auto` /
/// `--gain auto`.
#[derive(clap::Args, Clone, Debug)]
pub(crate) struct PilotArgs {
    /// How the gain follows from mu in the design.
    #[arg(long, value_enum, default_value = "sufficient")]
    pub(crate) gains: GainsArg,
    /// Which bound enters T_min.
    #[arg(long, value_enum, default_value = "general")]
    pub(crate) bound: BoundArg,
    /// Number of pilot -> design passes (the first pilot uses --pilot-mu, --pilot-gain and
    /// the exact alpha; later ones the previous design with the cheap alpha).
    #[arg(long, default_value_t = PASSES)]
    pub(crate) passes: usize,
    /// mu of every constraint in the first pilot (when mu is designed; given mu are used
    /// by every pilot).
    #[arg(long, default_value_t = PILOT_MU)]
    pub(crate) pilot_mu: f64,
    /// Gain of every constraint in the first pilot [default: 2 eps / (100 h), so that a
    /// layer is crossed in about 100 steps].
    #[arg(long)]
    pub(crate) pilot_gain: Option<f64>,
    /// Factor (>= 1) on the pilot bounds before designing.
    #[arg(long, default_value_t = SAFETY)]
    pub(crate) safety: f64,
    /// How many times the first pilot runs again, with ten times its gains, when it
    /// leaves a layer (its gains were below the model's drift).
    #[arg(long, default_value_t = PILOT_RETRIES)]
    pub(crate) pilot_retries: usize,
    /// The most wall time, in seconds, all pilot runs together may take [default: 10 for
    /// `daec run`, no limit for `daec design`].
    #[arg(long, value_name = "SECONDS")]
    pub(crate) pilot_budget: Option<f64>,
}

/// Most pilot -> design passes: each is a pilot run over the whole pilot duration, and
/// the design settles in two or three.
pub(crate) const MAX_PASSES: usize = 20;

impl PilotArgs {
    /// Checks the values of these options before any pilot runs.
    pub(crate) fn validate(&self) -> Result<(), Reported> {
        use crate::messages::{at_least, check, positive};
        check(self.passes >= 1, || {
            "--passes must be at least 1".to_string()
        })?;
        positive("--pilot-mu", self.pilot_mu)?;
        if let Some(k) = self.pilot_gain {
            positive("--pilot-gain", k)?;
        }
        if let Some(b) = self.pilot_budget {
            positive("--pilot-budget", b)?;
        }
        at_least("--safety", self.safety, 1.0)
    }

    /// Refuse, before any work, more passes than [`MAX_PASSES`] or, with a fixed step,
    /// pilot runs that together take more than `max_steps` steps over `duration`
    /// (error-controlled pilots take the steps their motion needs).
    pub(crate) fn check_work(
        &self,
        duration: f64,
        fixed_step: Option<f64>,
        max_steps: f64,
    ) -> Result<(), Reported> {
        if self.passes == 0 || self.passes > MAX_PASSES {
            error!(
                "--passes {}: give 1 to {MAX_PASSES} (each pass is a pilot run of the whole --pilot duration; two or three settle the design)",
                self.passes
            );
            return Err(Reported);
        }
        let Some(step) = fixed_step else {
            return Ok(());
        };
        let steps = self.passes as f64 * duration / step;
        if steps > max_steps {
            error!(
                "{} pilot runs of {duration} s at a step of {step:e} are {steps:.3e} steps, more than the {max_steps:e} this command takes",
                self.passes
            );
            hint!("a shorter --pilot, fewer --passes, or a larger --step for the pilots");
            return Err(Reported);
        }
        Ok(())
    }

    /// The automatic design of `model` with pilots under `base` (its eps, step, time
    /// span, settle time, policy and reaching rule are used). With `mu`, the surfaces are
    /// given and only the gains are designed; with `fixed_gain`, every pass (the pilots
    /// included) uses that gain and only mu is designed.
    pub(crate) fn auto_design(
        &self,
        model: &dyn Model,
        base: &Settings,
        mu: Option<Vec<f64>>,
        fixed_gain: Option<f64>,
        default_budget: Option<f64>,
    ) -> Result<AutoDesign, Reported> {
        let m = model.n_constraints();
        // A fixed step (given) runs the pilots as the design procedure was built for:
        // RK4 with the thesis's step-end rule, every interval sampled at every step.
        // Error-controlled steps (the default) keep crossings located: a fixed step too
        // long for the layer would make the pilot leave it, and a long chain needs
        // intervals far shorter than any step chosen beforehand.
        let mut pilot = if base.integration.integrator.is_adaptive() {
            // At most the step of the thesis's procedure (1e-4 unless --step), so that
            // long intervals are sampled as densely as there.
            let h = base.integration.max_step.min(base.integration.step);
            base.clone().max_step(h)
        } else {
            base.clone()
                .integrator(Integrator::Rk4)
                .law(StepEnd::default())
        };
        pilot.layers.mu = vec![self.pilot_mu; m];
        pilot.layers.gains = match fixed_gain.or(self.pilot_gain) {
            Some(k) => vec![k; m],
            None => base
                .layers
                .eps
                .iter()
                .map(|&e| default_pilot_gain(e, base.integration.step))
                .collect(),
        };
        let opts = AutoDesignOptions {
            gain: fixed_gain.map_or(self.gains.choice(), GainChoice::Fixed),
            layer: self.bound.layer(),
            passes: self.passes,
            safety: self.safety,
            mu: mu.map_or_else(MuChoice::default, MuChoice::Given),
            pilot_retries: self.pilot_retries,
            budget: self
                .pilot_budget
                .or(default_budget)
                .map(std::time::Duration::from_secs_f64),
        };
        let spinner = crate::progress::spinner("designing mu and the gains (pilot runs)");
        let designed = auto_design(model, &base.layers.eps, &pilot, &opts);
        drop(spinner);
        let a = designed.map_err(|e| {
            error!(
                "automatic design of `{}`: {}",
                model.name(),
                crate::messages::pilot_run_error(model, &e)
            );
            crate::messages::pilot_run_error_fields(model, &e);
            Reported
        })?;
        if let Some(p) = a.passes.iter().find(|p| p.pilot_left_layer) {
            eprintln!(
                "warning: the designed pilot with gains {:e} .. {:e} left its layers at t = {:.6}; \
                 the design is from the bounds measured up to there and may be too weak \
                 (a longer --pilot, --safety, or given --mu and --gain)",
                p.gains.iter().copied().fold(f64::INFINITY, f64::min),
                p.gains.iter().copied().fold(0.0, f64::max),
                p.pilot.summary.t_end
            );
        }
        Ok(a)
    }
}

/// `values` expanded to one per constraint: one value applies to all.
pub(crate) fn per_constraint(what: &str, values: &[f64], m: usize) -> Result<Vec<f64>, Reported> {
    match values.len() {
        1 => Ok(vec![values[0]; m]),
        n if n == m => Ok(values.to_vec()),
        n => {
            let (constraints, give) = if m == 1 {
                ("1 constraint".to_string(), "1 value".to_string())
            } else {
                (format!("{m} constraints"), format!("1 or {m} values"))
            };
            error!("{what} has {n} values, the model has {constraints} (give {give})");
            Err(Reported)
        }
    }
}

/// The design of a model as JSON: per-constraint arrays `mu`, `gain`, `t_min`, the
/// bounds used (`beta_abs`, `m`: the largest over the passes), `t_min_design` and the
/// names of the quiet constraints (no best mu in the pilot: `quiet`).
pub(crate) fn design_json(model: &dyn Model, a: &AutoDesign) -> serde_json::Value {
    let m = model.n_constraints();
    let max_over = |f: &dyn Fn(&DesignPass, usize) -> f64| -> Vec<f64> {
        (0..m)
            .map(|i| a.passes.iter().map(|p| f(p, i)).fold(0.0, f64::max))
            .collect()
    };
    let c = &a.design.constraints;
    json!({
        "model": model.name(),
        "constraints": (0..m).map(|i| model.constraint_name(i)).collect::<Vec<_>>(),
        "mu": c.iter().map(|c| c.mu).collect::<Vec<_>>(),
        "gain": c.iter().map(|c| c.k).collect::<Vec<_>>(),
        "t_min": c.iter().map(|c| c.t_min).collect::<Vec<_>>(),
        "t_min_design": a.design.t_min,
        "beta_abs": max_over(&|p, i| p.pilot.estimate.beta_abs[i]),
        "m": max_over(&|p, i| p.pilot.estimate.m[i]),
        "passes": a.passes.len(),
        "quiet": a.design.quiet.iter().map(|&i| model.constraint_name(i)).collect::<Vec<_>>(),
    })
}
