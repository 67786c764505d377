//! The algebraic outputs of DBSMC (`z`, `z_eq`, `z*`) against the link tensions of the
//! true motion (minimal coordinates, Newton per particle), on the generated planar
//! double pendulum.

use std::f64::consts::FRAC_PI_2;

use dae_bench::{
    generated::DoublePendulum, scenes::TRUTH_TOL, scenes::chain_scene, truth::PlanarChain,
    truth::reference,
};
use dae_runtime::{Settings, Simulator, Summary, settings::Integrator, trace::NoTrace};

#[test]
fn truth_tensions_of_a_hanging_chain_carry_the_weight_below() {
    let chain = PlanarChain::new(vec![0.1, 0.2, 0.3], vec![0.5, 1.0, 1.5], 9.8).unwrap();
    let z = chain.tensions(&[0.0; 6]);
    for (k, expect) in [0.6, 0.5, 0.3].iter().enumerate() {
        assert!((z[k] - expect * 9.8).abs() < 1e-12, "{z:?}");
    }
    // A single pendulum swinging through the bottom: T = m (g + v^2 / L).
    let one = PlanarChain::new(vec![0.2], vec![1.5], 9.8).unwrap();
    let z = one.tensions(&[0.0, 2.0]);
    assert!((z[0] - 0.2 * (9.8 + 4.0 * 1.5)).abs() < 1e-12, "{z:?}");
}

/// `z*` at a state of the true motion (on the constraints, with their rates zero) is
/// the true tension: `Omega = w'' = 0` there is the physics of a rigid link.
#[test]
fn z_star_at_true_states_is_the_true_tension() {
    let chain = PlanarChain::double_pendulum();
    let model = DoublePendulum::default();
    for y in [[0.3, -1.2, 2.5, 1.0], [-FRAC_PI_2, 0.4, -0.7, 3.0]] {
        let x = chain.cartesian(&y);
        let truth = chain.tensions(&y);
        let settings = Settings::new(vec![1e-3; 2], vec![0.05; 2], vec![1.0; 2])
            .t_end(1e-3)
            .initial(x, vec![0.0; 2]);
        let mut sim = Simulator::new(&model, settings).unwrap();
        let s = sim.finish(&mut NoTrace).unwrap();
        for i in 0..2 {
            assert!(
                (s.z_star[i] - truth[i]).abs() < 1e-9 * (1.0 + truth[i].abs()),
                "z* {:?} vs {truth:?}",
                s.z_star
            );
        }
    }
}

/// Largest error of `z`, `z_eq`, `z*` at the end of the 2 s scene against the truth.
fn errors_at_the_end(eps: f64) -> [f64; 3] {
    let chain = PlanarChain::double_pendulum();
    let model = DoublePendulum::default();
    let theta0 = [-FRAC_PI_2, -FRAC_PI_2];
    let scene = chain_scene("dp", &model, &chain, &theta0, 2.0).unwrap();
    let mu = 0.05;
    let settings = Settings::new(vec![eps; 2], vec![mu; 2], scene.gains(mu, 1.5))
        .integrator(Integrator::DormandPrince)
        .t_end(2.0)
        .initial(scene.x0.clone(), scene.z0.clone());
    let s: Summary = Simulator::new(&model, settings)
        .unwrap()
        .run(&mut NoTrace)
        .unwrap();
    assert!(s.bound_held(), "{:?}", s.bound_loss);
    let mut y0 = theta0.to_vec();
    y0.extend([0.0, 0.0]);
    let truth = chain.tensions(&reference(&chain, &y0, 2.0, TRUTH_TOL).unwrap().angles);
    let err = |z: &[f64]| (0..2).fold(0.0f64, |m, i| m.max((z[i] - truth[i]).abs()));
    [err(&s.z), err(&s.z_eq), err(&s.z_star)]
}

#[test]
fn z_star_follows_the_true_tension_to_first_order_in_eps() {
    let e: Vec<[f64; 3]> = [1e-3, 1e-4, 1e-5].map(errors_at_the_end).to_vec();
    for (k, eps) in [1e-3, 1e-4, 1e-5].iter().enumerate() {
        eprintln!(
            "eps {eps:e}: |z - T| {:.3e}, |z_eq - T| {:.3e}, |z* - T| {:.3e}",
            e[k][0], e[k][1], e[k][2]
        );
    }
    for k in 0..2 {
        // z* converges (first order: a tenfold smaller layer, about a tenfold smaller
        // error), and it is better than z and z_eq at every layer.
        let ratio = e[k][2] / e[k + 1][2];
        assert!((4.0..=40.0).contains(&ratio), "z* ratio {ratio}");
    }
    for row in &e {
        assert!(row[2] < row[0] && row[2] < row[1], "{row:?}");
    }
}

/// Issue 12's target on the work-precision scene: the designed DBSMC at eps = 1e-3
/// spends at most 8 f evaluations per control update (the step rule of before, about
/// 34), holds its layer to 1 %, and its position error is no worse than before.
#[test]
fn designed_dbsmc_needs_at_most_eight_f_evaluations_per_update() {
    use dae_bench::{harness::DbsmcStep, harness::designed_bounds, harness::run_method};
    let chain = PlanarChain::double_pendulum();
    let model = DoublePendulum::default();
    let scene = chain_scene("dp", &model, &chain, &[-FRAC_PI_2, -FRAC_PI_2], 2.0).unwrap();
    let bounds = designed_bounds(&scene, 1e-3, 1e-3).unwrap();
    let eps = 1e-3;
    let now = run_method(
        &scene,
        &bounds.dbsmc(eps, Some(DbsmcStep::Adaptive), 1e-3).unwrap(),
        1,
    );
    let before = run_method(&scene, &bounds.dbsmc(eps, None, 1e-3).unwrap(), 1);
    let per_update = |r: &dae_bench::harness::Record| r.f_evals as f64 / r.updates as f64;
    eprintln!(
        "now: {} f / {} updates = {:.2}, pos err {:.3e}, max |s| / eps {:.4}; before: {:.2}, pos err {:.3e}, max |s| / eps {:.4}",
        now.f_evals,
        now.updates,
        per_update(&now),
        now.pos_err,
        now.max_s / eps,
        per_update(&before),
        before.pos_err,
        before.max_s / eps
    );
    assert!(now.ok && before.ok);
    assert!(per_update(&now) <= 8.0, "{now:?}");
    assert!(per_update(&before) > 25.0, "{before:?}");
    assert!(now.max_s <= 1.01 * eps, "{now:?}");
    assert!(now.pos_err <= before.pos_err, "{now:?} vs {before:?}");
}
