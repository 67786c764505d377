//! The arguments of `daec run` checked before any work: the lists and the policy parsed,
//! the numbers and the outputs checked, the integration chosen.

use super::{Args, IntegratorArg, MAX_STEPS};
use super::{CrossingArg, ReachingArg};
use crate::Reported;
use dae_runtime::settings::{
    Dbsmc, GainRule, Hold, InLayer, Integrator, Law, Reaching, Scope, StepEnd, Update,
};
use std::fs::File;
use std::path::Path;

/// `auto` or a comma-separated list of numbers.
pub(super) fn auto_or_list(what: &str, text: &str) -> Result<Option<Vec<f64>>, Reported> {
    if text.trim() == "auto" {
        return Ok(None);
    }
    text.split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
        .map_err(|e| {
            error!("{what} `{text}`: expected `auto` or numbers separated by commas ({e})");
            Reported
        })
}

/// `--scope`: `global` or `blocks:N`.
fn parse_scope(text: &str) -> Result<Scope, Reported> {
    if text == "global" {
        return Ok(Scope::Global);
    }
    match text.strip_prefix("blocks:").map(str::parse::<usize>) {
        Some(Ok(size)) if size >= 1 => Ok(Scope::Blocks { size }),
        _ => {
            error!(
                "--scope `{text}`: expected `global` or `blocks:N` with N >= 1 constraints per block"
            );
            Err(Reported)
        }
    }
}

/// `--policy`: the update rule of DBSMC, or `None` for SPSM.
fn parse_policy(text: &str, reaching: Reaching, scope: Scope) -> Result<Option<Update>, Reported> {
    match text {
        "monitor" => Ok(Some(Update::Monitor { reaching, scope })),
        "spsm" => Ok(None),
        _ => match text.strip_prefix("fixed:").map(str::parse::<f64>) {
            Some(Ok(p)) if p > 0.0 && p.is_finite() => Ok(Some(Update::Fixed { period: p })),
            Some(Ok(p)) => {
                error!("--policy fixed:{p}: the period must be finite and > 0");
                Err(Reported)
            }
            _ => {
                error!("--policy `{text}`: expected `monitor`, `fixed:PERIOD` or `spsm`");
                Err(Reported)
            }
        },
    }
}

/// The control law of the run and of the design's pilots, from `--policy`,
/// `--crossing`, `--reaching` and the extensions (`--follow-drift`, `--graze`,
/// `--ramp`, `--saturate`), each refused by name where the law cannot take it. The
/// pilots monitor with the run's crossing and reaching rules, fixed gains, `v` held and
/// `sgn(s)`: they measure what the design's gains must cover.
pub(super) struct Laws {
    pub(super) run: Law,
    pub(super) pilot: Law,
}

pub(super) fn laws(args: &Args) -> Result<Laws, Reported> {
    let reaching = match args.reaching {
        ReachingArg::Attract => Reaching::AttractingSurfaces,
        ReachingArg::Contract => Reaching::ContractingLayers,
    };
    let scope = parse_scope(&args.scope)?;
    let update = parse_policy(&args.policy, reaching, scope)?;
    if let (Scope::Blocks { .. }, false) = (scope, matches!(update, Some(Update::Monitor { .. }))) {
        error!(
            "--scope {}: block updates answer the rows that ask, which needs --policy monitor",
            args.scope
        );
        return Err(Reported);
    }
    let step_end = matches!(args.crossing, CrossingArg::StepEnd);
    let extensions = [
        ("--follow-drift", args.follow_drift.is_some()),
        ("--ramp", args.ramp),
        ("--saturate", args.saturate),
    ];
    let given = || extensions.iter().filter(|e| e.1).map(|e| e.0);
    if let (None, Some(flag)) = (update, given().next()) {
        error!(
            "{flag} changes the DBSMC law; --policy spsm saturates at every stage and takes none of --follow-drift, --ramp, --saturate"
        );
        return Err(Reported);
    }
    let needs_rates = given().find(|f| *f != "--saturate");
    if let (true, Some(flag)) = (step_end, needs_rates) {
        error!(
            "{flag} needs the rates s' at the step ends, which only located crossings give: drop --crossing step-end"
        );
        return Err(Reported);
    }
    if let (Scope::Blocks { .. }, Some(flag)) = (scope, needs_rates) {
        error!(
            "{flag} computes over every constraint at each update; --scope {} updates blocks: drop one of them",
            args.scope
        );
        return Err(Reported);
    }
    let in_layer = if args.saturate {
        InLayer::Saturate
    } else {
        InLayer::Sign
    };
    let monitor = Update::Monitor {
        reaching,
        scope: Scope::Global,
    };
    let (run, pilot) = match update {
        None if step_end => (Law::Spsm, StepEnd::default().into_monitor(monitor)),
        None => (Law::Spsm, Dbsmc::default().update(monitor).into()),
        Some(update) if step_end => (
            StepEnd {
                update,
                raise: None,
                in_layer,
            }
            .into(),
            StepEnd::default().into_monitor(monitor),
        ),
        Some(update) => {
            let gains = match args.follow_drift {
                Some(safety) => GainRule::FollowDrift {
                    safety,
                    graze: args.graze,
                    raise: None,
                },
                None => GainRule::Fixed,
            };
            let hold = if args.ramp {
                Hold::RampAgainstDrift
            } else {
                Hold::Constant
            };
            let run = Dbsmc::default()
                .update(update)
                .gains(gains)
                .hold(hold)
                .in_layer(in_layer);
            (run.into(), Dbsmc::default().update(monitor).into())
        }
    };
    Ok(Laws { run, pilot })
}

/// A step-end law that monitors.
trait IntoMonitor {
    fn into_monitor(self, monitor: Update) -> Law;
}

impl IntoMonitor for StepEnd {
    fn into_monitor(self, monitor: Update) -> Law {
        StepEnd {
            update: monitor,
            ..self
        }
        .into()
    }
}

/// A user-given number that must be finite and positive (or non-negative).
pub(super) fn check_number(flag: &str, value: f64, zero_ok: bool) -> Result<(), Reported> {
    let ok = value.is_finite() && (value > 0.0 || (zero_ok && value == 0.0));
    if ok {
        return Ok(());
    }
    let need = if zero_ok { ">= 0" } else { "> 0" };
    error!("{flag} {value}: must be a finite number {need}");
    Err(Reported)
}

/// The chosen integration: the integrator, its fixed step (if any) and whether each
/// was given or chosen.
pub(super) struct Integration {
    pub(super) integrator: Integrator,
    pub(super) step: f64,
    pub(super) fixed: bool,
    pub(super) chosen: bool,
}

pub(super) fn integration(args: &Args, law: Law) -> Integration {
    let choice = match (args.integrator, args.step, law) {
        (Some(i), _, _) => i,
        (None, Some(_), _) | (None, None, Law::Spsm) => IntegratorArg::Rk4,
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

/// The settings' field names as the flags a user wrote.
pub(super) fn flag(field: &str) -> &str {
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
        "saturate" => "--saturate",
        "scope" => "--scope",
        other => other,
    }
}

/// Check everything the user gave before any work: numbers, the outputs, and the
/// amount of work of fixed steps.
pub(super) fn check_args(args: &Args, integration: &Integration, m: usize) -> Result<(), Reported> {
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
        ("--every", args.every),
    ] {
        if let Some(v) = v {
            check_number(flag, v, false)?;
        }
    }
    if args.graze.is_some() && args.follow_drift.is_none() {
        error!("--graze limits the gains that follow the drift: give --follow-drift too");
        return Err(Reported);
    }
    if integration.fixed && (args.tol.is_some() || args.max_step.is_some()) {
        error!(
            "--tol and --max-step are for the error-controlled steps (--integrator dopri5 or bs3), not a fixed --step"
        );
        return Err(Reported);
    }
    if !integration.fixed && args.step.is_some() {
        error!(
            "--step is a fixed step; the error-controlled integrators take --tol and --max-step"
        );
        return Err(Reported);
    }
    if integration.fixed {
        let steps = args.t_end / integration.step;
        if steps > MAX_STEPS {
            error!(
                "--t-end {} with --step {:e} is {steps:.3e} steps, more than the {MAX_STEPS:e} this command takes (some minutes of work)",
                args.t_end, integration.step
            );
            hint!(
                "leave out --step (the step is then chosen by error control), or give a larger one"
            );
            return Err(Reported);
        }
    }
    let pilots = match (args.mu.trim() == "auto", args.gain.trim() == "auto") {
        (true, true) => args.design == super::DesignArg::Pilot,
        (false, false) => false,
        _ => true,
    };
    if m > 0 && pilots {
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
pub(super) fn check_outputs(csv: Option<&Path>, plot: Option<&Path>) -> Result<(), Reported> {
    if let Some(dir) = plot {
        let probe = dir.join(".daec-write-test");
        let written = std::fs::create_dir_all(dir).and_then(|()| std::fs::write(&probe, b""));
        let _ = std::fs::remove_file(&probe);
        if let Err(e) = written {
            error!("--plot `{}` cannot be written: {e}", dir.display());
            return Err(Reported);
        }
    }
    if let Some(path) = csv {
        // Created again (truncated) by the run; this only finds the error early.
        if let Err(e) = File::create(path) {
            error!("cannot create `{}`: {e}", path.display());
            return Err(Reported);
        }
    }
    Ok(())
}
