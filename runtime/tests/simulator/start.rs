//! `design::consistent_start`: the algebraic start values at which every constraint's
//! highest w-derivative vanishes, checked against closed forms and the hand-written
//! pendulum's analytic `Omega`.

use std::sync::LazyLock;

use crate::common::{self, Tracking, pendulum::Pendulum};
use dae_runtime::design::{StartError, consistent_start};
use dae_runtime::{Model, ModelInfo, Settings, Simulator, Trace};

/// The double pendulum hanging straight down at rest.
fn hanging() -> Vec<f64> {
    let mut x = vec![0.0; 12];
    x[2] = -2.0;
    x[5] = -4.0;
    x
}

#[test]
fn a_pendulum_hanging_at_rest_gets_the_static_tensions() {
    let p = Pendulum::default();
    let start = consistent_start(&p, 0.0, &hanging(), &[0.0, 0.0]).unwrap();
    // Closed form: the lower link carries m2 g, the upper one (m1 + m2) g.
    let (z1, z2) = ((p.m1 + p.m2) * p.g, p.m2 * p.g);
    assert!((start.z0[0] - z1).abs() <= 1e-12 * z1, "{:?}", start.z0);
    assert!((start.z0[1] - z2).abs() <= 1e-12 * z2, "{:?}", start.z0);
    // From z = 0 the accelerations are free fall against the pin: Omega_1 = g.
    assert!((start.residual_before - p.g).abs() < 1e-12);
    assert_eq!(start.worst_before, 0);
    assert!(start.residual_after <= 1e-12, "{}", start.residual_after);
    // Linear in z: one step solves it, the second only confirms.
    assert!((1..=2).contains(&start.iterations), "{}", start.iterations);
}

#[test]
fn a_swinging_pendulum_gets_the_z_its_omega_vanishes_at() {
    let p = Pendulum::default();
    // Both links at their lengths, swinging: centripetal terms enter Omega.
    let mut x = vec![0.0; 12];
    let (a, b) = (0.3f64, -0.7f64);
    x[0] = 2.0 * a.sin();
    x[2] = -2.0 * a.cos();
    x[3] = x[0] + 2.0 * b.sin();
    x[5] = x[2] - 2.0 * b.cos();
    x[6..9].copy_from_slice(&[1.5 * a.cos(), 0.4, 1.5 * a.sin()]);
    x[9..12].copy_from_slice(&[-0.8, 1.1, 0.2]);
    let start = consistent_start(&p, 0.0, &x, &[0.0, 0.0]).unwrap();
    // The oracle: the pendulum's analytic Omega at the values found.
    let omega = p.omega(&x, &start.z0);
    for (i, o) in omega.iter().enumerate() {
        assert!(o.abs() <= 1e-10, "Omega_{i} = {o} at z0 = {:?}", start.z0);
    }
}

#[test]
fn consistent_values_are_kept_without_an_iteration() {
    // The index-4 chain starts at z = -cos 0, where w''' = z + cos t vanishes.
    let start = consistent_start(&common::Chain, 0.0, &[0.0, 1.0, 0.0], &[-1.0]).unwrap();
    assert_eq!(start.z0, vec![-1.0]);
    assert_eq!(start.iterations, 0);
    assert_eq!(start.residual_before, 0.0);
}

#[test]
fn a_singular_j_omega_is_named() {
    let model = Tracking {
        singular: true,
        ..Tracking::default()
    };
    let err = consistent_start(&model, 0.0, &[0.5], &[0.0]).unwrap_err();
    assert_eq!(
        err,
        StartError::Singular {
            constraints: vec![0]
        }
    );
}

#[test]
fn wrong_lengths_are_an_error_not_a_panic() {
    let err = consistent_start(&Pendulum::default(), 0.0, &[0.0; 3], &[0.0; 2]).unwrap_err();
    assert!(matches!(err, StartError::Mismatch(_)), "{err}");
}

/// Index 1 and nonlinear in `z`: `x' = -x`, `0 = z^3 + z - 2 + x` (`J_Omega = 3 z^2 + 1`).
struct Cubic;

impl Model for Cubic {
    fn info(&self) -> &ModelInfo {
        static INFO: LazyLock<ModelInfo> =
            LazyLock::new(|| ModelInfo::new("cubic", &["x"], &["z"], &["c"], &[], &[1]));
        &INFO
    }
    fn param(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn set_param(&mut self, _: usize, _: f64) {}
    fn initial_state(&self, x: &mut [f64]) {
        x[0] = 0.0;
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z[0] = -3.0;
    }
    fn rhs(&self, _: f64, x: &[f64], _: &[f64], dx: &mut [f64]) {
        dx[0] = -x[0];
    }
    fn sliding(
        &self,
        _: f64,
        x: &[f64],
        z: &[f64],
        _: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        a: &mut [f64],
    ) {
        w[0] = z[0].powi(3) + z[0] - 2.0 + x[0];
        s[0] = w[0];
        a[0] = 0.0;
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &[(0, 0)]
    }
    fn jacobian(&self, _: f64, _: &[f64], z: &[f64], j: &mut [f64]) {
        j[0] = 3.0 * z[0] * z[0] + 1.0;
    }
    fn beta(&self, _: f64, x: &[f64], _: &[f64], b: &mut [f64]) {
        b[0] = -x[0];
    }
}

#[test]
fn a_nonlinear_dependence_on_z_converges_from_far_away() {
    // The only real root of z^3 + z - 2 is z = 1.
    let start = consistent_start(&Cubic, 0.0, &[0.0], &[-3.0]).unwrap();
    assert!((start.z0[0] - 1.0).abs() <= 1e-12, "{:?}", start.z0);
    assert!(start.iterations > 2, "{}", start.iterations);
    assert!(start.residual_after <= 1e-12);
}

#[test]
fn a_run_from_consistent_values_starts_inside_its_layers() {
    // At rest and consistent, the hanging pendulum has s = 0 at the start: no reaching.
    let p = Pendulum::default();
    let x = hanging();
    let start = consistent_start(&p, 0.0, &x, &[0.0, 0.0]).unwrap();
    let settings = Settings::new(vec![1e-3; 2], vec![0.05; 2], vec![0.5; 2])
        .t_end(0.05)
        .initial(x.clone(), start.z0.clone());
    let mut trace = Trace::new();
    let summary = Simulator::new(&p, settings.clone())
        .unwrap()
        .run(&mut trace)
        .unwrap();
    assert_eq!(summary.reaching_updates, 0);
    assert_eq!(summary.reaching_time, Some(0.0));
    // From z = 0 it must reach first: s_1 = mu^2 g is far outside the layer.
    let given = Simulator::new(&p, settings.initial(x, vec![0.0, 0.0]))
        .unwrap()
        .run(&mut Trace::new())
        .unwrap();
    assert!(given.reaching_updates > 0);
}
