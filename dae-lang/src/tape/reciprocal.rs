//! One reciprocal for each divisor that divides more than once.

use std::collections::HashMap;

use super::{BinaryOp, Instr, Operand, OperandKey, Tape};

/// A divisor that is not a literal, as a key.
fn key(o: Operand) -> Option<OperandKey> {
    (!matches!(o, Operand::Const(_))).then(|| o.key())
}

impl Tape {
    /// This tape with every `a / b` whose divisor `b` (not a literal) divides at least
    /// twice computed as `a * r`, `r = 1 / b` once, before the first of them. A
    /// division costs several multiplications (a link's unit vector divides three
    /// components and their products by one length), and the family programs divide
    /// by a few values many times. Each such result differs from the division by
    /// rounding (the two roundings of `a * (1 / b)` against the one of `a / b`); a
    /// divisor used once keeps its division. Linear in the length of the tape.
    pub fn with_shared_reciprocals(&self) -> Tape {
        let mut uses: HashMap<OperandKey, u32> = HashMap::new();
        for instr in &self.instrs {
            if let Instr::Binary(BinaryOp::Div, _, b) = *instr {
                if let Some(k) = key(b) {
                    *uses.entry(k).or_default() += 1;
                }
            }
        }
        if uses.values().all(|&n| n < 2) {
            return self.clone();
        }
        let mut out = Tape::new();
        // The operand of the new tape that holds each slot of this one.
        let mut moved: Vec<Operand> = Vec::with_capacity(self.instrs.len());
        let mut reciprocal: HashMap<OperandKey, Operand> = HashMap::new();
        let at = |o: Operand, moved: &[Operand]| match o {
            Operand::Slot(k) => moved[k as usize],
            o => o,
        };
        for instr in &self.instrs {
            let shared = match *instr {
                Instr::Binary(BinaryOp::Div, _, b) => {
                    key(b).filter(|k| uses.get(k).is_some_and(|&n| n >= 2))
                }
                _ => None,
            };
            let new = match (*instr, shared) {
                (Instr::Binary(_, a, b), Some(k)) => {
                    let (a, b) = (at(a, &moved), at(b, &moved));
                    let r = *reciprocal.entry(k).or_insert_with(|| {
                        out.push(Instr::Binary(BinaryOp::Div, Operand::Const(1.0), b))
                    });
                    out.push(Instr::Binary(BinaryOp::Mul, a, r))
                }
                (Instr::Unary(op, a), _) => out.push(Instr::Unary(op, at(a, &moved))),
                (Instr::Binary(op, a, b), None) => {
                    out.push(Instr::Binary(op, at(a, &moved), at(b, &moved)))
                }
            };
            moved.push(new);
        }
        for &o in &self.outputs {
            out.push_output(at(o, &moved));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tape::Inputs;
    use crate::{ParamId, StateId, VarRef};

    fn state(i: usize) -> Operand {
        Operand::Input(VarRef::State(StateId::new(i)))
    }

    fn eval(tape: &Tape, states: &[f64]) -> Vec<f64> {
        let inputs = Inputs {
            params: &[4.0],
            states,
            algs: &[],
            mu: &[],
            t: 0.0,
        };
        let mut slots = vec![0.0; tape.n_slots()];
        let mut out = vec![0.0; tape.outputs().len()];
        tape.eval(&inputs, &mut slots, &mut out);
        out
    }

    #[test]
    fn a_divisor_used_three_times_is_inverted_once_and_the_values_agree_to_rounding() {
        // len = sqrt(x0^2 + x1^2); u = (x0 / len, x1 / len, p0 / len); q = x0 / x1.
        let mut t = Tape::new();
        let (x0, x1) = (state(0), state(1));
        let p0 = Operand::Input(VarRef::Param(ParamId::new(0)));
        let a = t.push(Instr::Binary(BinaryOp::Mul, x0, x0));
        let b = t.push(Instr::Binary(BinaryOp::Mul, x1, x1));
        let s = t.push(Instr::Binary(BinaryOp::Add, a, b));
        let len = t.push(Instr::Unary(
            crate::tape::UnaryOp::Call(crate::Func::Sqrt),
            s,
        ));
        for num in [x0, x1, p0] {
            let u = t.push(Instr::Binary(BinaryOp::Div, num, len));
            t.push_output(u);
        }
        let q = t.push(Instr::Binary(BinaryOp::Div, x0, x1));
        t.push_output(q);
        let r = t.with_shared_reciprocals();
        let divs = |t: &Tape| {
            t.instrs()
                .iter()
                .filter(|i| matches!(i, Instr::Binary(BinaryOp::Div, ..)))
                .count()
        };
        // Three divisions by `len` became one reciprocal and three products; the
        // division by `x1`, used once, stays.
        assert_eq!((divs(&t), divs(&r)), (4, 2));
        assert_eq!(r.op_count(), t.op_count() + 1);
        for states in [[3.0, 4.0], [1e-3, -2.5e4], [-7.25, 0.1]] {
            let (want, got) = (eval(&t, &states), eval(&r, &states));
            for (w, g) in want.iter().zip(&got) {
                assert!((w - g).abs() <= 4.0 * f64::EPSILON * w.abs(), "{w} {g}");
            }
        }
    }

    #[test]
    fn a_tape_without_a_repeated_divisor_is_unchanged() {
        let mut t = Tape::new();
        let q = t.push(Instr::Binary(BinaryOp::Div, state(0), state(1)));
        let h = t.push(Instr::Binary(BinaryOp::Div, q, Operand::Const(2.0)));
        let k = t.push(Instr::Binary(BinaryOp::Div, h, Operand::Const(2.0)));
        t.push_output(k);
        assert_eq!(t.with_shared_reciprocals(), t);
    }
}
