//! The step that `Dbsmc::new` asks for: a fixed step must divide the frame, an
//! error-controlled integrator's unused `step` is not checked.

use dae_particles::{Backend, Dbsmc, FRAME, ParticleDae, ParticleModel, chain};
use dae_runtime::{Model, Settings, settings::AlphaChoice, settings::Integrator};

fn settings(model: &ParticleModel) -> Settings {
    let m = model.n_constraints();
    let eps: Vec<f64> = (0..m).map(|i| 1e-2 * model.rest_length(i)).collect();
    let mu = 0.25 * FRAME;
    let gains = eps.iter().map(|e| 8.0 * e / mu).collect();
    // 1 ms does not divide the frame of 1/60 s.
    Settings::new(eps, vec![mu; m], gains)
        .alpha(AlphaChoice::Exact)
        .step(1e-3)
}

#[test]
fn an_adaptive_integrator_needs_no_step_that_divides_the_frame() {
    let system = chain(5, 1.0).unwrap();
    let model = ParticleModel::new(&system).unwrap();
    let s = settings(&model).integrator(Integrator::DormandPrince);
    let mut backend = Dbsmc::new(model, s, "dopri").expect("the step is not used");
    backend.advance_to(FRAME).unwrap();
    assert!((backend.time() - FRAME).abs() < 1e-12, "{}", backend.time());
}

#[test]
fn a_fixed_step_that_does_not_divide_the_frame_is_refused() {
    let system = chain(5, 1.0).unwrap();
    let model = ParticleModel::new(&system).unwrap();
    let s = settings(&model).integrator(Integrator::Rk4);
    let e = Dbsmc::new(model, s, "rk4").unwrap_err();
    assert!(e.reason.contains("does not divide the frame"), "{e:?}");
}
