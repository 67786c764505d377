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

/// What a model is called and what it has: its name, the names of its states,
/// algebraic unknowns, constraints and parameters, and each constraint's index. One
/// value, built once, that [`Model::info`] lends; the simulator, the traces and the
/// reports read every name from it.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ModelInfo {
    /// The model's name.
    pub name: String,
    /// The names of the `n` differential states.
    pub states: Vec<String>,
    /// The names of the `m` algebraic unknowns.
    pub algs: Vec<String>,
    /// The names of the `m` constraints.
    pub constraints: Vec<String>,
    /// The names of the parameters.
    pub params: Vec<String>,
    /// The index `r_i` of each constraint (its relative degree), all at least 1.
    pub indices: Vec<usize>,
}

impl ModelInfo {
    /// The metadata from borrowed names (the constants of generated code, say).
    pub fn new(
        name: &str,
        states: &[&str],
        algs: &[&str],
        constraints: &[&str],
        params: &[&str],
        indices: &[usize],
    ) -> Self {
        let owned = |names: &[&str]| names.iter().map(|n| n.to_string()).collect();
        Self {
            name: name.to_string(),
            states: owned(states),
            algs: owned(algs),
            constraints: owned(constraints),
            params: owned(params),
            indices: indices.to_vec(),
        }
    }

    /// Whether the lists agree: one algebraic unknown and one index `>= 1` per
    /// constraint. The reason if not.
    pub fn check(&self) -> Result<(), String> {
        let m = self.constraints.len();
        if self.algs.len() != m || self.indices.len() != m {
            return Err(format!(
                "{} algebraic unknowns and {} indices for {m} constraints",
                self.algs.len(),
                self.indices.len()
            ));
        }
        if let Some(i) = self.indices.iter().position(|&r| r == 0) {
            return Err(format!(
                "constraint {i} (`{}`) has index 0; every index is at least 1",
                self.constraints[i]
            ));
        }
        Ok(())
    }
}

/// A DAE model `x' = f(t, x, z), 0 = g(t, x, z)` prepared for a sliding-mode realization.
///
/// An implementation gives its metadata once ([`Model::info`]) and the evaluations;
/// the sizes and names below are read from the metadata.
pub trait Model {
    /// The model's name, sizes, names and indices.
    fn info(&self) -> &ModelInfo;
    /// The model's name.
    fn name(&self) -> &str {
        &self.info().name
    }
    /// Number of differential states `n`.
    fn n_states(&self) -> usize {
        self.info().states.len()
    }
    /// Number of algebraic unknowns, equal to the number of constraints `m`.
    fn n_constraints(&self) -> usize {
        self.info().constraints.len()
    }
    /// Number of parameters.
    fn n_params(&self) -> usize {
        self.info().params.len()
    }
    /// Name of state `i`.
    fn state_name(&self, i: usize) -> &str {
        &self.info().states[i]
    }
    /// Name of algebraic unknown `i`.
    fn alg_name(&self, i: usize) -> &str {
        &self.info().algs[i]
    }
    /// Name of constraint `i`.
    fn constraint_name(&self, i: usize) -> &str {
        &self.info().constraints[i]
    }
    /// Name of parameter `i`.
    fn param_name(&self, i: usize) -> &str {
        &self.info().params[i]
    }
    /// The index `r_i` of each constraint (its relative degree), all at least 1.
    fn indices(&self) -> &[usize] {
        &self.info().indices
    }
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
    /// a particle) spares `J_Omega` at every step that ends without an update. Every
    /// compiled model gives it (the rate program: in the generated code, and in
    /// `family::FamilyInstance` for the interpreter and the family models, feature
    /// `families`); a hand-written model may leave it to the simulator.
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
    fn info(&self) -> &ModelInfo {
        (**self).info()
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
            fn info(&self) -> &ModelInfo { (**self).info() }
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

/// The constraint family of a constraint's name: `link[3]` is in `link` (the naming of
/// family instances), `rod` alone.
pub fn constraint_family(name: &str) -> &str {
    name.split_once('[').map_or(name, |(f, _)| f)
}

/// The constraint family ([`constraint_family`]) of each constraint, numbered in the
/// order of first appearance.
pub fn constraint_families<M: Model + ?Sized>(model: &M) -> Vec<usize> {
    let mut index: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    (0..model.n_constraints())
        .map(|i| {
            let family = constraint_family(model.constraint_name(i));
            let next = index.len();
            *index.entry(family).or_insert(next)
        })
        .collect()
}
