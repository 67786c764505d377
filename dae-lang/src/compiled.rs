//! The compiled form of a model: names, structure and one [`Tape`] per function.
//!
//! This is the hand-off between the analysis and its two back ends: the Rust code
//! generator ([`crate::codegen`]) and the interpreter (which evaluates the tapes
//! directly). Both implement the runtime's `Model` trait from the same `CompiledModel`,
//! so they can be checked against each other.

use crate::tape::Tape;

/// Models with at most this many constraints get a dense `J_Omega` (every entry listed,
/// structural zeros included); larger ones list only the structural nonzeros.
pub const DENSE_JACOBIAN_MAX: usize = 8;

/// Everything needed to evaluate a model, as straight-line programs.
#[derive(Clone, Debug, PartialEq)]
pub struct CompiledModel {
    /// Model name.
    pub name: String,
    /// Parameters with their default values, in declaration order.
    pub params: Vec<(String, f64)>,
    /// State names.
    pub states: Vec<String>,
    /// Algebraic names.
    pub algs: Vec<String>,
    /// Constraint names.
    pub constraints: Vec<String>,
    /// Index `r_i` of each constraint.
    pub indices: Vec<usize>,
    /// `(row, col)` entries of `J_Omega`, row-major sorted.
    pub jacobian_pattern: Vec<(usize, usize)>,
    /// Initial states from parameters (outputs: one per state).
    pub init_state: Tape,
    /// Initial algebraic guesses from parameters (outputs: one per algebraic).
    pub init_alg: Tape,
    /// `f(t, x, z)` (outputs: one per state).
    pub rhs: Tape,
    /// Outputs: the w-derivatives (flat, constraint by constraint), then `s` (m), then
    /// the cheap `alpha_hat` (m). Reads `mu`.
    pub sliding: Tape,
    /// Outputs: the values of `J_Omega` at `jacobian_pattern`.
    pub jacobian: Tape,
    /// Outputs: `beta` (m).
    pub beta: Tape,
}

impl CompiledModel {
    /// Total length of the flat w-derivative array (`sum r_i`).
    pub fn w_len(&self) -> usize {
        self.indices.iter().sum()
    }

    /// The tapes with their names, in the order the code generator emits them.
    pub fn functions(&self) -> [(&'static str, &Tape); 6] {
        [
            ("initial_state", &self.init_state),
            ("initial_alg", &self.init_alg),
            ("rhs", &self.rhs),
            ("sliding", &self.sliding),
            ("jacobian", &self.jacobian),
            ("beta", &self.beta),
        ]
    }
}
