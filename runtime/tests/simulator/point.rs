//! What the simulator records at a point is the model's at that point: every sample's
//! `s` and `w` equal a fresh evaluation of `Model::sliding` at the sample's own `(t, x,
//! z)`.
//!
//! An accepted error-controlled (or fixed, tested) step keeps the `s` that its test of
//! the error in `s` evaluated, so that test must evaluate the solution last: from
//! 65d2b22 to its fix it evaluated the embedded solution last, an accepted point
//! carried the embedded solution's `w` and `alpha_hat`, and the crossings were located
//! with them (the stability suite's 100 s double pendulum left its layer at 83.7 s).
//! Both tests below failed then (RK4: `w_1` 1.3976924062437 recorded against
//! 1.3976924062396).

use crate::common;

use common::pendulum::Pendulum;
use dae_runtime::{Model, Settings, Simulator, Trace, model::w_offsets, settings::Integrator};

fn check(integrator: Integrator) {
    let (mu, beta) = ([0.076, 0.066], [1.3e3, 2.3e3]);
    let gains = (0..2).map(|i| mu[i] * mu[i] * beta[i]).collect();
    let mut settings = Settings::new(vec![0.05; 2], mu.to_vec(), gains)
        .integrator(integrator)
        .t_end(1.0);
    if !integrator.is_adaptive() {
        settings = settings.step(1e-3);
    }
    let model = Pendulum::default();
    let mut trace = Trace::new();
    Simulator::new(&model, settings)
        .unwrap()
        .run(&mut trace)
        .unwrap();
    let offs = w_offsets(model.indices());
    let (mut w, mut s, mut ah) = (vec![0.0; offs[2]], vec![0.0; 2], vec![0.0; 2]);
    assert!(trace.len() > 100, "{} samples", trace.len());
    for k in 0..trace.len() {
        let t = trace.times()[k];
        model.sliding(t, trace.x(k), trace.z(k), &mu, &mut w, &mut s, &mut ah);
        for i in 0..2 {
            let (ws, wm) = (trace.w(k)[i], w[offs[i]]);
            assert!(
                (ws - wm).abs() <= 1e-12 * (1.0 + wm.abs()),
                "{integrator:?}: w_{i} recorded {ws:e}, the model's {wm:e} at t = {t}"
            );
            let (ss, sm) = (trace.s(k)[i], s[i]);
            assert!(
                (ss - sm).abs() <= 1e-12 * (1.0 + sm.abs()),
                "{integrator:?}: s_{i} recorded {ss:e}, the model's {sm:e} at t = {t}"
            );
        }
    }
}

#[test]
fn a_recorded_point_is_the_models_own_with_error_controlled_steps() {
    check(Integrator::DormandPrince);
    check(Integrator::BogackiShampine);
}

#[test]
fn a_recorded_point_is_the_models_own_with_fixed_steps() {
    check(Integrator::Rk4);
    check(Integrator::Euler);
}
