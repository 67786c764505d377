//! Evaluation of construction-time expressions (set sizes, map formulas, parameter
//! values, initial values): the reference semantics the compiled form documents.
//!
//! Values are typed as the checker typed them: integers (`i64`, exact; an overflow is an
//! error), reals (`f64`) and conditions. An operation on two integers stays an integer
//! (`+ - *`, `min`, `max`, `div`, `mod`, `if`), any real operand makes it real, `/` and
//! `^` are real. A map is evaluated lazily, once, into an array.

use crate::ast::{BinOp, LogicOp, Span};
use crate::model::{IntOp, MapDef, MapKind, RExpr};
use crate::{Func, MapId, VarRef};

/// A construction-time value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Val {
    /// An integer.
    I(i64),
    /// A real number.
    R(f64),
    /// A condition.
    B(bool),
}

impl Val {
    /// As a real number (a condition is 1 or 0).
    pub(crate) fn real(self) -> f64 {
        match self {
            Val::I(i) => i as f64,
            Val::R(r) => r,
            Val::B(b) => f64::from(u8::from(b)),
        }
    }
}

/// An error of evaluation: what went wrong, and the span of the declaration it belongs
/// to (filled in by the caller when it knows better).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct EvalError {
    pub message: String,
    pub span: Span,
    pub hint: String,
}

fn err(message: String, span: Span, hint: &str) -> EvalError {
    EvalError {
        message,
        span,
        hint: hint.into(),
    }
}

/// What an expression may read: size values, set sizes, maps (evaluated on demand) and
/// parameter values (by parameter component, one value per element or one for a scalar).
pub(crate) struct Env<'a> {
    pub sizes: &'a [i64],
    pub set_sizes: &'a [Option<usize>],
    pub map_defs: &'a [MapDef],
    /// Evaluated maps (`None`: not yet); given maps are filled in by the caller.
    pub maps: &'a mut Vec<Option<Vec<u32>>>,
    pub params: &'a [Vec<f64>],
    /// Names of the sets and sizes, for messages.
    pub set_names: &'a [String],
}

impl Env<'_> {
    /// The size of a set (the unit has size 1).
    pub(crate) fn set_size(&self, set: Option<crate::SetId>) -> Result<usize, EvalError> {
        match set {
            None => Ok(1),
            Some(s) => self
                .set_sizes
                .get(s.index())
                .copied()
                .flatten()
                .ok_or_else(|| {
                    err(
                        format!(
                            "the size of set `{}` is not known",
                            self.set_names.get(s.index()).map_or("?", |n| n.as_str())
                        ),
                        Span::default(),
                        "give the size of this set",
                    )
                }),
        }
    }

    /// Evaluates map `m` into its array (and the maps it depends on).
    pub(crate) fn ensure_map(&mut self, m: MapId) -> Result<(), EvalError> {
        if self.maps[m.index()].is_some() {
            return Ok(());
        }
        let def = &self.map_defs[m.index()];
        let n = self.set_size(def.domain)?;
        let span = def.span;
        let values: Vec<u32> = match &def.kind {
            MapKind::Given => {
                return Err(err(
                    format!("map `{}` is not given", def.name),
                    span,
                    "give this map's values (an edge list) at construction",
                ));
            }
            MapKind::Identity => (0..n).map(|e| e as u32).collect(),
            MapKind::ToUnit => vec![0; n],
            MapKind::Chain(ms) => {
                let ms = ms.clone();
                for &k in &ms {
                    self.ensure_map(k)?;
                }
                (0..n)
                    .map(|e| {
                        ms.iter().fold(e as u32, |x, k| {
                            self.maps[k.index()].as_ref().map_or(0, |a| a[x as usize])
                        })
                    })
                    .collect()
            }
            MapKind::Formula(f) => {
                let f = f.clone();
                let def_name = def.name.clone();
                let codomain = def.codomain;
                let size = self.set_size(codomain)?;
                let mut out = Vec::with_capacity(n);
                for e in 0..n {
                    let v = self.eval(&f, e).map_err(|mut x| {
                        if x.span == Span::default() {
                            x.span = span;
                        }
                        x
                    })?;
                    out.push(self.index_value(v, size, &def_name, e, span, codomain)?);
                }
                out
            }
        };
        self.maps[m.index()] = Some(values);
        Ok(())
    }

    /// A map's value as an element of a set of `size` elements.
    fn index_value(
        &self,
        v: Val,
        size: usize,
        map: &str,
        e: usize,
        span: Span,
        codomain: Option<crate::SetId>,
    ) -> Result<u32, EvalError> {
        let set = codomain
            .and_then(|s| self.set_names.get(s.index()))
            .map_or("the unit", |n| n.as_str());
        match v {
            Val::I(i) if i >= 0 && (i as u64) < size as u64 => Ok(i as u32),
            Val::I(i) => Err(err(
                format!(
                    "map `{map}` points outside its set: element {e} goes to {i}, but `{set}` has {size} element{} (0..{size})",
                    if size == 1 { "" } else { "s" }
                ),
                span,
                "check the formula against the set sizes (elements count from 0)",
            )),
            _ => Err(err(
                format!("map `{map}` gives a value that is not an integer at element {e}"),
                span,
                "a map formula is an integer formula",
            )),
        }
    }

    /// The image of element `e` under map `m`.
    fn map_at(&mut self, m: MapId, e: usize) -> Result<usize, EvalError> {
        self.ensure_map(m)?;
        let a = self.maps[m.index()].as_ref().expect("evaluated above");
        a.get(e).map(|&x| x as usize).ok_or_else(|| {
            err(
                format!(
                    "map `{}` read at element {e}, outside its domain",
                    self.map_defs[m.index()].name
                ),
                self.map_defs[m.index()].span,
                "check the formula against the set sizes",
            )
        })
    }

    /// The value of `x` at element `e` of its context.
    pub(crate) fn eval(&mut self, x: &RExpr, e: usize) -> Result<Val, EvalError> {
        Ok(match x {
            RExpr::Num(v) => {
                if v.fract() == 0.0 && v.abs() < 9.0e15 {
                    Val::I(*v as i64)
                } else {
                    Val::R(*v)
                }
            }
            RExpr::Var(VarRef::Size(s)) => Val::I(self.sizes[s.index()]),
            RExpr::Var(VarRef::Elem(_)) => Val::I(e as i64),
            RExpr::Var(VarRef::Param(p)) => {
                let values = &self.params[p.index()];
                let i = if values.len() == 1 { 0 } else { e };
                Val::R(values.get(i).copied().unwrap_or(f64::NAN))
            }
            RExpr::Var(_) | RExpr::Let(_) | RExpr::Sum(..) => {
                return Err(err(
                    "internal error: a construction-time expression reads a variable".into(),
                    Span::default(),
                    "please report this model as a bug",
                ));
            }
            RExpr::Gather(m, inner) => {
                let at = self.map_at(*m, e)?;
                self.eval(inner, at)?
            }
            RExpr::Neg(a) => match self.eval(a, e)? {
                Val::I(i) => Val::I(i.checked_neg().ok_or_else(overflow)?),
                v => Val::R(-v.real()),
            },
            RExpr::Binary(op, a, b) => {
                let (a, b) = (self.eval(a, e)?, self.eval(b, e)?);
                binary(*op, a, b)?
            }
            RExpr::Call(f, args) => {
                let vals = args
                    .iter()
                    .map(|a| self.eval(a, e))
                    .collect::<Result<Vec<_>, _>>()?;
                call(*f, &vals)
            }
            RExpr::Compare(op, a, b) => {
                let (a, b) = (self.eval(a, e)?, self.eval(b, e)?);
                Val::B(match (a, b) {
                    (Val::I(x), Val::I(y)) => op.holds(x, y),
                    _ => op.holds(a.real(), b.real()),
                })
            }
            RExpr::Logic(op, a, b) => {
                let a = self.eval(a, e)? == Val::B(true);
                // Both sides are evaluated: a formula is total, and its errors show.
                let b = self.eval(b, e)? == Val::B(true);
                Val::B(match op {
                    LogicOp::And => a && b,
                    LogicOp::Or => a || b,
                })
            }
            RExpr::Not(a) => Val::B(self.eval(a, e)? != Val::B(true)),
            RExpr::If(c, a, b) => {
                if self.eval(c, e)? == Val::B(true) {
                    self.eval(a, e)?
                } else {
                    self.eval(b, e)?
                }
            }
            RExpr::Int(op, a, b) => {
                let (a, b) = (self.eval(a, e)?, self.eval(b, e)?);
                let (Val::I(a), Val::I(b)) = (a, b) else {
                    return Err(err(
                        "`div` and `mod` take integers".into(),
                        Span::default(),
                        "use integers (sizes, elements, maps, whole numbers)",
                    ));
                };
                if b == 0 {
                    return Err(err(
                        format!(
                            "`{}` by zero",
                            if *op == IntOp::Div { "div" } else { "mod" }
                        ),
                        Span::default(),
                        "the divisor of `div` and `mod` must not be 0 with these sizes",
                    ));
                }
                let q = a.checked_div_euclid(b).ok_or_else(overflow)?;
                // Floor division (the quotient rounded down, also for a negative divisor).
                let q = if b < 0 && a.rem_euclid(b) != 0 {
                    q - 1
                } else {
                    q
                };
                match op {
                    IntOp::Div => Val::I(q),
                    IntOp::Mod => Val::I(a - b * q),
                }
            }
        })
    }
}

fn overflow() -> EvalError {
    err(
        "integer overflow in a construction-time formula".into(),
        Span::default(),
        "the sizes are too large for this formula",
    )
}

fn binary(op: BinOp, a: Val, b: Val) -> Result<Val, EvalError> {
    if let (Val::I(x), Val::I(y)) = (a, b) {
        let r = match op {
            BinOp::Add => x.checked_add(y),
            BinOp::Sub => x.checked_sub(y),
            BinOp::Mul => x.checked_mul(y),
            BinOp::Div | BinOp::Pow => None,
        };
        match (op, r) {
            (BinOp::Add | BinOp::Sub | BinOp::Mul, Some(r)) => return Ok(Val::I(r)),
            (BinOp::Add | BinOp::Sub | BinOp::Mul, None) => return Err(overflow()),
            _ => {}
        }
    }
    let (x, y) = (a.real(), b.real());
    Ok(Val::R(match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
        BinOp::Pow => x.powf(y),
    }))
}

fn call(f: Func, vals: &[Val]) -> Val {
    match (f, vals) {
        (Func::Min, [Val::I(a), Val::I(b)]) => Val::I(*a.min(b)),
        (Func::Max, [Val::I(a), Val::I(b)]) => Val::I(*a.max(b)),
        (Func::Abs, [Val::I(a)]) if *a != i64::MIN => Val::I(a.abs()),
        (_, [a]) => Val::R(f.apply1(a.real())),
        (_, [a, b]) => Val::R(f.apply2(a.real(), b.real())),
        _ => Val::R(f64::NAN),
    }
}
