//! The one-call design of the particle API ([`Dbsmc::online`], [`online_settings`]):
//! the frame-tied design of the runtime at the scene's frame, layers relative to each
//! link's length, holding its strain bound on a heavy-ended chain; a bound that is no
//! bound is refused with what is wrong.

use dae_particles::{
    Backend, Dbsmc, FRAME, ParticleDae, ParticleModel, Scene, chain, online_settings,
};
use dae_runtime::{Model, design::Online};

/// The settings are the runtime's online design at the scene's frame, with layers of
/// `eps` times each link's rest length (here a chain whose end particle is 100 times
/// heavier: the links' rest lengths are all 1/N, the layers too).
#[test]
fn online_settings_are_the_frame_tied_design_with_layers_relative_to_each_link() {
    assert_eq!(
        Online::default().frame,
        FRAME,
        "the design's frame is the scene's"
    );
    let model = ParticleModel::new(&chain(6, 1e2).unwrap()).unwrap();
    let s = online_settings(&model, 2e-3).unwrap();
    let m = model.n_constraints();
    let layers: Vec<f64> = (0..m).map(|i| 2e-3 * model.rest_length(i)).collect();
    assert_eq!(s.layers.eps, layers);
    let want = Online::default().settings(layers).unwrap();
    assert_eq!(s.layers.mu, want.layers.mu);
    assert_eq!(s.layers.mu[0], FRAME / 4.0);
    assert!(
        s.law.follows_drift().is_some(),
        "the gains follow the drift"
    );
}

/// A chain of 10 links whose end is 100 times heavier than the other particles,
/// released horizontal, run for half a second (the swing down, where the end pulls
/// hardest) with every link within 0.1 % of its length: at every frame the worst
/// strain is within 1.05 eps, and no sliding layer was left.
#[test]
fn the_online_backend_holds_the_strain_bound_on_a_heavy_ended_chain() {
    let eps = 1e-3;
    let system = chain(10, 1e2).unwrap();
    let model = ParticleModel::new(&system).unwrap();
    let backend = Dbsmc::online(model, eps, "online").unwrap();
    let mut scene = Scene::new(&system, backend).unwrap();
    for _ in 0..30 {
        let frame = scene.step().unwrap();
        assert!(
            frame.strain <= 1.05 * eps,
            "strain {} on link {} at frame {}",
            frame.strain,
            frame.link,
            frame.index
        );
    }
    let counters = scene.backend().counters();
    assert_eq!(counters.layer_lost_at(), None);
    assert!(
        counters.updates() > 0,
        "the control was updated: {counters:?}"
    );
    // The end fell: it is well below where it started.
    assert!(
        scene.positions()[10][2] < -0.3,
        "{:?}",
        scene.positions()[10]
    );
}

/// A strain bound that is zero, negative or not a number is an error naming the
/// bound, from the settings and from the backend alike, never a panic.
#[test]
fn a_bound_that_is_not_positive_is_refused_with_its_value() {
    let system = chain(3, 1.0).unwrap();
    for eps in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let model = ParticleModel::new(&system).unwrap();
        let e = online_settings(&model, eps).unwrap_err();
        assert!(e.to_string().contains("eps"), "{e}");
        let e = Dbsmc::online(model, eps, "bad").unwrap_err();
        assert_eq!(e.method, "bad");
        assert!(
            e.reason.contains("online design") && e.reason.contains("eps"),
            "{e}"
        );
    }
}
