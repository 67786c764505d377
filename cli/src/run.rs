//! `daec run FILE ...`: simulate a model with DBSMC on the interpreter.

use crate::Reported;
use crate::bounded::values_text;
use crate::pilot::{PilotArgs, design_json, per_constraint};
use dae_runtime::{
    AlphaChoice, CsvSink, Decimate, Model, Policy, Reaching, Settings, SimError, Simulator,
    SolverChoice, Summary, Tee, Trace, plot_run,
};
use serde_json::json;
use std::fs::File;
use std::io::{self, BufWriter};
use std::path::PathBuf;

/// Most rows written to `--csv` (and kept for `--plot`) before steps are decimated.
const MAX_ROWS: u64 = 200_000;

/// Arguments of `daec run`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.dae` file.
    file: PathBuf,
    /// The model to run when the file holds several.
    #[arg(long)]
    model: Option<String>,
    /// A size or a scalar parameter of the model: `--set N=1000 --set m_end=10`
    /// (repeatable; for a version-1 model, its parameters).
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = crate::family::parse_assignment)]
    set: Vec<(String, f64)>,
    /// The sets and maps of a family model given at construction (`set P;`,
    /// `map a[l in L] -> P;`): a file of `set NAME SIZE` lines and `edges SET: MAP ...`
    /// blocks with one line per element (docs/language.md, "Topology files").
    #[arg(long, value_name = "FILE")]
    topology: Option<PathBuf>,
    /// End time (seconds; the run starts at 0).
    #[arg(long)]
    t_end: f64,
    /// Layer half-widths eps: one value for every constraint, or one per constraint.
    #[arg(long, value_delimiter = ',', required = true)]
    eps: Vec<f64>,
    /// Surface time constants mu (like --eps), or `auto` (design from pilot runs).
    #[arg(long)]
    mu: String,
    /// Gains k (like --eps), or `auto` (from the design's gain choice, --gains).
    #[arg(long)]
    gain: String,
    /// Integration step h (RK4).
    #[arg(long, default_value_t = 1e-4)]
    step: f64,
    /// Update policy: `monitor`, `fixed:PERIOD` or `spsm`.
    #[arg(long, default_value = "monitor")]
    policy: String,
    /// Reaching phase rule.
    #[arg(long, value_enum, default_value = "attract")]
    reaching: ReachingArg,
    /// alpha_hat: the cheap one, or the exact alpha.
    #[arg(long, value_enum, default_value = "cheap")]
    alpha: AlphaArg,
    /// Statistics start this many seconds after t = 0, and never before the end of the
    /// reaching phase [default: at the end of the reaching phase].
    #[arg(long, default_value_t = 0.0)]
    settle: f64,
    /// Fail if the reaching phase takes longer than this many seconds.
    #[arg(long)]
    reaching_limit: Option<f64>,
    /// Duration of the pilot runs of `--mu auto` / `--gain auto` [default: --t-end].
    #[arg(long)]
    pilot: Option<f64>,
    #[command(flatten)]
    pilot_args: PilotArgs,
    /// Stream the trace to this CSV file (every step, or every k-th step so that at most
    /// 200000 rows and 10^7 values are written).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Write the charts (sliding.svg, periods.svg, errors.svg) into this folder.
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    /// Solver of J_s at the control updates: `auto` (exact: dense up to 16 constraints,
    /// `tree` when the Jacobian pattern's graph is a forest, `sparse` otherwise),
    /// `dense`, `sparse`, `tree`, or an approximate inverse checked by (T 3.22):
    /// `jacobi`, `gauss-seidel:K` (K sweeps), `cg:K` (K iterations), `ilu0`.
    #[arg(long, default_value = "auto", value_parser = parse_solver)]
    solver: SolverChoice,
}

fn parse_solver(text: &str) -> Result<SolverChoice, String> {
    text.parse()
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum ReachingArg {
    /// Attracting surfaces (the thesis example).
    Attract,
    /// Contracting boundary layers.
    Contract,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum AlphaArg {
    /// alpha_hat without the mu^(r-1) beta term (covered by the gain).
    Cheap,
    /// The exact alpha (one beta evaluation per update).
    Exact,
}

/// `auto` or a comma-separated list of numbers.
fn auto_or_list(what: &str, text: &str) -> Result<Option<Vec<f64>>, Reported> {
    if text.trim() == "auto" {
        return Ok(None);
    }
    text.split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
        .map_err(|e| {
            eprintln!(
                "error: {what} `{text}`: expected `auto` or numbers separated by commas ({e})"
            );
            Reported
        })
}

fn parse_policy(text: &str) -> Result<Policy, Reported> {
    match text {
        "monitor" => Ok(Policy::Monitor),
        "spsm" => Ok(Policy::Spsm),
        _ => match text.strip_prefix("fixed:").map(str::parse::<f64>) {
            Some(Ok(p)) => Ok(Policy::Fixed(p)),
            _ => {
                eprintln!("error: --policy `{text}`: expected `monitor`, `fixed:PERIOD` or `spsm`");
                Err(Reported)
            }
        },
    }
}

/// What the design step found, for the summary and the charts.
struct DesignInfo {
    json: serde_json::Value,
    t_min: f64,
}

pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    let model = crate::family::runnable(
        &args.file,
        args.model.as_deref(),
        &args.set,
        args.topology.as_deref(),
    )?;
    let model = &*model;
    let m = model.n_constraints();
    let eps = per_constraint("--eps", &args.eps, m)?;
    let policy = parse_policy(&args.policy)?;
    let mut settings = Settings::new(eps.clone(), vec![1.0; m], vec![1.0; m])
        .step(args.step)
        .t_end(args.t_end)
        .settle(args.settle)
        .solver(args.solver)
        .policy(policy)
        .reaching(match args.reaching {
            ReachingArg::Attract => Reaching::AttractingSurfaces,
            ReachingArg::Contract => Reaching::ContractingLayers,
        })
        .alpha(match args.alpha {
            AlphaArg::Cheap => AlphaChoice::Cheap,
            AlphaArg::Exact => AlphaChoice::Exact,
        });
    if let Some(l) = args.reaching_limit {
        settings = settings.reaching_limit(l);
    }
    let mu = auto_or_list("--mu", &args.mu)?;
    let gain = auto_or_list("--gain", &args.gain)?;
    let pilot_base = settings
        .clone()
        .t_end(args.pilot.unwrap_or(args.t_end))
        .policy(Policy::Monitor)
        .alpha(AlphaChoice::Cheap);
    let design = match (mu, gain) {
        (Some(mu), Some(k)) => {
            settings.mu = per_constraint("--mu", &mu, m)?;
            settings.gains = per_constraint("--gain", &k, m)?;
            None
        }
        // At least one of them `auto`: the pilots design it; given mu are kept, a given
        // gain (one value for all) is used throughout.
        (mu, k) => {
            let mu = mu.map(|mu| per_constraint("--mu", &mu, m)).transpose()?;
            let fixed = match k {
                None => None,
                Some(k) => {
                    let k = per_constraint("--gain", &k, m)?;
                    if k.iter().any(|v| *v != k[0]) {
                        eprintln!("error: --mu auto takes one --gain value (or `auto`)");
                        return Err(Reported);
                    }
                    Some(k[0])
                }
            };
            let a = args.pilot_args.auto_design(model, &pilot_base, mu, fixed)?;
            settings.mu = a.design.constraints.iter().map(|c| c.mu).collect();
            settings.gains = a.design.constraints.iter().map(|c| c.k).collect();
            if fixed.is_some() && settings.alpha == AlphaChoice::Cheap {
                warn_uncovered_beta(model, &settings, &a);
            }
            Some(DesignInfo {
                json: design_json(model, &a),
                t_min: a.design.t_min,
            })
        }
    };
    let summary = simulate(args, model, settings.clone(), design.as_ref())?;
    print_summary(args, model, &settings, &summary, design.as_ref());
    Ok(())
}

/// A fixed gain with the cheap alpha_hat must still cover the neglected `mu^(r-1) |beta|`
/// (T 3.17); say so when the pilot bounds show that it does not.
fn warn_uncovered_beta(model: &dyn Model, settings: &Settings, a: &dae_runtime::AutoDesign) {
    for (i, &r) in model.indices().iter().enumerate() {
        let beta = a
            .passes
            .iter()
            .map(|p| p.pilot.estimate.beta_abs[i])
            .fold(0.0, f64::max);
        let need = settings.mu[i].powi(r as i32 - 1) * beta;
        if settings.gains[i] <= need {
            eprintln!(
                "warning: gain {} of `{}` does not cover mu^(r-1) |beta| = {need:.4} neglected by the cheap alpha_hat; use --alpha exact or a larger gain",
                settings.gains[i],
                model.constraint_name(i)
            );
        }
    }
}

fn simulate(
    args: &Args,
    model: &dyn Model,
    settings: Settings,
    design: Option<&DesignInfo>,
) -> Result<Summary, Reported> {
    let steps = ((settings.t_end - settings.t_start) / settings.step)
        .ceil()
        .max(1.0) as u64;
    let every = crate::bounded::trace_every(model, steps, MAX_ROWS);
    let csv = match &args.csv {
        None => None,
        Some(path) => match File::create(path) {
            Ok(f) => Some(Decimate::new(CsvSink::new(BufWriter::new(f))).every(every)),
            Err(e) => {
                eprintln!("error: cannot create `{}`: {e}", path.display());
                return Err(Reported);
            }
        },
    };
    let trace = args
        .plot
        .as_ref()
        .map(|_| Decimate::new(Trace::new()).every(every));
    // Each output keeps its own decimation (both are `None` without --csv and --plot).
    let mut sink = Tee(csv, trace);
    let mut sim = Simulator::new(model, settings.clone()).map_err(|e| {
        eprintln!("error: {e}");
        Reported
    })?;
    let summary = match sim.run(&mut sink) {
        Ok(s) => s,
        Err(e) => {
            report_failure(model, &e);
            if let Some(c) = sink.0.take() {
                // The rows up to the failure stay in the file.
                if let Err(e) = io::Write::flush(&mut c.into_inner().into_inner()) {
                    eprintln!("error: writing the CSV: {e}");
                }
            }
            return Err(Reported);
        }
    };
    if let (Some(dir), Some(trace)) = (&args.plot, &sink.1) {
        let t_min = design.map(|d| d.t_min);
        plot_run(dir, model.name(), trace.inner(), &settings.eps, t_min).map_err(|e| {
            eprintln!("error: charts in `{}`: {e}", dir.display());
            Reported
        })?;
    }
    Ok(summary)
}

fn report_failure(model: &dyn Model, e: &SimError) {
    eprintln!("error: simulation of `{}` failed: {e}", model.name());
    let hint = match e {
        SimError::NonFinite { .. } => {
            "the motion diverged: try a smaller --step, smaller gains or a larger --mu"
        }
        SimError::SingularJacobian { .. } => {
            "J_Omega lost rank here: the algebraic unknowns no longer determine these constraints"
        }
        SimError::ReachingTimeout { .. } => "increase the gains or the layers",
        SimError::SolverFailed { .. } => "choose another --solver (dense always applies)",
        _ => "",
    };
    if !hint.is_empty() {
        eprintln!("  hint: {hint}");
    }
}

fn print_summary(
    args: &Args,
    model: &dyn Model,
    settings: &Settings,
    s: &Summary,
    design: Option<&DesignInfo>,
) {
    if args.json {
        let mut v = json!({
            "model": s.model,
            "constraints": s.constraints,
            "eps": settings.eps,
            "mu": settings.mu,
            "gain": settings.gains,
            "design": design.map(|d| d.json.clone()),
            "t_end": s.t_end,
            "steps": s.steps,
            "updates": s.updates,
            "reaching_updates": s.reaching_updates,
            "reach_time": s.reaching_time,
            "stats_from": s.stats_from,
            "period_min": s.min_period,
            "period_avg": s.mean_period,
            "max_abs_s": s.max_abs_s,
            "max_abs_w": s.max_abs_w,
            "robustness_violations": s.robustness_violations,
            "solver": {
                "name": s.solver.name,
                "choice": s.solver.choice.to_string(),
                "factorisations": s.solver.factorisations,
                "solves": s.solver.solves,
                "iterations": s.solver.iterations,
                "robustness_failures": s.solver.robustness_failures,
            },
            "states": (0..model.n_states()).map(|i| model.state_name(i)).collect::<Vec<_>>(),
            "x_final": s.x,
            "z_final": s.z,
            "z_eq_final": s.z_eq,
            "wall_seconds": s.wall_time,
        });
        crate::bounded::summarise(&mut v, model);
        println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
        return;
    }
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.6}"));
    println!(
        "model {} to t = {}: {} steps, {} updates ({} while reaching)",
        s.model, s.t_end, s.steps, s.updates, s.reaching_updates
    );
    println!(
        "  mu = {}, gains = {}, eps = {}",
        values_text(&settings.mu),
        values_text(&settings.gains),
        values_text(&settings.eps)
    );
    if let Some(d) = design {
        println!("  design T_min = {}", d.t_min);
    }
    println!(
        "  reaching time {}, statistics from {}",
        opt(s.reaching_time),
        opt(s.stats_from)
    );
    println!(
        "  update period min {}, average {}",
        opt(s.min_period),
        opt(s.mean_period)
    );
    let listed = crate::bounded::listed_constraints(&s.max_abs_s, &settings.eps);
    if listed.len() < s.constraints.len() {
        println!(
            "  {} constraints; the {} with the largest max |s| / eps:",
            s.constraints.len(),
            listed.len()
        );
    }
    for (i, c) in listed.iter().map(|&i| (i, &s.constraints[i])) {
        println!(
            "  {c}: max |s| = {:.6}, max |w| = {:.6}",
            s.max_abs_s[i], s.max_abs_w[i]
        );
    }
    println!(
        "  solver {}: {} factorisations, {} solves, {} iterations, {} robustness failures",
        s.solver.name,
        s.solver.factorisations,
        s.solver.solves,
        s.solver.iterations,
        s.robustness_violations
            .map_or("unchecked".to_string(), |v| v.to_string())
    );
    println!("  wall time {:.3} s", s.wall_time);
}
