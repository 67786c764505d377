//! Baselines (a), (b), (c) against closed forms and the truth.

use crate::common;

use dae_runtime::settings::Law;
use std::f64::consts::FRAC_PI_2;

use common::{Cubic, Tracking};
#[cfg(feature = "bdf")]
use dae_bench::{baseline::BdfSettings, baseline::bdf_index1};
use dae_bench::{
    baseline::IndexOneRk4, baseline::IndexOneSettings, baseline::ZSolver,
    baseline::largest_stable_step, baseline::spsm_stable, generated::DoublePendulum,
    harness::Method, harness::run_method, scenes::chain_scene, truth::PlanarChain,
};
use dae_runtime::{Settings, Simulator, trace::NoTrace};

#[test]
fn index_one_keeps_s_at_round_off_with_one_newton_iteration_per_stage_on_an_affine_model() {
    let chain = PlanarChain::double_pendulum();
    let dae = DoublePendulum::default();
    let scene = chain_scene("dp", &dae, &chain, &[-FRAC_PI_2, -1.0], 1.0).unwrap();
    let set = IndexOneSettings {
        mu: vec![0.05; 2],
        step: 1e-3,
        t_start: 0.0,
        t_end: 1.0,
        newton_tol: 1e-12,
        initial: Some(scene.initial()),
    };
    let s = IndexOneRk4::new(&dae, set).unwrap().run(None).unwrap();
    assert!(
        s.max_abs_s.iter().all(|v| *v <= 1e-12),
        "max |s| {:?}",
        s.max_abs_s
    );
    assert!(
        s.max_abs_w.iter().all(|v| *v <= 1e-9),
        "max |w| {:?}",
        s.max_abs_w
    );
    // Omega is affine in z: every stage needs at most one J_s solve.
    assert!(
        s.j_solves <= 4 * s.steps + 1,
        "{} solves for {} steps",
        s.j_solves,
        s.steps
    );
}

#[test]
fn index_one_reproduces_the_closed_form_of_the_tracking_model() {
    let set = IndexOneSettings {
        mu: vec![0.1],
        step: 1e-3,
        t_start: 0.0,
        t_end: 2.0,
        newton_tol: 1e-13,
        initial: None,
    };
    let s = IndexOneRk4::new(&Tracking::default(), set)
        .unwrap()
        .run(None)
        .unwrap();
    assert!(
        (s.x[0] - 2.0f64.sin()).abs() < 1e-12,
        "x(2) - sin 2 = {:e}",
        s.x[0] - 2.0f64.sin()
    );
    assert!(
        (s.z[0] - 2.0f64.sin() - 2.0f64.cos()).abs() < 1e-11,
        "z(2) = {}",
        s.z[0]
    );
}

#[test]
fn index_one_matches_the_truth_of_the_double_pendulum() {
    let chain = PlanarChain::double_pendulum();
    let dae = DoublePendulum::default();
    let scene = chain_scene("dp", &dae, &chain, &[-FRAC_PI_2, -FRAC_PI_2], 1.0).unwrap();
    let rk = run_method(
        &scene,
        &Method::IndexOne {
            mu: 0.05,
            step: 5e-4,
        },
        1,
    );
    assert!(rk.ok && rk.pos_err < 1e-9, "index-1 RK4: {rk:?}");
}

#[cfg(feature = "bdf")]
#[test]
fn bdf_matches_the_truth_of_the_double_pendulum() {
    let chain = PlanarChain::double_pendulum();
    let dae = DoublePendulum::default();
    let scene = chain_scene("dp", &dae, &chain, &[-FRAC_PI_2, -FRAC_PI_2], 1.0).unwrap();
    let set = BdfSettings {
        mu: vec![0.05; 2],
        rtol: 1e-10,
        atol: 1e-10,
        t_start: 0.0,
        t_end: 1.0,
        initial: Some(scene.initial()),
    };
    let b = bdf_index1(&dae, &set, None).unwrap();
    let err = scene.position_error(&b.x);
    assert!(err < 1e-6, "BDF position error {err:e}");
    assert!(
        b.max_abs_w.iter().all(|w| *w < 1e-6),
        "BDF max|w| {:?}",
        b.max_abs_w
    );
    assert!((b.t_end - 1.0).abs() < 1e-12);
}

#[test]
fn step_search_brackets_a_known_threshold() {
    let threshold = 0.0123;
    let r = largest_stable_step(|h| h <= threshold, 1e-5, 1.0, 20);
    let (s, u) = (r.stable.unwrap(), r.unstable.unwrap());
    assert!(s <= threshold && u > threshold && u / s < 1.001, "{r:?}");
    assert_eq!(r.trials, 22);
    assert_eq!(
        largest_stable_step(|_| true, 1e-5, 1.0, 5).stable,
        Some(1.0)
    );
    assert_eq!(largest_stable_step(|_| false, 1e-5, 1.0, 5).stable, None);
}

#[test]
fn spsm_holds_at_a_small_step_and_not_at_a_large_one() {
    let chain = PlanarChain::double_pendulum();
    let dae = DoublePendulum::default();
    let scene = chain_scene("dp", &dae, &chain, &[-FRAC_PI_2, -FRAC_PI_2], 1.0).unwrap();
    let eps = vec![1e-3; 2];
    let run = |h: f64| {
        let set = Settings::new(eps.clone(), vec![0.05; 2], scene.gains(0.05, 1.5))
            .step(h)
            .t_end(1.0)
            .law(Law::Spsm)
            .check_robustness(false);
        Simulator::new(&dae, set.initial(scene.x0.clone(), scene.z0.clone()))
            .unwrap()
            .run(&mut NoTrace)
    };
    let small = run(1e-4).unwrap();
    assert!(spsm_stable(&small, &eps), "{small:?}");
    // Far beyond RK4's stability limit of the layer dynamics (h k / eps ~ 1e2).
    match run(0.2) {
        Err(_) => {}
        Ok(big) => assert!(!spsm_stable(&big, &eps), "{big:?}"),
    }
}

#[test]
fn z_solver_iterates_newton_to_the_root_of_a_nonlinear_constraint() {
    let mut zs = ZSolver::new(&Cubic::default(), &[1.0], 1e-13).unwrap();
    let mut z = [0.0f64];
    let iters = zs.solve(&Cubic::default(), 0.0, &[10.0], &mut z).unwrap();
    assert!((z[0] - 2.0).abs() < 1e-14, "z = {}", z[0]);
    assert!(iters > 2, "{iters} iterations from z = 0");
    assert_eq!(zs.j_solves, iters as u64);
    assert!(zs.sliding()[0].abs() <= 1e-13);
}

#[cfg(not(feature = "bdf"))]
#[test]
fn bdf_method_without_the_feature_is_a_recorded_error() {
    let chain = PlanarChain::double_pendulum();
    let dae = DoublePendulum::default();
    let scene = chain_scene("dp", &dae, &chain, &[-FRAC_PI_2, -FRAC_PI_2], 0.1).unwrap();
    let r = run_method(
        &scene,
        &Method::Bdf {
            mu: 0.05,
            tol: 1e-6,
        },
        1,
    );
    assert!(!r.ok);
    assert_eq!(r.error, dae_bench::harness::BDF_MISSING);
}
