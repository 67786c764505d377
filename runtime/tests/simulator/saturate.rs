//! The law saturated inside the layer ([`Settings::saturate_in_layer`]): the rate the
//! simulator's control asks for, read back from the tracking model's closed-form `s'`,
//! at updates forced inside the layer; and the layer kept, by an independent fine
//! integration of the held `z`.

use crate::common;

use common::{
    TRACKING_EPS as EPS, TRACKING_MU as MU, Tracking, tracking_max_s, tracking_settings as settings,
};
use dae_runtime::settings::{Dbsmc, InLayer};
use dae_runtime::{Settings, Simulator, Trace};

const GAIN: f64 = 0.05;

/// `s` and `s'` of the tracking model at `(t, x, z)` with `v` held, from its equations:
/// `s = mu (z - x - cos t) + (x - sin t)`, `s' = mu (v - (z - x) + sin t) + (z - x -
/// cos t)` along `x' = z - x`, `z' = v`.
fn s_and_rate(t: f64, x: f64, z: f64, v: f64) -> (f64, f64) {
    let s = MU * (z - x - t.cos()) + (x - t.sin());
    let ds = MU * (v - (z - x) + t.sin()) + (z - x - t.cos());
    (s, ds)
}

/// Updates forced at `t = 1.0, 1.1, ... 2.9`: for each, `s` there and the rate `s'`
/// right after it, from the closed form with the `v` the run then holds (read from `z`
/// a microsecond later: `z` is linear while `v` is held).
fn rates_at_forced_updates(settings: Settings) -> Vec<(f64, f64)> {
    let mut sim = Simulator::new(Tracking::default(), settings).unwrap();
    let mut trace = Trace::new();
    sim.start(&mut trace).unwrap();
    let mut out = Vec::new();
    for j in 0..20 {
        let t = 1.0 + 0.1 * j as f64;
        sim.advance_to(t, &mut trace).unwrap();
        sim.request_update();
        let (x, z) = (sim.state()[0], sim.alg()[0]);
        let dt = 1e-6;
        let before = trace.update_times().len();
        sim.advance_to(t + dt, &mut trace).unwrap();
        assert_eq!(
            trace.update_times().len(),
            before + 1,
            "one update at t = {t}"
        );
        let v = (sim.alg()[0] - z) / dt;
        out.push(s_and_rate(t, x, z, v));
    }
    out
}

#[test]
fn saturated_inside_the_layer_the_rate_is_the_gain_times_s_over_eps() {
    let sat =
        rates_at_forced_updates(settings(GAIN).law(Dbsmc::default().in_layer(InLayer::Saturate)));
    let sgn = rates_at_forced_updates(settings(GAIN));
    let inside = |r: &[(f64, f64)]| r.iter().filter(|(s, _)| s.abs() < 0.9 * EPS).count();
    assert!(inside(&sat) >= 5, "{sat:?}");
    assert!(inside(&sgn) >= 5, "{sgn:?}");
    for &(s, ds) in &sat {
        let want = -GAIN * (s / EPS).clamp(-1.0, 1.0);
        assert!(
            (ds - want).abs() <= 1e-6 * GAIN,
            "saturated: s = {s:e}, s' = {ds:e}, -k sat(s/eps) = {want:e}"
        );
    }
    // The method's own law at the same kind of points: the full gain, whatever s.
    for &(s, ds) in &sgn {
        let want = -GAIN * s.signum();
        assert!(
            (ds - want).abs() <= 1e-6 * GAIN,
            "sgn: s = {s:e}, s' = {ds:e}, -k sgn(s) = {want:e}"
        );
    }
}

#[test]
fn the_saturated_run_keeps_the_layer_by_an_independent_fine_integration() {
    let mut trace = Trace::new();
    let summary = Simulator::new(
        Tracking::default(),
        settings(GAIN).law(Dbsmc::default().in_layer(InLayer::Saturate)),
    )
    .unwrap()
    .run(&mut trace)
    .unwrap();
    assert!(summary.bound_loss.is_none(), "{:?}", summary.bound_loss);
    let from = summary.reaching_time.expect("reached");
    let (t, updates) = (trace.times(), trace.update_times());
    let (mut max, mut checked) = (0.0f64, 0);
    for (j, &tb) in updates.iter().enumerate() {
        let end = updates.get(j + 1).copied().unwrap_or(3.0);
        let Some(k) = t.iter().position(|&s| s == tb) else {
            continue;
        };
        if tb < from || k + 1 >= t.len() || t[k + 1] > end {
            continue;
        }
        // The interval's z from the held v (read from the trace).
        let zb = trace.z(k)[0];
        let v = (trace.z(k + 1)[0] - zb) / (t[k + 1] - tb);
        let z = |tau: f64| zb + v * (tau - tb);
        max = max.max(tracking_max_s(z, (tb, trace.x(k)[0]), end));
        checked += 1;
    }
    assert!(checked > 10, "{checked} intervals");
    assert!(max <= 1.01 * EPS, "max |s| {max} by the fine integration");
}
