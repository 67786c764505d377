//! `daec design`: the gain and surface design of docs/method.md section 5, from given bounds
//! (one constraint) or from a pilot run of a model (every constraint).

use crate::pilot::{PilotArgs, design_json, per_constraint};
use crate::{Reported, family, messages};
use dae_runtime::{
    Settings, design::ConstraintSpec, design::DesignError, design::MAX_INDEX, design::MuSearch,
    design::optimise_mu, settings::Integrator,
};
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
    /// A size or a scalar parameter of the model: `--set N=1000 --set m_end=10`
    /// (repeatable; for a version-1 model, its parameters).
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = crate::family::parse_assignment)]
    set: Vec<(String, f64)>,
    /// The sets and maps of a family model given at construction (like `daec run
    /// --topology`).
    #[arg(long, value_name = "FILE")]
    topology: Option<PathBuf>,
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
    /// A fixed integration step for the pilot runs (RK4, updates noticed at step ends,
    /// the thesis's procedure) [default: error-controlled steps (Dormand-Prince) with
    /// the crossings located, as `daec run`].
    #[arg(long)]
    step: Option<f64>,
    /// Seconds after the reaching phase before the pilot's bounds are collected.
    #[arg(long, default_value_t = 0.0)]
    settle: f64,
    #[command(flatten)]
    pilot_args: PilotArgs,
    /// Print JSON.
    #[arg(long)]
    pub(crate) json: bool,
}

pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    match &args.file {
        None => from_bounds(args),
        Some(file) => from_pilot(args, file),
    }
}

fn from_bounds(args: &Args) -> Result<(), Reported> {
    if !args.set.is_empty() || args.topology.is_some() {
        error!("--set and --topology are for a model file");
        return Err(Reported);
    }
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
        error!(
            "without a model file, `daec design` needs {}",
            missing.join(", ")
        );
        return Err(Reported);
    }
    let [eps] = args.eps[..] else {
        error!("without a model file, give one --eps value");
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
        error!("{message}");
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
        error!("with a model file, `daec design` needs --pilot SECONDS");
        return Err(Reported);
    };
    if args.index.is_some() || args.beta.is_some() || args.m.is_some() {
        error!("--index, --beta and --m are for a single constraint without a file");
        return Err(Reported);
    }
    // Every value checked before the model is read and any pilot runs.
    messages::positive("--pilot", duration)?;
    messages::all_positive("--eps", &args.eps)?;
    if let Some(h) = args.step {
        messages::positive("--step", h)?;
    }
    messages::at_least("--settle", args.settle, 0.0)?;
    messages::check(args.settle < duration, || {
        format!(
            "--settle ({} s) must be shorter than --pilot ({duration} s): the bounds are \
             collected after it",
            args.settle
        )
    })?;
    args.pilot_args.validate()?;
    let model = family::runnable(
        file,
        args.model.as_deref(),
        &args.set,
        args.topology.as_deref(),
    )?;
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
        error!("--pilot {duration}: must be a finite number > 0");
        return Err(Reported);
    }
    // The default pilot gain is 2 eps / (100 h) with this h (1e-4 for error control).
    let step = args.step.unwrap_or(1e-4);
    args.pilot_args
        .check_work(duration, args.step, crate::run::MAX_STEPS)?;
    let eps = per_constraint("--eps", &args.eps, m)?;
    let base = Settings::new(eps, vec![1.0; m], vec![1.0; m])
        .step(step)
        .integrator(if args.step.is_some() {
            Integrator::Rk4
        } else {
            Integrator::DormandPrince
        })
        .t_end(duration)
        .settle(args.settle);
    let a = args
        .pilot_args
        .auto_design(model, &base, None, None, None)?;
    let mut out = design_json(model, &a);
    if args.json {
        crate::bounded::summarise(&mut out, model);
        println!("{out}");
    } else {
        println!("model {}", model.name());
        // The constraints that set the period first: all of them for a small model, the
        // ones with the shortest T_i^min for a large one.
        let listed = dae_runtime::summary::listed_by(m, |i| -a.design.constraints[i].t_min);
        if listed.len() < m {
            println!(
                "  (the {} of {m} constraints with the shortest t_min; --json for all)",
                listed.len()
            );
        }
        for i in listed {
            let c = &a.design.constraints[i];
            println!(
                "  {}: mu = {}, gain = {}, t_min = {}  (|beta| <= {}, M = {}){}",
                model.constraint_name(i),
                c.mu,
                c.k,
                c.t_min,
                out["beta_abs"][i],
                out["m"][i],
                if a.design.quiet.binary_search(&i).is_ok() {
                    "  quiet"
                } else {
                    ""
                }
            );
        }
        if !a.design.quiet.is_empty() {
            println!(
                "  {} quiet constraint(s) (little drift in the pilot: no best mu; given the \
                 smallest mu that keeps T_min)",
                a.design.quiet.len()
            );
        }
        println!("  T_min = {}", a.design.t_min);
    }
    Ok(())
}
