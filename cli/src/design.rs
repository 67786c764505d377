//! `daec design`: the gain and surface design of method.md section 4, from given bounds
//! (one constraint) or from a pilot run of a model (every constraint).

use crate::{Reported, source};
use dae_runtime::{
    AutoDesign, AutoDesignOptions, ConstraintSpec, GainChoice, LayerBound, Model, MuSearch,
    Settings, auto_design, optimise_mu,
};
use serde_json::json;
use std::path::PathBuf;

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

/// Options of the pilot runs, shared by `daec design FILE` and `daec run --mu auto`.
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
    #[arg(long, default_value_t = 2)]
    pub(crate) passes: usize,
    /// mu of every constraint in the first pilot.
    #[arg(long, default_value_t = 0.1)]
    pub(crate) pilot_mu: f64,
    /// Gain of every constraint in the first pilot [default: 2 eps / (100 h), so that a
    /// layer is crossed in about 100 steps].
    #[arg(long)]
    pub(crate) pilot_gain: Option<f64>,
    /// Factor (>= 1) on the pilot bounds before designing.
    #[arg(long, default_value_t = 1.0)]
    pub(crate) safety: f64,
}

impl PilotArgs {
    /// The automatic design of `model` with a pilot under `base` (its eps, step, time
    /// span, settle time, policy and reaching rule are used). With `fixed_gain`, every
    /// pass (the pilots included) uses that gain and only mu is designed.
    pub(crate) fn auto_design(
        &self,
        model: &dyn Model,
        base: &Settings,
        fixed_gain: Option<f64>,
    ) -> Result<AutoDesign, Reported> {
        let m = model.n_constraints();
        let mut pilot = base.clone();
        pilot.mu = vec![self.pilot_mu; m];
        pilot.gains = match (fixed_gain, self.pilot_gain) {
            (Some(k), _) | (None, Some(k)) => vec![k; m],
            (None, None) => base
                .eps
                .iter()
                .map(|e| 2.0 * e / (100.0 * base.step))
                .collect(),
        };
        let opts = AutoDesignOptions {
            gain: fixed_gain.map_or(self.gains.choice(), GainChoice::Fixed),
            layer: self.bound.layer(),
            passes: self.passes,
            safety: self.safety,
            search: MuSearch::default(),
        };
        auto_design(model, &base.eps, &pilot, &opts).map_err(|e| {
            eprintln!("error: automatic design of `{}`: {e}", model.name());
            Reported
        })
    }
}

/// Arguments of `daec design`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// A `.dae` file: design every constraint of its model from a pilot run (--pilot).
    /// Without a file, design one constraint from --index, --eps, --beta and --m.
    file: Option<PathBuf>,
    /// The model to use when the file holds several.
    #[arg(long)]
    model: Option<String>,
    /// Index r of the constraint (without a file).
    #[arg(long)]
    index: Option<usize>,
    /// Layer half-width eps: one value, or one per constraint of the model.
    #[arg(long, value_delimiter = ',', required = true)]
    eps: Vec<f64>,
    /// Bound on |beta| (without a file).
    #[arg(long)]
    beta: Option<f64>,
    /// Drift bound M of w^(r) (without a file).
    #[arg(long)]
    m: Option<f64>,
    /// Duration of the pilot run, in seconds (with a file).
    #[arg(long)]
    pilot: Option<f64>,
    /// Integration step of the pilot run.
    #[arg(long, default_value_t = 1e-4)]
    step: f64,
    /// Seconds after the reaching phase before the pilot's bounds are collected.
    #[arg(long, default_value_t = 0.0)]
    settle: f64,
    #[command(flatten)]
    pilot_args: PilotArgs,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    match &args.file {
        None => from_bounds(args),
        Some(file) => from_pilot(args, file),
    }
}

fn from_bounds(args: &Args) -> Result<(), Reported> {
    let missing: Vec<&str> = [
        ("--index", args.index.is_none()),
        ("--beta", args.beta.is_none()),
        ("--m", args.m.is_none()),
    ]
    .iter()
    .filter(|(_, miss)| *miss)
    .map(|(n, _)| *n)
    .collect();
    if !missing.is_empty() {
        eprintln!(
            "error: without a model file, `daec design` needs {}",
            missing.join(", ")
        );
        return Err(Reported);
    }
    let [eps] = args.eps[..] else {
        eprintln!("error: without a model file, give one --eps value");
        return Err(Reported);
    };
    let spec = ConstraintSpec {
        r: args.index.unwrap_or(0),
        eps,
        m: args.m.unwrap_or(0.0),
        beta_abs: args.beta.unwrap_or(0.0),
        layer: args.pilot_args.bound.layer(),
    };
    let gain = args.pilot_args.gains.choice();
    let d = optimise_mu(&spec, gain, &MuSearch::default()).map_err(|e| {
        eprintln!("error: {e}");
        Reported
    })?;
    if args.json {
        println!("{}", json!({"mu": d.mu, "gain": d.k, "t_min": d.t_min}));
    } else {
        println!("mu = {}\ngain = {}\nt_min = {}", d.mu, d.k, d.t_min);
    }
    Ok(())
}

fn from_pilot(args: &Args, file: &std::path::Path) -> Result<(), Reported> {
    let Some(duration) = args.pilot else {
        eprintln!("error: with a model file, `daec design` needs --pilot SECONDS");
        return Err(Reported);
    };
    if args.index.is_some() || args.beta.is_some() || args.m.is_some() {
        eprintln!("error: --index, --beta and --m are for a single constraint without a file");
        return Err(Reported);
    }
    let model = source::interpreted(file, args.model.as_deref())?;
    let m = model.n_constraints();
    let eps = crate::run::per_constraint("--eps", &args.eps, m)?;
    let base = Settings::new(eps, vec![1.0; m], vec![1.0; m])
        .step(args.step)
        .t_end(duration)
        .settle(args.settle);
    let a = args.pilot_args.auto_design(&model, &base, None)?;
    let out = design_json(&model, &a);
    if args.json {
        println!("{out}");
    } else {
        println!("model {}", model.name());
        for (i, c) in a.design.constraints.iter().enumerate() {
            println!(
                "  {}: mu = {}, gain = {}, t_min = {}  (|beta| <= {}, M = {})",
                model.constraint_name(i),
                c.mu,
                c.k,
                c.t_min,
                out["beta_abs"][i],
                out["m"][i]
            );
        }
        println!("  T_min = {}", a.design.t_min);
    }
    Ok(())
}

/// The design of a model as JSON: per-constraint arrays `mu`, `gain`, `t_min`, the
/// bounds used (`beta_abs`, `m`: the largest over the passes) and `t_min_design`.
pub(crate) fn design_json(model: &dyn Model, a: &AutoDesign) -> serde_json::Value {
    let m = model.n_constraints();
    let max_over = |f: &dyn Fn(&dae_runtime::DesignPass, usize) -> f64| -> Vec<f64> {
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
    })
}
