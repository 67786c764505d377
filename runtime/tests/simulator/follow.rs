//! Gains that follow the drift of `s'` ([`GainRule::FollowDrift`], with and without
//! its `graze`): the gain the
//! simulator ends with against the rule evaluated on the recorded run with the model's
//! closed-form `s'`, and the bound with the followed gains by an independent fine
//! integration. (That a fixed gain too small for the drift loses a layer the followed
//! gain keeps is tested on a particle chain: `bench/tests/suite/particles.rs`.)

use crate::common;

use common::{
    TRACKING_EPS as EPS, TRACKING_MU as MU, Tracking, assert_refused, independent_max_s,
    tracking_settings as settings,
};
use dae_runtime::settings::{Dbsmc, GainRule};
use dae_runtime::{Settings, Simulator, Trace};

/// `s' = mu (v - (z - x) + sin t) + (z - x - cos t)` of the tracking model, from its
/// equations (not from the simulator).
fn s_rate(t: f64, x: f64, z: f64, v: f64) -> f64 {
    MU * (v - (z - x) + t.sin()) + (z - x - t.cos())
}

#[test]
fn the_followed_gain_is_the_rule_applied_to_the_drift_of_the_recorded_run() {
    followed_gain_against_the_rule(None);
}

#[test]
fn the_grazing_gain_is_the_rule_applied_to_the_drift_of_the_recorded_run() {
    followed_gain_against_the_rule(Some(0.05));
}

/// The gains in use, read piece by piece, against `max(k, safety * min(2 sqrt(eps D),
/// D T / 2))` (`T = min_return`, infinite without its `graze`) with `D` the
/// rule's memory of the drifts measured on the recorded run.
fn followed_gain_against_the_rule(min_return: Option<f64>) {
    let (gain, safety) = (0.01, 1.5);
    let settings = follow(settings(gain), safety, min_return);
    let ret = min_return.unwrap_or(f64::INFINITY);
    let mut trace = Trace::new();
    let mut sim = Simulator::new(Tracking::default(), settings).unwrap();
    // Driven in pieces to read the gains in use after each.
    sim.start(&mut trace).unwrap();
    let mut seen = Vec::new();
    for k in 1..=600 {
        sim.advance_to(k as f64 * 0.005, &mut trace).unwrap();
        seen.push((sim.time(), sim.gains()[0]));
    }
    sim.finish(&mut trace).unwrap();
    // The rule on the recorded run: v held before and after each update (z is linear
    // in t within a step), s' from the model's equations.
    let t = trace.times();
    let at = |u: f64| {
        t.iter()
            .position(|&s| s == u)
            .expect("an update is a sample")
    };
    let v_before = |k: usize| (trace.z(k)[0] - trace.z(k - 1)[0]) / (t[k] - t[k - 1]);
    let v_after = |k: usize| (trace.z(k + 1)[0] - trace.z(k)[0]) / (t[k + 1] - t[k]);
    let rate = |k: usize, v: f64| s_rate(t[k], trace.x(k)[0], trace.z(k)[0], v);
    let updates = trace.update_times();
    assert!(updates.len() > 20, "{} updates", updates.len());
    let mut expected = vec![(updates[0], gain)];
    let (mut drift, mut k_prev) = (0.0f64, at(updates[0]));
    let mut grazing = 0;
    for &u in &updates[1..] {
        let k = at(u);
        if k + 1 == t.len() {
            break; // an update at the very end has no step after it
        }
        let measured =
            (rate(k, v_before(k)) - rate(k_prev, v_after(k_prev))).abs() / (t[k] - t[k_prev]);
        drift = measured.max(0.5 * drift);
        let (sweep, graze) = (2.0 * (EPS * drift).sqrt(), 0.5 * drift * ret);
        if graze < sweep && safety * graze > gain {
            grazing += 1;
        }
        expected.push((u, gain.max(safety * sweep.min(graze))));
        k_prev = k;
    }
    assert!(
        expected.iter().filter(|(_, k)| *k > gain).count() > 10,
        "the drift never asked for more than the configured gain"
    );
    if min_return.is_some() {
        assert!(grazing > 10, "{grazing} updates set a grazing gain");
    }
    let mut compared = 0;
    for (time, k) in seen {
        let Some(&(u, want)) = expected.iter().rev().find(|(u, _)| *u <= time) else {
            continue;
        };
        if expected.last().is_some_and(|(last, _)| u == *last) && u < *updates.last().unwrap() {
            continue; // past the last update the rule was evaluated for
        }
        assert!(
            (k - want).abs() <= 1e-6 * want,
            "gain {k} at t = {time} against {want} from the update at {u}"
        );
        compared += 1;
    }
    assert!(compared > 300, "{compared} pieces compared");
}

#[test]
fn the_followed_gain_keeps_the_bound_by_an_independent_fine_integration() {
    // A configured gain far below the rule's: the gain is raised at the updates, up to
    // the sweeping gain or only to a grazing one, and the motion between them,
    // integrated independently, stays in the layer.
    let gain = 0.001;
    for graze in [None, Some(0.05)] {
        let settings = follow(settings(gain), 1.0, graze);
        let mut trace = Trace::new();
        let summary = Simulator::new(Tracking::default(), settings)
            .unwrap()
            .run(&mut trace)
            .unwrap();
        assert!(
            summary.bound_loss.is_none(),
            "{graze:?}: {:?}",
            summary.bound_loss
        );
        assert!(
            summary.gains[0] > 10.0 * gain,
            "{graze:?}: gain {}",
            summary.gains[0]
        );
        let from = summary.reaching_time.expect("reached");
        let max = summary.max_abs_s.as_ref().unwrap()[0];
        let fine = independent_max_s(&Tracking::default(), &[MU], &trace, from, 16)[0];
        assert!(
            max <= 1.01 * EPS && fine <= 1.01 * EPS,
            "{graze:?}: max |s| {max}, fine {fine}"
        );
    }
}

#[test]
fn a_safety_factor_that_is_not_positive_and_finite_is_refused() {
    let refused = |label: &str, s, what: &str| assert_refused(label, s, "follow_drift", what);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        refused(
            &bad.to_string(),
            follow(settings(0.2), bad, None),
            "finite and > 0",
        );
    }
}

#[test]
fn a_grazing_return_that_is_not_positive_and_finite_is_refused() {
    let refused = |label: &str, s, what: &str| assert_refused(label, s, "graze", what);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        refused(
            &bad.to_string(),
            follow(settings(0.2), 1.0, Some(bad)),
            "finite and > 0",
        );
    }
}

/// The settings with gains that follow the drift (and graze with `min_return`).
fn follow(settings: Settings, safety: f64, graze: Option<f64>) -> Settings {
    settings.law(Dbsmc::default().gains(GainRule::FollowDrift {
        safety,
        graze,
        raise: None,
    }))
}
