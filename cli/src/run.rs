//! `daec run FILE ...`: simulate a model with DBSMC on the interpreter.
//!
//! With only `--t-end` and `--eps`, everything else is chosen: `mu` and the gains by
//! the automatic design (pilot runs), the step by error control (Dormand-Prince 5(4),
//! tolerance from the layers), crossings located inside the steps. The summary says
//! what was chosen and whether the layer held; the exit status says it too
//! ([`Outcome`]).

use crate::Reported;
use crate::bounded::{listed_constraints, triggered_text, values_text};
use crate::pilot::{PilotArgs, design_json, per_constraint};
use dae_runtime::{
    AlphaChoice, Crossing, CsvSink, Decimate, Integrator, Model, NEAR_SINGULAR, Policy, Quantity,
    Reaching, Settings, SimError, Simulator, SolverChoice, Summary, Tee, Trace, plot_run,
};
use serde_json::json;
use std::fs::File;
use std::io::{self, BufWriter};
use std::path::{Path, PathBuf};

/// Most rows written to `--csv` (and kept for `--plot`) before steps are decimated.
const MAX_ROWS: u64 = 200_000;

/// Most fixed steps a run (or all its pilot runs together) may take. The interpreted
/// 3-D double pendulum takes about 2.5 us per RK4 step (README, Performance), so this
/// is some four minutes of work; beyond it `daec run` refuses up front and says why.
pub(crate) const MAX_STEPS: f64 = 1e8;

/// How a run ended, and the exit status that says it (README, "What a run reports").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Outcome {
    /// The layers were reached and held to the end (exit status 0).
    Held,
    /// A layer was left after reaching (exit status 3).
    BoundLost,
    /// The reaching phase did not finish by `--t-end` (exit status 4).
    NotReached,
}

impl Outcome {
    /// The process exit status of the outcome.
    pub(crate) fn code(self) -> u8 {
        match self {
            Outcome::Held => 0,
            Outcome::BoundLost => 3,
            Outcome::NotReached => 4,
        }
    }
}

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
    /// Surface time constants mu (like --eps), or `auto` (designed from pilot runs).
    #[arg(long, default_value = "auto")]
    mu: String,
    /// Gains k (like --eps), or `auto` (from the design's gain choice, --gains).
    #[arg(long, default_value = "auto")]
    gain: String,
    /// A fixed integration step (RK4, or --integrator euler), the longest taken (steps are
    /// shortened at crossings and where their error in s would exceed 1e-3 of eps)
    /// [default: steps chosen by error control, see --integrator and --tol].
    #[arg(long)]
    step: Option<f64>,
    /// Integrator: `dopri5` (Dormand-Prince 5(4), error-controlled; the default without
    /// --step), `bs3` (Bogacki-Shampine 3(2), error-controlled), `rk4` (the default with
    /// --step) or `euler`; the fixed-step ones use --step (1e-4 if not given).
    #[arg(long, value_enum)]
    integrator: Option<IntegratorArg>,
    /// Tolerance of the error-controlled steps (rtol = atol) [default: 0.01 times the
    /// smallest eps].
    #[arg(long)]
    tol: Option<f64>,
    /// Longest error-controlled step [default: unlimited; the samples of --csv and
    /// --plot are the steps' ends, about one per control interval, so give this for a
    /// denser trace].
    #[arg(long)]
    max_step: Option<f64>,
    /// How the update moment is found: `located` inside the step (the bound holds for
    /// any step), or `step-end` (the thesis's rule, which overshoots by up to one step).
    #[arg(long, value_enum, default_value = "located")]
    crossing: CrossingArg,
    /// Update policy: `monitor`, `fixed:PERIOD` or `spsm` (SPSM takes a fixed step,
    /// --step or 1e-4).
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
    /// Duration of the pilot runs of the automatic design [default: --t-end].
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
    /// Let the gains follow the drift of s' measured between updates, with this safety
    /// factor (at least the given gains, up to the gain that sweeps the layer against
    /// the drift; Settings::follow_drift).
    #[arg(long, value_name = "SAFETY")]
    follow_drift: Option<f64>,
    /// With --follow-drift: raise a gain only as far as its grazing returns need to stay
    /// this many seconds apart (Settings::graze).
    #[arg(long, value_name = "MIN_RETURN")]
    graze: Option<f64>,
    /// Let v ramp between updates at the rate that cancels the drift of s' found at each
    /// update, instead of holding it (Settings::ramp_against_drift).
    #[arg(long)]
    ramp: bool,
}

fn parse_solver(text: &str) -> Result<SolverChoice, String> {
    text.parse()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum IntegratorArg {
    /// Dormand-Prince 5(4) with error control.
    Dopri5,
    /// Bogacki-Shampine 3(2) with error control.
    Bs3,
    /// Classical Runge-Kutta with the fixed --step.
    Rk4,
    /// Explicit Euler with the fixed --step.
    Euler,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum CrossingArg {
    /// Located inside the step (the step is cut there).
    Located,
    /// Noticed at the end of the step (the thesis's rule).
    StepEnd,
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
            Some(Ok(p)) if p > 0.0 && p.is_finite() => Ok(Policy::Fixed(p)),
            Some(Ok(p)) => {
                eprintln!("error: --policy fixed:{p}: the period must be finite and > 0");
                Err(Reported)
            }
            _ => {
                eprintln!("error: --policy `{text}`: expected `monitor`, `fixed:PERIOD` or `spsm`");
                Err(Reported)
            }
        },
    }
}

/// A user-given number that must be finite and positive (or non-negative).
fn check_number(flag: &str, value: f64, zero_ok: bool) -> Result<(), Reported> {
    let ok = value.is_finite() && (value > 0.0 || (zero_ok && value == 0.0));
    if ok {
        return Ok(());
    }
    let need = if zero_ok { ">= 0" } else { "> 0" };
    eprintln!("error: {flag} {value}: must be a finite number {need}");
    Err(Reported)
}

/// The chosen integration: the integrator, its fixed step (if any) and whether each
/// was given or chosen.
struct Integration {
    integrator: Integrator,
    step: f64,
    fixed: bool,
    chosen: bool,
}

fn integration(args: &Args, policy: Policy) -> Integration {
    let choice = match (args.integrator, args.step, policy) {
        (Some(i), _, _) => i,
        (None, Some(_), _) | (None, None, Policy::Spsm) => IntegratorArg::Rk4,
        (None, None, _) => IntegratorArg::Dopri5,
    };
    let integrator = match choice {
        IntegratorArg::Dopri5 => Integrator::DormandPrince,
        IntegratorArg::Bs3 => Integrator::BogackiShampine,
        IntegratorArg::Rk4 => Integrator::Rk4,
        IntegratorArg::Euler => Integrator::Euler,
    };
    Integration {
        integrator,
        step: args.step.unwrap_or(1e-4),
        fixed: !integrator.is_adaptive(),
        chosen: args.integrator.is_none() && args.step.is_none(),
    }
}

/// What the design step found, for the summary and the charts.
struct DesignInfo {
    json: serde_json::Value,
    t_min: f64,
}

/// The settings' field names as the flags a user wrote.
fn flag(field: &str) -> &str {
    match field {
        "eps" => "--eps",
        "mu" => "--mu",
        "gains" => "--gain",
        "step" => "--step",
        "t_end" => "--t-end",
        "settle" => "--settle",
        "reaching_limit" => "--reaching-limit",
        "policy" => "--policy",
        "tolerance" => "--tol",
        "max_step" => "--max-step",
        "crossing" => "--crossing",
        "integrator" => "--integrator",
        "solver" => "--solver",
        "follow_drift" => "--follow-drift",
        "graze" => "--graze",
        "ramp" => "--ramp",
        other => other,
    }
}

/// Check everything the user gave before any work: numbers, the outputs, and the
/// amount of work of fixed steps.
fn check_args(args: &Args, integration: &Integration, m: usize) -> Result<(), Reported> {
    check_number("--t-end", args.t_end, false)?;
    for &e in &args.eps {
        check_number("--eps", e, false)?;
    }
    check_number("--settle", args.settle, true)?;
    for (flag, v) in [
        ("--step", args.step),
        ("--tol", args.tol),
        ("--max-step", args.max_step),
        ("--reaching-limit", args.reaching_limit),
        ("--pilot", args.pilot),
        ("--follow-drift", args.follow_drift),
        ("--graze", args.graze),
    ] {
        if let Some(v) = v {
            check_number(flag, v, false)?;
        }
    }
    if args.graze.is_some() && args.follow_drift.is_none() {
        eprintln!("error: --graze limits the gains that follow the drift: give --follow-drift too");
        return Err(Reported);
    }
    if integration.fixed && (args.tol.is_some() || args.max_step.is_some()) {
        eprintln!(
            "error: --tol and --max-step are for the error-controlled steps (--integrator dopri5 or bs3), not a fixed --step"
        );
        return Err(Reported);
    }
    if !integration.fixed && args.step.is_some() {
        eprintln!(
            "error: --step is a fixed step; the error-controlled integrators take --tol and --max-step"
        );
        return Err(Reported);
    }
    if integration.fixed {
        let steps = args.t_end / integration.step;
        if steps > MAX_STEPS {
            eprintln!(
                "error: --t-end {} with --step {:e} is {steps:.3e} steps, more than the {MAX_STEPS:e} this command takes (some minutes of work)",
                args.t_end, integration.step
            );
            eprintln!(
                "  hint: leave out --step (the step is then chosen by error control), or give a larger one"
            );
            return Err(Reported);
        }
    }
    if m > 0 && (args.mu.trim() == "auto" || args.gain.trim() == "auto") {
        args.pilot_args.check_work(
            args.pilot.unwrap_or(args.t_end),
            integration.fixed.then_some(integration.step),
            MAX_STEPS,
        )?;
    }
    check_outputs(args.csv.as_deref(), args.plot.as_deref())
}

/// The output files and folders are created (and the folder written to) before the run,
/// so that a run is never lost to an output that cannot be written.
fn check_outputs(csv: Option<&Path>, plot: Option<&Path>) -> Result<(), Reported> {
    if let Some(dir) = plot {
        let probe = dir.join(".daec-write-test");
        let written = std::fs::create_dir_all(dir).and_then(|()| std::fs::write(&probe, b""));
        let _ = std::fs::remove_file(&probe);
        if let Err(e) = written {
            eprintln!("error: --plot `{}` cannot be written: {e}", dir.display());
            return Err(Reported);
        }
    }
    if let Some(path) = csv {
        // Created again (truncated) by the run; this only finds the error early.
        if let Err(e) = File::create(path) {
            eprintln!("error: cannot create `{}`: {e}", path.display());
            return Err(Reported);
        }
    }
    Ok(())
}

pub(crate) fn run(args: &Args) -> Result<Outcome, Reported> {
    let boxed = crate::family::runnable(
        &args.file,
        args.model.as_deref(),
        &args.set,
        args.topology.as_deref(),
    )?;
    let model: &dyn Model = &*boxed;
    let m = model.n_constraints();
    let policy = parse_policy(&args.policy)?;
    let integ = integration(args, policy);
    check_args(args, &integ, m)?;
    let eps = per_constraint("--eps", &args.eps, m)?;
    let crossing = match args.crossing {
        CrossingArg::Located => Crossing::default(),
        CrossingArg::StepEnd => Crossing::StepEnd,
    };
    let mut settings = Settings::new(eps.clone(), vec![1.0; m], vec![1.0; m])
        .step(integ.step)
        .integrator(integ.integrator)
        .crossing(crossing)
        .max_steps(MAX_STEPS as u64)
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
    if let Some(tol) = args.tol {
        settings = settings.tolerance(tol, tol);
    }
    if let Some(h) = args.max_step {
        settings = settings.max_step(h);
    }
    let mu = auto_or_list("--mu", &args.mu)?;
    let gain = auto_or_list("--gain", &args.gain)?;
    for (what, list) in [("--mu", &mu), ("--gain", &gain)] {
        for &v in list.iter().flatten() {
            check_number(what, v, false)?;
        }
    }
    // The pilots run as the run (error-controlled, or RK4 at a given --step), see
    // PilotArgs::auto_design.
    let pilot_base = settings
        .clone()
        .t_end(args.pilot.unwrap_or(args.t_end))
        .policy(Policy::Monitor)
        .alpha(AlphaChoice::Cheap);
    let design = match (mu, gain) {
        _ if m == 0 => None,
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
                        eprintln!("error: with --mu auto, give one --gain value (or `auto`)");
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
    // After the design: its pilots run with the gains they design.
    if let Some(safety) = args.follow_drift {
        settings = settings.follow_drift(safety);
    }
    if let Some(t) = args.graze {
        settings = settings.graze(t);
    }
    if args.ramp {
        settings = settings.ramp_against_drift();
    }
    let summary = simulate(args, model, settings.clone(), design.as_ref())?;
    let outcome = if !summary.bound_held() && summary.reaching_time.is_none() {
        Outcome::NotReached
    } else if summary.bound_loss.is_some() {
        Outcome::BoundLost
    } else {
        Outcome::Held
    };
    let report = Report {
        args,
        model,
        settings: &settings,
        summary: &summary,
        design: design.as_ref(),
        integration: &integ,
        outcome,
    };
    report.print();
    Ok(outcome)
}

/// A fixed gain with the cheap alpha_hat must still cover the neglected `mu^(r-1) |beta|`
/// (T 3.17); say so when the pilot bounds show that it does not.
fn warn_uncovered_beta(model: &dyn Model, settings: &Settings, a: &dae_runtime::AutoDesign) {
    let mut uncovered = 0usize;
    for (i, &r) in model.indices().iter().enumerate() {
        let beta = a
            .passes
            .iter()
            .map(|p| p.pilot.estimate.beta_abs[i])
            .fold(0.0, f64::max);
        let need = settings.mu[i].powi(r as i32 - 1) * beta;
        if settings.gains[i] <= need {
            uncovered += 1;
            // A large model gets the first few by name and a count, not a line each.
            if uncovered <= crate::bounded::TEXT_LINES_MAX {
                eprintln!(
                    "warning: gain {} of `{}` does not cover mu^(r-1) |beta| = {need:.4} neglected by the cheap alpha_hat; use --alpha exact or a larger gain",
                    settings.gains[i],
                    model.constraint_name(i)
                );
            }
        }
    }
    if uncovered > crate::bounded::TEXT_LINES_MAX {
        eprintln!(
            "warning: ... {uncovered} constraints in all whose gain does not cover mu^(r-1) |beta|"
        );
    }
}

fn simulate(
    args: &Args,
    model: &dyn Model,
    settings: Settings,
    design: Option<&DesignInfo>,
) -> Result<Summary, Reported> {
    // Decimation from the number of fixed steps (error-controlled runs take about one
    // step per control interval, or at least t_end / max_step).
    let h = if settings.integrator.is_adaptive() {
        settings.max_step
    } else {
        settings.step
    };
    let steps = ((settings.t_end - settings.t_start) / h).ceil();
    let every = if steps.is_finite() {
        crate::bounded::trace_every(model, steps as u64, MAX_ROWS)
    } else {
        1
    };
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
        match &e {
            SimError::Settings { field, reason } => {
                eprintln!("error: {}: {reason}", flag(field))
            }
            e => eprintln!("error: {e}"),
        }
        Reported
    })?;
    let summary = match sim.run(&mut sink) {
        Ok(s) => s,
        Err(e) => {
            report_failure(model, &settings, args.step.is_some(), &e);
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

fn report_failure(model: &dyn Model, settings: &Settings, fixed_step: bool, e: &SimError) {
    eprintln!("error: simulation of `{}` failed: {e}", model.name());
    let hint = match e {
        SimError::NonFinite {
            value, kind, name, ..
        } if value.is_nan() => {
            let what = match kind {
                Quantity::State => "state",
                Quantity::Algebraic => "algebraic unknown",
                Quantity::Control => "control rate of",
                Quantity::Sliding => "sliding variable of",
                Quantity::Residual => "residual of",
            };
            format!(
                "{what} `{name}` is NaN, not infinite: an expression was evaluated outside its domain (sqrt or ln of a negative number, 0/0, or inf - inf after an overflow), which is not necessarily a divergence; check the expressions the model evaluates with the values near this time"
            )
        }
        SimError::NonFinite { .. } => {
            let mut tries = Vec::new();
            if fixed_step {
                tries.push("a smaller --step");
            } else {
                tries.push("a smaller --tol");
            }
            tries.push("smaller gains");
            // A larger mu only helps while mu is moderate (mu^(r-1) scales J_s).
            if settings.mu.iter().all(|&m| m < 1.0) {
                tries.push("a larger --mu");
            }
            format!("the motion diverged: try {}", tries.join(", "))
        }
        SimError::SingularJacobian { .. } => {
            "J_Omega lost rank here: the algebraic unknowns no longer determine these constraints".into()
        }
        SimError::ReachingTimeout { .. } => "increase the gains or the layers".into(),
        SimError::SolverFailed { .. } => "choose another --solver (dense always applies)".into(),
        SimError::StepLimit { .. } | SimError::StepUnderflow { .. } => {
            "the step control could not go on: a larger --tol, or a fixed --step to see where the motion goes".into()
        }
        _ => String::new(),
    };
    if !hint.is_empty() {
        eprintln!("  hint: {hint}");
    }
}

/// Everything the summary reports.
struct Report<'a> {
    args: &'a Args,
    model: &'a dyn Model,
    settings: &'a Settings,
    summary: &'a Summary,
    design: Option<&'a DesignInfo>,
    integration: &'a Integration,
    outcome: Outcome,
}

impl Report<'_> {
    fn print(&self) {
        if let Some(line) = self.loud_line() {
            // On stderr too, so that a script reading stdout (or a user reading only
            // the end) cannot miss it.
            eprintln!("error: {line}");
        }
        if self.args.json {
            let mut v = self.json();
            crate::bounded::summarise(&mut v, self.model);
            println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
        } else {
            self.text();
        }
    }

    /// The line that says the run did not keep its promise.
    fn loud_line(&self) -> Option<String> {
        let s = self.summary;
        match self.outcome {
            Outcome::Held => None,
            Outcome::NotReached => Some(format!(
                "the layers were not reached by t = {}: the reaching phase did not finish (exit status 4)",
                s.t_end
            )),
            Outcome::BoundLost => {
                let l = s.bound_loss.as_ref()?;
                let mut line = format!(
                    "BOUND LOST: `{}` left its layer at t = {:.6} after reaching; max |s|/eps = {:.4} (`{}`, at t = {:.6}); {} step(s), {:.4e} s outside",
                    l.first_constraint,
                    l.first_time,
                    l.worst_ratio,
                    l.worst_constraint,
                    l.worst_time,
                    l.steps_outside,
                    l.time_outside
                );
                if let Some(ns) = &l.near_singular {
                    line.push_str(&format!(
                        "; J_s was nearly singular at t = {:.6} (pivot ratio {:.2e} < {NEAR_SINGULAR:e})",
                        ns.t, ns.pivot_ratio
                    ));
                }
                line.push_str(" (exit status 3)");
                Some(line)
            }
        }
    }

    fn integrator_name(&self) -> String {
        let st = self.settings;
        match st.integrator {
            Integrator::DormandPrince | Integrator::BogackiShampine => {
                let tol = st.effective_tolerance();
                let name = if st.integrator == Integrator::DormandPrince {
                    "Dormand-Prince 5(4)"
                } else {
                    "Bogacki-Shampine 3(2)"
                };
                let how = if st.tolerance.is_some() {
                    ""
                } else if st.eps.is_empty() {
                    " (the default without constraints)"
                } else {
                    " (0.01 x the smallest eps)"
                };
                format!("{name}, tolerance {:e}{how}", tol.rtol)
            }
            Integrator::Rk4 => format!("RK4, fixed step {:e}", st.step),
            Integrator::Euler => format!("Euler, fixed step {:e}", st.step),
        }
    }

    fn crossing_name(&self) -> String {
        match self.settings.crossing {
            Crossing::Located { tol } => format!("located in the step (to {tol:e} of eps)"),
            Crossing::StepEnd => "at step ends (thesis rule)".into(),
        }
    }

    fn json(&self) -> serde_json::Value {
        let (s, st, model) = (self.summary, self.settings, self.model);
        let tol = st.effective_tolerance();
        let given = |text: &str| {
            if text.trim() == "auto" {
                "designed"
            } else {
                "given"
            }
        };
        json!({
            "model": s.model,
            "constraints": s.constraints,
            "status": match self.outcome {
                Outcome::Held => "held",
                Outcome::BoundLost => "bound lost",
                Outcome::NotReached => "not reached",
            },
            "exit_status": self.outcome.code(),
            "eps": st.eps,
            "mu": st.mu,
            "gain": st.gains,
            "chosen": {
                "mu": if model.n_constraints() == 0 { "none" } else { given(&self.args.mu) },
                "gain": if model.n_constraints() == 0 { "none" } else { given(&self.args.gain) },
                "integrator": if self.integration.chosen { "chosen" } else { "given" },
            },
            "integrator": {
                "name": format!("{:?}", st.integrator),
                "adaptive": st.integrator.is_adaptive(),
                "step": (!st.integrator.is_adaptive()).then_some(st.step),
                "rtol": st.integrator.is_adaptive().then_some(tol.rtol),
                "atol": st.integrator.is_adaptive().then_some(tol.atol),
                "max_step": st.max_step.is_finite().then_some(st.max_step),
                "crossing": self.crossing_name(),
            },
            "design": self.design.map(|d| d.json.clone()),
            "t_end": s.t_end,
            "steps": s.steps,
            "rejected_steps": s.rejected_steps,
            "located_crossings": s.located_crossings,
            "unlocated_steps": s.unlocated_steps,
            "updates": s.updates,
            "f_evals": s.f_evals,
            "f_evals_per_update": s.f_evals as f64 / s.updates.max(1) as f64,
            "reaching_updates": s.reaching_updates,
            "triggered_updates": s.triggered_updates,
            "reach_time": s.reaching_time,
            "stats_from": s.stats_from,
            "period_min": s.min_period,
            "period_avg": s.mean_period,
            "max_abs_s": s.max_abs_s,
            "max_abs_w": s.max_abs_w,
            "max_abs_s_seen": s.seen_max_abs_s,
            "max_abs_w_seen": s.seen_max_abs_w,
            "bound_loss": s.bound_loss,
            "min_pivot_ratio": s.min_pivot_ratio.map(|(r, t)| json!({"ratio": r, "t": t})),
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
            "z_star_final": s.z_star,
            "s_final": s.s,
            "w_final": s.w,
            "wall_seconds": s.wall_time,
        })
    }

    fn text(&self) {
        let (s, st) = (self.summary, self.settings);
        if let Some(line) = self.loud_line() {
            println!("{line}");
        }
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.6}"));
        println!(
            "model {} to t = {}: {} steps ({} rejected, {} cut at a crossing), {} updates ({} while reaching), {} f evaluations ({:.1} per update)",
            s.model,
            s.t_end,
            s.steps,
            s.rejected_steps,
            s.located_crossings,
            s.updates,
            s.reaching_updates,
            s.f_evals,
            s.f_evals as f64 / s.updates.max(1) as f64
        );
        if s.unlocated_steps > 0 {
            println!(
                "  {} steps taken whole by the progress guard (no progress in the steps before them): crossings were not located inside them",
                s.unlocated_steps
            );
        }
        let m = self.model.n_constraints();
        if m == 0 {
            println!("  no constraints: integrated as an ODE");
        } else {
            let how = |text: &str| {
                if text.trim() == "auto" {
                    "designed"
                } else {
                    "given"
                }
            };
            println!(
                "  mu = {} ({}), gains = {} ({}), eps = {}",
                values_text(&st.mu),
                how(&self.args.mu),
                values_text(&st.gains),
                how(&self.args.gain),
                values_text(&st.eps)
            );
        }
        println!(
            "  integrator {} ({}), crossings {}",
            self.integrator_name(),
            if self.integration.chosen {
                "chosen"
            } else {
                "given"
            },
            self.crossing_name()
        );
        if let Some(d) = self.design {
            println!("  design T_min = {}", d.t_min);
        }
        let window = match (s.reaching_time, s.stats_from) {
            _ if m == 0 => "none (no constraints)".to_string(),
            (None, _) => "not reached".to_string(),
            (Some(r), None) => format!(
                "reached at {r:.6}; statistics window not entered (--settle {} reaches past the end)",
                self.args.settle
            ),
            (Some(r), Some(f)) => format!("reached at {r:.6}, statistics from {f:.6}"),
        };
        println!("  layers {window}");
        println!(
            "  update period min {}, average {}",
            opt(s.min_period),
            opt(s.mean_period)
        );
        if let Some(line) = triggered_text(&s.triggered_updates, &s.constraints) {
            println!("{line}");
        }
        let listed = listed_constraints(s.max_abs_s.as_ref().unwrap_or(&s.seen_max_abs_s), &st.eps);
        if listed.len() < m {
            println!(
                "  {m} constraints; the {} with the largest max |s| / eps:",
                listed.len()
            );
        }
        for (i, c) in listed.iter().map(|&i| (i, &s.constraints[i])) {
            match (&s.max_abs_s, &s.max_abs_w) {
                (Some(ms), Some(mw)) => println!(
                    "  {c}: max |s| = {:.6} ({:.4} eps), max |w| = {:.6}",
                    ms[i],
                    ms[i] / st.eps[i],
                    mw[i]
                ),
                _ => println!(
                    "  {c}: no statistics (window not entered); seen max |s| = {:.6}, max |w| = {:.6}; at the end s = {:.6}, w = {:.6}",
                    s.seen_max_abs_s[i], s.seen_max_abs_w[i], s.s[i], s.w[i]
                ),
            }
        }
        if m == 0 {
            println!("  final x = {}", values_text(&s.x));
        } else {
            println!(
                "  final z = {}, z_eq = {}, z* = {}",
                values_text(&s.z),
                values_text(&s.z_eq),
                values_text(&s.z_star)
            );
            println!(
                "  solver {}: {} factorisations, {} solves, {} iterations, {} robustness failures",
                s.solver.name,
                s.solver.factorisations,
                s.solver.solves,
                s.solver.iterations,
                s.robustness_violations
                    .map_or("unchecked".to_string(), |v| v.to_string())
            );
        }
        println!("  wall time {:.3} s", s.wall_time);
    }
}
