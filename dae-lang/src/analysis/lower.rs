//! Lowering a checked [`Model`] into the symbolic arena.

use crate::ast::BinOp;
use crate::maps::MapTable;
use crate::model::{Model, RExpr};
use crate::sym::{Arena, Id, LeafSets};
use crate::{Func, VarRef};

/// A model in the arena: lets as shared nodes, `f` per state, `g` per constraint.
#[derive(Clone, Debug)]
pub struct Lowered {
    /// The arena holding every expression.
    pub arena: Arena,
    /// `f[k]`: the right-hand side of `der(x_k)`.
    pub f: Vec<Id>,
    /// `g[i]`: the residual `lhs - rhs` of constraint `i`.
    pub g: Vec<Id>,
    /// `lets[j]`: the node of `let` number `j`.
    pub lets: Vec<Id>,
}

/// Lower a model's equations. `simplify = false` builds without the simplifying rules
/// (for measuring). A let is lowered once and every use refers to its node, so lets are
/// shared, not copied. The initial values are lowered separately, after the analysis.
pub fn lower(model: &Model, simplify: bool) -> Lowered {
    let mut arena = if model.is_family() {
        Arena::with_families(
            simplify,
            leaf_sets(model),
            MapTable::new(model.maps.clone()),
        )
    } else if simplify {
        Arena::new()
    } else {
        Arena::unsimplified()
    };
    let mut lets = Vec::with_capacity(model.lets.len());
    for l in &model.lets {
        let id = Lowering::new(model, &lets).expr(&mut arena, &l.expr);
        lets.push(id);
    }
    let mut lowering = Lowering::new(model, &lets);
    let f: Vec<Id> = model
        .ders
        .iter()
        .map(|d| lowering.expr(&mut arena, &d.expr))
        .collect();
    let g = model
        .constraints
        .iter()
        .map(|c| lowering.expr(&mut arena, &c.residual))
        .collect();
    Lowered { arena, f, g, lets }
}

/// The sets of a family model's leaves.
pub(crate) fn leaf_sets(model: &Model) -> LeafSets {
    LeafSets {
        params: model.params.iter().map(|p| p.family.over).collect(),
        states: model.states.iter().map(|p| p.family.over).collect(),
        algs: model.algs.iter().map(|p| p.family.over).collect(),
        inputs: model.inputs.iter().map(|p| p.family.over).collect(),
        constraints: model.constraints.iter().map(|c| c.over).collect(),
    }
}

/// Lower the initial values of the states and the initial guesses of the algebraic
/// unknowns (expressions over the parameters) into `arena`.
pub(crate) fn lower_initial(arena: &mut Arena, model: &Model) -> (Vec<Id>, Vec<Id>) {
    let mut lowering = Lowering::new(model, &[]);
    let states = model
        .states
        .iter()
        .map(|s| lowering.expr(arena, &s.init))
        .collect();
    let algs = model
        .algs
        .iter()
        .map(|a| lowering.expr(arena, &a.init))
        .collect();
    (states, algs)
}

/// What an expression of `model` may refer to: its variables, and the lets lowered so
/// far. A reference the checked-model contract rules out (a variable out of range, a
/// realization parameter, a later let, a wrong arity) lowers to NaN, which the
/// initial-point check then reports, so that no tape ever reads outside its inputs.
struct Lowering<'a> {
    lets: &'a [Id],
    /// Parameters, states, algebraic unknowns, inputs, sets, sizes.
    counts: [usize; 6],
}

impl<'a> Lowering<'a> {
    fn new(model: &Model, lets: &'a [Id]) -> Self {
        Lowering {
            lets,
            counts: [
                model.params.len(),
                model.states.len(),
                model.algs.len(),
                model.inputs.len(),
                model.sets.len(),
                model.sizes.len(),
            ],
        }
    }

    fn in_range(&self, v: VarRef) -> bool {
        let [params, states, algs, inputs, sets, sizes] = self.counts;
        match v {
            VarRef::Param(i) => i.index() < params,
            VarRef::State(i) => i.index() < states,
            VarRef::Alg(i) => i.index() < algs,
            VarRef::Time => true,
            // Introduced by the analysis, never written in a model.
            VarRef::Mu(_) | VarRef::AlgRate(_) => false,
            VarRef::Input(i, _) => i.index() < inputs,
            VarRef::Elem(s) => s.index() < sets,
            VarRef::Size(s) => s.index() < sizes,
        }
    }

    fn expr(&mut self, arena: &mut Arena, e: &RExpr) -> Id {
        match e {
            RExpr::Num(v) => arena.num(*v),
            RExpr::Var(v) if self.in_range(*v) => arena.var(*v),
            RExpr::Var(_) => arena.num(f64::NAN),
            RExpr::Let(l) => self
                .lets
                .get(l.index())
                .copied()
                .unwrap_or_else(|| arena.num(f64::NAN)),
            RExpr::Neg(a) => {
                let a = self.expr(arena, a);
                arena.neg(a)
            }
            RExpr::Binary(op, a, b) => {
                let a = self.expr(arena, a);
                let b = self.expr(arena, b);
                match op {
                    BinOp::Add => arena.add(a, b),
                    BinOp::Sub => arena.sub(a, b),
                    BinOp::Mul => arena.mul(a, b),
                    BinOp::Div => arena.div(a, b),
                    BinOp::Pow => arena.pow(a, b),
                }
            }
            RExpr::Call(f, args) => self.call(arena, *f, args),
            RExpr::Gather(m, _) | RExpr::Sum(m, _) if m.index() >= arena.maps().defs().len() => {
                arena.num(f64::NAN)
            }
            RExpr::Gather(m, a) => {
                let a = self.expr(arena, a);
                arena.gather(*m, a)
            }
            RExpr::Sum(m, a) => {
                let a = self.expr(arena, a);
                arena.sum(*m, a)
            }
            // Construction-time forms have no node: a model whose equations held one
            // would break the checked-model contract; NaN gets it reported.
            RExpr::Compare(..)
            | RExpr::Logic(..)
            | RExpr::Not(_)
            | RExpr::If(..)
            | RExpr::Int(..) => arena.num(f64::NAN),
        }
    }

    fn call(&mut self, arena: &mut Arena, f: Func, args: &[RExpr]) -> Id {
        if args.len() != f.arity() {
            return arena.num(f64::NAN);
        }
        let ids: Vec<Id> = args.iter().map(|a| self.expr(arena, a)).collect();
        arena.call(f, &ids)
    }
}
