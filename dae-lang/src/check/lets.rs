//! Ordering of `let` definitions: each must come after the ones it uses.

use crate::ast::Decl;
use crate::diag::Diagnostic;
use crate::model::RExpr;

/// The `let`s used by `e` (indices in source order), each once, in order of appearance.
pub(super) fn let_uses(e: &RExpr, out: &mut Vec<usize>) {
    e.visit(&mut |e| {
        if let RExpr::Let(l) = e {
            if !out.contains(&l.index()) {
                out.push(l.index());
            }
        }
    });
}

/// The result of ordering: a valid order, or the cycles found.
pub(super) struct Order {
    /// Source indices in an order where each definition follows those it uses; among
    /// independent ones the source order is kept. Definitions on a cycle are left out.
    pub order: Vec<usize>,
    /// Each cycle once, as source indices `a, b, ...` meaning `a -> b -> ... -> a`.
    pub cycles: Vec<Vec<usize>>,
}

/// Orders the definitions given `uses[i]`, the definitions that definition `i` uses.
///
/// A depth-first search in source order, emitting a definition after everything it
/// uses. It keeps its own stack rather than recursing, so a long chain of definitions
/// cannot exhaust the call stack.
pub(super) fn order(uses: &[Vec<usize>]) -> Order {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Active,
        Done,
        OnCycle,
    }
    let n = uses.len();
    let mut mark = vec![Mark::New; n];
    let mut order = Vec::with_capacity(n);
    let mut cycles = Vec::new();
    for root in 0..n {
        if mark[root] != Mark::New {
            continue;
        }
        // (definition, index of its next use to visit)
        let mut stack: Vec<(usize, usize)> = vec![(root, 0)];
        mark[root] = Mark::Active;
        while let Some(&mut (node, ref mut next)) = stack.last_mut() {
            if let Some(&dep) = uses[node].get(*next) {
                *next += 1;
                match mark.get(dep).copied() {
                    Some(Mark::New) => {
                        mark[dep] = Mark::Active;
                        stack.push((dep, 0));
                    }
                    Some(Mark::Active) => {
                        // A back edge: the cycle is the stack from `dep` to the top.
                        let from = stack.iter().position(|&(d, _)| d == dep).unwrap_or(0);
                        let cycle: Vec<usize> = stack[from..].iter().map(|&(d, _)| d).collect();
                        cycles.push(cycle);
                    }
                    _ => {}
                }
            } else {
                stack.pop();
                let on_cycle = cycles.iter().any(|c| c.contains(&node))
                    || uses[node]
                        .iter()
                        .any(|&d| mark.get(d) == Some(&Mark::OnCycle));
                if on_cycle {
                    mark[node] = Mark::OnCycle;
                } else {
                    mark[node] = Mark::Done;
                    order.push(node);
                }
            }
        }
    }
    Order { order, cycles }
}

/// Renumbers the `let` references of `e` with `new_index[source index]`.
pub(super) fn renumber(e: &mut RExpr, new_index: &[usize]) {
    match e {
        RExpr::Let(l) => {
            if let Some(&j) = new_index.get(l.index()) {
                *l = crate::LetId::new(j);
            }
        }
        RExpr::Num(_) | RExpr::Var(_) => {}
        RExpr::Neg(a) | RExpr::Not(a) | RExpr::Gather(_, a) | RExpr::Sum(_, a) => {
            renumber(a, new_index)
        }
        RExpr::Binary(_, a, b)
        | RExpr::Compare(_, a, b)
        | RExpr::Logic(_, a, b)
        | RExpr::Int(_, a, b) => {
            renumber(a, new_index);
            renumber(b, new_index);
        }
        RExpr::If(c, a, b) => {
            renumber(c, new_index);
            renumber(a, new_index);
            renumber(b, new_index);
        }
        RExpr::Call(_, args) => args.iter_mut().for_each(|a| renumber(a, new_index)),
    }
}

/// The error of a cycle among `let`s (`cycle` indexes `decls`), at its first definition,
/// the others on the cycle as related places.
pub(super) fn cycle_error(cycle: &[usize], decls: &[&Decl]) -> Diagnostic {
    let names: Vec<&str> = cycle.iter().map(|&i| decls[i].name.name.as_str()).collect();
    let path = format!("{} -> {}", names.join(" -> "), names[0]);
    let first = decls[cycle[0]];
    let mut d = Diagnostic::new(
        format!("the definitions form a cycle: {path}"),
        first.name.span,
        if cycle.len() == 1 {
            "uses itself".to_string()
        } else {
            "this definition starts the cycle".into()
        },
    )
    .hint("a `let` may not use itself, directly or through other `let`s: break the cycle");
    for &i in &cycle[1..] {
        d = d.related(
            decls[i].name.span,
            format!("`{}` is on the cycle", decls[i].name.name),
        );
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uses_come_first_and_source_order_is_kept_otherwise() {
        // 0 uses 2, 1 uses nothing, 2 uses 1, 3 uses nothing.
        let o = order(&[vec![2], vec![], vec![1], vec![]]);
        assert!(o.cycles.is_empty());
        assert_eq!(o.order, vec![1, 2, 0, 3]);
    }

    #[test]
    fn cycles_are_found_once_each() {
        // 0 -> 1 -> 0, 2 -> 2, 3 uses 0 (not on a cycle itself, but cannot be ordered).
        let o = order(&[vec![1], vec![0], vec![2], vec![0], vec![]]);
        assert_eq!(o.cycles, vec![vec![0, 1], vec![2]]);
        assert_eq!(o.order, vec![4]);
    }

    #[test]
    fn a_long_chain_does_not_recurse() {
        let n = 200_000;
        let uses: Vec<Vec<usize>> = (0..n)
            .map(|i| if i + 1 < n { vec![i + 1] } else { vec![] })
            .collect();
        let o = order(&uses);
        assert_eq!(o.order.len(), n);
        assert_eq!(o.order[0], n - 1);
    }
}
