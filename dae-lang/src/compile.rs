//! From the analysis to the compiled form: the programs over sets of every model
//! (`crate::family`).

use crate::analysis::{ConstraintAnalysis, SymbolicModel};
use crate::compiled::CompiledModel;
use crate::model::Model;

/// Build the compiled form of an analysed model: `sym` holds its expressions and
/// `constraints` the constraints' names and indices. Of `model` only the declarations
/// are read: every expression was lowered once by the analysis (the initial values are
/// the construction's, `crate::family::Construction`).
pub(crate) fn compile(
    model: &Model,
    constraints: &[ConstraintAnalysis],
    sym: &SymbolicModel,
) -> CompiledModel {
    let programs = crate::family::compile(model, constraints, sym);
    CompiledModel {
        name: model.name.clone(),
        params: model
            .params
            .iter()
            .filter(|p| p.family.over.is_none())
            .map(|p| (p.name.clone(), p.default))
            .collect(),
        states: model.states.iter().map(|s| s.name.clone()).collect(),
        algs: model.algs.iter().map(|a| a.name.clone()).collect(),
        constraints: model.constraints.iter().map(|c| c.name.clone()).collect(),
        indices: constraints.iter().map(|c| c.index).collect(),
        programs: Box::new(programs),
        family: model.is_family(),
    }
}
