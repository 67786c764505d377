//! Arena nodes emitted as a tape.
//!
//! The arena is hash-consed, so emitting each node reachable from a function's outputs
//! once, children first, is common-subexpression elimination over all outputs of that
//! function. The arena's n-ary normal form (`c + sum a_k t_k`, `c * prod b_k^e_k`) is
//! turned back into the cheapest binary operations: `a - b` rather than `a + (-1) b`,
//! a quotient of products rather than negative powers, `powi` for integer exponents and
//! `sqrt` for half-integer ones. Powers of one base that occur in several places of a
//! function (`l^-1`, `l^-3`, ...) share their `sqrt` and `powi` slots, and an
//! instruction already on the tape with the same operands (`m * l` at the head of two
//! products, `a * b` and `b * a`) is not written again: the n-ary nodes share no
//! partial products in the arena, so this is where they are found.

use std::collections::HashMap;

use super::{BinaryOp, Instr, Operand, OperandKey, Tape, UnaryOp};
use crate::Func;
use crate::sym::{Arena, Id, Node};

/// Emit the nodes reachable from `roots` as one tape whose outputs are the roots.
#[cfg(test)]
pub(crate) fn emit(arena: &Arena, roots: &[Id]) -> Tape {
    let mut e = Emitter::new(arena);
    for &id in &arena.reachable(roots) {
        let o = e.node(id);
        e.done.insert(id, o);
    }
    for r in roots {
        let o = e.done[r];
        e.tape.push_output(o);
    }
    e.tape
}

/// Emits arena nodes into one tape (also used for the groups of family programs, with
/// the operands of the nodes computed elsewhere entered in `done` first).
pub(crate) struct Emitter<'a> {
    arena: &'a Arena,
    pub(crate) tape: Tape,
    /// Operand of every node emitted so far.
    pub(crate) done: HashMap<Id, Operand>,
    /// `(base, 2 * exponent)` -> operand, for powers with a half-integer or integer
    /// exponent, so that `sqrt(b)` and `b^k` are computed once per tape.
    powers: HashMap<(Id, i64), Operand>,
    /// The instructions on the tape by what they compute (see [`Key`]).
    written: HashMap<Key, Operand>,
}

/// What an instruction computes: its operation and operands, the two operands of `+`
/// and `*` in a fixed order (both orders give the same bits).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Unary(UnaryOp, OperandKey),
    Binary(BinaryOp, OperandKey, OperandKey),
}

impl<'a> Emitter<'a> {
    /// An emitter writing a new tape.
    pub(crate) fn new(arena: &'a Arena) -> Emitter<'a> {
        Emitter {
            arena,
            tape: Tape::new(),
            done: HashMap::new(),
            powers: HashMap::new(),
            written: HashMap::new(),
        }
    }
}

impl Emitter<'_> {
    fn get(&self, id: Id) -> Operand {
        self.done[&id]
    }

    fn un(&mut self, op: UnaryOp, a: Operand) -> Operand {
        self.write(Key::Unary(op, a.key()), Instr::Unary(op, a))
    }

    fn bin(&mut self, op: BinaryOp, a: Operand, b: Operand) -> Operand {
        let (x, y) = (a.key(), b.key());
        let key = if matches!(op, BinaryOp::Add | BinaryOp::Mul) {
            Key::Binary(op, x.min(y), x.max(y))
        } else {
            Key::Binary(op, x, y)
        };
        self.write(key, Instr::Binary(op, a, b))
    }

    /// `instr` on the tape, or the slot of the same computation written before.
    fn write(&mut self, key: Key, instr: Instr) -> Operand {
        if let Some(&o) = self.written.get(&key) {
            return o;
        }
        let o = self.tape.push(instr);
        self.written.insert(key, o);
        o
    }

    /// Emits node `id` (its children are in `done`); its operand.
    pub(crate) fn node(&mut self, id: Id) -> Operand {
        match self.arena.node(id) {
            Node::Const(c) => Operand::Const(c.0),
            Node::Var(v) => Operand::Input(*v),
            Node::Add(c, terms) => {
                let terms: Vec<(Operand, f64)> =
                    terms.iter().map(|(t, a)| (self.get(*t), a.0)).collect();
                self.sum(c.0, &terms)
            }
            Node::Mul(c, factors) => {
                let factors: Vec<(Id, f64)> = factors.iter().map(|(b, e)| (*b, e.0)).collect();
                self.product(c.0, &factors)
            }
            Node::Pow(a, b) => {
                let (a, b) = (self.get(*a), self.get(*b));
                self.bin(BinaryOp::Call(Func::Pow), a, b)
            }
            Node::F1(f, a) => {
                let a = self.get(*a);
                self.un(UnaryOp::Call(*f), a)
            }
            Node::F2(f, a, b) => {
                let (a, b) = (self.get(*a), self.get(*b));
                self.bin(BinaryOp::Call(*f), a, b)
            }
            // A family program resolves gathers and sums before emitting a group (they
            // are operands there); a version-1 arena has none.
            Node::Gather(..) | Node::Sum(..) => Operand::Const(f64::NAN),
        }
    }

    /// `c + sum a_k t_k`, with positive terms first so that negative ones become
    /// subtractions. A NaN coefficient or constant is kept (added), not dropped.
    pub(crate) fn sum(&mut self, c: f64, terms: &[(Operand, f64)]) -> Operand {
        let mut acc: Option<Operand> = None;
        let mut ordered: Vec<&(Operand, f64)> = terms.iter().filter(|t| t.1 > 0.0).collect();
        ordered.extend(terms.iter().filter(|t| t.1 <= 0.0 || t.1.is_nan()));
        for &&(t, a) in &ordered {
            let mag = a.abs();
            let term = if mag == 1.0 {
                t
            } else {
                self.bin(BinaryOp::Mul, Operand::Const(mag), t)
            };
            acc = Some(match acc {
                None if a < 0.0 => self.un(UnaryOp::Neg, term),
                None => term,
                Some(s) if a < 0.0 => self.bin(BinaryOp::Sub, s, term),
                Some(s) => self.bin(BinaryOp::Add, s, term),
            });
        }
        match acc {
            None => Operand::Const(c),
            Some(s) if c < 0.0 => self.bin(BinaryOp::Sub, s, Operand::Const(-c)),
            Some(s) if c != 0.0 => self.bin(BinaryOp::Add, s, Operand::Const(c)),
            Some(s) => s,
        }
    }

    /// `c * prod b_k^e_k` as `c * (numerator) / (denominator)`.
    fn product(&mut self, c: f64, factors: &[(Id, f64)]) -> Operand {
        let mut num: Option<Operand> = None;
        let mut den: Option<Operand> = None;
        for &(b, e) in factors {
            let (slot, mag) = if e > 0.0 {
                (&mut num, e)
            } else {
                (&mut den, -e)
            };
            let p = self.power(b, mag);
            let prev = slot.take();
            let next = match prev {
                None => p,
                Some(acc) => self.bin(BinaryOp::Mul, acc, p),
            };
            if e > 0.0 {
                num = Some(next);
            } else {
                den = Some(next);
            }
        }
        let mag = c.abs();
        let scaled = match num {
            None => Operand::Const(mag),
            Some(n) if mag == 1.0 => n,
            Some(n) => self.bin(BinaryOp::Mul, Operand::Const(mag), n),
        };
        let q = match den {
            None => scaled,
            Some(d) => self.bin(BinaryOp::Div, scaled, d),
        };
        if c < 0.0 { self.un(UnaryOp::Neg, q) } else { q }
    }

    /// `b^e` for `e > 0`: `powi` for integers, `sqrt` times `powi` for half-integers,
    /// `powf` otherwise.
    fn power(&mut self, b: Id, e: f64) -> Operand {
        let base = self.get(b);
        if e == 1.0 {
            return base;
        }
        let twice = 2.0 * e;
        if twice.fract() == 0.0 && twice <= 64.0 {
            let key = (b, twice as i64);
            if let Some(o) = self.powers.get(&key) {
                return *o;
            }
            let k = twice as i64;
            let o = if k % 2 == 0 {
                self.un(UnaryOp::Powi((k / 2) as i32), base)
            } else {
                let root = match self.powers.get(&(b, 1)) {
                    Some(r) => *r,
                    None => {
                        let r = self.un(UnaryOp::Call(Func::Sqrt), base);
                        self.powers.insert((b, 1), r);
                        r
                    }
                };
                match k / 2 {
                    0 => root,
                    1 => self.bin(BinaryOp::Mul, base, root),
                    n => {
                        let p = self.power(b, n as f64);
                        self.bin(BinaryOp::Mul, p, root)
                    }
                }
            };
            self.powers.insert(key, o);
            return o;
        }
        self.bin(BinaryOp::Call(Func::Pow), base, Operand::Const(e))
    }
}

#[cfg(test)]
mod tests {
    use super::emit;
    use crate::sym::Arena;
    use crate::tape::{Inputs, Instr};
    use crate::{Func, StateId, VarRef};

    /// Two products with the head `x0 * x1` (two n-ary nodes of the arena, which
    /// shares no partial products): the head is on the tape once, and every output is
    /// what the expressions say.
    #[test]
    fn an_instruction_already_on_the_tape_is_not_written_again() {
        let mut a = Arena::new();
        let x: Vec<_> = (0..3)
            .map(|i| a.var(VarRef::State(StateId::new(i))))
            .collect();
        let head = a.mul(x[0], x[1]);
        let p = a.mul(head, x[2]);
        let s = a.call(Func::Sin, &[x[2]]);
        let q = a.mul(head, s);
        let tape = emit(&a, &[p, q]);
        // x0 * x1 once, then * x2 and * sin(x2).
        let muls = tape
            .instrs()
            .iter()
            .filter(|i| matches!(i, Instr::Binary(super::BinaryOp::Mul, ..)))
            .count();
        assert_eq!(muls, 3);
        let states = [0.7, -1.3, 2.1];
        let inputs = Inputs {
            params: &[],
            states: &states,
            algs: &[],
            mu: &[],
            t: 0.0,
        };
        let mut slots = vec![0.0; tape.n_slots()];
        let mut out = vec![0.0; 2];
        tape.eval(&inputs, &mut slots, &mut out);
        let [x0, x1, x2] = states;
        assert_eq!(out[0], x0 * x1 * x2);
        assert_eq!(out[1], x0 * x1 * x2.sin());
    }
}
