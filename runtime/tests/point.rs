//! What the simulator records at a point is the model's at that point: every sample's
//! `s` and `w` equal a fresh evaluation of `Model::sliding` at the sample's own `(t, x,
//! z)`.
//!
//! **Known bug, open (ignored until fixed).** Since commit 65d2b22 an accepted
//! error-controlled (or fixed, tested) step keeps the `s` its test of the error in `s`
//! evaluated instead of evaluating it again; that test (`trial_layer_error`) evaluates
//! the embedded solution last, so an accepted point carries the embedded solution's
//! `w` and `alpha_hat`, not the solution's, and the crossings are located with them.
//! The stability suite's double pendulum (uniform `mu = 0.05`, eps = 5e-4, 100 s)
//! leaves its layer at 83.7 s (3.2 eps); it held before. Evaluating the embedded
//! solution first makes these tests pass and that run hold again (bit for bit as
//! before 65d2b22), but then `daec run` of the 8 x 8 cloth with the frame-tied
//! settings (cli/tests/family.rs) stops with a step-size underflow at 0.028 s: the
//! fix is not landed until that is understood (issue 13's closing note of
//! 2026-11-26).

mod common;

use common::pendulum::Pendulum;
use dae_runtime::{Integrator, Model, Settings, Simulator, Trace, w_offsets};

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
#[ignore = "known bug since 65d2b22: accepted points carry the embedded solution's w and alpha_hat (module docs)"]
fn a_recorded_point_is_the_models_own_with_error_controlled_steps() {
    check(Integrator::DormandPrince);
    check(Integrator::BogackiShampine);
}

#[test]
#[ignore = "known bug since 65d2b22: accepted points carry the embedded solution's w and alpha_hat (module docs)"]
fn a_recorded_point_is_the_models_own_with_fixed_steps() {
    check(Integrator::Rk4);
    check(Integrator::Euler);
}
