//! The compiled form of a model: names, structure and one [`Tape`] per function.
//!
//! This is the hand-off between the analysis and its two back ends: the Rust code
//! generator (crate `dae-codegen`) and the interpreter (which evaluates the tapes
//! directly). Both implement the runtime's `Model` trait from the same `CompiledModel`,
//! so they can be checked against each other.
//!
//! A family model (language version 2) is compiled into
//! [`CompiledModel::family`] ([`crate::family::FamilyModel`]: programs over sets and
//! everything construction needs); its version-1 tapes are then empty, and the name
//! lists hold the templates' names (component families), not the instance's.

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
    /// The compiled form of a family model (`None` for a model without families). When
    /// set, the tapes above are empty, `params` lists the scalar parameters with their
    /// values at the default sizes, `states`, `algs` and `constraints` the names of the
    /// component families and constraint families, `indices` the index of each
    /// constraint family, and `jacobian_pattern` is empty (built at construction).
    pub family: Option<Box<crate::family::FamilyModel>>,
}

impl CompiledModel {
    /// Whether this is a family model (see [`CompiledModel::family`]).
    pub fn is_family(&self) -> bool {
        self.family.is_some()
    }

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
