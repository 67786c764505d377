//! Typed resolution of expressions in version-2 models: numbers (integers or reals),
//! conditions and vectors, expanded into scalar components.
//!
//! An expression is resolved in an [`Env`]: the context set (whose element is at hand),
//! the element names in scope and how each is reached from the element at hand, and the
//! place it stands in ([`Where`]), which decides what it may read and whether the
//! construction-time forms (`if`, comparisons, `and`, `or`, `not`, `div`, `mod`) are
//! allowed.

use super::decl::COMPONENTS;
use super::{Checker, Kind, LET_STRIDE, LetState};
use crate::ast::{BinOp, Expr, ExprKind, Span};
use crate::check::names::{KEYWORDS, suggest};
use crate::diag::Diagnostic;
use crate::model::{IntOp, RExpr};
use crate::{AlgId, Func, InputId, LetId, MapId, ParamId, SetId, StateId, VarRef};

/// The type of a resolved expression.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Ty {
    Int,
    Real,
    Bool,
    Vec(u8),
}

impl Ty {
    pub(super) fn words(self) -> String {
        match self {
            Ty::Int | Ty::Real => "a number".into(),
            Ty::Bool => "a condition".into(),
            Ty::Vec(d) => format!("a vec{d}"),
        }
    }

    fn is_number(self) -> bool {
        matches!(self, Ty::Int | Ty::Real)
    }
}

/// A resolved expression: its scalar components (one for a number or a condition).
#[derive(Clone, Debug)]
pub(super) struct Val {
    pub comps: Vec<RExpr>,
    pub ty: Ty,
}

impl Val {
    fn scalar(e: RExpr, ty: Ty) -> Val {
        Val { comps: vec![e], ty }
    }

    /// The vector dimension (1 for a number or a condition).
    pub(super) fn dim(&self) -> u8 {
        match self.ty {
            Ty::Vec(d) => d,
            _ => 1,
        }
    }
}

/// Where an expression stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Where {
    /// The size of a set: sizes and whole numbers.
    SetSize,
    /// The formula of named map number `.0`: integers, the element, sizes, maps declared
    /// before it.
    MapFormula(usize),
    /// A formula written inside an index `x[...]`: an integer formula.
    Index,
    /// The value of parameter declaration number `.0`: earlier parameters, sizes, the
    /// element, maps.
    Param(usize),
    /// An initial value or an input's default: parameters, sizes, the element, maps.
    Init,
    /// `let`, `der`, constraint: everything but the construction-time forms.
    Equation,
}

impl Where {
    fn integers_only(self) -> bool {
        matches!(self, Where::SetSize | Where::MapFormula(_) | Where::Index)
    }

    fn construction(self) -> bool {
        self != Where::Equation
    }

    fn words(self) -> &'static str {
        match self {
            Where::SetSize => "the size of a set",
            Where::MapFormula(_) => "a map formula",
            Where::Index => "an index",
            Where::Param(_) => "a parameter's value",
            Where::Init => "an initial value",
            Where::Equation => "an equation",
        }
    }
}

/// How an element name in scope is reached from the element at hand.
#[derive(Clone, Copy, Debug)]
pub(super) enum Via {
    /// It is the element at hand.
    Here,
    /// It is the image of the element at hand under this map.
    Map(MapId),
    /// It is not determined by the element at hand (inside a full sum, or a sum whose
    /// condition does not name it): the span of that sum.
    Undetermined(Span),
}

/// An element name in scope.
#[derive(Clone, Debug)]
pub(super) struct Binding {
    pub name: String,
    pub set: SetId,
    pub via: Via,
}

/// The environment of an expression.
#[derive(Clone, Debug)]
pub(super) struct Env {
    pub ctx: Option<SetId>,
    pub binders: Vec<Binding>,
    pub place: Where,
    /// The declaration the expression belongs to (for messages).
    pub owner: String,
}

impl Env {
    pub(super) fn binding(&self, name: &str) -> Option<&Binding> {
        self.binders.iter().rev().find(|b| b.name == name)
    }
}

fn int_or_real(a: Ty, b: Ty) -> Ty {
    if a == Ty::Int && b == Ty::Int {
        Ty::Int
    } else {
        Ty::Real
    }
}

fn bin(op: BinOp, a: RExpr, b: RExpr) -> RExpr {
    RExpr::Binary(op, Box::new(a), Box::new(b))
}

/// `sum_i a_i * b_i` (a dot product of components).
fn dot(a: &[RExpr], b: &[RExpr]) -> RExpr {
    let mut terms = a
        .iter()
        .zip(b)
        .map(|(x, y)| bin(BinOp::Mul, x.clone(), y.clone()));
    let first = terms.next().unwrap_or(RExpr::Num(0.0));
    terms.fold(first, |acc, t| bin(BinOp::Add, acc, t))
}

impl Checker<'_> {
    pub(super) fn err(&mut self, d: Diagnostic) -> Option<Val> {
        self.diags.push(d);
        None
    }

    /// Resolves `e` in `env`; `None` after an error (already reported).
    pub(super) fn expr(&mut self, e: &Expr, env: &Env) -> Option<Val> {
        match &e.kind {
            ExprKind::Num(v) => {
                let int = v.fract() == 0.0 && v.abs() < 9.0e15;
                if !int && env.place.integers_only() {
                    return self.err(
                        Diagnostic::new(
                            format!("a float in {}", env.place.words()),
                            e.span,
                            "not a whole number",
                        )
                        .hint(format!(
                            "{} is an integer formula: use whole numbers, sizes, elements and maps",
                            env.place.words()
                        )),
                    );
                }
                Some(Val::scalar(
                    RExpr::Num(*v),
                    if int { Ty::Int } else { Ty::Real },
                ))
            }
            ExprKind::Time => {
                if env.place != Where::Equation {
                    return self.not_here("time `t`", e.span, env);
                }
                Some(Val::scalar(RExpr::Var(VarRef::Time), Ty::Real))
            }
            ExprKind::Name(n) => self.name(n, e.span, env),
            ExprKind::Neg(a) => {
                let v = self.expr(a, env)?;
                if v.ty == Ty::Bool {
                    return self.mismatch("`-`", &v, e.span, "a number or a vector");
                }
                let comps = v
                    .comps
                    .into_iter()
                    .map(|c| RExpr::Neg(Box::new(c)))
                    .collect();
                Some(Val { comps, ty: v.ty })
            }
            ExprKind::Binary(op, a, b) => {
                let a = self.expr(a, env);
                let b = self.expr(b, env);
                self.binary(*op, a?, b?, e.span, env)
            }
            ExprKind::Call(f, args) => self.call(&f.name, f.span, args, e.span, env),
            ExprKind::Index(base, idx) => self.access(base, idx, e.span, env),
            ExprKind::Field(base, f) => {
                let v = self.expr(base, env)?;
                let Ty::Vec(d) = v.ty else {
                    return self.err(
                        Diagnostic::new(
                            format!("`.{}` of {}", f.name, v.ty.words()),
                            f.span,
                            "not a vector",
                        )
                        .hint("components `.x`, `.y`, `.z` belong to vectors (`vec2`, `vec3`)"),
                    );
                };
                match COMPONENTS[..d as usize].iter().position(|c| *c == f.name) {
                    Some(c) => Some(Val::scalar(v.comps[c].clone(), Ty::Real)),
                    None => self.err(
                        Diagnostic::new(
                            format!("a vec{d} has no component `.{}`", f.name),
                            f.span,
                            "no such component",
                        )
                        .hint(if d == 2 {
                            "the components of a vec2 are `.x` and `.y`"
                        } else {
                            "the components of a vec3 are `.x`, `.y` and `.z`"
                        }),
                    ),
                }
            }
            ExprKind::Sum {
                elem,
                set,
                cond,
                body,
            } => self.sum(elem, set, cond.as_deref(), body, e.span, env),
            ExprKind::Compare(op, a, b) => {
                self.construction_only(&format!("the comparison `{}`", op.symbol()), e.span, env)?;
                let (a, b) = (self.expr(a, env), self.expr(b, env));
                let (a, b) = (a?, b?);
                if !a.ty.is_number() || !b.ty.is_number() {
                    let bad = if a.ty.is_number() { &b } else { &a };
                    return self.mismatch(&format!("`{}`", op.symbol()), bad, e.span, "numbers");
                }
                let c = RExpr::Compare(
                    *op,
                    Box::new(a.comps[0].clone()),
                    Box::new(b.comps[0].clone()),
                );
                Some(Val::scalar(c, Ty::Bool))
            }
            ExprKind::Logic(op, a, b) => {
                let word = if *op == crate::ast::LogicOp::And {
                    "and"
                } else {
                    "or"
                };
                self.construction_only(&format!("`{word}`"), e.span, env)?;
                let (a, b) = (self.condition(a, env), self.condition(b, env));
                let c = RExpr::Logic(*op, Box::new(a?), Box::new(b?));
                Some(Val::scalar(c, Ty::Bool))
            }
            ExprKind::Not(a) => {
                self.construction_only("`not`", e.span, env)?;
                let a = self.condition(a, env)?;
                Some(Val::scalar(RExpr::Not(Box::new(a)), Ty::Bool))
            }
            ExprKind::If(c, a, b) => {
                self.construction_only("`if`", e.span, env)?;
                let c = self.condition(c, env);
                let (a, b) = (self.expr(a, env), self.expr(b, env));
                let (c, a, b) = (c?, a?, b?);
                let ty = match (a.ty, b.ty) {
                    (x, y) if x.is_number() && y.is_number() => int_or_real(x, y),
                    (x, y) if x == y && x != Ty::Bool => x,
                    _ => {
                        return self.err(
                            Diagnostic::new(
                                format!(
                                    "the branches of `if` are {} and {}",
                                    a.ty.words(),
                                    b.ty.words()
                                ),
                                e.span,
                                "different types",
                            )
                            .hint("both branches of `if ... then ... else ...` have the same type"),
                        );
                    }
                };
                let comps = a
                    .comps
                    .into_iter()
                    .zip(b.comps)
                    .map(|(x, y)| RExpr::If(Box::new(c.clone()), Box::new(x), Box::new(y)))
                    .collect();
                Some(Val { comps, ty })
            }
        }
    }

    /// A condition (a comparison, `and`, `or`, `not`).
    fn condition(&mut self, e: &Expr, env: &Env) -> Option<RExpr> {
        let v = self.expr(e, env)?;
        if v.ty != Ty::Bool {
            self.diags.push(
                Diagnostic::new(
                    format!("expected a condition, found {}", v.ty.words()),
                    e.span,
                    "not a condition",
                )
                .hint("a condition compares numbers: `p == 0`, `l < N`, combined with `and`, `or`, `not`"),
            );
            return None;
        }
        v.comps.into_iter().next()
    }

    /// The error for a construction-time form in an equation.
    fn construction_only(&mut self, what: &str, span: Span, env: &Env) -> Option<()> {
        if env.place.construction() {
            return Some(());
        }
        self.diags.push(
            Diagnostic::new(format!("{what} in an equation"), span, "not allowed in an equation")
                .hint(
                    "`if`, comparisons, `and`, `or`, `not`, `div` and `mod` are for construction-time \
                     expressions (sizes, maps, parameter values, initial values): use a per-element \
                     parameter, e.g. `param free[p in P] = if p == 0 then 0 else 1;`, and multiply by it",
                ),
        );
        None
    }

    fn mismatch(&mut self, what: &str, v: &Val, span: Span, expected: &str) -> Option<Val> {
        self.err(
            Diagnostic::new(
                format!("{what} takes {expected}, not {}", v.ty.words()),
                span,
                "vector/scalar mismatch",
            )
            .hint("vectors add and subtract, scale by numbers, and give numbers with `dot`, `norm` and `.x`"),
        )
    }

    fn not_here(&mut self, what: &str, span: Span, env: &Env) -> Option<Val> {
        let hint = match env.place {
            Where::SetSize => "a set's size is a formula over sizes and whole numbers",
            Where::MapFormula(_) | Where::Index => {
                "a map formula uses whole numbers, sizes, elements and maps"
            }
            Where::Param(_) => {
                "a parameter's value uses numbers, sizes, the element and parameters declared before it"
            }
            Where::Init => "initial values may use only numbers, sizes, elements and parameters",
            Where::Equation => "see docs/language.md",
        };
        let owner = &env.owner;
        let message = match env.place {
            Where::SetSize => format!("the size of set `{owner}` uses {what}"),
            Where::MapFormula(_) => format!("the formula of map `{owner}` uses {what}"),
            Where::Index => format!("an index uses {what}"),
            Where::Param(_) => format!("the default of parameter `{owner}` uses {what}"),
            Where::Init => format!("the initial value of `{owner}` uses {what}"),
            Where::Equation => format!("`{owner}` uses {what}"),
        };
        self.err(Diagnostic::new(message, span, "not allowed here").hint(hint))
    }

    fn binary(&mut self, op: BinOp, a: Val, b: Val, span: Span, env: &Env) -> Option<Val> {
        let sym = match op {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Pow => "^",
        };
        if env.place.integers_only() && matches!(op, BinOp::Div | BinOp::Pow) {
            return self.err(
                Diagnostic::new(format!("`{sym}` in {}", env.place.words()), span, "not an integer operation")
                    .hint("an integer formula uses `+ - *`, `div(a, b)`, `mod(a, b)`, `min`, `max` and `if`"),
            );
        }
        match (op, a.ty, b.ty) {
            (_, x, y) if x.is_number() && y.is_number() => {
                let ty = if matches!(op, BinOp::Div | BinOp::Pow) {
                    Ty::Real
                } else {
                    int_or_real(x, y)
                };
                let e = bin(op, a.comps[0].clone(), b.comps[0].clone());
                Some(Val::scalar(e, ty))
            }
            (BinOp::Add | BinOp::Sub, Ty::Vec(d), Ty::Vec(e)) if d == e => {
                let comps = a
                    .comps
                    .into_iter()
                    .zip(b.comps)
                    .map(|(x, y)| bin(op, x, y))
                    .collect();
                Some(Val { comps, ty: a.ty })
            }
            (BinOp::Mul, x, Ty::Vec(_)) if x.is_number() => {
                let s = a.comps[0].clone();
                let comps = b.comps.into_iter().map(|y| bin(op, s.clone(), y)).collect();
                Some(Val { comps, ty: b.ty })
            }
            (BinOp::Mul | BinOp::Div, Ty::Vec(_), y) if y.is_number() => {
                let s = b.comps[0].clone();
                let comps = a.comps.into_iter().map(|x| bin(op, x, s.clone())).collect();
                Some(Val { comps, ty: a.ty })
            }
            _ => {
                let hint = match (op, a.ty, b.ty) {
                    (BinOp::Mul, Ty::Vec(_), Ty::Vec(_)) => {
                        "two vectors do not multiply: use `dot(a, b)` (a number) or `cross(a, b)` (a vec3)"
                    }
                    (_, Ty::Bool, _) | (_, _, Ty::Bool) => {
                        "a condition is not a number: write `if c then 1 else 0`"
                    }
                    _ => {
                        "vectors add to vectors of the same size and scale by numbers; `norm(v)`, `dot(a, b)` and `v.x` give numbers"
                    }
                };
                self.err(
                    Diagnostic::new(
                        format!("`{sym}` of {} and {}", a.ty.words(), b.ty.words()),
                        span,
                        "vector/scalar mismatch",
                    )
                    .hint(hint),
                )
            }
        }
    }

    fn call(
        &mut self,
        name: &str,
        name_span: Span,
        args: &[Expr],
        span: Span,
        env: &Env,
    ) -> Option<Val> {
        let vals: Vec<Option<Val>> = args.iter().map(|a| self.expr(a, env)).collect();
        let arity = match name {
            "vec2" => Some(2),
            "vec3" | "dot" | "cross" | "div" | "mod" => Some(if name == "vec3" { 3 } else { 2 }),
            "norm" => Some(1),
            _ => None,
        };
        if let Some(n) = arity {
            if args.len() != n {
                return self.err(
                    Diagnostic::new(
                        format!(
                            "function `{name}` takes {n} argument{} but {} {} given",
                            if n == 1 { "" } else { "s" },
                            args.len(),
                            if args.len() == 1 { "was" } else { "were" }
                        ),
                        span,
                        format!("{} arguments", args.len()),
                    )
                    .hint(format!("call it as `{}`", family_signature(name))),
                );
            }
            let vals: Vec<Val> = vals.into_iter().collect::<Option<_>>()?;
            return self.family_call(name, vals, span, env);
        }
        let Some(f) = Func::from_name(name) else {
            return self.unknown_function(name, name_span);
        };
        if f.arity() != args.len() {
            let plural = |k: usize| if k == 1 { "argument" } else { "arguments" };
            return self.err(
                Diagnostic::new(
                    format!(
                        "function `{name}` takes {} {} but {} {} given",
                        f.arity(),
                        plural(f.arity()),
                        args.len(),
                        if args.len() == 1 { "was" } else { "were" }
                    ),
                    span,
                    format!("{} {}", args.len(), plural(args.len())),
                )
                .hint(format!("call it as `{}`", func_signature(f))),
            );
        }
        let vals: Vec<Val> = vals.into_iter().collect::<Option<_>>()?;
        if let Some(bad) = vals.iter().find(|v| !v.ty.is_number()) {
            let bad = bad.clone();
            return self.mismatch(&format!("`{name}`"), &bad, span, "numbers");
        }
        let int =
            matches!(f, Func::Min | Func::Max | Func::Abs) && vals.iter().all(|v| v.ty == Ty::Int);
        if env.place.integers_only() && !int {
            return self.err(
                Diagnostic::new(format!("`{name}` in {}", env.place.words()), span, "not an integer function")
                    .hint("an integer formula uses `+ - *`, `div(a, b)`, `mod(a, b)`, `min`, `max` and `if`"),
            );
        }
        let e = RExpr::Call(f, vals.into_iter().map(|v| v.comps[0].clone()).collect());
        Some(Val::scalar(e, if int { Ty::Int } else { Ty::Real }))
    }

    fn family_call(&mut self, name: &str, vals: Vec<Val>, span: Span, env: &Env) -> Option<Val> {
        match name {
            "vec2" | "vec3" => {
                if let Some(bad) = vals.iter().find(|v| !v.ty.is_number()) {
                    let bad = bad.clone();
                    return self.mismatch(&format!("`{name}`"), &bad, span, "numbers");
                }
                let d = vals.len() as u8;
                let comps = vals.into_iter().map(|v| v.comps[0].clone()).collect();
                Some(Val {
                    comps,
                    ty: Ty::Vec(d),
                })
            }
            "div" | "mod" => {
                self.construction_only(&format!("`{name}`"), span, env)?;
                if vals.iter().any(|v| v.ty != Ty::Int) {
                    return self.err(
                        Diagnostic::new(
                            format!("`{name}` of a value that is not an integer"),
                            span,
                            "not integers",
                        )
                        .hint(
                            "`div` and `mod` take integers: whole numbers, sizes, elements, maps",
                        ),
                    );
                }
                let op = if name == "div" {
                    IntOp::Div
                } else {
                    IntOp::Mod
                };
                let [a, b]: [Val; 2] = vals.try_into().ok()?;
                let e = RExpr::Int(
                    op,
                    Box::new(a.comps[0].clone()),
                    Box::new(b.comps[0].clone()),
                );
                Some(Val::scalar(e, Ty::Int))
            }
            _ => {
                // dot, norm, cross: vectors.
                let d = match vals[0].ty {
                    Ty::Vec(d) => d,
                    _ => {
                        let v = vals[0].clone();
                        return self.mismatch(&format!("`{name}`"), &v, span, "vectors");
                    }
                };
                if vals.iter().any(|v| v.ty != Ty::Vec(d)) || (name == "cross" && d != 3) {
                    let v = vals
                        .iter()
                        .find(|v| v.ty != Ty::Vec(3))
                        .unwrap_or(&vals[0])
                        .clone();
                    let expected = if name == "cross" {
                        "two vec3"
                    } else {
                        "two vectors of one size"
                    };
                    return self.mismatch(&format!("`{name}`"), &v, span, expected);
                }
                match name {
                    "dot" => Some(Val::scalar(dot(&vals[0].comps, &vals[1].comps), Ty::Real)),
                    "norm" => {
                        let sq: Vec<RExpr> = vals[0]
                            .comps
                            .iter()
                            .map(|c| bin(BinOp::Pow, c.clone(), RExpr::Num(2.0)))
                            .collect();
                        let mut it = sq.into_iter();
                        let first = it.next().unwrap_or(RExpr::Num(0.0));
                        let s = it.fold(first, |acc, t| bin(BinOp::Add, acc, t));
                        Some(Val::scalar(RExpr::Call(Func::Sqrt, vec![s]), Ty::Real))
                    }
                    _ => {
                        let (a, b) = (&vals[0].comps, &vals[1].comps);
                        let c = |i: usize, j: usize| {
                            bin(
                                BinOp::Sub,
                                bin(BinOp::Mul, a[i].clone(), b[j].clone()),
                                bin(BinOp::Mul, a[j].clone(), b[i].clone()),
                            )
                        };
                        Some(Val {
                            comps: vec![c(1, 2), c(2, 0), c(0, 1)],
                            ty: Ty::Vec(3),
                        })
                    }
                }
            }
        }
    }

    fn unknown_function(&mut self, name: &str, span: Span) -> Option<Val> {
        let d = if let Some(e) = self.names.get(name) {
            Diagnostic::new(format!("`{name}` is not a function"), span, e.kind.words())
                .hint(format!("to multiply, write `{name} * (...)`"))
        } else if KEYWORDS.contains(&name) || super::decl::FAMILY_KEYWORDS.contains(&name) {
            Diagnostic::new(
                format!("reserved word `{name}` is not a function"),
                span,
                "reserved word",
            )
            .hint("see docs/language.md for the built-in functions")
        } else {
            let all: Vec<&str> = Func::ALL
                .iter()
                .map(|f| f.name())
                .chain(super::FAMILY_FUNCTIONS)
                .collect();
            let d = Diagnostic::new(
                format!("unknown function `{name}`"),
                span,
                "unknown function",
            );
            match suggest(name, all.iter().copied()) {
                Some(s) => d.hint(format!("did you mean `{s}`?")),
                None => d.hint(
                    "the functions are sin cos tan asin acos atan sinh cosh tanh exp ln sqrt abs \
                     sign atan2 pow min max, and vec2 vec3 dot norm cross div mod",
                ),
            }
        };
        self.err(d)
    }

    /// A bare name.
    fn name(&mut self, n: &str, span: Span, env: &Env) -> Option<Val> {
        if let Some(b) = env.binding(n) {
            let b = b.clone();
            let elem = RExpr::Var(VarRef::Elem(b.set));
            return match b.via {
                Via::Here => Some(Val::scalar(elem, Ty::Int)),
                Via::Map(m) => Some(Val::scalar(RExpr::Gather(m, Box::new(elem)), Ty::Int)),
                Via::Undetermined(sum) => self.undetermined(n, span, sum),
            };
        }
        let Some(entry) = self.names.get(n).copied() else {
            return self.unknown_name(n, span);
        };
        match entry.kind {
            Kind::Size => Some(Val::scalar(RExpr::Var(VarRef::Size(crate::SizeId::new(entry.first))), Ty::Int)),
            Kind::Set => self.err(
                Diagnostic::new(format!("`{n}` is a set, not a number"), span, "a set")
                    .hint("to use the number of elements, declare a size and write the set's size with it"),
            ),
            Kind::Map => {
                let dom = entry.over.map_or(String::new(), |s| self.sets[s.index()].elem.clone());
                self.err(
                    Diagnostic::new(format!("`{n}` is a map: it needs an element"), span, "a map")
                        .hint(format!("write `{n}[{dom}]` for the image of an element")),
                )
            }
            _ => {
                if let Some(set) = entry.over {
                    let s = &self.sets[set.index()];
                    let suggestion = match env.binders.iter().rev().find(|b| b.set == set) {
                        Some(b) => format!("write `{n}[{}]`", b.name),
                        None => format!("write `{n}[...]` with an element of `{}`", s.name),
                    };
                    return self.err(
                        Diagnostic::new(
                            format!("`{n}` is a family over `{}`: it needs an element", s.name),
                            span,
                            format!("one value per element of `{}`", s.name),
                        )
                        .hint(suggestion),
                    );
                }
                self.leaf(n, entry, span, env)
            }
        }
    }

    /// The components of a variable or `let` (read at the element at hand), after the
    /// rules of the place.
    pub(super) fn leaf(
        &mut self,
        n: &str,
        entry: super::Entry,
        span: Span,
        env: &Env,
    ) -> Option<Val> {
        let allowed = match (entry.kind, env.place) {
            (_, Where::Equation) => true,
            (Kind::Param, Where::Init) => true,
            (Kind::Param, Where::Param(i)) => {
                if entry.decl >= i {
                    let d = if self.param_decl.get(entry.first) == Some(&i) {
                        Diagnostic::new(
                            format!("parameter `{}` is defined in terms of itself", env.owner),
                            span,
                            "used in its own default",
                        )
                        .hint("give the parameter a value made of numbers, sizes and earlier parameters")
                    } else {
                        Diagnostic::new(
                            format!(
                                "the default of parameter `{}` uses `{n}`, which is declared after it",
                                env.owner
                            ),
                            span,
                            "declared later",
                        )
                        .related(entry.span, format!("`{n}` is declared here"))
                        .hint(format!("declare `{n}` before `{}`", env.owner))
                    };
                    return self.err(d);
                }
                true
            }
            _ => false,
        };
        if !allowed {
            return self.not_here(&format!("`{n}`, {}", entry.kind.words()), span, env);
        }
        // A `let`'s type is its value's: resolve it first.
        let dim = if entry.kind == Kind::Let {
            self.resolve_let(entry.first)?
        } else {
            entry.dim
        };
        let comps: Vec<RExpr> = (0..dim as usize)
            .map(|c| {
                let i = entry.first + c;
                match entry.kind {
                    Kind::Param => RExpr::Var(VarRef::Param(ParamId::new(i))),
                    Kind::State => RExpr::Var(VarRef::State(StateId::new(i))),
                    Kind::Alg => RExpr::Var(VarRef::Alg(AlgId::new(i))),
                    Kind::Input => RExpr::Var(VarRef::Input(InputId::new(i), 0)),
                    _ => RExpr::Let(LetId::new(entry.first * LET_STRIDE + c)),
                }
            })
            .collect();
        let ty = if dim == 1 { Ty::Real } else { Ty::Vec(dim) };
        Some(Val { comps, ty })
    }

    /// Resolves `let` declaration `d` if not done yet; its dimension.
    pub(super) fn resolve_let(&mut self, d: usize) -> Option<u8> {
        match &self.let_state[d] {
            LetState::Done(Some(c)) => return Some(c.len() as u8),
            LetState::Done(None) => return None,
            // Resolving `d` needs `d`: a cycle through the `let`s. Reported here, since
            // the `let`s on it get no value and so no uses for the ordering to see.
            LetState::InProgress => {
                let decl = self.lets[d];
                self.diags.push(
                    Diagnostic::new(
                        format!("the definition of `{}` uses itself", decl.name.name),
                        decl.name.span,
                        "uses itself, directly or through other `let`s",
                    )
                    .hint("a `let` may not use itself, directly or through other `let`s: break the cycle"),
                );
                return None;
            }
            LetState::Todo => {}
        }
        self.let_state[d] = LetState::InProgress;
        let decl = self.lets[d];
        let set = self.let_sets[d];
        let env = self.decl_env(decl, set, Where::Equation);
        let v = self.expr(&decl.value, &env);
        let v = v.and_then(|v| {
            if v.ty == Ty::Bool {
                self.mismatch(
                    &format!("`let {}`", decl.name.name),
                    &v,
                    decl.value.span,
                    "a number or a vector",
                )
            } else {
                self.check_declared_type(decl, &v)
            }
        });
        let dim = v.as_ref().map(Val::dim);
        self.let_state[d] = LetState::Done(v.map(|v| v.comps));
        dim
    }

    /// A value against the declaration's type annotation (a number without one).
    pub(super) fn check_declared_type(&mut self, decl: &crate::ast::Decl, v: &Val) -> Option<Val> {
        let declared = match decl.ty.as_ref().map(|t| t.name.as_str()) {
            Some("vec2") => Some(2),
            Some("vec3") => Some(3),
            Some(_) => return None, // unknown type: reported at the declaration
            None => None,
        };
        // A `let` without a type takes the type of its value.
        let lets = self
            .names
            .get(decl.name.name.as_str())
            .is_some_and(|e| e.kind == Kind::Let);
        let want = declared.unwrap_or(if lets { v.dim() } else { 1 });
        if v.dim() != want || v.ty == Ty::Bool {
            let what = if want == 1 {
                "a number".to_string()
            } else {
                format!("a vec{want}")
            };
            return self.err(
                Diagnostic::new(
                    format!(
                        "`{}` is {what}, but its value is {}",
                        decl.name.name,
                        v.ty.words()
                    ),
                    decl.value.span,
                    "vector/scalar mismatch",
                )
                .hint(if want == 1 {
                    "declare a vector with its type, e.g. `state x[p in P]: vec3 = vec3(0, 0, 0);`"
                        .to_string()
                } else {
                    format!("give it a vec{want}, e.g. `vec{want}(...)`")
                }),
            );
        }
        Some(v.clone())
    }

    /// The environment of a declaration's value: its set's element is at hand, named by
    /// its binder.
    pub(super) fn decl_env(
        &self,
        decl: &crate::ast::Decl,
        set: Option<SetId>,
        place: Where,
    ) -> Env {
        let mut binders = Vec::new();
        if let (Some(set), Some(b)) = (set, decl.binder.as_ref()) {
            if let Some(e) = &b.elem {
                binders.push(Binding {
                    name: e.name.clone(),
                    set,
                    via: Via::Here,
                });
            }
        }
        Env {
            ctx: set,
            binders,
            place,
            owner: decl.name.name.clone(),
        }
    }

    fn undetermined(&mut self, n: &str, span: Span, sum: Span) -> Option<Val> {
        self.err(
            Diagnostic::new(
                format!("`{n}` is not determined inside this sum"),
                span,
                "which element?",
            )
            .related(sum, "the sum")
            .hint(format!(
                "inside `sum(k in K where m[k] == {n}) ...` the element `{n}` is `m[k]`; a full sum, \
                 or a sum whose condition does not name `{n}` directly, cannot use it"
            )),
        )
    }

    pub(super) fn unknown_name(&mut self, n: &str, span: Span) -> Option<Val> {
        if let Some(f) = Func::from_name(n) {
            return self.err(
                Diagnostic::new(
                    format!("function `{n}` used without arguments"),
                    span,
                    "a function",
                )
                .hint(format!("call it: `{}`", func_signature(f))),
            );
        }
        if KEYWORDS.contains(&n) || super::decl::FAMILY_KEYWORDS.contains(&n) {
            return self.err(
                Diagnostic::new(format!("reserved word `{n}` cannot be used in an expression"), span, "reserved word")
                    .hint("reserved words are `model param state alg let der constraint t if then else and or not` and the function names"),
            );
        }
        let d = Diagnostic::new(
            format!("unknown name `{n}`"),
            span,
            format!("not declared in model `{}`", self.m.name.name),
        );
        let d = match suggest(n, self.ordered.iter().copied()) {
            Some(s) => d.hint(format!("did you mean `{s}`?")),
            None => d.hint(
                "declare it with `param`, `state`, `alg`, `let`, `input`, `size`, `set` or `map`",
            ),
        };
        self.err(d)
    }
}

fn func_signature(f: Func) -> String {
    match f {
        Func::Atan2 => "atan2(y, x)".into(),
        Func::Pow => "pow(a, b)".into(),
        Func::Min | Func::Max => format!("{}(a, b)", f.name()),
        _ => format!("{}(x)", f.name()),
    }
}

fn family_signature(name: &str) -> &'static str {
    match name {
        "vec2" => "vec2(x, y)",
        "vec3" => "vec3(x, y, z)",
        "dot" => "dot(a, b)",
        "cross" => "cross(a, b)",
        "norm" => "norm(v)",
        "div" => "div(a, b)",
        _ => "mod(a, b)",
    }
}
