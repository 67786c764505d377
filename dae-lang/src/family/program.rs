//! A compiled function of a family model: a [`Program`].
//!
//! # Semantics
//!
//! A program runs on an [`Instance`](super::Instance) (sizes, maps, layout) and the
//! values of one evaluation ([`Values`](super::Values): parameters, states, algebraic
//! unknowns, `mu`, input values, `t`), and writes its outputs (one or several flat
//! vectors: see [`FamilyModel`](super::FamilyModel) for which). One evaluation is:
//!
//! 1. every array with [`ArrayDef::accumulate`] is set to 0; for the jacobian program,
//!    output 0 (the values of `J_Omega`) is set to 0;
//! 2. the [`Group`]s, in order. A group over a set `S` runs its tape once for each
//!    element `e` of `S` (`0 .. |S|`, in any order: no element's run reads what another
//!    element's run of the same group writes, except through scatter-adds, which
//!    commute); a group over `None` runs it once. Each run evaluates the tape's
//!    instructions (as [`Tape::eval`](crate::tape::Tape::eval) does) with the operands
//!    read at `e`:
//!    * [`Operand::Input`]`(v)`: the variable `v` at slot `layout.X[v].at(e)` of its
//!      vector (stride 0 for a scalar variable, so the same value for every `e`):
//!      `Param` in the parameters, `State` in `x`, `Alg` in `z`, `Mu(c)` in `mu` at
//!      `layout.rows[c]`, `Input(i, j)` in the input values at
//!      `layout.input_value(i, j).at(e)`, `Time` is `t`, `Size(s)` the size's value,
//!      `Elem(S)` the number `e` itself;
//!    * [`Operand::Gather`]`(v, m)`: the same at element `maps[m][e]` instead of `e`
//!      (`Elem` gives `maps[m][e]` as a number);
//!    * [`Operand::Array`]`(a)`: `arrays[a][e]` (`arrays[a][0]` for a scalar array);
//!    * [`Operand::ArrayAt`]`(a, m)`: `arrays[a][maps[m][e]]`;
//!
//!    then output `i` of the tape goes to `sinks[i]`:
//!    * [`Sink::Out`]`(dest)`: written into an output vector at the slot [`Dest`] gives
//!      for `e`;
//!    * [`Sink::Store`]`(a)`: `arrays[a][e] = v` (`arrays[a][0]` for a scalar array);
//!    * [`Sink::ScatterAdd`]`(a, m)`: `arrays[a][maps[m][e]] += v` (the body of an
//!      incidence sum over the elements of `S`);
//!    * [`Sink::ScatterSub`]`(a, m)`: `arrays[a][maps[m][e]] -= v` (the body of a sum
//!      subtracted from the one that accumulates in `a`: two incidence sums into one
//!      codomain, `sum(l where a[l] == p) .. - sum(l where b[l] == p) ..`, share one
//!      accumulator);
//! 3. the [`EntryLoop`]s (jacobian program only): for coupling `c`, for every
//!    `[entry, l, k]` of the instance's `jacobian.lists[c]`,
//!    `values[entry] += sum over terms of R(l) * C(k)`, a [`Factor`] being a constant or
//!    an array read at `l` (row factors) or `k` (column factors), at 0 for a scalar
//!    array.
//!
//! Every element of every output family is written exactly once by the groups (the
//! jacobian's values are accumulated). Arrays never carry values between evaluations.

use std::collections::HashMap;

use crate::tape::{BinaryOp, Instr, Operand, Tape, UnaryOp};
use crate::{ArrayId, ConstraintId, MapId, SetId, StateId, VarRef};

/// A scratch array of a program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArrayDef {
    /// One value per element of this set, or one value (`None`).
    pub over: Option<SetId>,
    /// Set to 0 at the start of every evaluation (the accumulator of a sum).
    pub accumulate: bool,
}

/// Where an output value of a group goes, for the element `e` at hand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dest {
    /// `dx[layout.states[s].at(e)]` (rhs, output 0).
    Rhs(StateId),
    /// `w[layout.w[c].at(e) + j]`: derivative `j` of constraint `c` (sliding, output 0).
    W(ConstraintId, u32),
    /// `s[layout.rows[c].at(e)]` (sliding, output 1).
    S(ConstraintId),
    /// `alpha_hat[layout.rows[c].at(e)]` (sliding, output 2).
    AlphaHat(ConstraintId),
    /// `rate[layout.rows[c].at(e)]`: `Omega'`, or `beta` at `z' = 0` (rate, output 0).
    Rate(ConstraintId),
}

impl Dest {
    /// The output vector this goes to (0, or 1 for `S`, 2 for `AlphaHat`).
    pub fn output(self) -> usize {
        match self {
            Dest::S(_) => 1,
            Dest::AlphaHat(_) => 2,
            _ => 0,
        }
    }
}

/// What happens to one output of a group's tape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sink {
    /// Written to an output vector.
    Out(Dest),
    /// Stored into an array at the element at hand.
    Store(ArrayId),
    /// Added into an array at the image of the element at hand under the map.
    ScatterAdd(ArrayId, MapId),
    /// Subtracted from an array at the image of the element at hand under the map.
    ScatterSub(ArrayId, MapId),
}

/// Straight-line code run once (`over: None`) or once per element of a set.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// The set of the loop, or `None` for code run once.
    pub over: Option<SetId>,
    /// The code; its outputs go to `sinks` (same length, same order).
    pub tape: Tape,
    /// Where each output of the tape goes.
    pub sinks: Vec<Sink>,
}

/// A factor of a term of a `J_Omega` kernel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Factor {
    /// A number.
    Const(f64),
    /// An array read at the row element (row factor) or column element (column factor);
    /// at 0 for a scalar array.
    Array(ArrayId),
}

/// The kernel of one coupling: `values[entry] += sum_t row_t(l) * col_t(k)`.
#[derive(Clone, Debug, PartialEq)]
pub struct EntryLoop {
    /// Index of the coupling in `Construction::couplings` (and of its list in the
    /// instance's `jacobian.lists`).
    pub coupling: usize,
    /// `(row factor, column factor)` of each term.
    pub terms: Vec<(Factor, Factor)>,
}

/// A compiled function of a family model; see the module documentation.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// The scratch arrays.
    pub arrays: Vec<ArrayDef>,
    /// The groups, in the order they run.
    pub groups: Vec<Group>,
    /// The kernel loops of `J_Omega` (jacobian program only), after the groups.
    pub entries: Vec<EntryLoop>,
    /// How [`Program::eval`] runs each group (derived from the above).
    pub(super) plans: Vec<Plan>,
}

/// An argument of an instruction in the vectorised evaluator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Arg {
    /// A per-element operand (index into [`Plan::loads`]): read in place when it is
    /// contiguous, else gathered into a chunk buffer first.
    Load(u32),
    /// A register: a chunk buffer holding the result of an earlier instruction.
    Reg(u32),
    /// A value that is the same for every element of a run (index into the scalars).
    Scalar(u32),
    /// A literal.
    Const(f64),
}

/// One instruction of a plan, with the register its result goes to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Step {
    Unary(UnaryOp, Arg, u32),
    Binary(BinaryOp, Arg, Arg, u32),
}

/// How a group runs in the vectorised evaluator: the operands read per element, the
/// operands that are the same for every element, and the tape's instructions on chunk
/// buffers. The slots of the tape are given registers by liveness (a register is free
/// again after the last instruction reading its slot, unless an output reads it), so
/// that the buffers of a chunk stay few and in the first-level cache.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Plan {
    pub loads: Vec<Operand>,
    pub scalars: Vec<Operand>,
    pub steps: Vec<Step>,
    pub outputs: Vec<(Arg, Sink)>,
    /// Number of registers the steps use.
    pub regs: usize,
}

impl Program {
    /// A program from its parts; `is_family(v)` says whether a variable has one value
    /// per element (a family) or one value (a scalar), which the evaluator needs to
    /// know what to load per element.
    pub fn new(
        arrays: Vec<ArrayDef>,
        groups: Vec<Group>,
        entries: Vec<EntryLoop>,
        is_family: impl Fn(VarRef) -> bool,
    ) -> Program {
        // A few values (a link's length, a mass) divide many times in a group's tape.
        let groups: Vec<Group> = groups
            .into_iter()
            .map(|g| Group {
                tape: g.tape.with_shared_reciprocals(),
                ..g
            })
            .collect();
        let plans = groups
            .iter()
            .map(|g| plan(g, &arrays, &is_family))
            .collect();
        Program {
            arrays,
            groups,
            entries,
            plans,
        }
    }

    /// Instructions over all groups (the size of the code; per element of a loop).
    pub fn op_count(&self) -> usize {
        self.groups.iter().map(|g| g.tape.op_count()).sum()
    }
}

/// An operand read from outside the group's registers, as a hash key (constants and
/// slots are not loaded).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum OperandKey {
    Input(VarRef),
    Gather(VarRef, MapId),
    Array(crate::ArrayId),
    ArrayAt(crate::ArrayId, MapId),
}

impl OperandKey {
    fn of(o: Operand) -> Option<OperandKey> {
        match o {
            Operand::Input(v) => Some(OperandKey::Input(v)),
            Operand::Gather(v, m) => Some(OperandKey::Gather(v, m)),
            Operand::Array(a) => Some(OperandKey::Array(a)),
            Operand::ArrayAt(a, m) => Some(OperandKey::ArrayAt(a, m)),
            Operand::Const(_) | Operand::Slot(_) => None,
        }
    }
}

fn plan(g: &Group, arrays: &[ArrayDef], is_family: &impl Fn(VarRef) -> bool) -> Plan {
    let mut loads: Vec<Operand> = Vec::new();
    let mut scalars: Vec<Operand> = Vec::new();
    let per_element = |o: &Operand| match *o {
        Operand::Input(v) => g.over.is_some() && (matches!(v, VarRef::Elem(_)) || is_family(v)),
        Operand::Gather(..) | Operand::ArrayAt(..) => true,
        Operand::Array(a) => g.over.is_some() && arrays[a.index()].over.is_some(),
        Operand::Const(_) | Operand::Slot(_) => false,
    };
    // Each distinct operand once, with its index (a hash map: a group of a model
    // without sets reads every state and parameter, so a search of the lists would be
    // quadratic).
    let mut index: HashMap<OperandKey, u32> = HashMap::new();
    for o in g.tape.operands() {
        let Some(key) = OperandKey::of(o) else {
            continue;
        };
        let list = if per_element(&o) {
            &mut loads
        } else {
            &mut scalars
        };
        index.entry(key).or_insert_with(|| {
            list.push(o);
            (list.len() - 1) as u32
        });
    }
    // Liveness of the slots: the last instruction reading each (outputs keep theirs to
    // the end of the chunk).
    let instrs = g.tape.instrs();
    let mut last_use = vec![usize::MAX; instrs.len()];
    for (i, ins) in instrs.iter().enumerate() {
        let (a, b) = match *ins {
            Instr::Unary(_, a) => (a, None),
            Instr::Binary(_, a, b) => (a, Some(b)),
        };
        for o in std::iter::once(a).chain(b) {
            if let Operand::Slot(k) = o {
                last_use[k as usize] = i;
            }
        }
    }
    for o in g.tape.outputs() {
        if let Operand::Slot(k) = *o {
            last_use[k as usize] = usize::MAX - 1;
        }
    }
    let mut reg_of = vec![0u32; instrs.len()];
    let mut free: Vec<u32> = Vec::new();
    let mut regs = 0u32;
    let arg = |o: Operand, reg_of: &[u32]| match o {
        Operand::Const(c) => Arg::Const(c),
        Operand::Slot(k) => Arg::Reg(reg_of[k as usize]),
        o => {
            let at = OperandKey::of(o).map_or(0, |k| index[&k]);
            if per_element(&o) {
                Arg::Load(at)
            } else {
                Arg::Scalar(at)
            }
        }
    };
    let mut steps = Vec::with_capacity(instrs.len());
    for (i, ins) in instrs.iter().enumerate() {
        // The destination is taken before the operands' registers are freed, so that it
        // is never one of them (the evaluator borrows it apart from the sources).
        let dst = free.pop().unwrap_or_else(|| {
            regs += 1;
            regs - 1
        });
        reg_of[i] = dst;
        let (step, read) = match *ins {
            Instr::Unary(op, a) => (Step::Unary(op, arg(a, &reg_of), dst), [Some(a), None]),
            Instr::Binary(op, a, b) => (
                Step::Binary(op, arg(a, &reg_of), arg(b, &reg_of), dst),
                [Some(a), Some(b)],
            ),
        };
        steps.push(step);
        let mut freed = [None, None];
        for (f, o) in freed.iter_mut().zip(read.into_iter().flatten()) {
            if let Operand::Slot(k) = o {
                if last_use[k as usize] == i {
                    *f = Some(reg_of[k as usize]);
                }
            }
        }
        // An instruction may read the same slot twice: free its register once.
        if freed[0] == freed[1] {
            freed[1] = None;
        }
        free.extend(freed.into_iter().flatten());
        // A result nobody reads (not produced by the compiler, but harmless).
        if last_use[i] == usize::MAX {
            free.push(dst);
        }
    }
    let outputs = g
        .tape
        .outputs()
        .iter()
        .zip(&g.sinks)
        .map(|(o, s)| (arg(*o, &reg_of), *s))
        .collect();
    Plan {
        loads,
        scalars,
        steps,
        outputs,
        regs: regs as usize,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Func;
    use crate::ids::{ConstraintId, ParamId};

    /// `sqrt((x^2 + 1)^2)` and `x^2` as outputs: four instructions in two registers at
    /// most, plus the one an output keeps.
    #[test]
    fn registers_are_reused_after_the_last_read_and_never_alias_a_source() {
        let x = Operand::Input(VarRef::Param(ParamId::new(0)));
        let mut tape = Tape::new();
        let s0 = tape.push(Instr::Binary(BinaryOp::Mul, x, x));
        let s1 = tape.push(Instr::Binary(BinaryOp::Add, s0, Operand::Const(1.0)));
        let s2 = tape.push(Instr::Binary(BinaryOp::Mul, s1, s1));
        let s3 = tape.push(Instr::Unary(UnaryOp::Call(Func::Sqrt), s2));
        let s4 = tape.push(Instr::Unary(UnaryOp::Neg, s3));
        tape.push_output(s4);
        tape.push_output(s0);
        let out = Sink::Out(Dest::Rate(ConstraintId::new(0)));
        let group = Group {
            over: Some(SetId::new(0)),
            tape,
            sinks: vec![out, out],
        };
        let p = plan(&group, &[], &|_| true);
        // s0 keeps its register (an output reads it); s1..s4 take turns in two others.
        assert_eq!(p.regs, 3);
        assert_eq!(p.loads, vec![x]);
        for step in &p.steps {
            let (d, srcs) = match *step {
                Step::Unary(_, a, d) => (d, vec![a]),
                Step::Binary(_, a, b, d) => (d, vec![a, b]),
            };
            assert!(
                !srcs.contains(&Arg::Reg(d)),
                "{step:?} writes a register it reads"
            );
        }
        let Step::Unary(_, _, r4) = p.steps[4] else {
            panic!("the last step is the negation");
        };
        assert_eq!(p.outputs[0].0, Arg::Reg(r4));
        let Step::Binary(_, _, _, r0) = p.steps[0] else {
            panic!("the first step is the product");
        };
        assert_eq!(p.outputs[1].0, Arg::Reg(r0));
        assert_ne!(r0, r4);
    }
}
