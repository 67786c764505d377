//! `daec run FILE ...`: simulate a model with DBSMC on the interpreter.

use crate::design::PilotArgs;
use crate::{Reported, source};
use dae_runtime::{
    AlphaChoice, ConstraintSpec, CsvSink, Decimate, ErrorSeries, Layout, Model, NoTrace, Policy,
    Reaching, Sample, Settings, SimError, Simulator, Sink, SlidingSeries, SolverChoice, Summary,
    Trace, YScale, pilot_run, pilot_specs, plot_errors, plot_periods, plot_sliding, t_min,
};
use serde_json::json;
use std::fs::File;
use std::io::{self, BufWriter};
use std::path::{Path, PathBuf};

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
    /// 200000 rows are written).
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

/// `values` expanded to one per constraint: one value applies to all.
pub(crate) fn per_constraint(what: &str, values: &[f64], m: usize) -> Result<Vec<f64>, Reported> {
    match values.len() {
        1 => Ok(vec![values[0]; m]),
        n if n == m => Ok(values.to_vec()),
        n => {
            eprintln!(
                "error: {what} has {n} values, the model has {m} constraints (give 1 or {m})"
            );
            Err(Reported)
        }
    }
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
    let model = source::interpreted(&args.file, args.model.as_deref())?;
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
        (None, k) => {
            let pa = &args.pilot_args;
            let mut fixed = None;
            if let Some(k) = k {
                let k = per_constraint("--gain", &k, m)?;
                if k.iter().any(|v| *v != k[0]) {
                    eprintln!("error: --mu auto takes one --gain value (or `auto`)");
                    return Err(Reported);
                }
                fixed = Some(k[0]);
            }
            let a = pa.auto_design(&model, &pilot_base, fixed)?;
            settings.mu = a.design.constraints.iter().map(|c| c.mu).collect();
            settings.gains = a.design.constraints.iter().map(|c| c.k).collect();
            if fixed.is_some() && settings.alpha == AlphaChoice::Cheap {
                warn_uncovered_beta(&model, &settings, &a);
            }
            Some(DesignInfo {
                json: crate::design::design_json(&model, &a),
                t_min: a.design.t_min,
            })
        }
        (Some(mu), None) => {
            settings.mu = per_constraint("--mu", &mu, m)?;
            Some(gains_for_mu(
                &args.pilot_args,
                &model,
                &pilot_base,
                &mut settings,
            )?)
        }
    };
    let summary = simulate(args, &model, settings.clone(), design.as_ref())?;
    print_summary(args, &model, &settings, &summary, design.as_ref());
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

/// `--mu LIST --gain auto`: one pilot at the given mu (exact alpha, the pilot gain), then
/// `k_i` from the gain choice at that mu and the measured bounds.
fn gains_for_mu(
    pa: &PilotArgs,
    model: &dyn Model,
    base: &Settings,
    settings: &mut Settings,
) -> Result<DesignInfo, Reported> {
    let mut pilot = base.clone().alpha(AlphaChoice::Exact);
    pilot.mu = settings.mu.clone();
    pilot.gains = match pa.pilot_gain {
        Some(k) => vec![k; settings.mu.len()],
        None => base
            .eps
            .iter()
            .map(|e| 2.0 * e / (100.0 * base.step))
            .collect(),
    };
    let fail = |e: &dyn std::fmt::Display| {
        eprintln!("error: pilot run of `{}`: {e}", model.name());
        Reported
    };
    let run = pilot_run(model, &pilot).map_err(|e| fail(&e))?;
    let specs = pilot_specs(model.indices(), &base.eps, &run.estimate, pa.bound.layer())
        .map_err(|e| fail(&e))?;
    let mut tm = Vec::new();
    settings.gains.clear();
    for (spec, &mu) in specs.iter().zip(&settings.mu) {
        let spec = ConstraintSpec {
            m: spec.m * pa.safety,
            beta_abs: spec.beta_abs * pa.safety,
            ..*spec
        };
        let k = pa.gains.choice().gain(&spec, mu).map_err(|e| fail(&e))?;
        settings.gains.push(k);
        tm.push(t_min(&spec, mu, k).map_err(|e| fail(&e))?);
    }
    let t = tm.iter().copied().fold(f64::INFINITY, f64::min);
    Ok(DesignInfo {
        json: json!({
            "mu": settings.mu, "gain": settings.gains, "t_min": tm, "t_min_design": t,
            "beta_abs": run.estimate.beta_abs, "m": run.estimate.m,
        }),
        t_min: t,
    })
}

/// A CSV stream and/or an in-memory trace for the charts.
struct RunSink {
    csv: Option<Decimate<CsvSink<BufWriter<File>>>>,
    trace: Option<Decimate<Trace>>,
}

impl Sink for RunSink {
    fn begin(&mut self, layout: &Layout) -> io::Result<()> {
        if let Some(c) = &mut self.csv {
            c.begin(layout)?;
        }
        if let Some(t) = &mut self.trace {
            t.begin(layout)?;
        }
        Ok(())
    }
    fn wants(&self, step: u64, t: f64) -> bool {
        self.csv.as_ref().is_some_and(|c| c.wants(step, t))
            || self.trace.as_ref().is_some_and(|c| c.wants(step, t))
    }
    fn record(&mut self, s: &Sample<'_>) -> io::Result<()> {
        if let Some(c) = &mut self.csv {
            if s.last || s.step == 0 || c.wants(s.step, s.t) {
                c.record(s)?;
            }
        }
        if let Some(c) = &mut self.trace {
            if s.last || s.step == 0 || c.wants(s.step, s.t) {
                c.record(s)?;
            }
        }
        Ok(())
    }
    fn update(&mut self, t: f64) -> io::Result<()> {
        if let Some(c) = &mut self.csv {
            c.update(t)?;
        }
        if let Some(c) = &mut self.trace {
            c.update(t)?;
        }
        Ok(())
    }
    fn finish(&mut self) -> io::Result<()> {
        if let Some(c) = &mut self.csv {
            c.finish()?;
        }
        Ok(())
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
    let every = steps.div_ceil(MAX_ROWS).max(1);
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
    let mut sink = RunSink { csv, trace };
    let mut sim = Simulator::new(model, settings.clone()).map_err(|e| {
        eprintln!("error: {e}");
        Reported
    })?;
    let outcome = if sink.csv.is_none() && sink.trace.is_none() {
        sim.run(&mut NoTrace)
    } else {
        sim.run(&mut sink)
    };
    let summary = match outcome {
        Ok(s) => s,
        Err(e) => {
            report_failure(model, &e);
            if let Some(c) = sink.csv.take() {
                // The rows up to the failure stay in the file.
                if let Err(e) = io::Write::flush(&mut c.into_inner().into_inner()) {
                    eprintln!("error: writing the CSV: {e}");
                }
            }
            return Err(Reported);
        }
    };
    if let (Some(dir), Some(trace)) = (&args.plot, &sink.trace) {
        write_charts(
            dir,
            model,
            &settings,
            trace.inner(),
            design.map(|d| d.t_min),
        )?;
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

fn write_charts(
    dir: &Path,
    model: &dyn Model,
    settings: &Settings,
    trace: &Trace,
    t_min: Option<f64>,
) -> Result<(), Reported> {
    let fail = |e: &dyn std::fmt::Display| {
        eprintln!("error: charts in `{}`: {e}", dir.display());
        Reported
    };
    std::fs::create_dir_all(dir).map_err(|e| fail(&e))?;
    let m = model.n_constraints();
    let t = trace.times();
    let col = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { (0..t.len()).map(f).collect() };
    let s: Vec<Vec<f64>> = (0..m).map(|i| col(&|k| trace.s(k)[i])).collect();
    let w: Vec<Vec<f64>> = (0..m).map(|i| col(&|k| trace.w(k)[i])).collect();
    let sliding: Vec<SlidingSeries<'_>> = (0..m)
        .map(|i| SlidingSeries {
            name: model.constraint_name(i),
            s: &s[i],
            eps: settings.eps[i],
        })
        .collect();
    let errors: Vec<ErrorSeries<'_>> = (0..m)
        .map(|i| ErrorSeries {
            name: model.constraint_name(i),
            w: &w[i],
        })
        .collect();
    let name = model.name();
    let sliding_path = dir.join("sliding.svg");
    plot_sliding(
        &sliding_path,
        &format!("{name}: sliding variables"),
        t,
        &sliding,
    )
    .map_err(|e| fail(&e))?;
    let errors_path = dir.join("errors.svg");
    plot_errors(
        &errors_path,
        &format!("{name}: constraint errors"),
        t,
        &errors,
        YScale::Log,
    )
    .map_err(|e| fail(&e))?;
    let periods_path = dir.join("periods.svg");
    if trace.update_times().len() >= 2 {
        plot_periods(
            &periods_path,
            &format!("{name}: update periods"),
            trace.update_times(),
            t_min,
        )
        .map_err(|e| fail(&e))?;
    }
    Ok(())
}

fn print_summary(
    args: &Args,
    model: &dyn Model,
    settings: &Settings,
    s: &Summary,
    design: Option<&DesignInfo>,
) {
    if args.json {
        let v = json!({
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
        println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
        return;
    }
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.6}"));
    println!(
        "model {} to t = {}: {} steps, {} updates ({} while reaching)",
        s.model, s.t_end, s.steps, s.updates, s.reaching_updates
    );
    println!(
        "  mu = {:?}, gains = {:?}, eps = {:?}",
        settings.mu, settings.gains, settings.eps
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
    for (i, c) in s.constraints.iter().enumerate() {
        match (&s.max_abs_s, &s.max_abs_w) {
            (Some(ms), Some(mw)) => {
                println!("  {c}: max |s| = {:.6}, max |w| = {:.6}", ms[i], mw[i])
            }
            _ => println!(
                "  {c}: not reached; largest |s| seen {:.6}, |w| {:.6}",
                s.seen_max_abs_s[i], s.seen_max_abs_w[i]
            ),
        }
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
