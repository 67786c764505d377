//! Typed resolution of expressions in version-2 models: numbers (integers or reals),
//! conditions and vectors, expanded into scalar components.
//!
//! An expression is resolved in an [`Env`]: the context set (whose element is at hand),
//! the element names in scope and how each is reached from the element at hand, and the
//! place it stands in ([`Where`]), which decides what it may read and whether the
//! construction-time forms (`if`, comparisons, `and`, `or`, `not`, `div`, `mod`) are
//! allowed.

use super::Checker;
use super::decl::COMPONENTS;
use crate::ast::{BinOp, Expr, ExprKind, Span};
use crate::check::names::suggest;
use crate::diag::Diagnostic;
use crate::model::{IntOp, RExpr};
use crate::{Func, MapId, SetId, VarRef};

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
    pub(super) fn scalar(e: RExpr, ty: Ty) -> Val {
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

    pub(super) fn mismatch(
        &mut self,
        what: &str,
        v: &Val,
        span: Span,
        expected: &str,
    ) -> Option<Val> {
        self.err(
            Diagnostic::new(
                format!("{what} takes {expected}, not {}", v.ty.words()),
                span,
                "vector/scalar mismatch",
            )
            .hint("vectors add and subtract, scale by numbers, and give numbers with `dot`, `norm` and `.x`"),
        )
    }

    pub(super) fn not_here(&mut self, what: &str, span: Span, env: &Env) -> Option<Val> {
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
        let (label, hint) = match (self.version1, env.place) {
            // The words of version 1, where they have always been.
            (true, Where::Param(_) | Where::Init) => {
                let time = what == "time `t`";
                let hint = match (env.place, time) {
                    (Where::Param(_), true) => {
                        "parameters are constants: use numbers and parameters declared before it"
                    }
                    (Where::Param(_), false) => {
                        "a parameter default may use only numbers and parameters declared before it"
                    }
                    (_, true) => {
                        "initial values are computed before the simulation starts: use numbers \
                         and parameters"
                    }
                    _ => "initial values may use only numbers and parameters",
                };
                let label = match what.split_once(", ") {
                    _ if time => "time is not allowed here",
                    Some((_, kind)) => kind,
                    None => "not allowed here",
                };
                (label, hint)
            }
            _ => ("not allowed here", hint),
        };
        self.err(Diagnostic::new(message, span, label).hint(hint))
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
        } else if name == "t" {
            Diagnostic::new("`t` (time) is not a function", span, "time")
                .hint("to multiply, write `t * (...)`")
        } else if name == "der" {
            Diagnostic::new(
                "`der` is allowed only at the start of an equation",
                span,
                "here",
            )
            .hint("write `der(x) = ...;` as an item of its own")
        } else if super::decl::is_reserved(name, self.version1) && Func::from_name(name).is_none() {
            Diagnostic::new(
                format!("reserved word `{name}` is not a function"),
                span,
                "reserved word",
            )
            .hint("see docs/language.md for the built-in functions")
        } else {
            let version2 = if self.version1 {
                &[][..]
            } else {
                &super::FAMILY_FUNCTIONS[..]
            };
            let all: Vec<&str> = Func::ALL
                .iter()
                .map(|f| f.name())
                .chain(version2.iter().copied())
                .collect();
            let d = Diagnostic::new(
                format!("unknown function `{name}`"),
                span,
                "unknown function",
            );
            match suggest(name, all.iter().copied()) {
                Some(s) => d.hint(format!("did you mean `{s}`?")),
                None if self.version1 => d.hint(
                    "the functions are sin cos tan asin acos atan sinh cosh tanh exp ln sqrt abs \
                     sign atan2 pow min max",
                ),
                None => d.hint(
                    "the functions are sin cos tan asin acos atan sinh cosh tanh exp ln sqrt abs \
                     sign atan2 pow min max, and vec2 vec3 dot norm cross div mod",
                ),
            }
        };
        self.err(d)
    }
}

pub(super) fn func_signature(f: Func) -> String {
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
