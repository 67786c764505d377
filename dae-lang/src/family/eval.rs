//! The vectorised interpreter of family programs: each instruction runs over a chunk of
//! elements (up to [`CHUNK`]) at a time, so that its dispatch is paid once per chunk,
//! not once per element. Allocation-free once the [`Scratch`] is built.

use super::construct::Instance;
use super::program::{Arg, Dest, Factor, Plan, Program, Sink, Step};
use crate::tape::{BinaryOp, Operand, UnaryOp, binary, unary};
use crate::{Func, VarRef};

/// Elements per chunk.
pub const CHUNK: usize = 128;

/// The values of one evaluation (the runtime's vectors, in the instance's layout).
#[derive(Clone, Copy, Debug)]
pub struct Values<'a> {
    /// Parameters.
    pub params: &'a [f64],
    /// States `x`.
    pub states: &'a [f64],
    /// Algebraic unknowns `z`.
    pub algs: &'a [f64],
    /// Realization parameters, one per constraint row.
    pub mu: &'a [f64],
    /// Input values (each with its derivatives).
    pub inputs: &'a [f64],
    /// Time.
    pub t: f64,
}

/// The working memory of [`Program::eval`] for one program and instance.
#[derive(Clone, Debug)]
pub struct Scratch {
    arrays: Vec<Vec<f64>>,
    bufs: Vec<f64>,
    scalars: Vec<f64>,
}

impl Scratch {
    /// Scratch for `p` on `inst` (allocates; build it once, at construction).
    pub fn new(p: &Program, inst: &Instance) -> Scratch {
        let arrays = p
            .arrays
            .iter()
            .map(|a| vec![0.0; inst.set_size(a.over)])
            .collect();
        let bufs = p
            .plans
            .iter()
            .map(|pl| pl.loads.len() + pl.steps.len())
            .max()
            .unwrap_or(0)
            * CHUNK;
        let scalars = p.plans.iter().map(|pl| pl.scalars.len()).max().unwrap_or(0);
        Scratch {
            arrays,
            bufs: vec![0.0; bufs],
            scalars: vec![0.0; scalars],
        }
    }
}

/// The value of a variable at element `e`.
#[inline]
fn var(v: VarRef, e: usize, inst: &Instance, x: &Values<'_>) -> f64 {
    let l = &inst.layout;
    match v {
        VarRef::Param(i) => x.params[l.params[i.index()].at(e)],
        VarRef::State(i) => x.states[l.states[i.index()].at(e)],
        VarRef::Alg(i) => x.algs[l.algs[i.index()].at(e)],
        VarRef::Mu(c) => x.mu[l.rows[c.index()].at(e)],
        VarRef::Input(i, j) => x.inputs[l.input_values[i.index()].at(e) + j as usize],
        VarRef::Time => x.t,
        VarRef::Elem(_) => e as f64,
        VarRef::Size(s) => inst.size_values[s.index()] as f64,
    }
}

/// An array's value at element `e` (its only value if it is scalar).
#[inline]
fn at(a: &[f64], e: usize) -> f64 {
    if a.len() == 1 { a[0] } else { a[e] }
}

impl Program {
    /// Evaluates the program (see the module documentation of [`Program`] for what it
    /// computes) into `out` (the outputs of this function, e.g. `[dx]` for `rhs`,
    /// `[w, s, alpha_hat]` for `sliding`, `[values]` for `jacobian`), using `scratch`
    /// (built for this program and instance). Allocates nothing.
    ///
    /// # Panics
    /// If a vector is shorter than the instance's layout says (a programming error of
    /// the caller, never a user error).
    pub fn eval(
        &self,
        inst: &Instance,
        x: &Values<'_>,
        scratch: &mut Scratch,
        out: &mut [&mut [f64]],
    ) {
        let Scratch {
            arrays,
            bufs,
            scalars,
        } = scratch;
        for (a, def) in arrays.iter_mut().zip(&self.arrays) {
            if def.accumulate {
                a.fill(0.0);
            }
        }
        if !self.entries.is_empty() {
            out[0].fill(0.0);
        }
        for (g, plan) in self.groups.iter().zip(&self.plans) {
            let n = inst.set_size(g.over);
            run_group(plan, n, inst, x, arrays, bufs, scalars, out);
        }
        for el in &self.entries {
            let values = &mut *out[0];
            let list = &inst.jacobian.lists[el.coupling];
            let factor = |f: Factor, e: usize| match f {
                Factor::Const(c) => c,
                Factor::Array(a) => at(&arrays[a.index()], e),
            };
            for &[entry, l, k] in list {
                let mut v = 0.0;
                for &(r, c) in &el.terms {
                    v += factor(r, l as usize) * factor(c, k as usize);
                }
                values[entry as usize] += v;
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn run_group(
    plan: &Plan,
    n: usize,
    inst: &Instance,
    x: &Values<'_>,
    arrays: &mut [Vec<f64>],
    bufs: &mut [f64],
    scalars: &mut [f64],
    out: &mut [&mut [f64]],
) {
    for (s, o) in scalars.iter_mut().zip(&plan.scalars) {
        *s = match *o {
            Operand::Input(v) => var(v, 0, inst, x),
            Operand::Array(a) => arrays[a.index()][0],
            Operand::Const(c) => c,
            // Per-element operands are loads, never scalars.
            _ => f64::NAN,
        };
    }
    let nl = plan.loads.len();
    let mut start = 0;
    while start < n {
        let len = CHUNK.min(n - start);
        for (i, o) in plan.loads.iter().enumerate() {
            let buf = &mut bufs[i * CHUNK..i * CHUNK + len];
            load(*o, start, buf, inst, x, arrays);
        }
        for (k, step) in plan.steps.iter().enumerate() {
            let (lower, upper) = bufs.split_at_mut((nl + k) * CHUNK);
            let dst = &mut upper[..len];
            let get = |a: Arg| match a {
                Arg::Buf(b) => Src::Slice(&lower[b as usize * CHUNK..b as usize * CHUNK + len]),
                Arg::Scalar(s) => Src::Value(scalars[s as usize]),
                Arg::Const(c) => Src::Value(c),
            };
            match *step {
                Step::Unary(op, a) => un(op, get(a), dst),
                Step::Binary(op, a, b) => bi(op, get(a), get(b), dst),
            }
        }
        for &(a, sink) in &plan.outputs {
            for j in 0..len {
                let e = start + j;
                let v = match a {
                    Arg::Buf(b) => bufs[b as usize * CHUNK + j],
                    Arg::Scalar(s) => scalars[s as usize],
                    Arg::Const(c) => c,
                };
                match sink {
                    Sink::Out(d) => {
                        let l = &inst.layout;
                        let slot = match d {
                            Dest::Rhs(s) => l.states[s.index()].at(e),
                            Dest::W(c, j) => l.w[c.index()].at(e) + j as usize,
                            Dest::S(c) | Dest::AlphaHat(c) | Dest::Beta(c) => {
                                l.rows[c.index()].at(e)
                            }
                        };
                        out[d.output()][slot] = v;
                    }
                    Sink::Store(arr) => {
                        let a = &mut arrays[arr.index()];
                        let i = if a.len() == 1 { 0 } else { e };
                        a[i] = v;
                    }
                    Sink::ScatterAdd(arr, m) => {
                        let to = inst.maps[m.index()][e] as usize;
                        arrays[arr.index()][to] += v;
                    }
                }
            }
        }
        start += len;
    }
}

/// Fills `buf` with operand `o` at elements `start .. start + buf.len()`.
fn load(
    o: Operand,
    start: usize,
    buf: &mut [f64],
    inst: &Instance,
    x: &Values<'_>,
    arrays: &[Vec<f64>],
) {
    let l = &inst.layout;
    match o {
        Operand::Input(v) => strided(v, buf, |j| start + j, inst, x),
        Operand::Gather(v, m) => {
            let map = &inst.maps[m.index()][start..start + buf.len()];
            if let VarRef::Elem(_) = v {
                for (b, &e) in buf.iter_mut().zip(map) {
                    *b = e as f64;
                }
            } else {
                let (vec, slot, off) = source(v, inst, x);
                for (b, &e) in buf.iter_mut().zip(map) {
                    *b = vec[slot.at(e as usize) + off];
                }
            }
        }
        Operand::Array(a) => buf.copy_from_slice(&arrays[a.index()][start..start + buf.len()]),
        Operand::ArrayAt(a, m) => {
            let arr = &arrays[a.index()];
            let map = &inst.maps[m.index()][start..start + buf.len()];
            for (b, &e) in buf.iter_mut().zip(map) {
                *b = arr[e as usize];
            }
        }
        Operand::Const(c) => buf.fill(c),
        Operand::Slot(_) => {}
    }
    let _ = l;
}

/// The vector, slot and extra offset a variable is read from.
fn source<'v>(
    v: VarRef,
    inst: &Instance,
    x: &Values<'v>,
) -> (&'v [f64], super::layout::Slot, usize) {
    let l = &inst.layout;
    match v {
        VarRef::Param(i) => (x.params, l.params[i.index()], 0),
        VarRef::State(i) => (x.states, l.states[i.index()], 0),
        VarRef::Alg(i) => (x.algs, l.algs[i.index()], 0),
        VarRef::Mu(c) => (x.mu, l.rows[c.index()], 0),
        VarRef::Input(i, j) => (x.inputs, l.input_values[i.index()], j as usize),
        // Not read from a vector (handled by the callers).
        VarRef::Time | VarRef::Elem(_) | VarRef::Size(_) => {
            (&[], super::layout::Slot::default(), 0)
        }
    }
}

/// `buf[j] = v at element index(j)`.
#[inline]
fn strided(
    v: VarRef,
    buf: &mut [f64],
    index: impl Fn(usize) -> usize,
    inst: &Instance,
    x: &Values<'_>,
) {
    match v {
        VarRef::Elem(_) => {
            for (j, b) in buf.iter_mut().enumerate() {
                *b = index(j) as f64;
            }
        }
        VarRef::Time | VarRef::Size(_) => buf.fill(var(v, 0, inst, x)),
        _ => {
            let (vec, slot, off) = source(v, inst, x);
            for (j, b) in buf.iter_mut().enumerate() {
                *b = vec[slot.at(index(j)) + off];
            }
        }
    }
}

/// An argument: a chunk of values or one value for all.
#[derive(Clone, Copy)]
enum Src<'a> {
    Slice(&'a [f64]),
    Value(f64),
}

#[inline(always)]
fn map1(a: Src<'_>, dst: &mut [f64], f: impl Fn(f64) -> f64) {
    match a {
        Src::Slice(s) => {
            for (d, &v) in dst.iter_mut().zip(s) {
                *d = f(v);
            }
        }
        Src::Value(v) => dst.fill(f(v)),
    }
}

#[inline(always)]
fn map2(a: Src<'_>, b: Src<'_>, dst: &mut [f64], f: impl Fn(f64, f64) -> f64) {
    match (a, b) {
        (Src::Slice(x), Src::Slice(y)) => {
            for ((d, &u), &v) in dst.iter_mut().zip(x).zip(y) {
                *d = f(u, v);
            }
        }
        (Src::Slice(x), Src::Value(v)) => {
            for (d, &u) in dst.iter_mut().zip(x) {
                *d = f(u, v);
            }
        }
        (Src::Value(u), Src::Slice(y)) => {
            for (d, &v) in dst.iter_mut().zip(y) {
                *d = f(u, v);
            }
        }
        (Src::Value(u), Src::Value(v)) => dst.fill(f(u, v)),
    }
}

fn un(op: UnaryOp, a: Src<'_>, dst: &mut [f64]) {
    match op {
        UnaryOp::Neg => map1(a, dst, |v| -v),
        UnaryOp::Powi(2) => map1(a, dst, |v| v * v),
        UnaryOp::Powi(n) => map1(a, dst, |v| v.powi(n)),
        UnaryOp::Call(Func::Sqrt) => map1(a, dst, f64::sqrt),
        UnaryOp::Call(_) => map1(a, dst, |v| unary(op, v)),
    }
}

fn bi(op: BinaryOp, a: Src<'_>, b: Src<'_>, dst: &mut [f64]) {
    match op {
        BinaryOp::Add => map2(a, b, dst, |u, v| u + v),
        BinaryOp::Sub => map2(a, b, dst, |u, v| u - v),
        BinaryOp::Mul => map2(a, b, dst, |u, v| u * v),
        BinaryOp::Div => map2(a, b, dst, |u, v| u / v),
        BinaryOp::Call(_) => map2(a, b, dst, |u, v| binary(op, u, v)),
    }
}
