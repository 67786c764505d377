//! The compiled form of a model: names, structure, the programs every back end can run
//! and, for a model without sets, one [`Tape`] per function.
//!
//! This is the hand-off between the analysis and its back ends: the interpreter (which
//! runs the programs) and the Rust code generator (crate `dae-codegen`). Both implement
//! the runtime's `Model` trait from the same `CompiledModel`, so they can be checked
//! against each other.

use crate::family::FamilyModel;
use crate::tape::Tape;

/// Models with at most this many constraints get a dense `J_Omega` in their tapes (every
/// entry listed, structural zeros included); larger ones list only the structural
/// nonzeros.
pub const DENSE_JACOBIAN_MAX: usize = 8;

/// Everything needed to evaluate a model.
#[derive(Clone, Debug, PartialEq)]
pub struct CompiledModel {
    /// Model name.
    pub name: String,
    /// The scalar parameters with their default values (at the default sizes), in
    /// declaration order.
    pub params: Vec<(String, f64)>,
    /// The state declarations' names (of a family: the family's, e.g. `x`).
    pub states: Vec<String>,
    /// The algebraic declarations' names.
    pub algs: Vec<String>,
    /// The constraint declarations' names.
    pub constraints: Vec<String>,
    /// Index `r_i` of each constraint declaration.
    pub indices: Vec<usize>,
    /// The four programs over sets and the construction data (sizes, sets, maps,
    /// declarations, couplings of `J_Omega`): what the interpreter runs at any sizes. A
    /// model without sets has programs of one group each, run once.
    pub programs: Box<FamilyModel>,
    /// A model without sizes, sets or inputs (language version 1): its functions as
    /// straight-line tapes, which the analysis evaluates at the initial point (and whose
    /// initial values the code generator prints). `None` for a family model, which only
    /// construction at given sizes can evaluate.
    pub tapes: Option<Box<Tapes>>,
}

/// The functions of a model without sets as straight-line programs over its flat
/// vectors (see [`CompiledModel::tapes`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Tapes {
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
    /// Whether this is a family model: one that needs sizes to be evaluated (it has no
    /// [`CompiledModel::tapes`]).
    pub fn is_family(&self) -> bool {
        self.tapes.is_none()
    }

    /// Total length of the flat w-derivative array (`sum r_i`) of a model without
    /// sets (of a family model: per element of each constraint family, summed over the
    /// declarations).
    pub fn w_len(&self) -> usize {
        self.indices.iter().sum()
    }
}

impl Tapes {
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
