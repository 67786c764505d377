//! The development stand-in chain DAE against finite differences.

use dae_bench::{standin::PlanarChainDae, truth::PlanarChain};
use dae_runtime::Model;

fn model() -> (PlanarChainDae, Vec<f64>, Vec<f64>) {
    let chain = PlanarChain::new(vec![0.1, 0.2, 0.3], vec![0.5, 1.0, 1.5], 9.8).unwrap();
    let dae = PlanarChainDae::new(&chain).unwrap();
    // Off the manifold on purpose: the formulas must hold everywhere.
    let x = vec![
        0.3, -0.4, 0.5, -0.2, 1.0, -1.1, 0.1, 0.7, 1.9, -2.0, -1.0, 0.4,
    ];
    let z = vec![1.5, -0.7, 2.2];
    (dae, x, z)
}

fn derivs(dae: &PlanarChainDae, x: &[f64], z: &[f64]) -> Vec<f64> {
    let (mut w, mut s, mut ah) = (vec![0.0; 9], vec![0.0; 3], vec![0.0; 3]);
    dae.sliding(0.0, x, z, &[0.1; 3], &mut w, &mut s, &mut ah);
    w
}

/// `x +- d f(x, z)`.
fn along_flow(dae: &PlanarChainDae, x: &[f64], z: &[f64], d: f64) -> (Vec<f64>, Vec<f64>) {
    let mut f = vec![0.0; 12];
    dae.rhs(0.0, x, z, &mut f);
    let p = x.iter().zip(&f).map(|(a, b)| a + d * b).collect();
    let m = x.iter().zip(&f).map(|(a, b)| a - d * b).collect();
    (p, m)
}

#[test]
fn w_derivatives_match_central_differences_along_the_flow() {
    let (dae, x, z) = model();
    let w = derivs(&dae, &x, &z);
    let d = 1e-6;
    let (xp, xm) = along_flow(&dae, &x, &z, d);
    let (wp, wm) = (derivs(&dae, &xp, &z), derivs(&dae, &xm, &z));
    for k in 0..3 {
        for j in 0..2 {
            let fd = (wp[3 * k + j] - wm[3 * k + j]) / (2.0 * d);
            let an = w[3 * k + j + 1];
            assert!(
                (fd - an).abs() < 1e-6 * (1.0 + an.abs()),
                "link {k} w^({}) {an} vs {fd}",
                j + 1
            );
        }
    }
}

#[test]
fn beta_matches_the_central_difference_of_omega_along_the_flow() {
    let (dae, x, z) = model();
    let d = 1e-6;
    let (xp, xm) = along_flow(&dae, &x, &z, d);
    let (wp, wm) = (derivs(&dae, &xp, &z), derivs(&dae, &xm, &z));
    let mut beta = [0.0; 3];
    dae.beta(0.0, &x, &z, &mut beta);
    for k in 0..3 {
        let fd = (wp[3 * k + 2] - wm[3 * k + 2]) / (2.0 * d);
        assert!(
            (fd - beta[k]).abs() < 1e-5 * (1.0 + fd.abs()),
            "link {k}: beta {} vs {fd}",
            beta[k]
        );
    }
}

#[test]
fn jacobian_matches_central_differences_of_omega_in_z() {
    let (dae, x, z) = model();
    let pattern = dae.jacobian_pattern().to_vec();
    let mut vals = vec![0.0; pattern.len()];
    dae.jacobian(0.0, &x, &z, &mut vals);
    let mut dense = [[0.0; 3]; 3];
    for (&(i, j), v) in pattern.iter().zip(&vals) {
        dense[i][j] = *v;
    }
    let d = 1e-6;
    for j in 0..3 {
        let (mut zp, mut zm) = (z.clone(), z.clone());
        zp[j] += d;
        zm[j] -= d;
        let (wp, wm) = (derivs(&dae, &x, &zp), derivs(&dae, &x, &zm));
        for i in 0..3 {
            let fd = (wp[3 * i + 2] - wm[3 * i + 2]) / (2.0 * d);
            assert!(
                (fd - dense[i][j]).abs() < 1e-6 * (1.0 + fd.abs()),
                "J[{i}][{j}] {} vs {fd}",
                dense[i][j]
            );
        }
    }
}
