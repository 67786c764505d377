//! From the analysis to the compiled form: each function's outputs emitted as a tape
//! (`crate::tape::emit`), for a version-1 model, or as the programs over sets of a
//! family model (`crate::family`).

use crate::analysis::{ConstraintAnalysis, SymbolicModel};
use crate::compiled::{CompiledModel, DENSE_JACOBIAN_MAX};
use crate::model::Model;
use crate::sym::Id;
use crate::tape::emit::{emit, emit_outputs};
/// Build the compiled form of an analysed model: `sym` holds its expressions and
/// `constraints` the constraints' names and indices. Of `model` only the names and
/// parameter defaults are read: every expression, the initial values included, was
/// lowered once by the analysis.
pub(crate) fn compile(
    model: &Model,
    constraints: &[ConstraintAnalysis],
    sym: &SymbolicModel,
) -> CompiledModel {
    if model.is_family() {
        return crate::family::compile(model, constraints, sym);
    }
    let arena = &sym.arena;
    let m = sym.constraints.len();
    let mut pattern: Vec<(usize, usize)> = Vec::new();
    let mut jac_ids: Vec<Option<Id>> = Vec::new();
    for (row, c) in sym.constraints.iter().enumerate() {
        if m <= DENSE_JACOBIAN_MAX {
            for col in 0..m {
                pattern.push((row, col));
                jac_ids.push(
                    c.jacobian_row
                        .iter()
                        .find(|(k, _)| k.index() == col)
                        .map(|(_, id)| *id),
                );
            }
        } else {
            for (col, id) in &c.jacobian_row {
                pattern.push((row, col.index()));
                jac_ids.push(Some(*id));
            }
        }
    }

    let mut sliding: Vec<Id> = sym
        .constraints
        .iter()
        .flat_map(|c| c.w.iter().copied())
        .collect();
    sliding.extend(sym.constraints.iter().map(|c| c.s));
    sliding.extend(sym.constraints.iter().map(|c| c.alpha_hat));
    let beta: Vec<Id> = sym.constraints.iter().map(|c| c.beta).collect();

    CompiledModel {
        name: model.name.clone(),
        params: model
            .params
            .iter()
            .map(|p| (p.name.clone(), p.default))
            .collect(),
        states: sym.names.states.clone(),
        algs: sym.names.algs.clone(),
        constraints: constraints.iter().map(|c| c.name.clone()).collect(),
        indices: constraints.iter().map(|c| c.index).collect(),
        jacobian_pattern: pattern,
        init_state: emit(arena, &sym.init_state),
        init_alg: emit(arena, &sym.init_alg),
        rhs: emit(arena, &sym.f),
        sliding: emit(arena, &sliding),
        jacobian: emit_outputs(arena, &jac_ids),
        beta: emit(arena, &beta),
        family: None,
    }
}
