//! The pilot run and the automatic design: an index-2 model with closed-form `beta` and
//! `w''` derivative as the oracle, and the 3-D double pendulum against the thesis bounds.

use crate::common;

use common::Tracking;
use common::pendulum::Pendulum;
use dae_runtime::settings::{Law, StepEnd};
use dae_runtime::{
    Settings, Simulator, Trace, design::AutoDesignOptions, design::ConstraintSpec,
    design::GainChoice, design::LayerBound, design::MuChoice, design::PilotRunError,
    design::auto_design, design::pilot_run, design::t_min,
};

/// Tracking (`x' = z - x`, `0 = x - sin t`): `beta = -(z - x) + sin t` and, with `v`
/// held, `d/dt w'' = d/dt (v + beta) = -(v - (z - x)) + cos t`. The pilot's `|beta|` must
/// be the largest closed-form `|beta|` over the window's samples, and its `M` (largest
/// chord slope of `w''` from an update) must lie between the largest `|d/dt w''|` at an
/// update and the largest `|d/dt w''|` anywhere in the window.
#[test]
fn tracking_pilot_matches_closed_form_beta_and_drift() {
    let model = Tracking::default();
    let settings = Settings::new(vec![1e-3], vec![0.05], vec![0.1])
        .step(1e-3)
        .t_end(3.0)
        .settle(0.5);
    let run = pilot_run(&model, &settings).unwrap();
    let mut trace = Trace::new();
    Simulator::new(&model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    let from = run.summary.stats_from.unwrap();
    let ups: Vec<f64> = trace
        .update_times()
        .iter()
        .copied()
        .filter(|t| *t >= from)
        .collect();
    assert!(ups.len() > 10, "{} updates in the window", ups.len());
    let t = trace.times();
    let (mut beta_max, mut d_all, mut d_at_update) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..t.len() - 1 {
        if t[i] < ups[0] {
            continue;
        }
        let (x, z) = (trace.x(i)[0], trace.z(i)[0]);
        beta_max = beta_max.max((-(z - x) + t[i].sin()).abs());
        // The held v of the interval starting at or containing t[i].
        let v = (trace.z(i + 1)[0] - z) / (t[i + 1] - t[i]);
        let d = (-(v - (z - x)) + t[i].cos()).abs();
        d_all = d_all.max(d);
        if ups.contains(&t[i]) {
            d_at_update = d_at_update.max(d);
        }
    }
    let e = &run.estimate;
    assert!(
        (e.beta_abs[0] - beta_max).abs() <= 1e-12 * beta_max,
        "{e:?} vs {beta_max}"
    );
    assert!(e.m[0] <= d_all * (1.0 + 1e-6), "{e:?} vs {d_all}");
    assert!(e.m[0] >= 0.99 * d_at_update, "{e:?} vs {d_at_update}");
    assert_eq!(e.intervals, ups.len());
}

#[test]
fn spsm_cannot_be_a_pilot() {
    let settings = Settings::new(vec![1e-3], vec![0.05], vec![0.1]).law(Law::Spsm);
    assert!(matches!(
        pilot_run(&Tracking::default(), &settings),
        Err(PilotRunError::Mismatch(_))
    ));
}

/// docs/method.md section 8: the thesis's pilot bounds are |beta| <= 1.3e3 / 2.3e3,
/// M = 9e4 / 11e4, and the relaxed design with (T 4.6) gives mu = 0.076 / 0.066,
/// T_min = 0.0062 / 0.0053. Two passes from mu = 0.1, k = 40 (exact alpha) over 10 s must
/// land within a factor of 3 of those bounds and within 0.01 of those mu (the motion is
/// chaotic, so the bounds depend on the trajectory the pilot happens to take).
/// The thesis's pilot of the 3-D double pendulum: crossings noticed at the ends of RK4
/// steps of 1e-4 s, over 10 s, bounds from t = 1 s on.
fn thesis_pilot() -> Settings {
    Settings::new(vec![0.2; 2], vec![0.1; 2], vec![40.0; 2])
        .step(1e-4)
        .law(StepEnd::default())
        .t_end(10.0)
        .settle(1.0)
}

#[test]
fn auto_design_of_the_pendulum_is_of_the_thesis_order() {
    let pilot = thesis_pilot();
    let opts = AutoDesignOptions {
        gain: GainChoice::Relaxed,
        layer: LayerBound::TightIndex3,
        ..Default::default()
    };
    let a = auto_design(&Pendulum::default(), &[0.2, 0.2], &pilot, &opts).unwrap();
    assert_eq!(a.passes.len(), 2);
    let beta: Vec<f64> = (0..2)
        .map(|i| {
            a.passes
                .iter()
                .map(|p| p.pilot.estimate.beta_abs[i])
                .fold(0.0, f64::max)
        })
        .collect();
    let m: Vec<f64> = (0..2)
        .map(|i| {
            a.passes
                .iter()
                .map(|p| p.pilot.estimate.m[i])
                .fold(0.0, f64::max)
        })
        .collect();
    eprintln!(
        "pilot bounds |beta| {beta:?} M {m:?}; design {:?}",
        a.design
    );
    for (got, thesis) in beta
        .iter()
        .zip([1.3e3, 2.3e3])
        .chain(m.iter().zip([9e4, 11e4]))
    {
        assert!(
            *got > thesis / 3.0 && *got < thesis * 3.0,
            "{got} vs {thesis}"
        );
    }
    for (c, mu) in a.design.constraints.iter().zip([0.076, 0.066]) {
        assert!((c.mu - mu).abs() < 0.01, "{:?}", a.design);
    }
    // The second pass ran the first pass's design with the cheap alpha.
    assert_eq!(a.passes[1].mu[0], a.passes[0].design.constraints[0].mu);
}

/// With given mu, every pilot runs at that mu (the first with the exact alpha and the
/// pilot gain, the next with the designed gain and the cheap alpha) and the design keeps
/// it: the gain is the gain choice at that mu with the largest bounds of all passes, and
/// `T_min` is (T 3.14) at that mu and gain. The wrong number of mu is an error.
#[test]
fn auto_design_at_given_mu_designs_only_the_gains() {
    let model = Tracking::default();
    let pilot = Settings::new(vec![1e-3], vec![0.5], vec![0.1])
        .step(1e-3)
        .t_end(3.0)
        .settle(0.5);
    let opts = AutoDesignOptions {
        gain: GainChoice::Sufficient,
        mu: MuChoice::Given(vec![0.07]),
        ..Default::default()
    };
    let a = auto_design(&model, &[2e-3], &pilot, &opts).unwrap();
    assert_eq!(a.passes.len(), 2);
    assert_eq!(a.passes[0].mu, [0.07]);
    assert_eq!(a.passes[0].gains, [0.1]);
    assert_eq!(a.passes[1].mu, [0.07]);
    assert_eq!(a.passes[1].gains, [a.passes[0].design.constraints[0].k]);
    let largest = |f: &dyn Fn(&dae_runtime::design::DesignPass) -> f64| {
        a.passes.iter().map(f).fold(0.0, f64::max)
    };
    let spec = ConstraintSpec {
        r: 2,
        eps: 2e-3,
        m: largest(&|p| p.pilot.estimate.m[0]),
        beta_abs: largest(&|p| p.pilot.estimate.beta_abs[0]),
        layer: LayerBound::General,
    };
    let c = a.design.constraints[0];
    assert_eq!(c.mu, 0.07);
    assert_eq!(c.k, GainChoice::Sufficient.gain(&spec, 0.07).unwrap());
    assert_eq!(c.t_min, t_min(&spec, 0.07, c.k).unwrap());

    let two = AutoDesignOptions {
        mu: MuChoice::Given(vec![0.07, 0.07]),
        ..opts
    };
    assert!(matches!(
        auto_design(&model, &[2e-3], &pilot, &two),
        Err(PilotRunError::Mismatch(_))
    ));
}

/// A pilot with located crossings whose gains are below the drift of its layer (the
/// cheap alpha_hat neglects `mu |beta|`, far above a gain of 1e-4 here) is stopped at
/// the loss with the error naming where, instead of crawling on outside its layer.
#[test]
fn a_pilot_that_leaves_its_layer_stops_there_with_the_loss() {
    use dae_runtime::settings::Integrator;
    let model = Tracking::default();
    let weak = 1e-4;
    let pilot = Settings::new(vec![1e-3], vec![0.05], vec![weak])
        .integrator(Integrator::DormandPrince)
        .max_step(1e-3)
        .t_end(3.0);
    match pilot_run(&model, &pilot) {
        Err(PilotRunError::LayerLost {
            constraint,
            t,
            ratio,
            gain_min,
            gain_max,
            ..
        }) => {
            assert_eq!(constraint, 0);
            assert!(
                t > 0.0 && t < 3.0 && ratio > 1.0,
                "t = {t}, |s|/eps = {ratio}"
            );
            assert_eq!((gain_min, gain_max), (weak, weak));
        }
        other => panic!("expected the weak pilot to leave its layer, got {other:?}"),
    }
}

/// A budget stops the pilots where it runs out, with the pass and how far its pilot came;
/// the same design without a budget finishes.
#[test]
fn pilots_over_their_budget_stop_with_where_they_were() {
    let pilot = thesis_pilot();
    let opts = AutoDesignOptions {
        budget: Some(std::time::Duration::from_millis(1)),
        ..Default::default()
    };
    match auto_design(&Pendulum::default(), &[0.2, 0.2], &pilot, &opts) {
        Err(PilotRunError::OverBudget { budget, pass, t }) => {
            assert_eq!(budget, std::time::Duration::from_millis(1));
            assert_eq!(pass, 1);
            assert!(t > 0.0 && t < 10.0, "{t}");
        }
        other => panic!("{other:?}"),
    }
}
