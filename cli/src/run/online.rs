//! `--design online` (the default of `--mu auto --gain auto`): the runtime's
//! [`Online`] design from the layers and `--frame`, with the flags it leaves open.

use super::{AlphaArg, Args, CrossingArg, DesignInfo, IntegratorArg, OnOff, ReachingArg};
use crate::Reported;
use crate::pilot::{self, BoundArg, GainsArg, PilotArgs};
use dae_runtime::design::Online;
use dae_runtime::settings::{AlphaChoice, Hold, Reaching, Scope, Update};
use dae_runtime::{Settings, design::DesignError};
use serde_json::json;

/// The flags whose choice the online design makes, and what it chooses.
fn conflicts(args: &Args) -> Option<(&'static str, &'static str)> {
    let adaptive = matches!(
        args.integrator,
        None | Some(IntegratorArg::Dopri5 | IntegratorArg::Bs3)
    );
    [
        (args.policy != "monitor", "--policy", "monitored updates"),
        (
            matches!(args.crossing, CrossingArg::StepEnd),
            "--crossing step-end",
            "crossings located in the step",
        ),
        (
            args.follow_drift.is_some() || args.graze.is_some(),
            "--follow-drift/--graze",
            "gains that follow the drift with grazing returns mu/8 apart",
        ),
        (
            args.scope != "global",
            "--scope",
            "gains that follow the drift, which every row's update measures",
        ),
        (
            args.step.is_some() || !adaptive,
            "--step/--integrator",
            "error-controlled steps of at most mu/2",
        ),
        (args.pilot.is_some(), "--pilot", "no pilot run"),
    ]
    .into_iter()
    .find(|c| c.0)
    .map(|c| (c.1, c.2))
    .or_else(|| pilot_option_given(&args.pilot_args).map(|flag| (flag, "no pilot run")))
}

/// The first option of the pilot design that differs from its default (given on the
/// command line: the online design would leave it unused).
fn pilot_option_given(p: &PilotArgs) -> Option<&'static str> {
    [
        ("--gains", !matches!(p.gains, GainsArg::Sufficient)),
        ("--bound", !matches!(p.bound, BoundArg::General)),
        ("--passes", p.passes != pilot::PASSES),
        ("--pilot-mu", p.pilot_mu != pilot::PILOT_MU),
        ("--pilot-gain", p.pilot_gain.is_some()),
        ("--safety", p.safety != pilot::SAFETY),
        ("--pilot-retries", p.pilot_retries != pilot::PILOT_RETRIES),
        ("--pilot-budget", p.pilot_budget.is_some()),
    ]
    .into_iter()
    .find(|o| o.1)
    .map(|o| o.0)
}

/// Puts the online design into `settings` (built from the flags): `mu`, the gains and the
/// law, the exact alpha unless `--alpha`, its tolerance and longest step unless `--tol`
/// and `--max-step`.
pub(super) fn apply(args: &Args, settings: &mut Settings) -> Result<DesignInfo, Reported> {
    if let Some((flag, sets)) = conflicts(args) {
        error!(
            "{flag}: the online design (--design online, the default with --mu auto --gain auto) chooses {sets}"
        );
        hint!("--design pilot designs from pilot runs, or give --mu and --gain");
        return Err(Reported);
    }
    let mut online = Online::frame(args.frame);
    match args.mu_search {
        Some(OnOff::Off) => online.search = None,
        // Asked for by name: whatever the size of the model.
        Some(OnOff::On) => online.search_up_to = usize::MAX,
        None => {}
    }
    let designed = online.settings(settings.layers.eps.clone()).map_err(|e| {
        let message = match e {
            DesignError::NotPositive { name: "frame", .. }
            | DesignError::NotPositive { name: "mu", .. } => {
                format!("--frame {}: must be a finite number > 0", args.frame)
            }
            e => e.to_string(),
        };
        error!("online design: {message}");
        Reported
    })?;
    let designed_search = designed.layers.adapt_mu.is_some();
    let reaching = match args.reaching {
        ReachingArg::Attract => Reaching::AttractingSurfaces,
        ReachingArg::Contract => Reaching::ContractingLayers,
    };
    let mut law = designed.law;
    if let dae_runtime::settings::Law::Dbsmc(d) = &mut law {
        d.update = Update::Monitor {
            reaching,
            scope: Scope::Global,
        };
        if args.ramp {
            d.hold = Hold::RampAgainstDrift;
        }
    }
    settings.layers.mu = designed.layers.mu;
    settings.layers.gains = designed.layers.gains;
    settings.layers.adapt_mu = designed.layers.adapt_mu;
    settings.law = law;
    if args.alpha.is_none() {
        settings.alpha = AlphaChoice::Exact;
    }
    if args.tol.is_none() {
        settings.integration.tolerance = designed.integration.tolerance;
    }
    if args.max_step.is_none() {
        settings.integration.max_step = designed.integration.max_step;
    }
    // The design's own step (a frame; `--step` is refused above), so that a run here is
    // the run of `Online::settings` from Rust and of `daec fmu`'s FMU.
    settings.integration.step = designed.integration.step;
    let mu = online.mu();
    let alpha = match args.alpha {
        Some(AlphaArg::Cheap) => "the cheap alpha_hat (given)",
        _ => "the exact alpha",
    };
    Ok(DesignInfo {
        json: json!({
            "method": "online",
            "frame": online.frame,
            "mu": mu,
            "gain_floor": online.floor,
            "graze": online.graze_per_mu * mu,
            "drift_safety": online.drift_safety,
            "mu_search": designed.layers.adapt_mu.map(|a| json!({
                "frame": a.frame,
                "window": a.window,
                "step": a.step,
                "min_scale": a.min_scale,
                "max_scale": a.max_scale,
            })),
        }),
        t_min: None,
        line: format!(
            "  design online (no pilot): frame {} s, mu = frame/4{}, gains from {} eps/mu following the drift (grazing returns mu/8 apart), rate -k s/eps inside the layer, {alpha}{}",
            online.frame,
            if designed_search {
                " at the start, then searched for frame by frame"
            } else {
                ""
            },
            online.floor,
            if args.ramp { ", v ramped" } else { "" }
        ),
    })
}
