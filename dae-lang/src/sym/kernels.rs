//! The `J_Omega` kernels of a family template: `d e(l) / d z[k]` for an algebraic
//! unknown `z` over `K`, as a list of terms.
//!
//! A term `(r, c, R, C)` means: where `r(l) == c(k)` (maps `r: ctx(e) -> X`,
//! `c: K -> X`), the derivative has the summand `R(l) * C(k)` (`R` in the context of
//! `e`, `C` in the context of `K`). Rules (the chain rule, with maps):
//!
//! * the leaf `z` itself: `(id, id, 1, 1)` (`z` at the element at hand depends on
//!   `z[k]` where `k` is that element);
//! * an arithmetic node: the chain rule; the local partial derivative multiplies the row
//!   factor. A scalar child in a family context has its row map lifted through the unit
//!   (`r` becomes "to the unit, then `r`"): the same for every element;
//! * `Gather(m, e')`: the row map becomes `m` then `r`, the row factor is gathered;
//! * `Sum(m, body)` over `k'` in `K'`: a term of the body with `r = c = id` (the body
//!   uses `z` at the summation element itself) becomes `(id, m, 1, R C)`: the row
//!   element `q` meets the column `k` when `m(k) == q`; a term whose row map goes through
//!   the unit (it does not depend on `k'`) becomes `(unit then r0, c, sum(m, R), C)`;
//!   anything else couples `z` through two maps (`z[g[k']]` summed over `k'`), which the
//!   kernels do not represent: an error.
//!
//! Terms with the same maps and the same column factor merge (their row factors add).

use std::collections::HashMap;
use std::rc::Rc;

use super::diff::outer_derivative;
use super::{Arena, Id, Node};
use crate::model::MapKind;
use crate::{AlgId, Func, MapId, VarRef};

/// One term of a kernel; see the module documentation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Term {
    /// From the row context to the meeting set.
    pub row_map: MapId,
    /// From the column's set to the meeting set.
    pub col_map: MapId,
    /// The row factor (context of the row).
    pub row: Id,
    /// The column factor (context of the column).
    pub col: Id,
}

/// A coupling through two maps: the `Sum` node where it was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TwoHop(pub Id);

/// The kernel terms of `d e / d z`, merged; see the module documentation.
pub fn jacobian_terms(arena: &mut Arena, e: Id, z: AlgId) -> Result<Vec<Term>, TwoHop> {
    let mut walk = Walk {
        a: arena,
        z,
        memo: HashMap::new(),
    };
    let terms = walk.terms(e)?;
    Ok(walk.merge(&terms))
}

struct Walk<'a> {
    a: &'a mut Arena,
    z: AlgId,
    memo: HashMap<Id, Rc<Vec<Term>>>,
}

impl Walk<'_> {
    fn terms(&mut self, e: Id) -> Result<Rc<Vec<Term>>, TwoHop> {
        if !self.a.has_alg(e) {
            return Ok(Rc::new(Vec::new()));
        }
        if let Some(t) = self.memo.get(&e) {
            return Ok(t.clone());
        }
        let t = Rc::new(self.node(e)?);
        self.memo.insert(e, t.clone());
        Ok(t)
    }

    /// The terms of child `c` of `e`, lifted to `e`'s context and scaled by `factor`
    /// (`None`: 1).
    fn chain(
        &mut self,
        e: Id,
        c: Id,
        factor: Option<Id>,
        out: &mut Vec<Term>,
    ) -> Result<(), TwoHop> {
        let ts = self.terms(c)?;
        if ts.is_empty() {
            return Ok(());
        }
        let (ctx_e, ctx_c) = (self.a.ctx(e), self.a.ctx(c));
        for t in ts.iter() {
            let row_map = if ctx_e.is_some() && ctx_c.is_none() {
                let span = self.a.maps().get(t.row_map).span;
                let unit = self.a.maps_mut().to_unit(ctx_e, span);
                self.a.maps_mut().compose(unit, t.row_map)
            } else {
                t.row_map
            };
            let row = match factor {
                Some(f) => self.a.mul(f, t.row),
                None => t.row,
            };
            out.push(Term { row_map, row, ..*t });
        }
        Ok(())
    }

    fn node(&mut self, e: Id) -> Result<Vec<Term>, TwoHop> {
        let mut out = Vec::new();
        match self.a.node(e).clone() {
            Node::Var(VarRef::Alg(k)) if k == self.z => {
                let ctx = self.a.ctx(e);
                let id = self.a.maps_mut().identity(ctx, Default::default());
                let one = self.a.num(1.0);
                out.push(Term {
                    row_map: id,
                    col_map: id,
                    row: one,
                    col: one,
                });
            }
            Node::Const(_) | Node::Var(_) => {}
            Node::Add(_, ts) => {
                for (t, a) in ts.iter() {
                    let f = (a.0 != 1.0).then(|| self.a.num(a.0));
                    self.chain(e, *t, f, &mut out)?;
                }
            }
            Node::Mul(c, fs) => {
                for k in 0..fs.len() {
                    let (b, ek) = (fs[k].0, fs[k].1.0);
                    if ek == 0.0 || !self.a.has_alg(b) {
                        continue;
                    }
                    let mut f: Vec<(Id, f64)> = fs.iter().map(|(b, e)| (*b, e.0)).collect();
                    f[k].1 = ek - 1.0;
                    let factor = self.a.product(c.0 * ek, &f);
                    self.chain(e, b, Some(factor), &mut out)?;
                }
            }
            Node::Pow(a, b) => {
                // d a^b = b a^(b-1) da + a^b ln(a) db
                if self.a.has_alg(a) {
                    let bm1 = self.a.lin(-1.0, &[(b, 1.0)]);
                    let p = self.a.pow(a, bm1);
                    let f = self.a.mul(b, p);
                    self.chain(e, a, Some(f), &mut out)?;
                }
                if self.a.has_alg(b) {
                    let ln = self.a.f1(Func::Ln, a);
                    let f = self.a.mul(e, ln);
                    self.chain(e, b, Some(f), &mut out)?;
                }
            }
            Node::F1(f, u) => {
                let d = outer_derivative(self.a, f, u, e);
                self.chain(e, u, Some(d), &mut out)?;
            }
            Node::F2(f, a, b) => {
                let (da, db) = match f {
                    Func::Atan2 => {
                        let (a2, b2) = (self.a.powf(a, 2.0), self.a.powf(b, 2.0));
                        let den = self.a.add(a2, b2);
                        let da = self.a.div(b, den);
                        let na = self.a.neg(a);
                        (da, self.a.div(na, den))
                    }
                    _ => {
                        // min: 1/2 - sign(a - b)/2 for a, 1/2 + sign(a - b)/2 for b; max swaps.
                        let diff = self.a.sub(a, b);
                        let sg = self.a.f1(Func::Sign, diff);
                        let s = if f == Func::Min { -0.5 } else { 0.5 };
                        (self.a.lin(0.5, &[(sg, s)]), self.a.lin(0.5, &[(sg, -s)]))
                    }
                };
                self.chain(e, a, Some(da), &mut out)?;
                self.chain(e, b, Some(db), &mut out)?;
            }
            Node::Gather(m, inner) => {
                for t in self.terms(inner)?.iter() {
                    let row_map = self.a.maps_mut().compose(m, t.row_map);
                    let row = self.a.gather(m, t.row);
                    out.push(Term { row_map, row, ..*t });
                }
            }
            Node::Sum(m, body) => {
                let k_set = self.a.maps().domain(m);
                let q_set = self.a.maps().codomain(m);
                let span = self.a.maps().get(m).span;
                for t in self.terms(body)?.iter() {
                    // The body's terms, seen from the summation element (a scalar body
                    // goes through the unit).
                    let row_map = if self.a.ctx(body).is_none() && k_set.is_some() {
                        let unit = self.a.maps_mut().to_unit(k_set, span);
                        self.a.maps_mut().compose(unit, t.row_map)
                    } else {
                        t.row_map
                    };
                    let maps = self.a.maps();
                    let identity = |x: MapId| maps.get(x).kind == MapKind::Identity;
                    if identity(row_map) && identity(t.col_map) && maps.domain(t.col_map) == k_set {
                        let one = self.a.num(1.0);
                        let col = self.a.mul(t.row, t.col);
                        let col_map = m;
                        let row_map = self.a.maps_mut().identity(q_set, span);
                        out.push(Term {
                            row_map,
                            col_map,
                            row: one,
                            col,
                        });
                    } else if let Some(r0) = self.a.maps_mut().through_unit(row_map) {
                        let unit = self.a.maps_mut().to_unit(q_set, span);
                        let row_map = self.a.maps_mut().compose(unit, r0);
                        let row = self.a.sum(m, t.row);
                        out.push(Term { row_map, row, ..*t });
                    } else {
                        return Err(TwoHop(e));
                    }
                }
            }
        }
        Ok(out)
    }

    /// Terms with equal maps and column factor merged (row factors added); zero terms
    /// dropped; in order of first appearance.
    fn merge(&mut self, terms: &[Term]) -> Vec<Term> {
        let mut order: Vec<(MapId, MapId, Id)> = Vec::new();
        let mut rows: HashMap<(MapId, MapId, Id), Vec<(Id, f64)>> = HashMap::new();
        for t in terms {
            let key = (t.row_map, t.col_map, t.col);
            rows.entry(key)
                .or_insert_with(|| {
                    order.push(key);
                    Vec::new()
                })
                .push((t.row, 1.0));
        }
        let mut out = Vec::with_capacity(order.len());
        for key in order {
            let row = self.a.lin(0.0, &rows[&key]);
            if self.a.as_const(row) == Some(0.0) || self.a.as_const(key.2) == Some(0.0) {
                continue;
            }
            out.push(Term {
                row_map: key.0,
                col_map: key.1,
                row,
                col: key.2,
            });
        }
        out
    }
}
