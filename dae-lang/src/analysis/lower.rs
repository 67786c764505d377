//! Lowering a checked [`Model`] into the symbolic arena.

use crate::ast::BinOp;
use crate::model::{Model, RExpr};
use crate::sym::{Arena, Id};

/// A model in the arena: lets as shared nodes, `f` per state, `g` per constraint.
#[derive(Clone, Debug)]
pub struct Lowered {
    /// The arena holding every expression (its flow is set to `f`).
    pub arena: Arena,
    /// `f[k]`: the right-hand side of `der(x_k)`.
    pub f: Vec<Id>,
    /// `g[i]`: the residual `lhs - rhs` of constraint `i`.
    pub g: Vec<Id>,
    /// `lets[j]`: the node of `let` number `j`.
    pub lets: Vec<Id>,
}

/// Lower a model. `simplify = false` builds without the simplifying rules (for measuring).
/// A let is lowered once and every use refers to its node, so lets are shared, not copied.
pub fn lower(model: &Model, simplify: bool) -> Lowered {
    let mut arena = if simplify {
        Arena::new()
    } else {
        Arena::unsimplified()
    };
    let mut lets = Vec::with_capacity(model.lets.len());
    for l in &model.lets {
        let id = lower_expr(&mut arena, &lets, &l.expr);
        lets.push(id);
    }
    let f: Vec<Id> = model
        .ders
        .iter()
        .map(|d| lower_expr(&mut arena, &lets, &d.expr))
        .collect();
    let g = model
        .constraints
        .iter()
        .map(|c| lower_expr(&mut arena, &lets, &c.residual))
        .collect();
    arena.set_flow(f.clone());
    Lowered { arena, f, g, lets }
}

/// Lower one expression; `lets` holds the nodes of the lets lowered so far. A reference
/// the checked-model contract rules out (a later let, a wrong arity) lowers to NaN, which
/// the initial-point check then reports instead of panicking.
pub(crate) fn lower_expr(arena: &mut Arena, lets: &[Id], e: &RExpr) -> Id {
    match e {
        RExpr::Num(v) => arena.num(*v),
        RExpr::Var(v) => arena.var(*v),
        RExpr::Let(l) => lets
            .get(l.index())
            .copied()
            .unwrap_or_else(|| arena.num(f64::NAN)),
        RExpr::Neg(a) => {
            let a = lower_expr(arena, lets, a);
            arena.neg(a)
        }
        RExpr::Binary(op, a, b) => {
            let a = lower_expr(arena, lets, a);
            let b = lower_expr(arena, lets, b);
            match op {
                BinOp::Add => arena.add(a, b),
                BinOp::Sub => arena.sub(a, b),
                BinOp::Mul => arena.mul(a, b),
                BinOp::Div => arena.div(a, b),
                BinOp::Pow => arena.pow(a, b),
            }
        }
        RExpr::Call(f, args) => {
            if args.len() != f.arity() {
                return arena.num(f64::NAN);
            }
            let ids: Vec<Id> = args.iter().map(|a| lower_expr(arena, lets, a)).collect();
            arena.call(*f, &ids)
        }
    }
}
