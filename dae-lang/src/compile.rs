//! From the analysis to the compiled form: the programs over sets of every model
//! (`crate::family`) and, for a model without sets, each function's outputs emitted as
//! a tape (`crate::tape::emit`).

use crate::analysis::{ConstraintAnalysis, SymbolicModel};
use crate::compiled::{CompiledModel, DENSE_JACOBIAN_MAX, Tapes};
use crate::model::Model;
use crate::sym::Id;
use crate::tape::emit::{emit, emit_outputs};

/// Build the compiled form of an analysed model: `sym` holds its expressions and
/// `constraints` the constraints' names and indices. Of `model` only the declarations
/// are read: every expression, the initial values included, was lowered once by the
/// analysis.
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
        tapes: (!model.is_family()).then(|| Box::new(tapes(sym))),
    }
}

/// The tapes of a model without sets.
fn tapes(sym: &SymbolicModel) -> Tapes {
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
    Tapes {
        jacobian_pattern: pattern,
        init_state: emit(arena, &sym.init_state),
        init_alg: emit(arena, &sym.init_alg),
        rhs: emit(arena, &sym.f),
        sliding: emit(arena, &sliding),
        jacobian: emit_outputs(arena, &jac_ids),
        beta: emit(arena, &beta),
    }
}
