//! Straight-line programs ("tapes"): the common form of every compiled function.
//!
//! The symbolic DAG of a model is hash-consed, so each node is already a unique
//! sub-expression. Emitting the nodes reachable from a function's outputs in topological
//! order, once each, is common-subexpression elimination across all the outputs of that
//! function. The result is a [`Tape`]: instruction `k` writes slot `k` from operands that
//! are constants, inputs or earlier slots. Two back ends read it: the Rust code generator
//! (one `let` per slot) and the interpreter ([`Tape::eval`]), so the interpreter is an
//! oracle for the generated code that shares no evaluation code with it.
//!
//! The tapes of a family model's programs ([`crate::family::Program`]) run once per
//! element of a set; their operands may read at *element paths* ([`Operand::Gather`],
//! [`Operand::Array`], [`Operand::ArrayAt`]); [`crate::family::Program`] documents what
//! they read. A version-1 tape has none of these.

use crate::{ArrayId, Func, MapId, VarRef};

pub(crate) mod emit;
mod reciprocal;

/// An operand of an instruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Operand {
    /// A literal.
    Const(f64),
    /// A variable read from the caller's [`Inputs`]; in a family program, a scalar
    /// variable, or a family variable at the element at hand.
    Input(VarRef),
    /// The result of an earlier instruction.
    Slot(u32),
    /// A family variable read at the image of the element at hand under the map (family
    /// programs only; `Gather(Elem(Q), m)` is the image itself, as a number).
    Gather(VarRef, MapId),
    /// A scratch array at the element at hand (its only value for a scalar array)
    /// (family programs only).
    Array(ArrayId),
    /// A scratch array at the image of the element at hand under the map (family
    /// programs only).
    ArrayAt(ArrayId, MapId),
}

/// An operand as a key of a hash map: what it reads, a literal by its bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum OperandKey {
    Const(u64),
    Input(VarRef),
    Slot(u32),
    Gather(VarRef, MapId),
    Array(ArrayId),
    ArrayAt(ArrayId, MapId),
}

impl Operand {
    /// This operand as a key ([`OperandKey`]).
    pub(crate) fn key(self) -> OperandKey {
        match self {
            Operand::Const(c) => OperandKey::Const(c.to_bits()),
            Operand::Input(v) => OperandKey::Input(v),
            Operand::Slot(k) => OperandKey::Slot(k),
            Operand::Gather(v, m) => OperandKey::Gather(v, m),
            Operand::Array(a) => OperandKey::Array(a),
            Operand::ArrayAt(a, m) => OperandKey::ArrayAt(a, m),
        }
    }
}

/// One-operand operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// `-a`
    Neg,
    /// A one-argument built-in function (never `Atan2`, `Pow`, `Min`, `Max`).
    Call(Func),
    /// `a^n` for a small integer `n` (evaluated with `powi`).
    Powi(i32),
}

/// Two-operand operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `a + b`
    Add,
    /// `a - b`
    Sub,
    /// `a * b`
    Mul,
    /// `a / b`
    Div,
    /// A two-argument built-in function: `pow` (a non-integer or symbolic exponent,
    /// evaluated with `powf`), `atan2`, `min` or `max`.
    Call(Func),
}

/// One instruction; its result goes to the slot with its own position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Instr {
    /// A unary operation.
    Unary(UnaryOp, Operand),
    /// A binary operation.
    Binary(BinaryOp, Operand, Operand),
}

/// A straight-line program with numbered outputs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tape {
    instrs: Vec<Instr>,
    outputs: Vec<Operand>,
}

/// The inputs of one evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Inputs<'a> {
    /// Parameter values.
    pub params: &'a [f64],
    /// States.
    pub states: &'a [f64],
    /// Algebraic unknowns.
    pub algs: &'a [f64],
    /// Realization parameters `mu`.
    pub mu: &'a [f64],
    /// Time.
    pub t: f64,
}

impl Inputs<'_> {
    /// The value of a variable. The variables of family models (inputs, elements,
    /// sizes) are NaN here: a version-1 tape never reads them.
    ///
    /// # Panics
    /// If its index is out of range for these inputs.
    pub fn var(&self, v: VarRef) -> f64 {
        match v {
            VarRef::Param(i) => self.params[i.index()],
            VarRef::State(i) => self.states[i.index()],
            VarRef::Alg(i) => self.algs[i.index()],
            VarRef::Mu(i) => self.mu[i.index()],
            VarRef::Time => self.t,
            VarRef::Input(..) | VarRef::Elem(_) | VarRef::Size(_) | VarRef::AlgRate(_) => f64::NAN,
        }
    }
}

impl Tape {
    /// An empty tape.
    pub fn new() -> Self {
        Tape::default()
    }

    /// Append an instruction; returns the operand that refers to its result.
    pub fn push(&mut self, instr: Instr) -> Operand {
        debug_assert!(
            self.operands_valid(&instr),
            "operand refers to a later slot"
        );
        self.instrs.push(instr);
        Operand::Slot((self.instrs.len() - 1) as u32)
    }

    /// Declare the next output.
    pub fn push_output(&mut self, value: Operand) {
        self.outputs.push(value);
    }

    /// The instructions, in evaluation order.
    pub fn instrs(&self) -> &[Instr] {
        &self.instrs
    }

    /// The outputs, in order.
    pub fn outputs(&self) -> &[Operand] {
        &self.outputs
    }

    /// Number of slots an evaluation needs (the length of the `slots` buffer of
    /// [`Tape::eval`]).
    pub fn n_slots(&self) -> usize {
        self.instrs.len()
    }

    /// Arithmetic operations of one evaluation (one per instruction).
    pub fn op_count(&self) -> usize {
        self.instrs.len()
    }

    /// The operands of every instruction and output, in order (for back ends that
    /// prepare what a tape reads).
    pub fn operands(&self) -> impl Iterator<Item = Operand> + '_ {
        self.instrs
            .iter()
            .flat_map(|i| match *i {
                Instr::Unary(_, a) => [Some(a), None],
                Instr::Binary(_, a, b) => [Some(a), Some(b)],
            })
            .flatten()
            .chain(self.outputs.iter().copied())
    }

    fn operands_valid(&self, instr: &Instr) -> bool {
        let ok = |o: &Operand| match o {
            Operand::Slot(k) => (*k as usize) < self.instrs.len(),
            _ => true,
        };
        match instr {
            Instr::Unary(_, a) => ok(a),
            Instr::Binary(_, a, b) => ok(a) && ok(b),
        }
    }

    /// Evaluate into `out` (`out.len() == outputs().len()`), using `slots`
    /// (`slots.len() >= n_slots()`) as scratch. Allocates nothing.
    ///
    /// # Panics
    /// If a buffer is too short or an input index is out of range for `inputs` (a
    /// programming error of the caller, never a user error).
    pub fn eval(&self, inputs: &Inputs<'_>, slots: &mut [f64], out: &mut [f64]) {
        for (k, instr) in self.instrs.iter().enumerate() {
            let v = match *instr {
                Instr::Unary(op, a) => unary(op, read(a, inputs, slots)),
                Instr::Binary(op, a, b) => {
                    binary(op, read(a, inputs, slots), read(b, inputs, slots))
                }
            };
            slots[k] = v;
        }
        for (o, operand) in out.iter_mut().zip(&self.outputs) {
            *o = read(*operand, inputs, slots);
        }
    }
}

fn read(o: Operand, inputs: &Inputs<'_>, slots: &[f64]) -> f64 {
    match o {
        Operand::Const(c) => c,
        Operand::Slot(k) => slots[k as usize],
        Operand::Input(v) => inputs.var(v),
        // Element paths belong to family programs (`Program::eval`), never to a
        // version-1 tape.
        Operand::Gather(..) | Operand::Array(_) | Operand::ArrayAt(..) => f64::NAN,
    }
}

pub(crate) fn unary(op: UnaryOp, a: f64) -> f64 {
    match op {
        UnaryOp::Neg => -a,
        UnaryOp::Powi(n) => a.powi(n),
        UnaryOp::Call(f) => f.apply1(a),
    }
}

pub(crate) fn binary(op: BinaryOp, a: f64, b: f64) -> f64 {
    match op {
        BinaryOp::Add => a + b,
        BinaryOp::Sub => a - b,
        BinaryOp::Mul => a * b,
        BinaryOp::Div => a / b,
        BinaryOp::Call(f) => f.apply2(a, b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eval_shares_slots_between_outputs() {
        // y0 = (x0 + p0)^2, y1 = sin(x0 + p0) * t
        let mut tape = Tape::new();
        let x = Operand::Input(VarRef::State(crate::StateId::new(0)));
        let p = Operand::Input(VarRef::Param(crate::ParamId::new(0)));
        let sum = tape.push(Instr::Binary(BinaryOp::Add, x, p));
        let sq = tape.push(Instr::Unary(UnaryOp::Powi(2), sum));
        let sn = tape.push(Instr::Unary(UnaryOp::Call(Func::Sin), sum));
        let y1 = tape.push(Instr::Binary(
            BinaryOp::Mul,
            sn,
            Operand::Input(VarRef::Time),
        ));
        tape.push_output(sq);
        tape.push_output(y1);
        let inputs = Inputs {
            params: &[0.5],
            states: &[1.0],
            algs: &[],
            mu: &[],
            t: 2.0,
        };
        let mut slots = vec![0.0; tape.n_slots()];
        let mut out = [0.0; 2];
        tape.eval(&inputs, &mut slots, &mut out);
        assert_eq!(out[0], 2.25);
        assert_eq!(out[1], 1.5f64.sin() * 2.0);
        assert_eq!(tape.op_count(), 4);
    }

    #[test]
    fn sign_is_zero_at_zero_and_nan_propagates() {
        let sign = |x| unary(UnaryOp::Call(Func::Sign), x);
        assert_eq!(sign(0.0), 0.0);
        assert_eq!(sign(-0.0), 0.0);
        assert_eq!(sign(3.0), 1.0);
        assert_eq!(sign(-2.0), -1.0);
        assert!(sign(f64::NAN).is_nan());
        assert!(binary(BinaryOp::Call(Func::Min), f64::NAN, 1.0).is_nan());
        assert!(binary(BinaryOp::Call(Func::Max), 1.0, f64::NAN).is_nan());
        assert_eq!(binary(BinaryOp::Call(Func::Min), -1.0, 1.0), -1.0);
    }
}
