//! The vectorised interpreter of family programs: each instruction runs over a chunk of
//! elements (up to [`CHUNK`]) at a time, so that its dispatch is paid once per chunk,
//! not once per element. Allocation-free once the [`Scratch`] is built.
//!
//! What keeps the per-chunk work close to the generated loops:
//! * the tape's slots live in a few registers (chunk buffers reused by liveness, see
//!   `Plan`), which stay in the first- and second-level caches;
//! * a per-element operand stored contiguously (a family variable of stride 1, a scratch
//!   array) is read in place; only strided reads and gathers are copied into a buffer,
//!   once per chunk, with the layout resolved once per group;
//! * each output is written by one loop per chunk (the sink chosen once), and the
//!   common `J_Omega` kernel (a few terms of array factors) by a loop over slices.
//!
//! The chunk size was tuned on the chain at 10^3 to 10^5 links (`family_codegen`
//! example of `dae-tests`): 128 elements cost about 10% more than 512; 1,024 and 2,048
//! were within 5% of 512.

use super::construct::Instance;
use super::program::{Arg, Dest, EntryLoop, Factor, Plan, Program, Sink, Step};
use crate::tape::{BinaryOp, Operand, UnaryOp, binary, unary};
use crate::{Func, VarRef};

/// Elements per chunk (see the module documentation).
pub const CHUNK: usize = 512;

/// The values of one evaluation (the runtime's vectors, in the instance's layout).
#[derive(Clone, Copy, Debug)]
pub struct Values<'a> {
    /// Parameters.
    pub params: &'a [f64],
    /// States `x`.
    pub states: &'a [f64],
    /// Algebraic unknowns `z`.
    pub algs: &'a [f64],
    /// Their rates `z'`, in the layout of `algs`: read by the rate program only (`Omega'`
    /// along `z' = alg_rates`); empty for the others.
    pub alg_rates: &'a [f64],
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
    /// Chunk buffers of the per-element operands that are not read in place.
    loads: Vec<f64>,
    /// Chunk buffers of the registers.
    regs: Vec<f64>,
    /// One chunk buffer for an output read from an array.
    spill: Vec<f64>,
    scalars: Vec<f64>,
    /// How each load of the group at hand is read (resolved once per group).
    cols: Vec<Col>,
}

impl Scratch {
    /// Scratch for `p` on `inst` (allocates; build it once, at construction).
    pub fn new(p: &Program, inst: &Instance) -> Scratch {
        let arrays = p
            .arrays
            .iter()
            .map(|a| vec![0.0; inst.set_size(a.over)])
            .collect();
        let max = |f: fn(&Plan) -> usize| p.plans.iter().map(f).max().unwrap_or(0);
        let loads = max(|pl| pl.loads.len());
        Scratch {
            arrays,
            loads: vec![0.0; loads * CHUNK],
            regs: vec![0.0; max(|pl| pl.regs) * CHUNK],
            spill: vec![0.0; CHUNK],
            scalars: vec![0.0; max(|pl| pl.scalars.len())],
            cols: Vec::with_capacity(loads),
        }
    }
}

/// One of the vectors of [`Values`].
#[derive(Clone, Copy, Debug)]
enum Vector {
    Params,
    States,
    Algs,
    AlgRates,
    Mu,
    Inputs,
}

fn vector<'a>(x: &Values<'a>, v: Vector) -> &'a [f64] {
    match v {
        Vector::Params => x.params,
        Vector::States => x.states,
        Vector::Algs => x.algs,
        Vector::AlgRates => x.alg_rates,
        Vector::Mu => x.mu,
        Vector::Inputs => x.inputs,
    }
}

/// How a per-element operand is read on this instance (its layout resolved).
#[derive(Clone, Copy, Debug)]
enum Col {
    /// `vector[offset + e]`, read in place.
    Direct(Vector, usize),
    /// `arrays[a][e]`, read in place.
    InArray(usize),
    /// `vector[offset + stride e]`.
    Strided(Vector, usize, usize),
    /// `vector[offset + stride maps[m][e]]`.
    Gather(Vector, usize, usize, usize),
    /// `arrays[a][maps[m][e]]`.
    ArrayAt(usize, usize),
    /// The element `e` itself, as a number.
    Index,
    /// `maps[m][e]`, as a number.
    IndexAt(usize),
    /// The same value for every element (time, a size).
    Value(f64),
}

/// The vector, first slot and stride a variable is read from (`None` for what is not
/// read from a vector).
fn source(v: VarRef, inst: &Instance) -> Option<(Vector, usize, usize)> {
    let l = &inst.layout;
    let (vec, slot, off) = match v {
        VarRef::Param(i) => (Vector::Params, l.params[i.index()], 0),
        VarRef::State(i) => (Vector::States, l.states[i.index()], 0),
        VarRef::Alg(i) => (Vector::Algs, l.algs[i.index()], 0),
        VarRef::AlgRate(i) => (Vector::AlgRates, l.algs[i.index()], 0),
        VarRef::Mu(c) => (Vector::Mu, l.rows[c.index()], 0),
        VarRef::Input(i, j) => (Vector::Inputs, l.input_value(i.index(), j as usize), 0),
        VarRef::Time | VarRef::Elem(_) | VarRef::Size(_) => return None,
    };
    Some((vec, slot.offset + off, slot.stride))
}

fn col(o: Operand, inst: &Instance, x: &Values<'_>) -> Col {
    match o {
        Operand::Input(VarRef::Elem(_)) => Col::Index,
        Operand::Gather(VarRef::Elem(_), m) => Col::IndexAt(m.index()),
        Operand::Input(v) => match source(v, inst) {
            Some((vec, off, 1)) => Col::Direct(vec, off),
            Some((vec, off, stride)) => Col::Strided(vec, off, stride),
            None => Col::Value(var(v, 0, inst, x)),
        },
        Operand::Gather(v, m) => match source(v, inst) {
            Some((vec, off, stride)) => Col::Gather(vec, off, stride, m.index()),
            None => Col::Value(var(v, 0, inst, x)),
        },
        Operand::Array(a) => Col::InArray(a.index()),
        Operand::ArrayAt(a, m) => Col::ArrayAt(a.index(), m.index()),
        Operand::Const(c) => Col::Value(c),
        // Slots are registers, never loads.
        Operand::Slot(_) => Col::Value(f64::NAN),
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
        VarRef::AlgRate(i) => x.alg_rates[l.algs[i.index()].at(e)],
        VarRef::Mu(c) => x.mu[l.rows[c.index()].at(e)],
        VarRef::Input(i, j) => x.inputs[l.input_value(i.index(), j as usize).at(e)],
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
        for (a, def) in scratch.arrays.iter_mut().zip(&self.arrays) {
            if def.accumulate {
                a.fill(0.0);
            }
        }
        if !self.entries.is_empty() {
            out[0].fill(0.0);
        }
        for (g, plan) in self.groups.iter().zip(&self.plans) {
            let n = inst.set_size(g.over);
            run_group(plan, n, inst, x, scratch, out);
        }
        let arrays = &scratch.arrays;
        for el in &self.entries {
            entry_loop(el, &inst.jacobian.lists[el.coupling], arrays, out[0]);
        }
    }
}

/// `values[entry] += sum over terms of R(l) * C(k)` for every `[entry, l, k]` of the
/// list (the terms summed left to right from 0, as the generated code does).
fn entry_loop(el: &EntryLoop, list: &[[u32; 3]], arrays: &[Vec<f64>], values: &mut [f64]) {
    let family = |f: Factor| match f {
        Factor::Array(a) if arrays[a.index()].len() > 1 => Some(&arrays[a.index()][..]),
        _ => None,
    };
    // The common kernel: every factor an array over a set, a few terms.
    const MAX: usize = 4;
    if el.terms.len() <= MAX
        && el
            .terms
            .iter()
            .all(|&(r, c)| family(r).is_some() && family(c).is_some())
    {
        let mut ts: [(&[f64], &[f64]); MAX] = [(&[], &[]); MAX];
        for (t, &(r, c)) in ts.iter_mut().zip(&el.terms) {
            *t = (family(r).unwrap_or(&[]), family(c).unwrap_or(&[]));
        }
        let ts = &ts[..el.terms.len()];
        for &[entry, l, k] in list {
            let (l, k) = (l as usize, k as usize);
            let mut v = 0.0;
            for (r, c) in ts {
                v += r[l] * c[k];
            }
            values[entry as usize] += v;
        }
        return;
    }
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

/// Runs one group over `0..n`, chunk by chunk.
fn run_group(
    plan: &Plan,
    n: usize,
    inst: &Instance,
    x: &Values<'_>,
    scratch: &mut Scratch,
    out: &mut [&mut [f64]],
) {
    let Scratch {
        arrays,
        loads,
        regs,
        spill,
        scalars,
        cols,
    } = scratch;
    for (s, o) in scalars.iter_mut().zip(&plan.scalars) {
        *s = match *o {
            Operand::Input(v) => var(v, 0, inst, x),
            Operand::Array(a) => arrays[a.index()][0],
            Operand::Const(c) => c,
            // Per-element operands are loads, never scalars.
            _ => f64::NAN,
        };
    }
    cols.clear();
    cols.extend(plan.loads.iter().map(|&o| col(o, inst, x)));
    let mut start = 0;
    while start < n {
        let len = CHUNK.min(n - start);
        for (i, &c) in cols.iter().enumerate() {
            load(
                c,
                start,
                &mut loads[i * CHUNK..i * CHUNK + len],
                inst,
                x,
                arrays,
            );
        }
        let chunk = Chunk {
            x,
            arrays,
            loads,
            cols,
            scalars,
            start,
            len,
        };
        for step in &plan.steps {
            let d = match *step {
                Step::Unary(_, _, d) | Step::Binary(_, _, _, d) => d as usize,
            };
            let (lower, rest) = regs.split_at_mut(d * CHUNK);
            let (dst, upper) = rest.split_at_mut(CHUNK);
            let dst = &mut dst[..len];
            let get = |a: Arg| chunk.get(a, lower, upper, d);
            match *step {
                Step::Unary(op, a, _) => un(op, get(a), dst),
                Step::Binary(op, a, b, _) => bi(op, get(a), get(b), dst),
            }
        }
        for &(a, sink) in &plan.outputs {
            // A value read from an array is copied first: the sink may write arrays.
            let v = match a {
                Arg::Load(i) => match cols[i as usize] {
                    Col::Direct(vec, off) => Src::Slice(&vector(x, vec)[off + start..][..len]),
                    Col::InArray(arr) => {
                        spill[..len].copy_from_slice(&arrays[arr][start..start + len]);
                        Src::Slice(&spill[..len])
                    }
                    _ => Src::Slice(&loads[i as usize * CHUNK..][..len]),
                },
                Arg::Reg(r) => Src::Slice(&regs[r as usize * CHUNK..][..len]),
                Arg::Scalar(s) => Src::Value(scalars[s as usize]),
                Arg::Const(c) => Src::Value(c),
            };
            sink_chunk(sink, v, start, len, inst, arrays, out);
        }
        start += len;
    }
}

/// What the steps of one chunk read.
struct Chunk<'a, 'v> {
    x: &'a Values<'v>,
    arrays: &'a [Vec<f64>],
    loads: &'a [f64],
    cols: &'a [Col],
    scalars: &'a [f64],
    start: usize,
    len: usize,
}

impl<'a> Chunk<'a, '_> {
    /// Argument `a` of a step whose destination is register `d` (registers below `d`
    /// are in `lower`, those above in `upper`).
    #[inline(always)]
    fn get<'s>(&self, a: Arg, lower: &'s [f64], upper: &'s [f64], d: usize) -> Src<'s>
    where
        'a: 's,
    {
        let len = self.len;
        match a {
            Arg::Reg(r) => {
                let r = r as usize;
                Src::Slice(if r < d {
                    &lower[r * CHUNK..r * CHUNK + len]
                } else {
                    let r = r - d - 1;
                    &upper[r * CHUNK..r * CHUNK + len]
                })
            }
            Arg::Load(i) => Src::Slice(match self.cols[i as usize] {
                Col::Direct(vec, off) => {
                    &vector(self.x, vec)[off + self.start..off + self.start + len]
                }
                Col::InArray(arr) => &self.arrays[arr][self.start..self.start + len],
                _ => &self.loads[i as usize * CHUNK..i as usize * CHUNK + len],
            }),
            Arg::Scalar(s) => Src::Value(self.scalars[s as usize]),
            Arg::Const(c) => Src::Value(c),
        }
    }
}

/// Output `v` of the elements `start .. start + len` goes to `sink`.
fn sink_chunk(
    sink: Sink,
    v: Src<'_>,
    start: usize,
    len: usize,
    inst: &Instance,
    arrays: &mut [Vec<f64>],
    out: &mut [&mut [f64]],
) {
    match sink {
        Sink::Out(d) => {
            let l = &inst.layout;
            let (slot, j) = match d {
                Dest::Rhs(s) => (l.states[s.index()], 0),
                Dest::W(c, j) => (l.w[c.index()], j as usize),
                Dest::S(c) | Dest::AlphaHat(c) | Dest::Rate(c) => (l.rows[c.index()], 0),
            };
            let o = &mut *out[d.output()];
            let first = slot.at(start) + j;
            if slot.stride == 1 {
                put(v, &mut o[first..first + len]);
            } else {
                // stride 0 (a scalar output): the one slot, written by each element.
                let step = slot.stride.max(1);
                let o = &mut o[first..];
                match v {
                    Src::Slice(s) => {
                        for (d, &v) in o.iter_mut().step_by(step).zip(s) {
                            *d = v;
                        }
                    }
                    Src::Value(v) => {
                        for d in o.iter_mut().step_by(step).take(len) {
                            *d = v;
                        }
                    }
                }
            }
        }
        Sink::Store(arr) => {
            let a = &mut arrays[arr.index()];
            if a.len() == 1 {
                a[0] = match v {
                    Src::Slice(s) => s[len - 1],
                    Src::Value(v) => v,
                };
            } else {
                put(v, &mut a[start..start + len]);
            }
        }
        Sink::ScatterAdd(arr, m) | Sink::ScatterSub(arr, m) => {
            let a = &mut arrays[arr.index()];
            let map = &inst.maps[m.index()][start..start + len];
            // `a + (-1 v)` is `a - v` to the bit: one loop for both.
            let sign = if matches!(sink, Sink::ScatterAdd(..)) {
                1.0
            } else {
                -1.0
            };
            match v {
                Src::Slice(s) => {
                    for (&to, &v) in map.iter().zip(s) {
                        a[to as usize] += sign * v;
                    }
                }
                Src::Value(v) => {
                    for &to in map {
                        a[to as usize] += sign * v;
                    }
                }
            }
        }
    }
}

/// `dst = v`.
#[inline]
fn put(v: Src<'_>, dst: &mut [f64]) {
    match v {
        Src::Slice(s) => dst.copy_from_slice(s),
        Src::Value(v) => dst.fill(v),
    }
}

/// Fills `buf` with the operand read as `c` at elements `start .. start + buf.len()`
/// (nothing for an operand read in place).
fn load(
    c: Col,
    start: usize,
    buf: &mut [f64],
    inst: &Instance,
    x: &Values<'_>,
    arrays: &[Vec<f64>],
) {
    let len = buf.len();
    match c {
        Col::Direct(..) | Col::InArray(_) => {}
        Col::Strided(vec, off, stride) => {
            let v = &vector(x, vec)[off + stride * start..];
            for (b, &s) in buf.iter_mut().zip(v.iter().step_by(stride)) {
                *b = s;
            }
        }
        Col::Gather(vec, off, stride, m) => {
            let v = vector(x, vec);
            let map = &inst.maps[m][start..start + len];
            for (b, &e) in buf.iter_mut().zip(map) {
                *b = v[off + stride * e as usize];
            }
        }
        Col::ArrayAt(a, m) => {
            let arr = &arrays[a];
            let map = &inst.maps[m][start..start + len];
            for (b, &e) in buf.iter_mut().zip(map) {
                *b = arr[e as usize];
            }
        }
        Col::Index => {
            for (j, b) in buf.iter_mut().enumerate() {
                *b = (start + j) as f64;
            }
        }
        Col::IndexAt(m) => {
            for (b, &e) in buf.iter_mut().zip(&inst.maps[m][start..start + len]) {
                *b = e as f64;
            }
        }
        Col::Value(v) => buf.fill(v),
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
