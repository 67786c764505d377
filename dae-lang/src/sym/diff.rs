//! Partial derivatives and the total time derivative, memoised per (node, variable).
//!
//! Both are one structural chain-rule walk that differs only in the derivative of the
//! leaves: `d/dv` has `dv/dv = 1` and 0 for every other leaf; the total time derivative
//! `D[e] = de/dt + sum_k (de/dx_k) f_k` has `D[t] = 1`, `D[x_k] = f_k` and 0 for
//! parameters, algebraic unknowns (z is held constant, docs/method.md section 1) and the
//! realization parameters; `D[input^(j)] = input^(j+1)`, and the derivative goes through
//! gathers and sums (both are linear). Walking once with these leaf rules gives the same expression as
//! summing partials, without building `n` partial derivatives first. A per-node bit set of
//! the leaf kinds below it answers "is this a constant for this variable?" in O(1).
//! The derivative along the motion ([`DiffContext::dt_moving`]) is the same walk with
//! `D[z_k] = z_k'` (the leaf [`VarRef::AlgRate`]): of `Omega`, `beta + J_Omega z'`.
//!
//! Non-smooth functions: `d abs(u) = sign(u) u'`, `d sign(u) = 0`, and
//! `d min(a, b) = (a' + b')/2 - sign(a - b) (a' - b')/2`,
//! `d max(a, b) = (a' + b')/2 + sign(a - b) (a' - b')/2`: the derivative of the active
//! branch away from ties, the mean of both at a tie (a subgradient there).

use std::collections::HashMap;

use super::{Arena, Id, Node, dep};
use crate::{Func, VarRef};

#[derive(Clone, Copy)]
enum Seed {
    Partial(Id),
    /// Along the flow with the algebraic unknowns held.
    Time,
    /// Along the flow with the algebraic unknowns moving: `D[z_k] = z_k'`.
    Motion,
}

/// What differentiation remembers between calls: the flow of the total time derivative
/// and the memos of both derivatives. It lives beside the [`Arena`], not in it: the arena
/// is only the expressions (what printing, evaluation and the tapes read), and a memo is
/// only valid for one flow, so a new flow is a new context.
#[derive(Clone, Debug, Default)]
pub struct DiffContext {
    /// The flow `f` used by the total time derivative, one expression per state.
    flow: Vec<Id>,
    /// Partial derivatives: (node, variable node) -> derivative.
    partial: HashMap<(Id, Id), Id>,
    /// Total time derivatives along `flow`.
    total: HashMap<Id, Id>,
    /// Total time derivatives along `flow` with the algebraic unknowns moving.
    moving: HashMap<Id, Id>,
}

impl DiffContext {
    /// A context whose total time derivative follows the flow `f` (one expression per
    /// state, in the arena the derivatives are taken in).
    pub fn new(flow: Vec<Id>) -> DiffContext {
        DiffContext {
            flow,
            ..DiffContext::default()
        }
    }

    /// The flow given to [`DiffContext::new`].
    pub fn flow(&self) -> &[Id] {
        &self.flow
    }

    /// The partial derivative `d e / d v` in `arena`, where `v` is a leaf (parameter,
    /// state, algebraic, time or realization parameter). For a non-leaf `v` the result
    /// is 0.
    pub fn diff(&mut self, arena: &mut Arena, e: Id, v: Id) -> Id {
        Walk {
            a: arena,
            ctx: self,
        }
        .d(e, Seed::Partial(v))
    }

    /// The total time derivative `D[e] = de/dt + sum_k (de/dx_k) f_k` in `arena`, with
    /// the algebraic unknowns held constant. A state with no flow entry has derivative
    /// NaN.
    pub fn dt(&mut self, arena: &mut Arena, e: Id) -> Id {
        Walk {
            a: arena,
            ctx: self,
        }
        .d(e, Seed::Time)
    }

    /// The total time derivative along the flow with the algebraic unknowns moving too:
    /// [`DiffContext::dt`] plus `sum_k (de/dz_k) z_k'`, each `z_k'` the leaf
    /// [`VarRef::AlgRate`]`(k)`. Of `Omega` it is `Omega' = beta + J_Omega z'`, with
    /// `J_Omega z'` in the form of `Omega`'s own terms (a family sum stays one sum)
    /// instead of an entry per pair of unknowns.
    pub fn dt_moving(&mut self, arena: &mut Arena, e: Id) -> Id {
        Walk {
            a: arena,
            ctx: self,
        }
        .d(e, Seed::Motion)
    }
}

/// One derivative being taken: the arena it builds in and the context it remembers in.
struct Walk<'a> {
    a: &'a mut Arena,
    ctx: &'a mut DiffContext,
}

impl Walk<'_> {
    fn d(&mut self, e: Id, seed: Seed) -> Id {
        let relevant = match seed {
            Seed::Partial(v) => self.a.deps(v) & self.a.deps(e) != 0,
            Seed::Time => self.a.deps(e) & (dep::STATE | dep::TIME | dep::INPUT) != 0,
            Seed::Motion => self.a.deps(e) & (dep::STATE | dep::TIME | dep::INPUT | dep::ALG) != 0,
        };
        if !relevant {
            return self.a.num(0.0);
        }
        let hit = match seed {
            Seed::Partial(v) => self.ctx.partial.get(&(e, v)),
            Seed::Time => self.ctx.total.get(&e),
            Seed::Motion => self.ctx.moving.get(&e),
        };
        if let Some(&r) = hit {
            return r;
        }
        let r = self.d_node(e, seed);
        match seed {
            Seed::Partial(v) => self.ctx.partial.insert((e, v), r),
            Seed::Time => self.ctx.total.insert(e, r),
            Seed::Motion => self.ctx.moving.insert(e, r),
        };
        r
    }

    fn is_zero(&self, id: Id) -> bool {
        self.a.simplifies() && self.a.as_const(id) == Some(0.0)
    }

    fn d_node(&mut self, e: Id, seed: Seed) -> Id {
        match self.a.node(e).clone() {
            Node::Const(_) | Node::Var(_) => {
                let one = match seed {
                    Seed::Partial(v) => e == v,
                    Seed::Time | Seed::Motion => {
                        matches!(self.a.node(e), Node::Var(VarRef::Time))
                    }
                };
                if one {
                    return self.a.num(1.0);
                }
                match (seed, self.a.node(e)) {
                    (Seed::Time | Seed::Motion, Node::Var(VarRef::State(k))) => {
                        let k = k.index();
                        self.ctx
                            .flow
                            .get(k)
                            .copied()
                            .unwrap_or_else(|| self.a.num(f64::NAN))
                    }
                    // The derivative of an input is its next derivative.
                    (Seed::Time | Seed::Motion, Node::Var(VarRef::Input(i, j))) => {
                        let next = VarRef::Input(*i, j.saturating_add(1));
                        self.a.var(next)
                    }
                    (Seed::Motion, Node::Var(VarRef::Alg(k))) => {
                        let rate = VarRef::AlgRate(*k);
                        self.a.var(rate)
                    }
                    _ => self.a.num(0.0),
                }
            }
            // Linear in the gathered node and the summand: the time derivative of a
            // gathered state is the gathered derivative.
            Node::Gather(m, a) => {
                let da = self.d(a, seed);
                self.a.gather(m, da)
            }
            Node::Sum(m, a) => {
                let da = self.d(a, seed);
                self.a.sum(m, da)
            }
            Node::Add(_, ts) => {
                let mut terms = Vec::with_capacity(ts.len());
                for (t, a) in ts.iter() {
                    let dt = self.d(*t, seed);
                    if !self.is_zero(dt) {
                        terms.push((dt, a.0));
                    }
                }
                self.a.lin(0.0, &terms)
            }
            Node::Mul(c, fs) => {
                let mut terms = Vec::with_capacity(fs.len());
                for k in 0..fs.len() {
                    let (b, ek) = (fs[k].0, fs[k].1.0);
                    // b^0 (only in an unsimplified arena) is the constant 1: writing its
                    // derivative as 0 * b^-1 * b' would be NaN at b = 0.
                    if ek == 0.0 {
                        continue;
                    }
                    let db = self.d(b, seed);
                    if self.is_zero(db) {
                        continue;
                    }
                    let mut f: Vec<(Id, f64)> = fs.iter().map(|(b, e)| (*b, e.0)).collect();
                    f[k].1 = ek - 1.0;
                    f.push((db, 1.0));
                    let t = self.a.product(c.0 * ek, &f);
                    terms.push((t, 1.0));
                }
                self.a.lin(0.0, &terms)
            }
            Node::Pow(a, b) => {
                // d a^b = a^b (ln(a) b' + b a'/a)
                let (da, db) = (self.d(a, seed), self.d(b, seed));
                let mut terms = Vec::new();
                if !self.is_zero(db) {
                    let ln = self.a.f1(Func::Ln, a);
                    terms.push((self.a.product(1.0, &[(e, 1.0), (ln, 1.0), (db, 1.0)]), 1.0));
                }
                if !self.is_zero(da) {
                    let bm1 = self.a.lin(-1.0, &[(b, 1.0)]);
                    let p = self.a.pow(a, bm1);
                    terms.push((self.a.product(1.0, &[(b, 1.0), (p, 1.0), (da, 1.0)]), 1.0));
                }
                self.a.lin(0.0, &terms)
            }
            Node::F1(f, u) => {
                let du = self.d(u, seed);
                if self.is_zero(du) {
                    return du;
                }
                let outer = outer_derivative(self.a, f, u, e);
                self.a.mul(outer, du)
            }
            Node::F2(f, a, b) => {
                let (da, db) = (self.d(a, seed), self.d(b, seed));
                match f {
                    Func::Atan2 => {
                        // d atan2(a, b) = (b a' - a b') / (a^2 + b^2)
                        let num1 = self.a.mul(b, da);
                        let num2 = self.a.mul(a, db);
                        let num = self.a.sub(num1, num2);
                        let (a2, b2) = (self.a.powf(a, 2.0), self.a.powf(b, 2.0));
                        let den = self.a.add(a2, b2);
                        self.a.div(num, den)
                    }
                    Func::Min | Func::Max => {
                        let mean = self.a.lin(0.0, &[(da, 0.5), (db, 0.5)]);
                        let half = self.a.lin(0.0, &[(da, 0.5), (db, -0.5)]);
                        let diff = self.a.sub(a, b);
                        let sg = self.a.f1(Func::Sign, diff);
                        let jump = self.a.mul(sg, half);
                        let s = if f == Func::Min { -1.0 } else { 1.0 };
                        self.a.lin(0.0, &[(mean, 1.0), (jump, s)])
                    }
                    // Not an F2 node (see `Arena::f2`).
                    _ => self.a.num(f64::NAN),
                }
            }
        }
    }
}

/// The derivative of the outer function `f` at `u`; `e = f(u)` for reuse (also used by
/// the `J_Omega` kernels).
pub(crate) fn outer_derivative(a: &mut Arena, f: Func, u: Id, e: Id) -> Id {
    match f {
        Func::Sin => a.f1(Func::Cos, u),
        Func::Cos => {
            let s = a.f1(Func::Sin, u);
            a.neg(s)
        }
        Func::Tan => {
            let t2 = a.powf(e, 2.0);
            a.lin(1.0, &[(t2, 1.0)])
        }
        Func::Asin | Func::Acos => {
            let u2 = a.powf(u, 2.0);
            let one_m = a.lin(1.0, &[(u2, -1.0)]);
            let c = if f == Func::Asin { 1.0 } else { -1.0 };
            a.product(c, &[(one_m, -0.5)])
        }
        Func::Atan => {
            let u2 = a.powf(u, 2.0);
            let one_p = a.lin(1.0, &[(u2, 1.0)]);
            a.powf(one_p, -1.0)
        }
        Func::Sinh => a.f1(Func::Cosh, u),
        Func::Cosh => a.f1(Func::Sinh, u),
        Func::Tanh => {
            let t2 = a.powf(e, 2.0);
            a.lin(1.0, &[(t2, -1.0)])
        }
        Func::Exp => e,
        Func::Ln => a.powf(u, -1.0),
        Func::Abs => a.f1(Func::Sign, u),
        Func::Sign => a.num(0.0),
        Func::Sqrt => a.product(0.5, &[(u, -0.5)]),
        // Not an F1 node (see `Arena::f1`).
        Func::Atan2 | Func::Pow | Func::Min | Func::Max => a.num(f64::NAN),
    }
}
