//! Crossings located inside the step: the bound `|s_i| <= eps_i` (up to 1 %) for any
//! step, checked against an independent fine integration between the recorded samples;
//! the located crossing time against a fine-step reference; the error-controlled step.

use crate::common;

use common::pendulum::Pendulum;
use common::{Chain, Tracking, independent_max_s, pendulum_settings as pendulum};
use dae_runtime::settings::StepEnd;
use dae_runtime::{
    Model, Settings, Simulator, Summary, Trace, settings::AlphaChoice, settings::Integrator,
};
use proptest::prelude::*;

/// A run with every step recorded; panics on failure.
fn traced<M: Model>(model: &M, settings: Settings) -> (Summary, Trace) {
    let mut trace = Trace::new();
    let s = Simulator::new(model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    (s, trace)
}

/// The bound after reaching, by the summary and by the independent fine integration.
fn assert_bound<M: Model>(label: &str, model: &M, settings: Settings, sub: usize) -> Summary {
    let (eps, mu) = (settings.layers.eps.clone(), settings.layers.mu.clone());
    let (s, trace) = traced(model, settings);
    let from = s.reaching_time.expect("reached");
    let max = s.max_abs_s.clone().expect("window entered");
    let fine = independent_max_s(model, &mu, &trace, from, sub);
    let worst = (0..eps.len()).fold(0.0f64, |w, i| w.max(max[i] / eps[i]).max(fine[i] / eps[i]));
    eprintln!("{label}: max |s| / eps after reaching {worst:.5} (summary and fine)");
    for i in 0..eps.len() {
        assert!(
            max[i] <= 1.01 * eps[i] && fine[i] <= 1.01 * eps[i],
            "{label}: constraint {i}: max |s| = {} (summary), {} (fine) against eps {}",
            max[i],
            fine[i],
            eps[i]
        );
    }
    assert!(s.bound_loss.is_none(), "{label}: {:?}", s.bound_loss);
    s
}

/// Today's rule for the fixed step before located crossings: one step moves `s` by at
/// most a fifth of the layer.
fn rule(eps: f64, gains: &[f64]) -> f64 {
    0.2 * eps / gains.iter().fold(0.0f64, |a, b| a.max(*b))
}

fn tracking(h: f64) -> Settings {
    Settings::new(vec![1e-3], vec![0.05], vec![0.2])
        .step(h)
        .t_end(2.0)
}

fn chain(h: f64) -> Settings {
    // Cheap alpha: the gain covers mu^3 |beta| <= mu^3 with a margin.
    Settings::new(vec![1e-4], vec![0.2], vec![0.012])
        .step(h)
        .t_end(2.0)
}

/// The pendulum for 5 s with its gains divided by `divisor` and the exact `alpha`.
fn weak_pendulum(integrator: Integrator, h: f64, divisor: f64) -> Settings {
    let s = pendulum(h);
    let gains = s.layers.gains.iter().map(|k| k / divisor).collect();
    Settings::new(s.layers.eps, s.layers.mu, gains)
        .alpha(AlphaChoice::Exact)
        .integrator(integrator)
        .step(h)
        .t_end(5.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// RK4 with a step from today's rule up to 100 times it: the bound holds on three
    /// models of index 2, 3 and 4.
    #[test]
    fn the_bound_holds_for_any_fixed_step(factor in 1.0f64..100.0, which in 0usize..3) {
        match which {
            0 => {
                let h = factor * rule(1e-3, &[0.2]);
                assert_bound(&format!("tracking h = {h}"), &Tracking::default(), tracking(h), 20);
            }
            1 => {
                let h = factor * rule(1e-4, &[0.012]);
                assert_bound(&format!("chain h = {h}"), &Chain, chain(h), 20);
            }
            _ => {
                let s = pendulum(1e-4);
                let h = factor * rule(0.2, &s.layers.gains);
                assert_bound(&format!("pendulum h = {h}"), &Pendulum::default(), pendulum(h), 20);
            }
        }
    }
}

#[test]
fn the_bound_holds_with_the_error_controlled_steps() {
    for integrator in [Integrator::DormandPrince, Integrator::BogackiShampine] {
        let label = |model: &str| format!("{model}, {integrator:?}");
        let s = assert_bound(
            &label("tracking"),
            &Tracking::default(),
            tracking(1.0).integrator(integrator),
            50,
        );
        assert!(s.steps < 1000, "{integrator:?}: {} steps", s.steps);
        assert_bound(
            &label("chain"),
            &Chain,
            chain(1.0).integrator(integrator),
            50,
        );
        assert_bound(
            &label("pendulum"),
            &Pendulum::default(),
            pendulum(1.0).integrator(integrator),
            50,
        );
    }
}

/// The crossing located by the simulator against a reference: from the sample at each
/// update (after reaching), the held `v` integrated with RK4 at 1e-6 s, the first time
/// `|s| = eps` by linear interpolation between the fine steps. They agree within the
/// root-finding tolerance: `|s|` is within `tol eps` of `eps` at the located crossing,
/// that is within `tol eps / |s'|` in time.
fn assert_crossing_times<M: Model>(label: &str, model: &M, settings: Settings) {
    let (eps, mu, tol) = (
        settings.layers.eps[0],
        settings.layers.mu[0],
        dae_runtime::settings::CROSSING_TOL,
    );
    let (s, trace) = traced(model, settings);
    let from = s.reaching_time.unwrap();
    let ups: Vec<f64> = trace
        .update_times()
        .iter()
        .copied()
        .filter(|&u| u > from)
        .collect();
    let t = trace.times();
    let (n, nw) = (model.n_states(), model.indices()[0]);
    let (mut w, mut sl, mut ah) = (vec![0.0; nw], [0.0], [0.0]);
    let mut checked = 0;
    for pair in ups.windows(2) {
        let (start, next) = (pair[0], pair[1]);
        let k = t.iter().position(|&x| x == start).unwrap();
        let dt = t[k + 1] - t[k];
        let v = (trace.z(k + 1)[0] - trace.z(k)[0]) / dt;
        let z0 = trace.z(k)[0];
        let mut x = trace.x(k).to_vec();
        let hf = 1e-6;
        let f = |tau: f64, x: &[f64]| -> Vec<f64> {
            let mut d = vec![0.0; n];
            model.rhs(tau, x, &[z0 + v * (tau - start)], &mut d);
            d
        };
        let mut tau = start;
        let mut prev = f64::NAN;
        let reference = loop {
            let k1 = f(tau, &x);
            let xa: Vec<f64> = (0..n).map(|i| x[i] + 0.5 * hf * k1[i]).collect();
            let k2 = f(tau + 0.5 * hf, &xa);
            let xb: Vec<f64> = (0..n).map(|i| x[i] + 0.5 * hf * k2[i]).collect();
            let k3 = f(tau + 0.5 * hf, &xb);
            let xc: Vec<f64> = (0..n).map(|i| x[i] + hf * k3[i]).collect();
            let k4 = f(tau + hf, &xc);
            for i in 0..n {
                x[i] += hf / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
            }
            tau += hf;
            let z = [z0 + v * (tau - start)];
            model.sliding(tau, &x, &z, &[mu], &mut w, &mut sl, &mut ah);
            let a = sl[0].abs();
            if a >= eps && tau > start + 10.0 * hf {
                // Between the fine steps |s| is linear to the last bits.
                break tau - hf * (a - eps) / (a - prev);
            }
            prev = a;
            assert!(tau < next + 0.1, "{label}: no crossing after {start}");
        };
        // |s'| at the reference crossing, from the last fine step.
        let rate = (sl[0].abs() - prev) / hf;
        let allowed = 1.5 * tol * eps / rate + 2.0 * hf;
        assert!(
            (next - reference).abs() <= allowed,
            "{label}: update at {next}, reference crossing {reference} (allowed {allowed:e})"
        );
        checked += 1;
    }
    assert!(checked >= 5, "{label}: {checked} intervals checked");
}

#[test]
fn located_crossings_agree_with_a_fine_step_reference() {
    assert_crossing_times(
        "tracking, RK4 h = 0.05",
        &Tracking::default(),
        tracking(0.05).t_end(0.6),
    );
    assert_crossing_times(
        "tracking, Dormand-Prince",
        &Tracking::default(),
        tracking(1.0)
            .integrator(Integrator::DormandPrince)
            .t_end(0.6),
    );
    assert_crossing_times(
        "chain (index 4), RK4 h = 0.05",
        &Chain,
        chain(0.05).t_end(0.5),
    );
}

#[test]
fn the_step_end_rule_overshoots_where_located_crossings_do_not() {
    // The same large step with the thesis's rule: the layer is left by most of a step's
    // motion, and the summary says so.
    let h = 30.0 * rule(1e-3, &[0.2]);
    let (s, _) = traced(&Tracking::default(), tracking(h).law(StepEnd::default()));
    let loss = s.bound_loss.clone().expect("the bound is lost");
    assert!(loss.worst_ratio > 1.5, "{loss:?}");
    assert_eq!(loss.first_constraint, "track");
    assert!(loss.steps_outside > 0 && loss.time_outside > 0.0);
    assert!(!s.bound_held());
    let (s, _) = traced(&Tracking::default(), tracking(h));
    assert!(s.bound_held(), "{:?}", s.bound_loss);
}

/// Gains a thirtieth and a hundredth of the pendulum's (the design's `mu^2 beta`
/// against the drift of `s'`): after an update at one level `s` turns back inside and
/// returns to the same level (most updates come from the side of the previous one), in
/// steps that start on that level. With the exact `alpha` (`s' = -k sgn(s)` right after
/// an update) only located returns keep the layer: by the summary and by an independent
/// fine integration. Each case failed before a fix: Dormand-Prince steps of 0.06 s met
/// the state tolerance but left `s` 10 % beyond the layer by the fine integration
/// (the test of each step's error in `s`, `LAYER_ERROR_PER_STEP`); RK4 steps of 0.1 s
/// fitted cubics that showed events the true `s` never reached, and the refinement
/// walked to the step's end past a real crossing (3.29 eps at 3.95 s; now the step is
/// cut at the cubic's event and looked at again).
#[test]
fn a_gain_that_only_grazes_the_layer_returns_to_its_level_without_leaving_it() {
    for (label, integrator, h, divisor) in [
        (
            "Dormand-Prince, gains / 30",
            Integrator::DormandPrince,
            1.0,
            30.0,
        ),
        ("RK4 h = 0.1, gains / 100", Integrator::Rk4, 0.1, 100.0),
        ("RK4 h = 1e-3, gains / 30", Integrator::Rk4, 1e-3, 30.0),
    ] {
        let settings = weak_pendulum(integrator, h, divisor);
        let (_, trace) = traced(&Pendulum::default(), settings.clone());
        let t = trace.times();
        let updates = trace.update_times();
        let at = |u: f64| {
            t.iter()
                .position(|&s| s == u)
                .expect("an update is a sample")
        };
        let same: usize = (0..2)
            .map(|i| {
                let side = |u: f64| trace.s(at(u))[i].signum();
                updates
                    .windows(2)
                    .filter(|w| side(w[0]) == side(w[1]))
                    .count()
            })
            .sum();
        assert!(
            same * 2 > updates.len(),
            "{label}: {same} of {} updates from the side of the previous one",
            updates.len()
        );
        assert_bound(label, &Pendulum::default(), settings, 50);
    }
}

/// The user's fixed step is the longest the runtime takes. RK4 steps of 0.1 s on the
/// pendulum with a tenth of its gains located every crossing of the integrated `s`,
/// yet the true `s` went 1.45 % beyond its layer inside them (by an independent fine
/// integration) while the summary saw nothing: the integration error of a step that
/// long, weighed into `s`, is larger than the layer's tolerance. Each fixed step now
/// bounds its estimated error in `s` by `LAYER_ERROR_PER_STEP` `eps_i`, from an embedded
/// solution built with `f` at the step's end, and is shortened (the next ones with it)
/// where it does not; explicit Euler alike. A step short enough is not changed.
#[test]
fn a_fixed_step_too_long_for_the_layer_is_shortened_to_keep_it() {
    for (label, integrator, h, divisor, shortened) in [
        ("RK4 h = 0.1, gains / 10", Integrator::Rk4, 0.1, 10.0, true),
        (
            "Euler h = 0.01, gains / 10",
            Integrator::Euler,
            0.01,
            10.0,
            true,
        ),
        ("RK4 h = 1e-4", Integrator::Rk4, 1e-4, 1.0, false),
    ] {
        let settings = weak_pendulum(integrator, h, divisor);
        let summary = assert_bound(label, &Pendulum::default(), settings, 50);
        eprintln!(
            "{label}: {} steps, {} rejected, {} cut",
            summary.steps, summary.rejected_steps, summary.located_crossings
        );
        assert_eq!(summary.rejected_steps > 0, shortened, "{label}");
    }
}
