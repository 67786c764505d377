//! `v` ramping between updates against the drift of `s'`
//! ([`Settings::ramp_against_drift`]): the ramp the simulator takes against the one the
//! tracking model's closed-form `s''` asks for, the bound by an independent fine
//! integration of the ramped `z`, and the updates it saves.

use crate::common;

use common::{
    TRACKING_EPS as EPS, TRACKING_MU as MU, Tracking, tracking_max_s, tracking_settings as settings,
};
use dae_runtime::settings::{Dbsmc, Hold};
use dae_runtime::{Settings, Simulator, Trace, settings::Integrator};

/// `s''` of the tracking model with `v` held, from its equations: `s' = mu (v - (z - x)
/// + sin t) + (z - x - cos t)` along `x' = z - x`, `z' = v`.
fn held_drift(t: f64, x: f64, z: f64, v: f64) -> f64 {
    let e = v - (z - x);
    MU * (-e + t.cos()) + (e + t.sin())
}

fn run(settings: Settings) -> (Trace, dae_runtime::Summary) {
    let mut trace = Trace::new();
    let summary = Simulator::new(Tracking::default(), settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    (trace, summary)
}

/// The ramp of each control interval read from the recorded `z` (three samples inside
/// it: `z` is quadratic there), as `(k, v, a)` with `k` the sample of the update.
fn ramps(trace: &Trace) -> Vec<(usize, f64, f64)> {
    let t = trace.times();
    let updates = trace.update_times();
    let mut out = Vec::new();
    for (j, &u) in updates.iter().enumerate() {
        let next = updates.get(j + 1).copied().unwrap_or(f64::INFINITY);
        let Some(k) = t.iter().position(|&s| s == u) else {
            continue;
        };
        if k + 2 >= t.len() || t[k + 2] > next {
            continue;
        }
        let z = |i: usize| trace.z(i)[0];
        let (h1, h2) = (t[k + 1] - t[k], t[k + 2] - t[k + 1]);
        let (d1, d2) = ((z(k + 1) - z(k)) / h1, (z(k + 2) - z(k + 1)) / h2);
        let a = 2.0 * (d2 - d1) / (t[k + 2] - t[k]);
        out.push((k, d1 - 0.5 * a * h1, a));
    }
    out
}

#[test]
fn the_ramp_cancels_the_drift_that_the_closed_form_gives_at_each_update() {
    for integrator in [Integrator::Rk4, Integrator::DormandPrince] {
        let (trace, summary) = run(settings(0.05)
            .integrator(integrator)
            .law(Dbsmc::default().hold(Hold::RampAgainstDrift)));
        assert!(summary.bound_loss.is_none(), "{integrator:?}");
        let t = trace.times();
        let found = ramps(&trace);
        assert!(
            found.len() > 10,
            "{integrator:?}: {} intervals",
            found.len()
        );
        for &(k, v, a) in &found {
            // s'' with the ramp is s''_held + mu a: zero at the update.
            let want = -held_drift(t[k], trace.x(k)[0], trace.z(k)[0], v) / MU;
            assert!(
                (a - want).abs() <= 1e-4 * want.abs().max(1.0),
                "{integrator:?} at t = {}: ramp {a}, closed form {want}",
                t[k]
            );
        }
        assert!(
            found.iter().filter(|(_, _, a)| a.abs() > 1.0).count() > 5,
            "{integrator:?}: the ramps are not all negligible"
        );
    }
}

#[test]
fn the_ramped_run_keeps_the_bound_by_an_independent_fine_integration() {
    let (trace, summary) = run(settings(0.05).law(Dbsmc::default().hold(Hold::RampAgainstDrift)));
    assert!(summary.bound_loss.is_none(), "{:?}", summary.bound_loss);
    let from = summary.reaching_time.expect("reached");
    let t = trace.times();
    let updates = trace.update_times();
    let mut max = 0.0f64;
    let mut checked = 0;
    for (k, v, _) in ramps(&trace) {
        if t[k] < from {
            continue;
        }
        // The interval's z from the closed-form ramp.
        let (tb, zb) = (t[k], trace.z(k)[0]);
        let a = -held_drift(tb, trace.x(k)[0], zb, v) / MU;
        let end = updates.iter().copied().find(|&u| u > tb).unwrap_or(3.0);
        let z = |tau: f64| zb + v * (tau - tb) + 0.5 * a * (tau - tb).powi(2);
        max = max.max(tracking_max_s(z, (tb, trace.x(k)[0]), end));
        checked += 1;
    }
    assert!(checked > 10, "{checked} intervals");
    assert!(max <= 1.01 * EPS, "max |s| {max} by the fine integration");
}

#[test]
fn the_ramp_lengthens_the_control_intervals_where_the_drift_changes_slowly() {
    let held = run(settings(0.05)).1;
    let ramped = run(settings(0.05).law(Dbsmc::default().hold(Hold::RampAgainstDrift))).1;
    assert!(held.bound_loss.is_none() && ramped.bound_loss.is_none());
    // Measured: 53 against 100.
    assert!(
        3 * ramped.updates < 2 * held.updates,
        "updates: ramped {}, held {}",
        ramped.updates,
        held.updates
    );
}
