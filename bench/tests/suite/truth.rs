//! The truth integrator against closed forms, its self-consistency, and the Cartesian
//! mapping against the stand-in DAE's constraints.

use std::f64::consts::PI;

use dae_bench::{
    standin::PlanarChainDae, truth::ChainWork, truth::Extrapolation, truth::PlanarChain,
    truth::reference,
};
use dae_runtime::Model;

/// Complete elliptic integral of the first kind by the arithmetic-geometric mean.
fn ellip_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    while (a - b).abs() > 1e-16 * a {
        let an = 0.5 * (a + b);
        b = (a * b).sqrt();
        a = an;
    }
    PI / (2.0 * a)
}

fn integrate(chain: &PlanarChain, y: &mut [f64], t_end: f64, tol: f64) {
    let mut work = ChainWork::new(chain.links());
    let ex = Extrapolation {
        rtol: tol,
        atol: tol,
        ..Extrapolation::default()
    };
    ex.integrate(|_, y, dy| chain.derivative(y, &mut work, dy), 0.0, y, t_end)
        .unwrap();
}

#[test]
fn small_angle_pendulum_returns_after_the_linear_period() {
    // theta0 = 1e-4: the exact period exceeds 2 pi sqrt(L/g) by theta0^2/16 ~ 6e-10.
    let chain = PlanarChain::new(vec![1.0], vec![1.5], 9.81).unwrap();
    let theta0 = 1e-4;
    let period = 2.0 * PI * (1.5f64 / 9.81).sqrt();
    let mut y = [theta0, 0.0];
    integrate(&chain, &mut y, period, 1e-13);
    assert!((y[0] - theta0).abs() < 1e-9 * theta0, "theta(T) = {}", y[0]);
    // Half a period: theta = -theta0.
    let mut y = [theta0, 0.0];
    integrate(&chain, &mut y, 0.5 * period, 1e-13);
    assert!(
        (y[0] + theta0).abs() < 1e-9 * theta0,
        "theta(T/2) = {}",
        y[0]
    );
}

#[test]
fn large_amplitude_pendulum_period_matches_the_elliptic_integral() {
    // Exact period 4 sqrt(L/g) K(sin(theta0/2)) at any amplitude.
    let chain = PlanarChain::new(vec![0.3], vec![2.0], 9.8).unwrap();
    let theta0 = 2.0;
    let period = 4.0 * (2.0f64 / 9.8).sqrt() * ellip_k((theta0 / 2.0f64).sin());
    let mut y = [theta0, 0.0];
    integrate(&chain, &mut y, period, 1e-13);
    assert!(
        (y[0] - theta0).abs() < 1e-10,
        "theta(T) - theta0 = {:e}",
        y[0] - theta0
    );
    assert!(y[1].abs() < 1e-9, "omega(T) = {:e}", y[1]);
}

#[test]
fn chaotic_double_pendulum_conserves_energy_and_agrees_across_tolerances() {
    let chain = PlanarChain::double_pendulum();
    let y0 = [-PI / 2.0, -PI / 2.0, 0.0, 0.0];
    let r = reference(&chain, &y0, 5.0, 1e-13).unwrap();
    assert!(
        r.energy_drift < 1e-10,
        "relative energy drift {:e}",
        r.energy_drift
    );
    // Step halving in disguise: the 100x looser run differs by its own error only.
    assert!(
        r.error_estimate < 1e-7,
        "difference to the looser run {:e}",
        r.error_estimate
    );
    // Independent of the adaptive integrator: classical RK4 with a tiny fixed step.
    let mut y = y0;
    let mut work = ChainWork::new(2);
    let h: f64 = 2.5e-4;
    let (mut k1, mut k2, mut k3, mut k4, mut ys) =
        ([0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4]);
    for _ in 0..(5.0f64 / h).round() as usize {
        chain.derivative(&y, &mut work, &mut k1);
        for i in 0..4 {
            ys[i] = y[i] + 0.5 * h * k1[i];
        }
        chain.derivative(&ys, &mut work, &mut k2);
        for i in 0..4 {
            ys[i] = y[i] + 0.5 * h * k2[i];
        }
        chain.derivative(&ys, &mut work, &mut k3);
        for i in 0..4 {
            ys[i] = y[i] + h * k3[i];
        }
        chain.derivative(&ys, &mut work, &mut k4);
        for i in 0..4 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
    }
    let p = chain.positions(&y);
    let diff = p
        .iter()
        .zip(&r.positions)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff < 1e-8, "RK4 h = 2.5e-4 vs extrapolation: {diff:e}");
}

#[test]
fn cartesian_mapping_satisfies_the_constraints_and_their_derivative() {
    let chain = PlanarChain::new(vec![0.1, 0.2, 0.3, 0.4], vec![0.5, 1.0, 1.5, 0.7], 9.8).unwrap();
    let dae = PlanarChainDae::new(&chain).unwrap();
    let y = [0.3, -1.2, 2.5, 0.1, 1.0, -0.5, 2.0, -3.0];
    let x = chain.cartesian(&y);
    let (mut w, mut s, mut ah) = ([0.0; 12], [0.0; 4], [0.0; 4]);
    dae.sliding(0.0, &x, &[0.0; 4], &[0.1; 4], &mut w, &mut s, &mut ah);
    for k in 0..4 {
        assert!(w[3 * k].abs() < 1e-14, "link {k}: w = {:e}", w[3 * k]);
        assert!(
            w[3 * k + 1].abs() < 1e-13,
            "link {k}: w' = {:e}",
            w[3 * k + 1]
        );
    }
    // Velocities are the time derivatives of the positions (central difference along
    // theta' = omega).
    let d = 1e-6;
    let (mut yp, mut ym) = (y, y);
    for i in 0..4 {
        yp[i] += d * y[4 + i];
        ym[i] -= d * y[4 + i];
    }
    let (xp, xm) = (chain.cartesian(&yp), chain.cartesian(&ym));
    for k in 0..4 {
        for c in 0..2 {
            let fd = (xp[4 * k + c] - xm[4 * k + c]) / (2.0 * d);
            assert!(
                (fd - x[4 * k + 2 + c]).abs() < 1e-8,
                "particle {k} velocity {c}"
            );
        }
    }
}

#[test]
fn minimal_coordinate_accelerations_match_the_cartesian_dae_with_consistent_forces() {
    // Two independent derivations: Lagrange in angles and Newton with link forces.
    let chain = PlanarChain::new(vec![0.1, 0.2, 0.3], vec![0.5, 1.0, 1.5], 9.8).unwrap();
    let dae = PlanarChainDae::new(&chain).unwrap();
    let y = [0.3, -1.2, 2.5, 1.0, -0.5, 2.0];
    let x = chain.cartesian(&y);
    let z = dae_bench::baseline::consistent_alg(&dae, 0.0, &x, &[0.1; 3], &[0.0; 3]).unwrap();
    let mut dx = [0.0; 12];
    dae.rhs(0.0, &x, &z, &mut dx);
    let mut dy = [0.0; 6];
    chain.derivative(&y, &mut ChainWork::new(3), &mut dy);
    let d = 1e-5;
    let (mut yp, mut ym) = (y, y);
    for i in 0..6 {
        yp[i] += d * dy[i];
        ym[i] -= d * dy[i];
    }
    let (cp, cm) = (chain.cartesian(&yp), chain.cartesian(&ym));
    for k in 0..3 {
        for c in 0..2 {
            let fd = (cp[4 * k + 2 + c] - cm[4 * k + 2 + c]) / (2.0 * d);
            let a = dx[4 * k + 2 + c];
            assert!(
                (fd - a).abs() < 1e-6 * (1.0 + a.abs()),
                "particle {k} acc {c}: {fd} vs {a}"
            );
        }
    }
}

#[test]
fn bad_chains_and_mismatched_scenes_are_errors() {
    use dae_bench::{scenes::SceneError, scenes::chain_scene, truth::TruthError};
    assert!(matches!(
        PlanarChain::new(vec![0.1], vec![1.0, 2.0], 9.8),
        Err(TruthError::InvalidChain(_))
    ));
    assert!(matches!(
        PlanarChain::new(vec![-0.1], vec![1.0], 9.8),
        Err(TruthError::InvalidChain(_))
    ));
    let chain = PlanarChain::double_pendulum();
    assert!(matches!(
        reference(&chain, &[0.1, 0.2, 0.0], 1.0, 1e-10),
        Err(TruthError::InvalidChain(_))
    ));
    let dae = PlanarChainDae::new(&chain).unwrap();
    let three = PlanarChain::new(vec![0.1; 3], vec![1.0; 3], 9.8).unwrap();
    assert!(matches!(
        chain_scene("x", &dae, &three, &[0.0; 3], 1.0),
        Err(SceneError::Truth(TruthError::InvalidChain(_)))
    ));
}
