//! `daec run FILE ...`: simulate a model with DBSMC on the interpreter.
//!
//! With only `--t-end` and `--eps`, everything else is chosen: `mu` and the gains by
//! the automatic design (pilot runs), the step by error control (Dormand-Prince 5(4),
//! tolerance from the layers), crossings located inside the steps. The summary says
//! what was chosen and whether the layer held; the exit status says it too
//! ([`Outcome`]).

mod args;
mod grid;
mod online;
mod report;

use self::args::{auto_or_list, check_args, check_number, flag, integration, laws};
use self::report::Report;
use crate::Reported;
use crate::pilot::{PilotArgs, design_json, per_constraint};
use crate::progress::Progress;
use crate::redundant::Redundant;
use dae_runtime::{
    Model, Settings, SimError, Simulator, Summary, Trace, charts::plot_run, design,
    design::ConsistentStart, error::Quantity, settings::AlphaChoice, solve::RedundantRows,
    solve::SolverChoice, trace::CsvSink, trace::Decimate, trace::Tee,
};
use std::fs::File;
use std::io::{self, BufWriter};
use std::path::PathBuf;

/// The default wall-time budget of all pilot runs of `daec run`, in seconds
/// (`--pilot-budget`).
const PILOT_BUDGET: f64 = 10.0;

/// Most rows written to `--csv` (and kept for `--plot`) before steps are decimated.
const MAX_ROWS: u64 = 200_000;

/// Most fixed steps a run (or all its pilot runs together) may take. The interpreted
/// 3-D double pendulum takes about 2.5 us per RK4 step (docs/performance.md), so this
/// is some four minutes of work; beyond it `daec run` refuses up front and says why.
pub(crate) const MAX_STEPS: f64 = 1e8;

/// How a run ended, and the exit status that says it (docs/cli.md, "What a run reports").
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
    /// Which rows a monitored update recomputes: `global` (every row), or `blocks:N`
    /// (only the blocks of the rows that asked, blocks of at most N constraints close in
    /// the graph of J_Omega; needs fixed gains and v held).
    #[arg(long, default_value = "global")]
    scope: String,
    /// alpha_hat: the cheap one, or the exact alpha [default: exact with the online
    /// design, cheap otherwise].
    #[arg(long, value_enum)]
    alpha: Option<AlphaArg>,
    /// How `--mu auto --gain auto` are designed: `online` (no pilot: mu a quarter of
    /// --frame, gains that follow the drift measured during the run, docs/cli.md) or
    /// `pilot` (the thesis's procedure: pilot runs estimate the bounds, mu maximises the
    /// guaranteed period).
    #[arg(long, value_enum, default_value = "online")]
    design: DesignArg,
    /// The time scale of the online design in seconds: the interval at which the motion
    /// is looked at (a frame); mu is a quarter of it.
    #[arg(long, default_value_t = 1.0 / 60.0)]
    frame: f64,
    /// With the online design: `on` searches, frame by frame, for the scale of mu at
    /// which the run costs least (from 1/16 to 64 times a quarter of --frame,
    /// dae_runtime::settings::AdaptiveMu); `off` keeps mu a quarter of --frame
    /// [default: on with the online design for models of at most 256 constraints].
    #[arg(long, value_enum)]
    mu_search: Option<OnOff>,
    /// Algebraic start values: `consistent` (the z at which every constraint's highest
    /// w-derivative vanishes, found by Newton's method from the model's values before
    /// anything else runs), or `given` (the model's `alg` values as written).
    #[arg(long, value_enum, default_value = "consistent")]
    start: StartArg,
    /// Statistics start this many seconds after t = 0, and never before the end of the
    /// reaching phase [default: at the end of the reaching phase].
    #[arg(long, default_value_t = 0.0)]
    settle: f64,
    /// Cut the run at t = H, 2H, .. and write only those samples to --csv and --plot,
    /// as a co-simulation importer runs `daec fmu`'s FMU with communication step H
    /// (the same cuts give the same trajectory).
    #[arg(long, value_name = "H")]
    every: Option<f64>,
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
    pub(crate) json: bool,
    /// Solver of J_s at the control updates: `auto` (exact: dense up to 16 constraints,
    /// `tree` when the Jacobian pattern's graph is a forest, `sparse` otherwise),
    /// `dense`, `sparse`, `tree`, or an approximate inverse checked by (T 3.22):
    /// `jacobi`, `gauss-seidel:K` (K sweeps), `cg:K` (K iterations), `ilu0`.
    #[arg(long, default_value = "auto", value_parser = parse_solver)]
    solver: SolverChoice,
    /// What a singular J_Omega does: `refuse` stops and names the constraints the
    /// others imply; `drop` sets them aside and solves the rest, which holds them
    /// where they are dependent as functions (a constraint stated twice, a family the
    /// others imply everywhere: docs/method.md, "Redundant constraints").
    #[arg(long, value_enum, default_value = "refuse")]
    redundant: RedundantArg,
    /// Let the gains follow the drift of s' measured between updates, with this safety
    /// factor (at least the given gains, up to the gain that sweeps the layer against
    /// the drift; GainRule::FollowDrift).
    #[arg(long, value_name = "SAFETY")]
    follow_drift: Option<f64>,
    /// With --follow-drift: raise a gain only as far as its grazing returns need to stay
    /// this many seconds apart (the `graze` of GainRule::FollowDrift).
    #[arg(long, value_name = "MIN_RETURN")]
    graze: Option<f64>,
    /// Let v ramp between updates at the rate that cancels the drift of s' found at each
    /// update, instead of holding it (Hold::RampAgainstDrift).
    #[arg(long)]
    ramp: bool,
    /// Inside the layer ask each constraint for the rate -k s/eps instead of -k sgn(s)
    /// (InLayer::Saturate; the same on the boundary, where the updates are
    /// asked for).
    #[arg(long)]
    saturate: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum RedundantArg {
    /// Stop at a singular J_Omega.
    Refuse,
    /// Set the implied constraints aside.
    Drop,
}

impl From<RedundantArg> for RedundantRows {
    fn from(a: RedundantArg) -> Self {
        match a {
            RedundantArg::Refuse => RedundantRows::Refuse,
            RedundantArg::Drop => RedundantRows::Drop,
        }
    }
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

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum DesignArg {
    /// From the layers and --frame alone (dae_runtime::design::Online).
    Online,
    /// From pilot runs (dae_runtime::design::auto_design).
    Pilot,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum StartArg {
    /// Solved for from the states (the run and its pilots start on the surfaces as far
    /// as z can put them there).
    Consistent,
    /// The model's own values.
    Given,
}

#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum AlphaArg {
    /// alpha_hat without the mu^(r-1) beta term (covered by the gain).
    Cheap,
    /// The exact alpha (one beta evaluation per update).
    Exact,
}

/// What the design step found, for the summary and the charts.
struct DesignInfo {
    json: serde_json::Value,
    /// The guaranteed period of a pilot design.
    t_min: Option<f64>,
    /// The line of the summary that says what was designed.
    line: String,
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
    let laws = laws(args)?;
    let integ = integration(args, laws.run);
    check_args(args, &integ, m)?;
    let eps = per_constraint("--eps", &args.eps, m)?;
    let mut settings = Settings::new(eps.clone(), vec![1.0; m], vec![1.0; m])
        .step(integ.step)
        .integrator(integ.integrator)
        .max_steps(MAX_STEPS as u64)
        .t_end(args.t_end)
        .settle(args.settle)
        .solver(args.solver)
        .redundant(args.redundant.into())
        .law(laws.run)
        .alpha(match args.alpha {
            Some(AlphaArg::Exact) => AlphaChoice::Exact,
            _ => AlphaChoice::Cheap,
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
    let start = match args.start {
        StartArg::Consistent if m > 0 => Some(consistent_start(model, &settings)?),
        _ => None,
    };
    if let Some(st) = &start {
        settings = settings.initial(st.x0.clone(), st.found.z0.clone());
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
        .law(laws.pilot)
        .alpha(AlphaChoice::Cheap);
    let online = m > 0 && mu.is_none() && gain.is_none() && args.design == DesignArg::Online;
    if args.mu_search.is_some() && !online {
        error!("--mu-search: only the online design searches for mu during the run");
        hint!("drop --mu-search, or use --design online with --mu auto --gain auto");
        return Err(Reported);
    }
    let design = match (mu, gain) {
        _ if m == 0 => None,
        (None, None) if online => Some(online::apply(args, &mut settings)?),
        (Some(mu), Some(k)) => {
            settings.layers.mu = per_constraint("--mu", &mu, m)?;
            settings.layers.gains = per_constraint("--gain", &k, m)?;
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
                        error!("with --mu auto, give one --gain value (or `auto`)");
                        return Err(Reported);
                    }
                    Some(k[0])
                }
            };
            let a =
                args.pilot_args
                    .auto_design(model, &pilot_base, mu, fixed, Some(PILOT_BUDGET))?;
            settings.layers.mu = a.design.constraints.iter().map(|c| c.mu).collect();
            settings.layers.gains = a.design.constraints.iter().map(|c| c.k).collect();
            if fixed.is_some() && settings.alpha == AlphaChoice::Cheap {
                warn_uncovered_beta(model, &settings, &a);
            }
            Some(DesignInfo {
                json: design_json(model, &a),
                t_min: Some(a.design.t_min),
                line: format!("  design T_min = {}", a.design.t_min),
            })
        }
    };
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
        start: start.as_ref(),
        integration: &integ,
        outcome,
    };
    report.print();
    Ok(outcome)
}

/// The consistent start of a run: the model's states and the algebraic values found for
/// them.
pub(crate) struct Start {
    pub(crate) x0: Vec<f64>,
    pub(crate) found: ConsistentStart,
}

/// The consistent algebraic values at the model's initial states (`--start consistent`).
fn consistent_start(model: &dyn Model, settings: &Settings) -> Result<Start, Reported> {
    let mut x0 = vec![0.0; model.n_states()];
    let mut z0 = vec![0.0; model.n_constraints()];
    model.initial_state(&mut x0);
    model.initial_alg(&mut z0);
    match design::consistent_start_with(
        model,
        settings.window.t_start,
        &x0,
        &z0,
        settings.redundant,
    ) {
        Ok(found) => Ok(Start { x0, found }),
        Err(e) => {
            error!(
                "no consistent algebraic start values for `{}`: {}",
                model.name(),
                start_error(model, settings.window.t_start, &e)
            );
            hint!(
                "--start given runs from the model's own values (the reaching phase then starts from them)"
            );
            Err(Reported)
        }
    }
}

/// For a singular `J_Omega` at the start of the run, the constraints the others imply
/// at the model's initial values (see [`Redundant`]), as a hint; `None` later in the run
/// or if `J_Omega` has full rank there.
fn redundant_at_start(model: &dyn Model, settings: &Settings, t: f64) -> Option<String> {
    if t != settings.window.t_start {
        return None;
    }
    let mut x = vec![0.0; model.n_states()];
    let mut z = vec![0.0; model.n_constraints()];
    model.initial_state(&mut x);
    model.initial_alg(&mut z);
    let r = Redundant::at(model, t, &x, &z)?;
    let mut text = format!("at the initial values J_Omega has {}", r.counts());
    for (_, line) in r.family_lines(model) {
        text.push_str(&format!("\n  {line}"));
    }
    text.push_str(&format!(
        "\n  there {}\n  remove the implied constraints, or make them forces, or start where they are independent",
        r.dependency(model)
    ));
    Some(text)
}

/// A [`design::StartError`] with the constraints named.
fn start_error(model: &dyn Model, t: f64, e: &design::StartError) -> String {
    use design::StartError;
    let names = |rows: &[usize]| {
        let listed: Vec<String> = rows
            .iter()
            .take(dae_runtime::summary::TEXT_LINES_MAX)
            .map(|&i| format!("`{}`", model.constraint_name(i)))
            .collect();
        let more = rows.len().saturating_sub(listed.len());
        if more > 0 {
            format!("{} and {more} more", listed.join(", "))
        } else {
            listed.join(", ")
        }
    };
    match e {
        StartError::Singular { constraints } => {
            let mut x = vec![0.0; model.n_states()];
            let mut z = vec![0.0; model.n_constraints()];
            model.initial_state(&mut x);
            model.initial_alg(&mut z);
            match Redundant::at(model, t, &x, &z) {
                Some(r) => {
                    let mut text = format!(
                        "J_Omega is singular at the initial values: {}, so the algebraic unknowns are not determined there",
                        r.counts()
                    );
                    for (_, line) in r.family_lines(model) {
                        text.push_str(&format!("\n  {line}"));
                    }
                    text.push_str(&format!("\n  there {}", r.dependency(model)));
                    text.push_str("\n  hint: remove the implied constraints, or make them forces, or start where they are independent");
                    text
                }
                None => format!(
                    "J_Omega is singular at the initial states: the rows of {} are dependent, so the algebraic unknowns are not determined there",
                    names(constraints)
                ),
            }
        }
        StartError::NonFinite {
            constraint,
            iteration,
        } => format!(
            "a non-finite value in `{}` {}",
            model.constraint_name(*constraint),
            if *iteration == 0 {
                "at the model's own values".to_string()
            } else {
                format!("at Newton iteration {iteration}")
            }
        ),
        StartError::NotConverged {
            iterations,
            residual,
            constraint,
        } => format!(
            "Newton's method did not converge in {iterations} iterations (the highest w-derivative of `{}` is still {residual:e})",
            model.constraint_name(*constraint)
        ),
        StartError::Mismatch(text) => text.clone(),
    }
}

/// A fixed gain with the cheap alpha_hat must still cover the neglected `mu^(r-1) |beta|`
/// (T 3.17); say so when the pilot bounds show that it does not.
fn warn_uncovered_beta(
    model: &dyn Model,
    settings: &Settings,
    a: &dae_runtime::design::AutoDesign,
) {
    let mut uncovered = 0usize;
    for (i, &r) in model.indices().iter().enumerate() {
        let beta = a
            .passes
            .iter()
            .map(|p| p.pilot.estimate.beta_abs[i])
            .fold(0.0, f64::max);
        let need = settings.layers.mu[i].powi(r as i32 - 1) * beta;
        if settings.layers.gains[i] <= need {
            uncovered += 1;
            // A large model gets the first few by name and a count, not a line each.
            if uncovered <= dae_runtime::summary::TEXT_LINES_MAX {
                eprintln!(
                    "warning: gain {} of `{}` does not cover mu^(r-1) |beta| = {need:.4} neglected by the cheap alpha_hat; use --alpha exact or a larger gain",
                    settings.layers.gains[i],
                    model.constraint_name(i)
                );
            }
        }
    }
    if uncovered > dae_runtime::summary::TEXT_LINES_MAX {
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
    let h = if settings.integration.integrator.is_adaptive() {
        settings.integration.max_step
    } else {
        settings.integration.step
    };
    let steps = ((settings.window.t_end - settings.window.t_start) / h).ceil();
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
                error!("cannot create `{}`: {e}", path.display());
                return Err(Reported);
            }
        },
    };
    let trace = args
        .plot
        .as_ref()
        .map(|_| Decimate::new(Trace::new()).every(every));
    // Each output keeps its own decimation (both are `None` without --csv and --plot);
    // the progress bar on a terminal asks for no samples of its own.
    let mut sink = Progress::new(
        grid::OnGrid::new(Tee(csv, trace), args.every),
        settings.window.t_start,
        settings.window.t_end,
        crate::progress::enabled(),
    );
    let mut sim = Simulator::new(model, settings.clone()).map_err(|e| {
        match &e {
            SimError::Settings { field, reason } => {
                error!("{}: {reason}", flag(field));
                crate::failure::field("setting", flag(field).into());
            }
            e => error!("{e}"),
        }
        Reported
    })?;
    let result = grid::run(&mut sim, args.every, &mut sink);
    sink.clear();
    let sink = &mut sink.inner_mut().inner;
    let summary = match result {
        Ok(s) => s,
        Err(e) => {
            report_failure(model, &settings, args.step.is_some(), &e);
            if let Some(c) = sink.0.take() {
                // The rows up to the failure stay in the file.
                if let Err(e) = io::Write::flush(&mut c.into_inner().into_inner()) {
                    error!("writing the CSV: {e}");
                }
            }
            return Err(Reported);
        }
    };
    if let (Some(dir), Some(trace)) = (&args.plot, &sink.1) {
        let t_min = design.and_then(|d| d.t_min);
        plot_run(
            dir,
            model.name(),
            trace.inner(),
            &settings.layers.eps,
            t_min,
        )
        .map_err(|e| {
            error!("charts in `{}`: {e}", dir.display());
            Reported
        })?;
    }
    Ok(summary)
}

fn report_failure(model: &dyn Model, settings: &Settings, fixed_step: bool, e: &SimError) {
    error!("simulation of `{}` failed: {e}", model.name());
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
            if settings.layers.mu.iter().all(|&m| m < 1.0) {
                tries.push("a larger --mu");
            }
            format!("the motion diverged: try {}", tries.join(", "))
        }
        SimError::SingularJacobian { t, .. } => match redundant_at_start(model, settings, *t) {
            Some(text) => text,
            None => "J_Omega lost rank here: the algebraic unknowns no longer determine these constraints".into(),
        },
        SimError::ReachingTimeout { .. } => "increase the gains or the layers".into(),
        SimError::SolverFailed { .. } => "choose another --solver (dense always applies)".into(),
        SimError::StepUnderflow {
            near_singular: Some(_),
            ..
        } => {
            "a configuration where J_Omega is singular lies within the layers: smaller --eps, or a model that keeps away from it (more slack in a taut line)".into()
        }
        SimError::StepLimit { .. } | SimError::StepUnderflow { .. } => {
            "the step control could not go on: a larger --tol, or a fixed --step to see where the motion goes".into()
        }
        _ => String::new(),
    };
    if !hint.is_empty() {
        hint!("{hint}");
    }
    crate::messages::sim_error_fields(e);
}
