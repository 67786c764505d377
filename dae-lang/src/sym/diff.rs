//! Partial derivatives and the total time derivative, memoised per (node, variable).
//!
//! Both are one structural chain-rule walk that differs only in the derivative of the
//! leaves: `d/dv` has `dv/dv = 1` and 0 for every other leaf; the total time derivative
//! `D[e] = de/dt + sum_k (de/dx_k) f_k` has `D[t] = 1`, `D[x_k] = f_k` and 0 for
//! parameters, algebraic unknowns (z is held constant, method.md section 1) and the
//! realization parameters. Walking once with these leaf rules gives the same expression as
//! summing partials, without building `n` partial derivatives first. A per-node bit set of
//! the leaf kinds below it answers "is this a constant for this variable?" in O(1).
//!
//! Non-smooth functions: `d abs(u) = sign(u) u'`, `d sign(u) = 0`, and
//! `d min(a, b) = (a' + b')/2 - sign(a - b) (a' - b')/2`,
//! `d max(a, b) = (a' + b')/2 + sign(a - b) (a' - b')/2`: the derivative of the active
//! branch away from ties, the mean of both at a tie (a subgradient there).

use super::{Arena, Id, Node, dep};
use crate::{Func, VarRef};

#[derive(Clone, Copy)]
enum Seed {
    Partial(Id),
    Time,
}

impl Arena {
    /// The partial derivative `d e / d v`, where `v` is a leaf (parameter, state, algebraic,
    /// time or realization parameter). For a non-leaf `v` the result is 0.
    pub fn diff(&mut self, e: Id, v: Id) -> Id {
        self.d(e, Seed::Partial(v))
    }

    /// Set the flow `f` (one expression per state) used by [`Arena::dt`]; clears its memo.
    pub fn set_flow(&mut self, f: Vec<Id>) {
        self.flow = f;
        self.tmemo.clear();
    }

    /// The flow set by [`Arena::set_flow`].
    pub fn flow(&self) -> &[Id] {
        &self.flow
    }

    /// The total time derivative `D[e] = de/dt + sum_k (de/dx_k) f_k` with the algebraic
    /// unknowns held constant. A state with no flow entry has derivative NaN.
    pub fn dt(&mut self, e: Id) -> Id {
        self.d(e, Seed::Time)
    }

    fn d(&mut self, e: Id, seed: Seed) -> Id {
        let relevant = match seed {
            Seed::Partial(v) => self.deps(v) & self.deps(e) != 0,
            Seed::Time => self.deps(e) & (dep::STATE | dep::TIME) != 0,
        };
        if !relevant {
            return self.num(0.0);
        }
        let hit = match seed {
            Seed::Partial(v) => self.dmemo.get(&(e, v)),
            Seed::Time => self.tmemo.get(&e),
        };
        if let Some(&r) = hit {
            return r;
        }
        let r = self.d_node(e, seed);
        match seed {
            Seed::Partial(v) => self.dmemo.insert((e, v), r),
            Seed::Time => self.tmemo.insert(e, r),
        };
        r
    }

    fn is_zero(&self, id: Id) -> bool {
        self.simplify && self.as_const(id) == Some(0.0)
    }

    fn d_node(&mut self, e: Id, seed: Seed) -> Id {
        match self.node(e).clone() {
            Node::Const(_) | Node::Var(_) => {
                let one = match seed {
                    Seed::Partial(v) => e == v,
                    Seed::Time => matches!(self.node(e), Node::Var(VarRef::Time)),
                };
                if one {
                    return self.num(1.0);
                }
                match (seed, self.node(e)) {
                    (Seed::Time, Node::Var(VarRef::State(k))) => {
                        let k = k.index();
                        self.flow
                            .get(k)
                            .copied()
                            .unwrap_or_else(|| self.num(f64::NAN))
                    }
                    _ => self.num(0.0),
                }
            }
            Node::Add(_, ts) => {
                let mut terms = Vec::with_capacity(ts.len());
                for (t, a) in ts.iter() {
                    let dt = self.d(*t, seed);
                    if !self.is_zero(dt) {
                        terms.push((dt, a.0));
                    }
                }
                self.lin(0.0, &terms)
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
                    let t = self.product(c.0 * ek, &f);
                    terms.push((t, 1.0));
                }
                self.lin(0.0, &terms)
            }
            Node::Pow(a, b) => {
                // d a^b = a^b (ln(a) b' + b a'/a)
                let (da, db) = (self.d(a, seed), self.d(b, seed));
                let mut terms = Vec::new();
                if !self.is_zero(db) {
                    let ln = self.f1(Func::Ln, a);
                    terms.push((self.product(1.0, &[(e, 1.0), (ln, 1.0), (db, 1.0)]), 1.0));
                }
                if !self.is_zero(da) {
                    let bm1 = self.lin(-1.0, &[(b, 1.0)]);
                    let p = self.pow(a, bm1);
                    terms.push((self.product(1.0, &[(b, 1.0), (p, 1.0), (da, 1.0)]), 1.0));
                }
                self.lin(0.0, &terms)
            }
            Node::F1(f, u) => {
                let du = self.d(u, seed);
                if self.is_zero(du) {
                    return du;
                }
                let outer = self.d_f1(f, u, e);
                self.mul(outer, du)
            }
            Node::F2(f, a, b) => {
                let (da, db) = (self.d(a, seed), self.d(b, seed));
                match f {
                    Func::Atan2 => {
                        // d atan2(a, b) = (b a' - a b') / (a^2 + b^2)
                        let num1 = self.mul(b, da);
                        let num2 = self.mul(a, db);
                        let num = self.sub(num1, num2);
                        let (a2, b2) = (self.powf(a, 2.0), self.powf(b, 2.0));
                        let den = self.add(a2, b2);
                        self.div(num, den)
                    }
                    Func::Min | Func::Max => {
                        let mean = self.lin(0.0, &[(da, 0.5), (db, 0.5)]);
                        let half = self.lin(0.0, &[(da, 0.5), (db, -0.5)]);
                        let diff = self.sub(a, b);
                        let sg = self.f1(Func::Sign, diff);
                        let jump = self.mul(sg, half);
                        let s = if f == Func::Min { -1.0 } else { 1.0 };
                        self.lin(0.0, &[(mean, 1.0), (jump, s)])
                    }
                    // Not an F2 node (see `Arena::f2`).
                    _ => self.num(f64::NAN),
                }
            }
        }
    }

    /// The derivative of the outer function `f` at `u`; `e = f(u)` for reuse.
    fn d_f1(&mut self, f: Func, u: Id, e: Id) -> Id {
        match f {
            Func::Sin => self.f1(Func::Cos, u),
            Func::Cos => {
                let s = self.f1(Func::Sin, u);
                self.neg(s)
            }
            Func::Tan => {
                let t2 = self.powf(e, 2.0);
                self.lin(1.0, &[(t2, 1.0)])
            }
            Func::Asin | Func::Acos => {
                let u2 = self.powf(u, 2.0);
                let one_m = self.lin(1.0, &[(u2, -1.0)]);
                let c = if f == Func::Asin { 1.0 } else { -1.0 };
                self.product(c, &[(one_m, -0.5)])
            }
            Func::Atan => {
                let u2 = self.powf(u, 2.0);
                let one_p = self.lin(1.0, &[(u2, 1.0)]);
                self.powf(one_p, -1.0)
            }
            Func::Sinh => self.f1(Func::Cosh, u),
            Func::Cosh => self.f1(Func::Sinh, u),
            Func::Tanh => {
                let t2 = self.powf(e, 2.0);
                self.lin(1.0, &[(t2, -1.0)])
            }
            Func::Exp => e,
            Func::Ln => self.powf(u, -1.0),
            Func::Abs => self.f1(Func::Sign, u),
            Func::Sign => self.num(0.0),
            Func::Sqrt => self.product(0.5, &[(u, -0.5)]),
            // Not an F1 node (see `Arena::f1`).
            Func::Atan2 | Func::Pow | Func::Min | Func::Max => self.num(f64::NAN),
        }
    }
}
