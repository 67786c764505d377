//! The [`Model`] trait: what the simulator needs from a compiled DAE model.
//!
//! Implemented by the code that `dae-lang` generates (one type per model) and by the
//! interpreter adapter in `daec`. All evaluation methods write into caller-provided
//! slices so that a simulation allocates nothing per step.
//!
//! Notation (see the crate docs): `n` states `x`, `m` algebraic unknowns `z` and as many
//! constraints `0 = g_i(t, x, z)`, constraint `i` of index `r_i`. The w-derivatives of
//! all constraints are stored back to back: constraint `i` owns `w[o_i .. o_i + r_i]`
//! with `o_i = r_0 + ... + r_{i-1}`, holding `w_i, w_i', ..., w_i^(r_i - 1)` in that
//! order (see [`w_offsets`]).

/// A DAE model `x' = f(t, x, z), 0 = g(t, x, z)` prepared for a sliding-mode realization.
pub trait Model {
    /// The model's name.
    fn name(&self) -> &str;
    /// Number of differential states `n`.
    fn n_states(&self) -> usize;
    /// Number of algebraic unknowns, equal to the number of constraints `m`.
    fn n_constraints(&self) -> usize;
    /// Number of parameters.
    fn n_params(&self) -> usize;
    /// Name of state `i`.
    fn state_name(&self, i: usize) -> &str;
    /// Name of algebraic unknown `i`.
    fn alg_name(&self, i: usize) -> &str;
    /// Name of constraint `i`.
    fn constraint_name(&self, i: usize) -> &str;
    /// Name of parameter `i`.
    fn param_name(&self, i: usize) -> &str;
    /// The index `r_i` of each constraint (its relative degree), all at least 1.
    fn indices(&self) -> &[usize];
    /// Current value of parameter `i`.
    fn param(&self, i: usize) -> f64;
    /// Change parameter `i`.
    fn set_param(&mut self, i: usize, value: f64);
    /// Initial state (evaluated with the current parameters); `x.len() == n`.
    fn initial_state(&self, x: &mut [f64]);
    /// Initial guess of the algebraic unknowns; `z.len() == m`.
    fn initial_alg(&self, z: &mut [f64]);
    /// `dx = f(t, x, z)`.
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]);
    /// The w-derivatives (layout in the module docs; `w.len() == sum r_i`), the sliding
    /// variables `s_i = sum_j C(r_i-1, j) mu_i^j w_i^(j)` and the cheap
    /// `alpha_hat_i = sum_{j>=1} C(r_i-1, j-1) mu_i^(j-1) w_i^(j)`, for the given `mu`.
    #[allow(clippy::too_many_arguments)]
    fn sliding(
        &self,
        t: f64,
        x: &[f64],
        z: &[f64],
        mu: &[f64],
        w: &mut [f64],
        s: &mut [f64],
        alpha_hat: &mut [f64],
    );
    /// The structural nonzeros `(row, col)` of `J_Omega = dOmega/dz`, row-major sorted.
    /// A small dense model lists every entry.
    fn jacobian_pattern(&self) -> &[(usize, usize)];
    /// The values of `J_Omega` at the entries of [`Model::jacobian_pattern`], in order.
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]);
    /// `beta = dOmega/dt + (dOmega/dx) f`, evaluated with the current `z`.
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]);
    /// The rate of `Omega` (each constraint's highest w-derivative `w_i^(r_i - 1)`)
    /// along the motion with `z' = zdot`: `beta + J_Omega zdot`, into `rate`. Returns
    /// whether the model provides it; the default does not (`false`, `rate` untouched),
    /// and the simulator then evaluates `J_Omega` and `beta` for it.
    ///
    /// With located crossings the simulator needs `s'` at the end of every step, and an
    /// update only at some: a model that evaluates this in one pass (a particle system:
    /// one pass over its links, where `J_Omega` has an entry per pair of links sharing
    /// a particle) spares `J_Omega` at every step that ends without an update. Family
    /// models give it (their compiled rate program, in
    /// `family::FamilyInstance`, feature `families`); version-1 models do not.
    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        let _ = (t, x, z, zdot, rate);
        false
    }
}

/// Forwards every method, so that a simulator can borrow its model
/// (`Simulator::new(&model, settings)`). Parameters cannot change through a shared
/// reference: [`Model::set_param`] panics here; give the simulator the model by value
/// (or as `&mut`) to change parameters between pieces of a run.
impl<T: Model + ?Sized> Model for &T {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn n_states(&self) -> usize {
        (**self).n_states()
    }
    fn n_constraints(&self) -> usize {
        (**self).n_constraints()
    }
    fn n_params(&self) -> usize {
        (**self).n_params()
    }
    fn state_name(&self, i: usize) -> &str {
        (**self).state_name(i)
    }
    fn alg_name(&self, i: usize) -> &str {
        (**self).alg_name(i)
    }
    fn constraint_name(&self, i: usize) -> &str {
        (**self).constraint_name(i)
    }
    fn param_name(&self, i: usize) -> &str {
        (**self).param_name(i)
    }
    fn indices(&self) -> &[usize] {
        (**self).indices()
    }
    fn param(&self, i: usize) -> f64 {
        (**self).param(i)
    }
    fn set_param(&mut self, i: usize, _: f64) {
        panic!(
            "set_param({i}) on a model borrowed by shared reference: give the simulator the model by value or as &mut to change its parameters"
        )
    }
    fn initial_state(&self, x: &mut [f64]) {
        (**self).initial_state(x)
    }
    fn initial_alg(&self, z: &mut [f64]) {
        (**self).initial_alg(z)
    }
    fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
        (**self).rhs(t, x, z, dx)
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
        (**self).sliding(t, x, z, mu, w, s, alpha_hat)
    }
    fn jacobian_pattern(&self) -> &[(usize, usize)] {
        (**self).jacobian_pattern()
    }
    fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
        (**self).jacobian(t, x, z, values)
    }
    fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
        (**self).beta(t, x, z, beta)
    }
    fn omega_rate(&self, t: f64, x: &[f64], z: &[f64], zdot: &[f64], rate: &mut [f64]) -> bool {
        (**self).omega_rate(t, x, z, zdot, rate)
    }
}

macro_rules! forward_owned {
    ($($ty:ty),*) => {$(
        /// Forwards every method (parameters can change).
        impl<T: Model + ?Sized> Model for $ty {
            fn name(&self) -> &str { (**self).name() }
            fn n_states(&self) -> usize { (**self).n_states() }
            fn n_constraints(&self) -> usize { (**self).n_constraints() }
            fn n_params(&self) -> usize { (**self).n_params() }
            fn state_name(&self, i: usize) -> &str { (**self).state_name(i) }
            fn alg_name(&self, i: usize) -> &str { (**self).alg_name(i) }
            fn constraint_name(&self, i: usize) -> &str { (**self).constraint_name(i) }
            fn param_name(&self, i: usize) -> &str { (**self).param_name(i) }
            fn indices(&self) -> &[usize] { (**self).indices() }
            fn param(&self, i: usize) -> f64 { (**self).param(i) }
            fn set_param(&mut self, i: usize, value: f64) { (**self).set_param(i, value) }
            fn initial_state(&self, x: &mut [f64]) { (**self).initial_state(x) }
            fn initial_alg(&self, z: &mut [f64]) { (**self).initial_alg(z) }
            fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
                (**self).rhs(t, x, z, dx)
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
                (**self).sliding(t, x, z, mu, w, s, alpha_hat)
            }
            fn jacobian_pattern(&self) -> &[(usize, usize)] { (**self).jacobian_pattern() }
            fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
                (**self).jacobian(t, x, z, values)
            }
            fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
                (**self).beta(t, x, z, beta)
            }
            fn omega_rate(
                &self,
                t: f64,
                x: &[f64],
                z: &[f64],
                zdot: &[f64],
                rate: &mut [f64],
            ) -> bool {
                (**self).omega_rate(t, x, z, zdot, rate)
            }
        }
    )*};
}

forward_owned!(&mut T, Box<T>);

/// Offsets of each constraint's w-derivatives in the flat `w` array, plus the total
/// length as the last element (`offsets.len() == m + 1`).
pub fn w_offsets(indices: &[usize]) -> Vec<usize> {
    let mut out = Vec::with_capacity(indices.len() + 1);
    let mut acc = 0;
    out.push(0);
    for r in indices {
        acc += r;
        out.push(acc);
    }
    out
}
