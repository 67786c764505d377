//! The compiled form of a model: names, structure and the programs every back end runs.
//!
//! This is the hand-off between the analysis and its back ends: the interpreter (which
//! runs the programs) and the Rust code generator (crate `dae-codegen`). Both implement
//! the runtime's `Model` trait from the same `CompiledModel`, so they can be checked
//! against each other.

use crate::family::FamilyModel;

/// A model without sets with at most this many constraints lists every entry of
/// `J_Omega` (structural zeros included); larger ones list only the structural nonzeros.
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
    /// A family model: one with sizes, sets or inputs, or initial values that need the
    /// construction-time forms ([`crate::model::Model::is_family`]). A model without
    /// (language version 1) is analysed at its initial point and generated as a type
    /// whose fields are its parameters; its initial values are the construction's
    /// formulas over them ([`crate::family::Construction`]).
    pub family: bool,
}

impl CompiledModel {
    /// Whether this is a family model ([`CompiledModel::family`]).
    pub fn is_family(&self) -> bool {
        self.family
    }

    /// Total length of the flat w-derivative array (`sum r_i`) of a model without
    /// sets (of a family model: per element of each constraint family, summed over the
    /// declarations).
    pub fn w_len(&self) -> usize {
        self.indices.iter().sum()
    }
}
