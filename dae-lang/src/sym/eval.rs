//! Numerical evaluation of arena nodes at a point.

use super::{Arena, Id, Node};
use crate::VarRef;

/// Values for every kind of leaf. A leaf whose index is out of range evaluates to NaN
/// (e.g. an `s_i` evaluated without realization parameters), never a panic.
#[derive(Clone, Copy, Debug, Default)]
pub struct Point<'a> {
    /// Parameter values, by index.
    pub params: &'a [f64],
    /// State values.
    pub states: &'a [f64],
    /// Algebraic values.
    pub algs: &'a [f64],
    /// Time.
    pub t: f64,
    /// Realization parameters `mu_1, mu_2, ...`.
    pub mu: &'a [f64],
}

/// `v ^ e` with the exact fast paths of the common exponents.
#[inline]
pub(crate) fn powe(v: f64, e: f64) -> f64 {
    if e == 1.0 {
        v
    } else if e == -1.0 {
        1.0 / v
    } else if e == 2.0 {
        v * v
    } else if e == 0.5 {
        v.sqrt()
    } else if e == -0.5 {
        1.0 / v.sqrt()
    } else if e.fract() == 0.0 && e.abs() < 64.0 {
        v.powi(e as i32)
    } else {
        v.powf(e)
    }
}

fn get(xs: &[f64], i: usize) -> f64 {
    xs.get(i).copied().unwrap_or(f64::NAN)
}

impl Point<'_> {
    /// The value of a variable (NaN if its index is out of range).
    pub fn var(&self, v: VarRef) -> f64 {
        match v {
            VarRef::Param(i) => get(self.params, i.index()),
            VarRef::State(i) => get(self.states, i.index()),
            VarRef::Alg(i) => get(self.algs, i.index()),
            VarRef::Time => self.t,
            VarRef::Mu(i) => get(self.mu, i.index()),
            // Family leaves need an instance (`Program::eval`); the rate of an unknown
            // is only in `Omega'`, which version-1 models do not compile.
            VarRef::Input(..) | VarRef::Elem(_) | VarRef::Size(_) | VarRef::AlgRate(_) => f64::NAN,
        }
    }
}

impl Arena {
    /// Evaluate nodes `0..=last` into `buf` (`buf[i]` is node `i`), reusing its storage:
    /// no allocation once `buf` has held that many values. Children precede parents, so
    /// one forward sweep suffices.
    pub fn eval_upto(&self, last: Id, p: &Point, buf: &mut Vec<f64>) {
        let n = last.index() + 1;
        buf.clear();
        buf.reserve(n);
        for node in &self.nodes[..n] {
            let v = match node {
                Node::Const(c) => c.0,
                Node::Var(v) => p.var(*v),
                Node::Add(c, ts) => ts.iter().fold(c.0, |s, (t, a)| {
                    let x = buf[t.index()];
                    if a.0 == 1.0 {
                        s + x
                    } else if a.0 == -1.0 {
                        s - x
                    } else {
                        s + a.0 * x
                    }
                }),
                Node::Mul(c, fs) => {
                    // Numerator and denominator apart: one division, and `x/x` is exactly 1.
                    let (mut num, mut den) = (1.0, 1.0);
                    for (b, e) in fs.iter() {
                        let x = buf[b.index()];
                        if e.0 >= 0.0 {
                            num *= powe(x, e.0);
                        } else {
                            den *= powe(x, -e.0);
                        }
                    }
                    let q = if den == 1.0 { num } else { num / den };
                    if c.0 == 1.0 { q } else { c.0 * q }
                }
                Node::Pow(a, b) => buf[a.index()].powf(buf[b.index()]),
                Node::F1(f, a) => f.apply1(buf[a.index()]),
                Node::F2(f, a, b) => f.apply2(buf[a.index()], buf[b.index()]),
                // Gathers and sums need an instance (`Program::eval`).
                Node::Gather(..) | Node::Sum(..) => f64::NAN,
            };
            buf.push(v);
        }
    }

    /// Evaluate every node into `buf` (see [`Arena::eval_upto`]).
    pub fn eval_all(&self, p: &Point, buf: &mut Vec<f64>) {
        if let Some(n) = self.len().checked_sub(1) {
            self.eval_upto(Id(n as u32), p, buf);
        } else {
            buf.clear();
        }
    }

    /// The value of one expression (allocates a scratch buffer; use [`Arena::eval_upto`]
    /// with a reused buffer in loops).
    pub fn eval(&self, id: Id, p: &Point) -> f64 {
        let mut buf = Vec::new();
        self.eval_upto(id, p, &mut buf);
        buf[id.index()]
    }
}
