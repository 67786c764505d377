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
    let mut f: Vec<Id> = model
        .ders
        .iter()
        .map(|d| lowering.expr(&mut arena, &d.expr))
        .collect();
    for m in &model.mass {
        let entries: Vec<Id> = m
            .entries
            .iter()
            .map(|e| lowering.expr(&mut arena, e))
            .collect();
        // A matrix that breaks the checked-model contract (not square over its states,
        // a state out of range) gives NaN derivatives, which the initial-point check
        // reports, rather than a panic.
        let n = m.states.len();
        if entries.len() != n * n || m.states.iter().any(|s| s.index() >= f.len()) {
            let nan = arena.num(f64::NAN);
            for s in &m.states {
                if let Some(slot) = f.get_mut(s.index()) {
                    *slot = nan;
                }
            }
            continue;
        }
        let rhs: Vec<Id> = m.states.iter().map(|s| f[s.index()]).collect();
        for (s, x) in m.states.iter().zip(solve(&mut arena, entries, rhs)) {
            f[s.index()] = x;
        }
    }
    let g = model
        .constraints
        .iter()
        .map(|c| lowering.expr(&mut arena, &c.residual))
        .collect();
    Lowered { arena, f, g, lets }
}

/// `x` with `M x = b` (`m`: `M` row-major), as expressions: Gaussian elimination in the
/// order written, without row exchanges (the checker has found every pivot non-zero at
/// the initial point), skipping the entries that are the constant 0, so that a block
/// diagonal or banded matrix costs what its blocks cost and a 1 x 1 matrix is `b / m`.
fn solve(arena: &mut Arena, mut m: Vec<Id>, mut b: Vec<Id>) -> Vec<Id> {
    let n = b.len();
    if n == 0 {
        return b;
    }
    let is_zero = |arena: &Arena, id: Id| arena.as_const(id) == Some(0.0);
    for k in 0..n {
        let pivot = m[k * n + k];
        for i in k + 1..n {
            if is_zero(arena, m[i * n + k]) {
                continue;
            }
            let l = arena.div(m[i * n + k], pivot);
            for j in k + 1..n {
                if !is_zero(arena, m[k * n + j]) {
                    let d = arena.mul(l, m[k * n + j]);
                    m[i * n + j] = arena.sub(m[i * n + j], d);
                }
            }
            let d = arena.mul(l, b[k]);
            b[i] = arena.sub(b[i], d);
        }
    }
    let mut x = vec![b[0]; n];
    for k in (0..n).rev() {
        let mut r = b[k];
        for j in k + 1..n {
            if !is_zero(arena, m[k * n + j]) {
                let d = arena.mul(m[k * n + j], x[j]);
                r = arena.sub(r, d);
            }
        }
        x[k] = arena.div(r, m[k * n + k]);
    }
    x
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

#[cfg(test)]
mod tests {
    use super::solve;
    use crate::sym::Arena;

    /// A mass matrix that breaks the checked-model contract (built by hand, one entry
    /// short) is an error at the initial point, not a panic.
    #[test]
    fn a_mass_matrix_that_is_not_square_is_reported_not_read() {
        let src = "model M { state x = 0, v = 1; alg z = 0; der(x) = v; \
                   mass [v] = [2]; der(v) = z; constraint c: x = 0; }";
        let mut model = crate::check_source(src).expect("checks").remove(0);
        model.mass[0].entries.clear();
        // `der(v)` lowers to NaN: the constraint then never reaches `z`.
        let errs = crate::analyze(&model, &crate::AnalysisOptions::default())
            .expect_err("a NaN derivative");
        assert!(
            errs[0].message.contains("constraint `c` has no index"),
            "{errs:?}"
        );
    }

    /// `solve` on numbers (the arena folds them) against `M x = b` multiplied out: a
    /// dense non-symmetric matrix and one with structural zeros, which are skipped.
    #[test]
    fn solve_gives_x_with_m_x_equal_to_b() {
        let n = 5;
        let mut seed = 7_u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for sparse in [false, true] {
            let m: Vec<f64> = (0..n * n)
                .map(|k| {
                    let (i, j) = (k / n, k % n);
                    if i == j {
                        3.0 + next()
                    } else if sparse && (i + 2 * j) % 3 == 0 {
                        0.0
                    } else {
                        next()
                    }
                })
                .collect();
            let b: Vec<f64> = (0..n).map(|_| next()).collect();
            let mut arena = Arena::new();
            let mi = m.iter().map(|&v| arena.num(v)).collect();
            let bi = b.iter().map(|&v| arena.num(v)).collect();
            let x: Vec<f64> = solve(&mut arena, mi, bi)
                .into_iter()
                .map(|id| arena.as_const(id).expect("numbers fold to a number"))
                .collect();
            for i in 0..n {
                let mx: f64 = (0..n).map(|j| m[i * n + j] * x[j]).sum();
                assert!(
                    (mx - b[i]).abs() < 1e-13,
                    "row {i}: M x = {mx}, b = {}",
                    b[i]
                );
            }
        }
    }
}
