//! `Simulator::rescale_mu`: a change of `mu` during a run keeps `s` where it was,
//! scales what the design ties to `mu`, keeps the layers, and is refused where the new
//! filter would not keep `|w| <= eps` from the present state.

use crate::common;

use common::pendulum::Pendulum;
use dae_runtime::settings::{Dbsmc, GainRule};
use std::sync::LazyLock;

use dae_runtime::{
    Model, ModelInfo, Settings, SimError, Simulator, settings::AlphaChoice, settings::Integrator,
    trace::NoTrace,
};

/// `s` of `model` at the simulator's present point, evaluated apart from it.
fn s_now<M: Model>(sim: &Simulator<M>) -> Vec<f64> {
    let m = sim.model().n_constraints();
    let nw: usize = sim.model().indices().iter().sum();
    let (mut w, mut s, mut ah) = (vec![0.0; nw], vec![0.0; m], vec![0.0; m]);
    sim.model().sliding(
        sim.time(),
        sim.state(),
        sim.alg(),
        &sim.settings().layers.mu,
        &mut w,
        &mut s,
        &mut ah,
    );
    s
}

fn pendulum() -> Settings {
    let (mu, beta) = ([0.076, 0.066], [1.3e3, 2.3e3]);
    let gains = (0..2).map(|i| mu[i] * mu[i] * beta[i]).collect();
    Settings::new(vec![0.2; 2], mu.to_vec(), gains)
        .integrator(Integrator::DormandPrince)
        .alpha(AlphaChoice::Exact)
        .max_step(0.01)
        .law(Dbsmc::default().gains(GainRule::FollowDrift {
            safety: 1.0,
            graze: Some(0.02),
            raise: None,
        }))
        .t_end(4.0)
}

#[test]
fn a_rescaled_mu_keeps_s_where_it_was_scales_the_design_and_keeps_the_layers() {
    let mut sim = Simulator::new(Pendulum::default(), pendulum()).unwrap();
    sim.start(&mut NoTrace).unwrap();
    let mut changes = 0;
    for (k, factor) in [0.5, 0.5, 2.0, 0.25, 4.0].into_iter().enumerate() {
        sim.advance_to(0.5 + 0.5 * k as f64, &mut NoTrace).unwrap();
        let (x, s) = (sim.state().to_vec(), s_now(&sim));
        let before = sim.settings().clone();
        if !sim.rescale_mu(factor).unwrap() {
            assert!(
                factor > 1.0,
                "a shrinking mu was refused at t = {}",
                sim.time()
            );
            assert_eq!(sim.settings().layers.mu, before.layers.mu);
            continue;
        }
        changes += 1;
        // The states are untouched, the tensions moved so that `s` did not jump.
        assert_eq!(sim.state(), &x[..]);
        for (i, (a, b)) in s_now(&sim).iter().zip(&s).enumerate() {
            assert!(
                (a - b).abs() <= 1e-9 * before.layers.eps[i],
                "s[{i}] {b} -> {a} at t = {} (factor {factor})",
                sim.time()
            );
        }
        let set = sim.settings();
        for i in 0..2 {
            assert_eq!(set.layers.mu[i], before.layers.mu[i] * factor);
            assert_eq!(set.layers.gains[i], before.layers.gains[i] / factor);
        }
        assert_eq!(
            set.integration.max_step,
            before.integration.max_step * factor
        );
        let graze = |s: &Settings| s.law.follows_drift().and_then(|(_, g)| g);
        assert_eq!(graze(set), graze(&before).map(|g| g * factor));
    }
    assert!(changes >= 3, "only {changes} changes made");
    sim.advance_to(4.0, &mut NoTrace).unwrap();
    let summary = sim.finish(&mut NoTrace).unwrap();
    assert!(summary.bound_held(), "{:?}", summary.bound_loss);
    let max = summary.max_abs_s.unwrap();
    // Within the monitor's tolerance of the layer, as without a change.
    assert!(
        max.iter()
            .all(|&m| m <= 0.2 * (1.0 + sim.settings().bound_tol)),
        "{max:?}"
    );
}

/// Index 3 with nothing but the tension: `x' = v`, `v' = z`, `0 = x`. `s = mu^2 z + 2
/// mu v + x`, `J_Omega = 1`, `beta = 0`.
struct Slider;

impl Model for Slider {
    fn info(&self) -> &ModelInfo {
        static INFO: LazyLock<ModelInfo> =
            LazyLock::new(|| ModelInfo::new("slider", &["x", "v"], &["z"], &["rail"], &[], &[3]));
        &INFO
    }
    fn param(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn set_param(&mut self, _: usize, _: f64) {}
    fn initial_state(&self, x: &mut [f64]) {
        x.fill(0.0);
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z.fill(0.0);
    }
    fn rhs(&self, _: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = z[0];
    }
    #[allow(clippy::too_many_arguments)]
    fn sliding(
        &self,
        _: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        ah: &mut [f64],
    ) {
        w.copy_from_slice(&[x[0], x[1], z[0]]);
        s[0] = mu[0] * mu[0] * z[0] + 2.0 * mu[0] * x[1] + x[0];
        ah[0] = x[1] + 2.0 * mu[0] * z[0];
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &[(0, 0)]
    }
    fn jacobian(&self, _: f64, _: &[f64], _: &[f64], j: &mut [f64]) {
        j[0] = 1.0;
    }
    fn beta(&self, _: f64, _: &[f64], _: &[f64], b: &mut [f64]) {
        b[0] = 0.0;
    }
}

/// At `x = 0`, `v = 0.05` with `eps = 1e-2`, `mu = 0.1`: `w + mu w' = 5e-3`. The filter
/// with `mu = 0.4` would start from `w + mu w' = 0.02 > eps` (and `|s| <= eps` would not
/// keep `|w| <= eps`: its free response overshoots), so growing 4x is refused; 1.5x
/// (`7.5e-3`) is made, and so is any shrinking.
#[test]
fn a_growing_mu_is_refused_where_the_new_filter_would_leave_the_layer() {
    let settings = Settings::new(vec![1e-2], vec![0.1], vec![0.5])
        .alpha(AlphaChoice::Exact)
        .integrator(Integrator::DormandPrince)
        .initial(vec![0.0, 0.05], vec![-10.0])
        .t_end(1.0);
    let mut sim = Simulator::new(Slider, settings).unwrap();
    sim.start(&mut NoTrace).unwrap();
    assert_eq!(sim.state(), &[0.0, 0.05]);
    let s = s_now(&sim)[0];
    assert!(!sim.rescale_mu(4.0).unwrap());
    assert_eq!(sim.settings().layers.mu, vec![0.1]);
    assert_eq!(s_now(&sim)[0], s, "a refused change moved nothing");
    assert!(sim.rescale_mu(1.5).unwrap());
    assert!((sim.settings().layers.mu[0] - 0.15).abs() < 1e-15);
    assert!((s_now(&sim)[0] - s).abs() < 1e-15);
    assert!(sim.rescale_mu(0.1).unwrap());
}

#[test]
fn a_factor_that_is_not_a_positive_number_or_a_mu_that_underflows_is_an_error() {
    let mut sim = Simulator::new(Pendulum::default(), pendulum()).unwrap();
    for factor in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        match sim.rescale_mu(factor) {
            Err(SimError::Settings {
                field: "mu",
                reason,
            }) => {
                assert!(reason.contains("finite and > 0"), "{reason}")
            }
            other => panic!("factor {factor}: {other:?}"),
        }
    }
    match sim.rescale_mu(1e-300) {
        Err(SimError::Settings {
            field: "mu",
            reason,
        }) => {
            assert!(reason.contains("`link1`"), "{reason}")
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        sim.settings().layers.mu,
        vec![0.076, 0.066],
        "nothing changed"
    );
    // Before the start it changes the settings the run starts with.
    assert!(sim.rescale_mu(0.5).unwrap());
    assert_eq!(sim.settings().layers.mu, vec![0.038, 0.033]);
}
