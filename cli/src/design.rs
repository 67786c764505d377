//! `daec design`: the gain and surface design of docs/method.md section 5, from given bounds
//! (one constraint) or from a pilot run of a model (every constraint).

use crate::pilot::{PilotArgs, design_json, per_constraint};
use crate::{Reported, family, messages};
use dae_runtime::{ConstraintSpec, DesignError, MAX_INDEX, MuSearch, Settings, optimise_mu};
use serde_json::json;
use std::path::PathBuf;

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
    let (index, beta, m) = (
        args.index.unwrap_or(0),
        args.beta.unwrap_or(0.0),
        args.m.unwrap_or(0.0),
    );
    messages::check((1..=MAX_INDEX).contains(&index), || {
        format!("--index must be in 1..={MAX_INDEX}, got {index}")
    })?;
    messages::all_positive("--eps", &args.eps)?;
    messages::at_least("--beta", beta, 0.0)?;
    messages::at_least("--m", m, 0.0)?;
    let spec = ConstraintSpec {
        r: index,
        eps,
        m,
        beta_abs: beta,
        layer: args.pilot_args.bound.layer(),
    };
    let gain = args.pilot_args.gains.choice();
    let d = optimise_mu(&spec, gain, &MuSearch::default()).map_err(|e| {
        let message = match e {
            // The flags are checked above: a quantity out of range now is one that the
            // design computed from them and that left the floating-point range.
            DesignError::NotPositive { .. } | DesignError::Negative { .. } => format!(
                "no finite gain for --beta {} and --m {} (--eps {}): the design leaves the \
                 range of floating-point numbers",
                messages::number(beta),
                messages::number(m),
                messages::number(eps)
            ),
            _ => messages::design_error(&e, None),
        };
        eprintln!("error: {message}");
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
    // Every value checked before the model is read and any pilot runs.
    messages::positive("--pilot", duration)?;
    messages::all_positive("--eps", &args.eps)?;
    messages::positive("--step", args.step)?;
    messages::at_least("--settle", args.settle, 0.0)?;
    messages::check(args.settle < duration, || {
        format!(
            "--settle ({} s) must be shorter than --pilot ({duration} s): the bounds are \
             collected after it",
            args.settle
        )
    })?;
    args.pilot_args.validate()?;
    let model = family::runnable(file, args.model.as_deref(), &[], None)?;
    let model = &*model;
    let m = model.n_constraints();
    if m == 0 {
        // An ODE is a DAE without constraints: nothing to design, and it runs as is.
        let note =
            "no constraints: there is no mu or gain to design (`daec run` integrates it as an ODE)";
        if args.json {
            println!(
                "{}",
                json!({"model": model.name(), "constraints": [], "mu": [], "gain": [], "note": note})
            );
        } else {
            println!("model {} has {note}", model.name());
        }
        return Ok(());
    }
    if !(duration.is_finite() && duration > 0.0) {
        eprintln!("error: --pilot {duration}: must be a finite number > 0");
        return Err(Reported);
    }
    if !(args.step.is_finite() && args.step > 0.0) {
        eprintln!("error: --step {}: must be a finite number > 0", args.step);
        return Err(Reported);
    }
    args.pilot_args
        .check_work(duration, args.step, crate::run::MAX_STEPS)?;
    let eps = per_constraint("--eps", &args.eps, m)?;
    let base = Settings::new(eps, vec![1.0; m], vec![1.0; m])
        .step(args.step)
        .t_end(duration)
        .settle(args.settle);
    let a = args.pilot_args.auto_design(model, &base, None, None)?;
    let out = design_json(model, &a);
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
