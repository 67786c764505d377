//! A model that gives `Omega`'s rate in one pass ([`Model::omega_rate`]): the simulator
//! reads `s'` from it at the end of every step and evaluates `J_Omega` only where an
//! update needs it. The pendulum with its rate written as `beta + J_Omega zdot` (summed
//! in the order the simulator sums them) must run to the bit as the pendulum without,
//! on every path that reads `s'` (fixed and error-controlled steps, cuts, updates, the
//! ramp against the drift, the gains that follow it), with fewer `J_Omega` evaluations.

use crate::common;

use common::pendulum::Pendulum;
use common::pendulum_settings as pendulum;
use dae_runtime::settings::{Dbsmc, GainRule, Hold};
use dae_runtime::{
    Model, Settings, Simulator, Summary, Trace, settings::AlphaChoice, settings::Integrator,
};

fn run<M: Model>(model: M, settings: Settings) -> (Summary, Trace) {
    let mut trace = Trace::new();
    let summary = Simulator::new(model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    (summary, trace)
}

#[test]
fn a_model_that_gives_omegas_rate_runs_to_the_bit_with_fewer_jacobians() {
    let designs = [
        ("RK4", pendulum(0.02)),
        (
            "RK4 ramped, exact alpha",
            pendulum(0.02)
                .law(Dbsmc::default().hold(Hold::RampAgainstDrift))
                .alpha(AlphaChoice::Exact),
        ),
        (
            "Dormand-Prince, ramped",
            pendulum(0.02)
                .integrator(Integrator::DormandPrince)
                .max_step(0.02)
                .law(Dbsmc::default().hold(Hold::RampAgainstDrift)),
        ),
        (
            "Dormand-Prince, gains following the drift",
            pendulum(0.02)
                .integrator(Integrator::DormandPrince)
                .max_step(0.02)
                .law(Dbsmc::default().gains(GainRule::FollowDrift {
                    safety: 1.0,
                    graze: None,
                    raise: None,
                })),
        ),
    ];
    let rated = Pendulum {
        composed_rate: true,
        ..Pendulum::default()
    };
    for (label, settings) in designs {
        let (plain, plain_trace) = run(Pendulum::default(), settings.clone());
        let (fast, fast_trace) = run(&rated, settings);
        assert!(plain.updates > 20, "{label}: {} updates", plain.updates);
        assert!(plain.located_crossings > 0, "{label}: no cut");
        assert_eq!(plain.rate_evals, 0, "{label}");
        assert!(fast.rate_evals >= fast.steps, "{label}: {fast:?}");
        assert_eq!(
            (fast.steps, fast.updates, fast.located_crossings),
            (plain.steps, plain.updates, plain.located_crossings),
            "{label}"
        );
        assert_eq!(fast.x, plain.x, "{label}: final state");
        assert_eq!(fast.z, plain.z, "{label}: final tensions");
        assert_eq!(fast_trace.times(), plain_trace.times(), "{label}");
        // `J_Omega` only where an update or a sample's `z*` needs it, never at a step's
        // end for `s'` alone.
        assert!(
            fast.jacobian_evals < plain.jacobian_evals,
            "{label}: J_Omega {} with the rate, {} without",
            fast.jacobian_evals,
            plain.jacobian_evals
        );
        eprintln!(
            "{label}: {} steps, {} updates; J_Omega {} against {}, beta {} against {}, rate {}",
            fast.steps,
            fast.updates,
            fast.jacobian_evals,
            plain.jacobian_evals,
            fast.beta_evals,
            plain.beta_evals,
            fast.rate_evals
        );
    }
}
