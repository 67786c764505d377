//! A hand-written test model with a closed-form solution.
#![allow(dead_code)]

use dae_runtime::Model;

/// Index 2: `x' = z - x, 0 = x - sin t`; exact `x = sin t`, `z = sin t + cos t`.
/// `Omega = w' = z - x - cos t` is affine in `z`.
pub struct Tracking;

impl Model for Tracking {
    fn name(&self) -> &str {
        "tracking"
    }
    fn n_states(&self) -> usize {
        1
    }
    fn n_constraints(&self) -> usize {
        1
    }
    fn n_params(&self) -> usize {
        0
    }
    fn state_name(&self, _: usize) -> &str {
        "x"
    }
    fn alg_name(&self, _: usize) -> &str {
        "z"
    }
    fn constraint_name(&self, _: usize) -> &str {
        "track"
    }
    fn param_name(&self, _: usize) -> &str {
        ""
    }
    fn indices(&self) -> &[usize] {
        &[2]
    }
    fn param(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn set_param(&mut self, _: usize, _: f64) {}
    fn initial_state(&self, x: &mut [f64]) {
        x[0] = 0.0;
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z[0] = 0.0;
    }
    fn rhs(&self, _: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        dx[0] = z[0] - x[0];
    }
    fn sliding(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        ah: &mut [f64],
    ) {
        w[0] = x[0] - t.sin();
        w[1] = z[0] - x[0] - t.cos();
        s[0] = mu[0] * w[1] + w[0];
        ah[0] = w[1];
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &[(0, 0)]
    }
    fn jacobian(&self, _: f64, _: &[f64], _: &[f64], j: &mut [f64]) {
        j[0] = 1.0;
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], b: &mut [f64]) {
        b[0] = t.sin() - (z[0] - x[0]);
    }
}

/// Index 1 and nonlinear in `z`: `x' = -z, 0 = z^3 + z - x`. At `x = 10` the
/// algebraic equation has the single real root `z = 2`.
pub struct Cubic;

impl Model for Cubic {
    fn name(&self) -> &str {
        "cubic"
    }
    fn n_states(&self) -> usize {
        1
    }
    fn n_constraints(&self) -> usize {
        1
    }
    fn n_params(&self) -> usize {
        0
    }
    fn state_name(&self, _: usize) -> &str {
        "x"
    }
    fn alg_name(&self, _: usize) -> &str {
        "z"
    }
    fn constraint_name(&self, _: usize) -> &str {
        "cubic"
    }
    fn param_name(&self, _: usize) -> &str {
        ""
    }
    fn indices(&self) -> &[usize] {
        &[1]
    }
    fn param(&self, _: usize) -> f64 {
        f64::NAN
    }
    fn set_param(&mut self, _: usize, _: f64) {}
    fn initial_state(&self, x: &mut [f64]) {
        x[0] = 10.0;
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z[0] = 0.0;
    }
    fn rhs(&self, _: f64, _: &[f64], z: &[f64], dx: &mut [f64]) {
        dx[0] = -z[0];
    }
    fn sliding(
        &self,
        _: f64,
        x: &[f64],
        z: &[f64],
        _: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        ah: &mut [f64],
    ) {
        w[0] = z[0] * z[0] * z[0] + z[0] - x[0];
        s[0] = w[0];
        ah[0] = 0.0;
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        &[(0, 0)]
    }
    fn jacobian(&self, _: f64, _: &[f64], z: &[f64], j: &mut [f64]) {
        j[0] = 3.0 * z[0] * z[0] + 1.0;
    }
    fn beta(&self, _: f64, _: &[f64], z: &[f64], b: &mut [f64]) {
        b[0] = z[0];
    }
}
