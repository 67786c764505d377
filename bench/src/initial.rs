//! Setting the initial state of any [`Model`] from outside.
//!
//! The runtime's [`Simulator`](dae_runtime::Simulator) starts from
//! [`Model::initial_state`] and [`Model::initial_alg`] and has no way to override them
//! (as of this crate's writing), so the harness wraps the model in [`WithInitial`],
//! which delegates everything except those two.

use dae_runtime::Model;

use crate::baseline::BaselineError;

/// A model with its initial state and initial algebraic guess replaced.
#[derive(Debug, Clone)]
pub struct WithInitial<'a, M: Model + ?Sized> {
    model: &'a M,
    x0: Vec<f64>,
    z0: Vec<f64>,
}

impl<'a, M: Model + ?Sized> WithInitial<'a, M> {
    /// Wrap `model`; `x0` and `z0` must have `n` and `m` values.
    pub fn new(model: &'a M, x0: Vec<f64>, z0: Vec<f64>) -> Result<Self, BaselineError> {
        let (n, m) = (model.n_states(), model.n_constraints());
        if x0.len() != n || z0.len() != m {
            return Err(BaselineError::Settings(format!(
                "initial state has {} values and guess {} for a model with {n} states and {m} unknowns",
                x0.len(),
                z0.len()
            )));
        }
        Ok(Self { model, x0, z0 })
    }
    /// The wrapped model.
    pub fn inner(&self) -> &'a M {
        self.model
    }
}

impl<M: Model + ?Sized> Model for WithInitial<'_, M> {
    fn name(&self) -> &str {
        self.model.name()
    }
    fn n_states(&self) -> usize {
        self.model.n_states()
    }
    fn n_constraints(&self) -> usize {
        self.model.n_constraints()
    }
    fn n_params(&self) -> usize {
        self.model.n_params()
    }
    fn state_name(&self, i: usize) -> &str {
        self.model.state_name(i)
    }
    fn alg_name(&self, i: usize) -> &str {
        self.model.alg_name(i)
    }
    fn constraint_name(&self, i: usize) -> &str {
        self.model.constraint_name(i)
    }
    fn param_name(&self, i: usize) -> &str {
        self.model.param_name(i)
    }
    fn indices(&self) -> &[usize] {
        self.model.indices()
    }
    fn param(&self, i: usize) -> f64 {
        self.model.param(i)
    }
    fn set_param(&mut self, _: usize, _: f64) {
        // Parameters belong to the wrapped model, which is borrowed immutably here:
        // change them on the model before wrapping it.
    }
    fn initial_state(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.x0);
    }
    fn initial_alg(&self, z: &mut [f64]) {
        z.copy_from_slice(&self.z0);
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        self.model.rhs(t, x, z, dx)
    }
    fn sliding(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        alpha_hat: &mut [f64],
    ) {
        self.model.sliding(t, x, z, mu, w, s, alpha_hat)
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        self.model.jacobian_pattern()
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        self.model.jacobian(t, x, z, values)
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        self.model.beta(t, x, z, beta)
    }
}
