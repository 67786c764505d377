//! The oracle of the template analysis: a family model at given sizes and maps written
//! out as the equivalent scalar (version-1) model, which the version-1 pipeline analyses
//! element by element. Tests compare every function of the two (never used by the
//! compiler itself: its cost grows with the sizes).
//!
//! The scalar model's vectors are the instance's, in the same order: its states,
//! algebraic unknowns and constraints are the instance's slots (named `x[3].y`,
//! `z[2]`, `link[2]`), its parameters are the instance's parameters, followed by one
//! parameter per input value (`pin[0].x`, `pin'[0].x`, ...: the input values vector)
//! and a last one, `t_input`, the time the input values are taken at: an input reads
//! as its Taylor polynomial `sum_q pin^(q) (t - t_input)^(q - j) / (q - j)!`, so that
//! the scalar model's time derivatives of an input are the given ones.

use super::construct::Instance;
use crate::ast::{BinOp, Span};
use crate::model::{
    ConstraintDef, DerDef, Family, LetDef, MassDef, Model, ParamDef, RExpr, VarDef,
};
use crate::{AlgId, LetId, ParamId, StateId, VarRef};

/// A family model written out at the sizes of an instance.
#[derive(Clone, Debug, PartialEq)]
pub struct Expanded {
    /// The scalar model.
    pub model: Model,
    /// Index of the first input-value parameter (= the length of the instance's
    /// parameter vector).
    pub input_params: usize,
    /// Index of `t_input`, the parameter holding the time of the input values.
    pub t_input: usize,
}

/// `name` at element `e`: `x.y` -> `x[e].y`; unchanged for a scalar.
fn at(name: &str, fam: Family, e: usize, primes: &str) -> String {
    let (base, comp) = match name.find('.') {
        Some(i) => (&name[..i], &name[i..]),
        None => (name, ""),
    };
    match fam.over {
        None => format!("{base}{primes}{comp}"),
        Some(_) => format!("{base}{primes}[{e}]{comp}"),
    }
}

struct Expander<'a> {
    m: &'a Model,
    inst: &'a Instance,
    /// First expanded let of each let component family.
    let_base: Vec<usize>,
    /// For each map a sum uses: the elements of the domain sent to each element.
    inverse: Vec<Option<Vec<Vec<u32>>>>,
    t_input: usize,
    input_params: usize,
}

impl Expander<'_> {
    fn size(&self, s: Option<crate::SetId>) -> usize {
        self.inst.set_size(s)
    }

    fn inverse(&mut self, m: crate::MapId) {
        if self.inverse[m.index()].is_some() {
            return;
        }
        let def = &self.inst.maps[m.index()];
        let n = self.size(self.m.maps.get(m.index()).and_then(|d| d.codomain));
        let mut inv = vec![Vec::new(); n];
        for (k, &q) in def.iter().enumerate() {
            inv[q as usize].push(k as u32);
        }
        self.inverse[m.index()] = Some(inv);
    }

    fn expr(&mut self, x: &RExpr, e: usize) -> RExpr {
        let inst = self.inst;
        let l = &inst.layout;
        match x {
            RExpr::Num(v) => RExpr::Num(*v),
            RExpr::Var(v) => match *v {
                VarRef::Param(p) => {
                    RExpr::Var(VarRef::Param(ParamId::new(l.params[p.index()].at(e))))
                }
                VarRef::State(s) => {
                    RExpr::Var(VarRef::State(StateId::new(l.states[s.index()].at(e))))
                }
                VarRef::Alg(a) => RExpr::Var(VarRef::Alg(AlgId::new(l.algs[a.index()].at(e)))),
                VarRef::AlgRate(a) => {
                    RExpr::Var(VarRef::AlgRate(AlgId::new(l.algs[a.index()].at(e))))
                }
                VarRef::Time | VarRef::Mu(_) => RExpr::Var(*v),
                VarRef::Elem(_) => RExpr::Num(e as f64),
                VarRef::Size(s) => RExpr::Num(inst.size_values[s.index()] as f64),
                VarRef::Input(i, j) => self.taylor(i, j, e),
            },
            RExpr::Let(id) => RExpr::Let(LetId::new(
                self.let_base[id.index()] + self.let_elem(*id, e),
            )),
            RExpr::Gather(m, inner) => {
                let to = inst.maps[m.index()][e] as usize;
                self.expr(inner, to)
            }
            RExpr::Sum(m, body) => {
                self.inverse(*m);
                let ks = self.inverse[m.index()]
                    .as_ref()
                    .map_or(Vec::new(), |inv| inv[e].clone());
                let mut acc: Option<RExpr> = None;
                for k in ks {
                    let t = self.expr(body, k as usize);
                    acc = Some(match acc {
                        None => t,
                        Some(a) => RExpr::Binary(BinOp::Add, Box::new(a), Box::new(t)),
                    });
                }
                acc.unwrap_or(RExpr::Num(0.0))
            }
            RExpr::Neg(a) => RExpr::Neg(Box::new(self.expr(a, e))),
            RExpr::Binary(op, a, b) => {
                RExpr::Binary(*op, Box::new(self.expr(a, e)), Box::new(self.expr(b, e)))
            }
            RExpr::Call(f, args) => RExpr::Call(*f, args.iter().map(|a| self.expr(a, e)).collect()),
            // Construction-time forms never occur in equations.
            RExpr::Compare(..)
            | RExpr::Logic(..)
            | RExpr::Not(_)
            | RExpr::If(..)
            | RExpr::Int(..) => RExpr::Num(f64::NAN),
        }
    }

    /// A scalar let in a family context is the same for every element.
    fn let_elem(&self, id: LetId, e: usize) -> usize {
        if self.m.lets[id.index()].family.over.is_some() {
            e
        } else {
            0
        }
    }

    /// Derivative `j` of input component `i` at element `e`: its Taylor polynomial at
    /// `t_input` from the given derivatives.
    fn taylor(&self, i: crate::InputId, j: u8, e: usize) -> RExpr {
        let input = &self.m.inputs[i.index()];
        let k = input.derivatives as usize;
        let l = &self.inst.layout;
        let slot = |q: usize| self.input_params + l.input_value(i.index(), q).at(e);
        let dt = RExpr::Binary(
            BinOp::Sub,
            Box::new(RExpr::Var(VarRef::Time)),
            Box::new(RExpr::Var(VarRef::Param(ParamId::new(self.t_input)))),
        );
        let mut acc: Option<RExpr> = None;
        let mut fact = 1.0;
        for q in (j as usize)..=k {
            let p = q - j as usize;
            if p > 0 {
                fact *= p as f64;
            }
            let c = RExpr::Var(VarRef::Param(ParamId::new(slot(q))));
            let term = if p == 0 {
                c
            } else {
                let pow = RExpr::Binary(
                    BinOp::Pow,
                    Box::new(dt.clone()),
                    Box::new(RExpr::Num(p as f64)),
                );
                let scaled = RExpr::Binary(BinOp::Mul, Box::new(c), Box::new(pow));
                RExpr::Binary(BinOp::Div, Box::new(scaled), Box::new(RExpr::Num(fact)))
            };
            acc = Some(match acc {
                None => term,
                Some(a) => RExpr::Binary(BinOp::Add, Box::new(a), Box::new(term)),
            });
        }
        acc.unwrap_or(RExpr::Num(0.0))
    }
}

/// The scalar model of family model `m` at instance `inst` (see the module docs).
pub fn expand(m: &Model, inst: &Instance) -> Expanded {
    let l = &inst.layout;
    let input_params = l.n_params;
    let t_input = input_params + l.n_input_values;
    let mut let_base = Vec::with_capacity(m.lets.len());
    let mut n_lets = 0;
    for d in &m.lets {
        let_base.push(n_lets);
        n_lets += inst.set_size(d.family.over);
    }
    let mut x = Expander {
        m,
        inst,
        let_base,
        inverse: vec![None; inst.maps.len()],
        t_input,
        input_params,
    };
    let span = Span::default();
    let scalar = Family::SCALAR;
    // Parameters: the instance's vector, then the input values, then `t_input`.
    let mut params: Vec<Option<ParamDef>> = vec![None; l.n_params];
    for (p, slot) in m.params.iter().zip(&l.params) {
        for e in 0..inst.set_size(p.family.over) {
            let v = inst.params[slot.at(e)];
            params[slot.at(e)] = Some(ParamDef {
                name: at(&p.name, p.family, e, ""),
                default: v,
                span: p.span,
                value: RExpr::Num(v),
                family: scalar,
            });
        }
    }
    let mut params: Vec<ParamDef> = params.into_iter().flatten().collect();
    let mut inputs: Vec<Option<ParamDef>> = vec![None; l.n_input_values];
    for (k, i) in m.inputs.iter().enumerate() {
        for e in 0..inst.set_size(i.family.over) {
            for q in 0..=i.derivatives as usize {
                let at_q = l.input_value(k, q).at(e);
                let v = inst.inputs[at_q];
                inputs[at_q] = Some(ParamDef {
                    name: at(&i.name, i.family, e, &crate::sym::primes(q)),
                    default: v,
                    span: i.span,
                    value: RExpr::Num(v),
                    family: scalar,
                });
            }
        }
    }
    params.extend(inputs.into_iter().flatten());
    params.push(ParamDef {
        name: "t_input".into(),
        default: 0.0,
        span,
        value: RExpr::Num(0.0),
        family: scalar,
    });
    // States, algebraic unknowns, ders, lets, constraints, at their slots.
    let vars = |defs: &[VarDef], slots: &[super::layout::Slot], n: usize, values: &[f64]| {
        let mut out: Vec<Option<VarDef>> = vec![None; n];
        for (d, slot) in defs.iter().zip(slots) {
            for e in 0..inst.set_size(d.family.over) {
                out[slot.at(e)] = Some(VarDef {
                    name: at(&d.name, d.family, e, ""),
                    init: RExpr::Num(values[slot.at(e)]),
                    span: d.span,
                    family: scalar,
                });
            }
        }
        out.into_iter().flatten().collect::<Vec<_>>()
    };
    let states = vars(&m.states, &l.states, l.n_states, &inst.states);
    let algs = vars(&m.algs, &l.algs, l.n_algs, &inst.algs);
    let mut lets = Vec::with_capacity(n_lets);
    for d in &m.lets {
        for e in 0..inst.set_size(d.family.over) {
            lets.push(LetDef {
                name: at(&d.name, d.family, e, ""),
                expr: x.expr(&d.expr, e),
                span: d.span,
                family: scalar,
            });
        }
    }
    let mut ders: Vec<Option<DerDef>> = vec![None; l.n_states];
    for (k, (d, slot)) in m.ders.iter().zip(&l.states).enumerate() {
        for e in 0..inst.set_size(m.states[k].family.over) {
            ders[slot.at(e)] = Some(DerDef {
                expr: x.expr(&d.expr, e),
                span: d.span,
            });
        }
    }
    // A mass matrix over a set: one matrix per element.
    let mut mass = Vec::new();
    for d in &m.mass {
        let over = d
            .states
            .first()
            .and_then(|s| m.states[s.index()].family.over);
        for e in 0..inst.set_size(over) {
            mass.push(MassDef {
                states: d
                    .states
                    .iter()
                    .map(|s| StateId::new(l.states[s.index()].at(e)))
                    .collect(),
                entries: d.entries.iter().map(|x_| x.expr(x_, e)).collect(),
                entry_spans: d.entry_spans.clone(),
                span: d.span,
            });
        }
    }
    let mut constraints = Vec::with_capacity(l.n_rows);
    for c in &m.constraints {
        for e in 0..inst.set_size(c.over) {
            constraints.push(ConstraintDef {
                name: at(
                    &c.name,
                    Family {
                        over: c.over,
                        ..scalar
                    },
                    e,
                    "",
                ),
                residual: x.expr(&c.residual, e),
                span: c.span,
                over: None,
            });
        }
    }
    Expanded {
        model: Model {
            name: m.name.clone(),
            span: m.span,
            params,
            states,
            algs,
            lets,
            ders: ders.into_iter().flatten().collect(),
            mass,
            constraints,
            sizes: Vec::new(),
            sets: Vec::new(),
            maps: Vec::new(),
            inputs: Vec::new(),
        },
        input_params,
        t_input,
    }
}
