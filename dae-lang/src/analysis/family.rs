//! What the analysis of a family model adds, on its templates (nothing here depends on
//! the sizes): `J_Omega` as kernels with the couplings they hold in, and the check that
//! every input is given with the derivatives the functions read.

use super::{ConstraintAnalysis, Kernel, SymbolicModel, family_name, text::wname};
use crate::diag::Diagnostic;
use crate::model::{ConstraintDef, Model};
use crate::sym::{Arena, Id, Names, Node, jacobian_terms};
use crate::{AlgId, VarRef};

/// The kernels of `J_Omega` of a constraint family: one per coupling (the unknown and
/// the maps its rows and columns meet through), each a sum of row times column factors.
pub(super) fn kernels(
    arena: &mut Arena,
    names: &Names,
    def: &ConstraintDef,
    omega: Id,
    cols: &[AlgId],
) -> Result<Vec<Kernel>, Diagnostic> {
    let mut kernels = Vec::new();
    for &k in cols {
        let terms = jacobian_terms(arena, omega, k).map_err(|_| two_hop(names, def, k))?;
        for t in terms {
            // A row factor whose node is scalar in a family: lifted through the unit.
            let row_map = if arena.ctx(omega).is_none() && def.over.is_some() {
                let unit = arena.maps_mut().to_unit(def.over, def.span);
                arena.maps_mut().compose(unit, t.row_map)
            } else {
                t.row_map
            };
            match kernels.iter_mut().find(|x: &&mut Kernel| {
                x.alg == k && x.row_map == row_map && x.col_map == t.col_map
            }) {
                Some(x) => x.terms.push((t.row, t.col)),
                None => kernels.push(Kernel {
                    alg: k,
                    row_map,
                    col_map: t.col_map,
                    terms: vec![(t.row, t.col)],
                }),
            }
        }
    }
    Ok(kernels)
}

fn two_hop(names: &Names, def: &ConstraintDef, k: AlgId) -> Diagnostic {
    let z = names.var(VarRef::Alg(k));
    Diagnostic::new(
        format!(
            "constraint `{}` couples with `{z}` through two maps, which the kernels of J_Omega do not support",
            def.name
        ),
        def.span,
        format!("dOmega/d{z} reaches `{z}` inside a sum at another element than the summation element"),
    )
    .hint(format!(
        "inside `sum(k in K where m[k] == q) ...`, use `{z}[k]` itself (not `{z}[g[k]]`): a row meets a column \
         through one shared element; write the coupling with a `let` over the set of `{z}` and sum that"
    ))
}

/// Every input read by a function at a derivative it does not give: located at the
/// input's declaration, naming the derivative and where it is needed.
pub(super) fn check_inputs(
    model: &Model,
    summaries: &[ConstraintAnalysis],
    sym: &SymbolicModel,
) -> Result<(), Vec<Diagnostic>> {
    if model.inputs.is_empty() {
        return Ok(());
    }
    let arena = &sym.arena;
    // (what needs it, the constraint if any, its roots), in the order of the functions.
    let mut places: Vec<(String, Option<usize>, Vec<Id>)> = Vec::new();
    for (k, &f) in sym.f.iter().enumerate() {
        places.push((format!("der({})", model.states[k].name), None, vec![f]));
    }
    for (i, (c, s)) in sym.constraints.iter().zip(summaries).enumerate() {
        for (j, &w) in c.w.iter().enumerate() {
            places.push((wname(&s.name, j, s.index), Some(i), vec![w]));
        }
        let factors: Vec<Id> = c
            .kernels
            .iter()
            .flat_map(|k| k.terms.iter().flat_map(|t| [t.0, t.1]))
            .collect();
        places.push((format!("J_Omega of `{}`", s.name), Some(i), factors));
        places.push((format!("beta_{}", s.name), Some(i), vec![c.beta]));
    }
    // Per input component: the highest derivative read and the first place reading it.
    let mut need: Vec<Option<(u8, usize)>> = vec![None; model.inputs.len()];
    for (p, (_, _, roots)) in places.iter().enumerate() {
        for id in arena.reachable(roots) {
            if let Node::Var(VarRef::Input(i, j)) = arena.node(id) {
                let n = &mut need[i.index()];
                if n.is_none_or(|(m, _)| *j > m) {
                    *n = Some((*j, p));
                }
            }
        }
    }
    let mut errors: Vec<Diagnostic> = Vec::new();
    for (i, input) in model.inputs.iter().enumerate() {
        let Some((j, p)) = need[i] else { continue };
        if j <= input.derivatives {
            continue;
        }
        let name = family_name(&input.name);
        if errors.iter().any(|d| d.span == input.span) {
            continue;
        }
        let (what, constraint, _) = &places[p];
        let mut d = Diagnostic::new(
            format!(
                "input `{name}` is used without the derivatives the index needs: {what} reads its derivative {j}, but it declares {}",
                input.derivatives
            ),
            input.span,
            format!("gives {} derivative{}", input.derivatives, if input.derivatives == 1 { "" } else { "s" }),
        )
        .hint(format!(
            "declare it `with {j} derivatives` (the caller then gives them during the run)"
        ));
        if let Some(c) = constraint {
            let def = &model.constraints[*c];
            d = d.related(
                def.span,
                format!("`{}` needs derivative {j} of `{name}`", def.name),
            );
        }
        errors.push(d);
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors)
    }
}
