//! Simplifying constructors (see the simplification contract in the module docs).
//!
//! Normal form kept by these constructors (when simplification is on):
//! * constants are folded; a sum never has a constant term, a product has a constant
//!   factor only when its power is not finite (`(-1)^0.5` is kept, not folded to NaN);
//! * `Add(c, terms)`: at least two parts (terms plus a non-zero `c`), terms sorted and
//!   unique, coefficients non-zero; a term is never a constant, a sum, or a product whose
//!   coefficient is not 1 (that coefficient moves into the sum);
//! * `Mul(c, factors)`: `c != 0`, factors sorted and unique, exponents non-zero; a factor is
//!   never a constant and never a product that could be distributed exactly; a scaled single
//!   sum `c * (a + b)` is distributed into the sum; a sum factor has no common coefficient
//!   (`(2a + 2b) x = 2 (a + b) x`);
//! * numeric powers are exponents in a `Mul`, so `x^1 = x`, `x^0 = 1`, `x*x = x^2`,
//!   `x^a * x^b = x^(a+b)`, `x/x = 1`, `--x = x` fall out of the merge.

use super::{Arena, Id, Node, Num};
use crate::model::MapKind;
use crate::{AlgId, ConstraintId, Func, MapId, ParamId, StateId, VarRef};

/// `v ^ e` for constant folding.
pub(super) fn pow_num(v: f64, e: f64) -> f64 {
    if e == 1.0 {
        v
    } else if e == -1.0 {
        1.0 / v
    } else {
        v.powf(e)
    }
}

/// The terms of a sum or the factors of a product.
type Factors = Box<[(Id, Num)]>;

fn is_int(e: f64) -> bool {
    e.fract() == 0.0
}

fn is_even_int(e: f64) -> bool {
    is_int(e) && (e / 2.0).fract() == 0.0
}

impl Arena {
    /// A number.
    pub fn num(&mut self, v: f64) -> Id {
        self.intern(Node::Const(Num::norm(v)))
    }

    /// A variable.
    pub fn var(&mut self, v: VarRef) -> Id {
        self.intern(Node::Var(v))
    }

    /// A parameter.
    pub fn param(&mut self, p: ParamId) -> Id {
        self.var(VarRef::Param(p))
    }

    /// A state.
    pub fn state(&mut self, x: StateId) -> Id {
        self.var(VarRef::State(x))
    }

    /// An algebraic unknown.
    pub fn alg(&mut self, z: AlgId) -> Id {
        self.var(VarRef::Alg(z))
    }

    /// Time `t`.
    pub fn time(&mut self) -> Id {
        self.var(VarRef::Time)
    }

    /// The realization parameter `mu` of a constraint.
    pub fn mu(&mut self, c: ConstraintId) -> Id {
        self.var(VarRef::Mu(c))
    }

    /// `c + sum a_k * t_k`.
    pub fn lin(&mut self, c: f64, terms: &[(Id, f64)]) -> Id {
        if !self.simplify {
            let ts = terms.iter().map(|&(t, a)| (t, Num::norm(a))).collect();
            return self.intern(Node::Add(Num::norm(c), ts));
        }
        let mut c = c;
        let mut acc: Vec<(Id, f64)> = Vec::with_capacity(terms.len());
        let mut rescale: Vec<(Factors, f64)> = Vec::new();
        for &(t, a) in terms {
            if a == 0.0 {
                // `0 * t` is 0 under the contract, but NaN for a constant `t` that is not
                // finite (IEEE `0 * inf`), and NaN plus anything is NaN.
                if self.is_non_finite_constant(t) {
                    return self.num(f64::NAN);
                }
                continue;
            }
            match self.node(t) {
                Node::Const(v) => c += a * v.0,
                Node::Add(c2, ts) => {
                    c += a * c2.0;
                    acc.extend(ts.iter().map(|(t2, a2)| (*t2, a * a2.0)));
                }
                Node::Mul(c2, fs) if c2.0 != 1.0 => rescale.push((fs.clone(), a * c2.0)),
                _ => acc.push((t, a)),
            }
        }
        for (fs, a) in rescale {
            let fs: Vec<(Id, f64)> = fs.iter().map(|(b, e)| (*b, e.0)).collect();
            let unit = self.product(1.0, &fs);
            acc.push((unit, a));
        }
        acc.sort_by_key(|(t, _)| *t);
        let mut merged: Vec<(Id, Num)> = Vec::with_capacity(acc.len());
        for (t, a) in acc {
            match merged.last_mut() {
                Some((t0, a0)) if *t0 == t => {
                    // `a inf + b inf` is `(a + b) inf` only for `a`, `b` of one sign:
                    // `inf - inf` is NaN, whatever the coefficients.
                    if a0.0.signum() != a.signum() && self.is_non_finite_constant(t) {
                        return self.num(f64::NAN);
                    }
                    a0.0 += a
                }
                _ => merged.push((t, Num(a))),
            }
        }
        // `t - t` is 0 under the contract, but `inf - inf` is NaN: a constant term that
        // is not finite is never cancelled.
        if merged
            .iter()
            .any(|(t, a)| a.0 == 0.0 && self.is_non_finite_constant(*t))
        {
            return self.num(f64::NAN);
        }
        merged.retain(|(_, a)| a.0 != 0.0);
        match merged.as_slice() {
            [] => self.num(c),
            [(t, a)] if c == 0.0 => {
                let (t, a) = (*t, a.0);
                if a == 1.0 {
                    t
                } else if let Node::Mul(c_t, fs) = self.node(t) {
                    // The loop above leaves unit-coefficient products, except where
                    // `product` keeps a coefficient it cannot fold into a non-finite
                    // constant factor (`-(-1.677/0)`): `a (c_t prod) = (a c_t) prod`.
                    let (c_t, fs) = (c_t.0, fs.clone());
                    self.intern(Node::Mul(Num::norm(a * c_t), fs))
                } else {
                    self.intern(Node::Mul(Num::norm(a), Box::new([(t, Num(1.0))])))
                }
            }
            _ => self.intern(Node::Add(Num::norm(c), merged.into_boxed_slice())),
        }
    }

    /// `c * prod b_k ^ e_k`.
    pub fn product(&mut self, c: f64, factors: &[(Id, f64)]) -> Id {
        if !self.simplify {
            let fs = factors.iter().map(|&(b, e)| (b, Num::norm(e))).collect();
            return self.intern(Node::Mul(Num::norm(c), fs));
        }
        let mut c = c;
        let mut acc: Vec<(Id, f64)> = Vec::with_capacity(factors.len());
        for &(b, e) in factors {
            if e == 0.0 {
                continue;
            }
            match self.node(b) {
                // A power of a constant that is not finite (`(-1)^0.5`, `0^-1`) stays a
                // factor, so that constants in the arena are finite where the input is.
                Node::Const(v) if pow_num(v.0, e).is_finite() => c *= pow_num(v.0, e),
                // A constant that is not finite stays whole: `((-1)^-0.5)^2` is NaN, its
                // distributed `(-1)^-1` is not.
                _ if self.is_non_finite_constant(b) => acc.push((b, e)),
                // Distributed only if the coefficient's power is finite: `(2x)^1e16` keeps
                // its factor rather than becoming `inf * x^1e16`.
                Node::Mul(c2, fs)
                    if Self::distributes(c2.0, fs, e) && pow_num(c2.0, e).is_finite() =>
                {
                    c *= pow_num(c2.0, e);
                    acc.extend(fs.iter().map(|(b2, e2)| (*b2, e2.0 * e)));
                }
                Node::Add(c0, ts) if Self::common_coefficient(c0.0, ts, e).is_some() => {
                    let g = Self::common_coefficient(c0.0, ts, e).expect("checked");
                    let unit: Vec<(Id, f64)> = ts.iter().map(|(t, _)| (*t, 1.0)).collect();
                    c *= pow_num(g, e);
                    let sum = self.lin(0.0, &unit);
                    acc.push((sum, e));
                }
                _ => acc.push((b, e)),
            }
        }
        if c == 0.0 {
            // `x * 0` is 0 under the contract, but `0 * inf` and `0 * NaN` are NaN: a
            // constant factor that is not finite is not dropped.
            let non_finite = acc
                .iter()
                .any(|&(b, e)| self.constant(b).is_some_and(|v| !pow_num(v, e).is_finite()));
            return self.num(if non_finite { f64::NAN } else { 0.0 });
        }
        acc.sort_by_key(|(b, _)| *b);
        let mut merged: Vec<(Id, Num)> = Vec::with_capacity(acc.len());
        for (b, e) in acc {
            match merged.last_mut() {
                Some((b0, e0)) if *b0 == b => {
                    // `x^a * x^b = x^(a + b)` under the contract, but for a constant `x`
                    // that is 0, infinite or NaN and exponents of opposite signs IEEE
                    // gives `0 * inf`, NaN (`x/x` included).
                    if e0.0.signum() != e.signum()
                        && self.constant(b).is_some_and(|v| v == 0.0 || !v.is_finite())
                    {
                        return self.num(f64::NAN);
                    }
                    e0.0 += e
                }
                _ => merged.push((b, Num(e))),
            }
        }
        merged.retain(|(_, e)| e.0 != 0.0);
        // Merging can make a kept product base distributable (`p^0.5 * p^0.5 = p^1`).
        let again = merged.iter().any(|(b, e)| match self.node(*b) {
            Node::Mul(c2, fs) => {
                !self.is_non_finite_constant(*b)
                    && Self::distributes(c2.0, fs, e.0)
                    && pow_num(c2.0, e.0).is_finite()
            }
            Node::Const(v) => pow_num(v.0, e.0).is_finite(),
            _ => false,
        });
        if again {
            let fs: Vec<(Id, f64)> = merged.iter().map(|(b, e)| (*b, e.0)).collect();
            return self.product(c, &fs);
        }
        match merged.as_slice() {
            [] => self.num(c),
            [(b, e)] if e.0 == 1.0 => {
                let b = *b;
                if c == 1.0 {
                    b
                } else if let Node::Add(c3, ts) = self.node(b) {
                    let c3 = c3.0;
                    let ts: Vec<(Id, f64)> = ts.iter().map(|(t, a)| (*t, a.0 * c)).collect();
                    self.lin(c3 * c, &ts)
                } else {
                    self.intern(Node::Mul(Num::norm(c), merged.into_boxed_slice()))
                }
            }
            _ => self.intern(Node::Mul(Num::norm(c), merged.into_boxed_slice())),
        }
    }

    /// The common coefficient `g` of a sum factor `(g t1 + g t2 + ...)^e` (no constant term,
    /// all coefficients equal, not 1), taken out as `g^e (t1 + t2 + ...)^e`: derivatives of
    /// squared norms give `2 a a' + 2 b b'`, and the 2 then cancels against the 1/2 of a
    /// square root. A negative `g` only for integer `e`. This also keeps a sum factor of a
    /// product canonical (`(2a + 2b) x` and `2 (a + b) x` are the same node).
    fn common_coefficient(c0: f64, ts: &[(Id, Num)], e: f64) -> Option<f64> {
        let g = ts.first()?.1.0;
        let same = ts.iter().all(|(_, a)| a.0 == g);
        (c0 == 0.0 && same && g != 1.0 && g.is_finite() && (g > 0.0 || is_int(e))).then_some(g)
    }

    /// Whether `(c * prod b_k^e_k)^e` is written `c^e * prod b_k^(e_k e)`.
    ///
    /// Under the simplification contract this is exact for an integer `e`; for other `e`
    /// only with one factor, `c > 0`, and an inner exponent that is not an even integer
    /// (`(x^2)^0.5 = |x|`, and `(x*y)^0.5` is finite for `x, y < 0` where
    /// `x^0.5 * y^0.5` is not). Over several factors we only distribute `e = +-1`
    /// (a product or a quotient, free): `(x*y)^2 = x^2 * y^2` would cost a power per factor.
    fn distributes(c: f64, fs: &[(Id, Num)], e: f64) -> bool {
        if fs.len() == 1 {
            is_int(e) || (c > 0.0 && !is_even_int(fs[0].1.0))
        } else {
            e.abs() == 1.0
        }
    }

    /// `a + b`
    pub fn add(&mut self, a: Id, b: Id) -> Id {
        self.lin(0.0, &[(a, 1.0), (b, 1.0)])
    }

    /// `a - b`
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        self.lin(0.0, &[(a, 1.0), (b, -1.0)])
    }

    /// `a * b`
    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        self.product(1.0, &[(a, 1.0), (b, 1.0)])
    }

    /// `a / b`
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        self.product(1.0, &[(a, 1.0), (b, -1.0)])
    }

    /// `-a`
    pub fn neg(&mut self, a: Id) -> Id {
        self.product(-1.0, &[(a, 1.0)])
    }

    /// `c * a`
    pub fn scale(&mut self, c: f64, a: Id) -> Id {
        self.product(c, &[(a, 1.0)])
    }

    /// `a ^ e` for a number `e`.
    pub fn powf(&mut self, a: Id, e: f64) -> Id {
        self.product(1.0, &[(a, e)])
    }

    /// `sqrt(a)`, stored as `a^0.5`.
    pub fn sqrt(&mut self, a: Id) -> Id {
        self.powf(a, 0.5)
    }

    /// `a ^ b`
    pub fn pow(&mut self, a: Id, b: Id) -> Id {
        if let Some(e) = self.as_const(b) {
            return self.powf(a, e);
        }
        if self.simplify && self.as_const(a) == Some(1.0) {
            return a;
        }
        self.intern(Node::Pow(a, b))
    }

    /// A one-argument function `f` (not `sqrt`, which is the power `^0.5`).
    pub fn f1(&mut self, f: Func, a: Id) -> Id {
        debug_assert!(f.arity() == 1 && f != Func::Sqrt, "{f:?} is not an F1 node");
        if self.simplify {
            if let Some(v) = self.as_const(a) {
                let r = f.apply1(v);
                if r.is_finite() {
                    return self.num(r);
                }
            }
            match (f, self.node(a)) {
                (Func::Abs | Func::Sign, Node::F1(g, _)) if *g == f => return a,
                (Func::Ln, Node::F1(Func::Exp, x)) => return *x,
                _ => {}
            }
        }
        self.intern(Node::F1(f, a))
    }

    /// `atan2`, `min` or `max` (`pow` is [`Arena::pow`]).
    pub fn f2(&mut self, f: Func, a: Id, b: Id) -> Id {
        debug_assert!(
            matches!(f, Func::Atan2 | Func::Min | Func::Max),
            "{f:?} is not an F2 node"
        );
        if self.simplify {
            if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b)) {
                let r = f.apply2(x, y);
                if r.is_finite() {
                    return self.num(r);
                }
            }
            if a == b && matches!(f, Func::Min | Func::Max) {
                return a;
            }
        }
        self.intern(Node::F2(f, a, b))
    }

    /// `e` (in the context of `m`'s codomain) at the image of the element at hand under
    /// `m`. A scalar is the same at every element (`Gather(m, scalar) = scalar`), the
    /// identity changes nothing, and a gather of a gather is one gather through the
    /// composed map. These rules hold whether or not the arena simplifies: they are the
    /// meaning of contexts.
    pub fn gather(&mut self, m: MapId, e: Id) -> Id {
        if self.ctx(e).is_none() || self.maps().get(m).kind == MapKind::Identity {
            return e;
        }
        if let Node::Gather(m1, inner) = *self.node(e) {
            let composed = self.maps_mut().compose(m, m1);
            return self.gather(composed, inner);
        }
        self.intern(Node::Gather(m, e))
    }

    /// The sum of `body` (in the context of `m`'s domain) over the elements `m` sends to
    /// the element at hand. A zero body is zero.
    pub fn sum(&mut self, m: MapId, body: Id) -> Id {
        if self.as_const(body) == Some(0.0) {
            return self.num(0.0);
        }
        self.intern(Node::Sum(m, body))
    }

    /// A call of a built-in function of the language (`args` has the function's arity).
    pub fn call(&mut self, f: Func, args: &[Id]) -> Id {
        match f {
            Func::Sqrt => self.sqrt(args[0]),
            Func::Pow => self.pow(args[0], args[1]),
            Func::Atan2 | Func::Min | Func::Max => self.f2(f, args[0], args[1]),
            _ => self.f1(f, args[0]),
        }
    }
}
