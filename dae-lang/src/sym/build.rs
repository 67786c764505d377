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

use super::{Arena, Fun1, Fun2, Id, Node, Num};
use crate::model::Func;

/// `v ^ e` for constant folding.
fn pow_num(v: f64, e: f64) -> f64 {
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

    /// Parameter `i`.
    pub fn param(&mut self, i: usize) -> Id {
        self.intern(Node::Param(i as u32))
    }

    /// State `i`.
    pub fn state(&mut self, i: usize) -> Id {
        self.intern(Node::State(i as u32))
    }

    /// Algebraic unknown `i`.
    pub fn alg(&mut self, i: usize) -> Id {
        self.intern(Node::Alg(i as u32))
    }

    /// Time `t`.
    pub fn time(&mut self) -> Id {
        self.intern(Node::Time)
    }

    /// Realization parameter `mu_{i+1}` of constraint `i`.
    pub fn mu(&mut self, i: usize) -> Id {
        self.intern(Node::Mu(i as u32))
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
                Some((t0, a0)) if *t0 == t => a0.0 += a,
                _ => merged.push((t, Num(a))),
            }
        }
        merged.retain(|(_, a)| a.0 != 0.0);
        match merged.as_slice() {
            [] => self.num(c),
            [(t, a)] if c == 0.0 => {
                let (t, a) = (*t, a.0);
                if a == 1.0 {
                    t
                } else if let Node::Mul(_, fs) = self.node(t) {
                    // Only unit-coefficient products reach here (see the loop above).
                    let fs = fs.clone();
                    self.intern(Node::Mul(Num::norm(a), fs))
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
                Node::Mul(c2, fs) if Self::distributes(c2.0, fs, e) => {
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
            return self.num(0.0);
        }
        acc.sort_by_key(|(b, _)| *b);
        let mut merged: Vec<(Id, Num)> = Vec::with_capacity(acc.len());
        for (b, e) in acc {
            match merged.last_mut() {
                Some((b0, e0)) if *b0 == b => e0.0 += e,
                _ => merged.push((b, Num(e))),
            }
        }
        merged.retain(|(_, e)| e.0 != 0.0);
        // Merging can make a kept product base distributable (`p^0.5 * p^0.5 = p^1`).
        let again = merged.iter().any(|(b, e)| match self.node(*b) {
            Node::Mul(c2, fs) => Self::distributes(c2.0, fs, e.0),
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

    /// A one-argument function.
    pub fn f1(&mut self, f: Fun1, a: Id) -> Id {
        if self.simplify {
            if let Some(v) = self.as_const(a) {
                let r = f.apply(v);
                if r.is_finite() {
                    return self.num(r);
                }
            }
            match (f, self.node(a)) {
                (Fun1::Abs | Fun1::Sign, Node::F1(g, _)) if *g == f => return a,
                (Fun1::Ln, Node::F1(Fun1::Exp, x)) => return *x,
                _ => {}
            }
        }
        self.intern(Node::F1(f, a))
    }

    /// A two-argument function.
    pub fn f2(&mut self, f: Fun2, a: Id, b: Id) -> Id {
        if self.simplify {
            if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b)) {
                let r = f.apply(x, y);
                if r.is_finite() {
                    return self.num(r);
                }
            }
            if a == b && matches!(f, Fun2::Min | Fun2::Max) {
                return a;
            }
        }
        self.intern(Node::F2(f, a, b))
    }

    /// A call of a built-in function of the language (`args` has the function's arity).
    pub fn call(&mut self, f: Func, args: &[Id]) -> Id {
        let a = args[0];
        let one = match f {
            Func::Sin => Fun1::Sin,
            Func::Cos => Fun1::Cos,
            Func::Tan => Fun1::Tan,
            Func::Asin => Fun1::Asin,
            Func::Acos => Fun1::Acos,
            Func::Atan => Fun1::Atan,
            Func::Sinh => Fun1::Sinh,
            Func::Cosh => Fun1::Cosh,
            Func::Tanh => Fun1::Tanh,
            Func::Exp => Fun1::Exp,
            Func::Ln => Fun1::Ln,
            Func::Abs => Fun1::Abs,
            Func::Sign => Fun1::Sign,
            Func::Sqrt => return self.sqrt(a),
            Func::Pow => return self.pow(a, args[1]),
            Func::Atan2 => return self.f2(Fun2::Atan2, a, args[1]),
            Func::Min => return self.f2(Fun2::Min, a, args[1]),
            Func::Max => return self.f2(Fun2::Max, a, args[1]),
        };
        self.f1(one, a)
    }
}

impl Fun1 {
    /// The function's value ([`Func::apply1`]).
    pub fn apply(self, x: f64) -> f64 {
        Func::from(self).apply1(x)
    }

    /// The name in the language.
    pub fn name(self) -> &'static str {
        Func::from(self).name()
    }
}

impl Fun2 {
    /// The function's value ([`Func::apply2`]).
    pub fn apply(self, a: f64, b: f64) -> f64 {
        Func::from(self).apply2(a, b)
    }

    /// The name in the language.
    pub fn name(self) -> &'static str {
        Func::from(self).name()
    }
}

impl From<Fun1> for Func {
    fn from(f: Fun1) -> Func {
        match f {
            Fun1::Sin => Func::Sin,
            Fun1::Cos => Func::Cos,
            Fun1::Tan => Func::Tan,
            Fun1::Asin => Func::Asin,
            Fun1::Acos => Func::Acos,
            Fun1::Atan => Func::Atan,
            Fun1::Sinh => Func::Sinh,
            Fun1::Cosh => Func::Cosh,
            Fun1::Tanh => Func::Tanh,
            Fun1::Exp => Func::Exp,
            Fun1::Ln => Func::Ln,
            Fun1::Abs => Func::Abs,
            Fun1::Sign => Func::Sign,
        }
    }
}

impl From<Fun2> for Func {
    fn from(f: Fun2) -> Func {
        match f {
            Fun2::Atan2 => Func::Atan2,
            Fun2::Min => Func::Min,
            Fun2::Max => Func::Max,
        }
    }
}
