//! Name resolution of expressions, with the rules of each place an expression can be:
//! parameter defaults use numbers and earlier parameters, initial values use numbers and
//! parameters, and the equations (`let`, `der`, `constraint`) may use everything.

use super::names::{KEYWORDS, Suggestions};
use crate::ast::{Expr, ExprKind, Span};
use crate::diag::Diagnostic;
use crate::model::RExpr;
use crate::{AlgId, Func, LetId, ParamId, StateId, VarRef};
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};

/// What a declared name is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Param,
    State,
    Alg,
    Let,
}

impl Kind {
    pub(super) fn words(self) -> &'static str {
        match self {
            Kind::Param => "a parameter",
            Kind::State => "a state",
            Kind::Alg => "an algebraic variable",
            Kind::Let => "a `let` definition",
        }
    }
}

/// A declared name: its kind, its index among the declarations of that kind (source
/// order) and the span of the name where it was declared.
#[derive(Clone, Copy, Debug)]
pub(super) struct Entry {
    pub kind: Kind,
    pub index: usize,
    pub span: Span,
}

/// Where an expression stands, which decides what it may refer to.
#[derive(Clone, Copy)]
pub(super) enum Ctx<'a> {
    /// `let`, `der` and `constraint`: everything, and time.
    Equation,
    /// The default of parameter number `index`, called `name`.
    ParamDefault { index: usize, name: &'a str },
    /// The initial value of the state or algebraic variable `name`.
    Init { name: &'a str },
}

/// The names of a model, first declaration of each.
pub(super) struct Scope<'a> {
    pub names: HashMap<&'a str, Entry>,
    /// Declared names in source order (for suggestions that do not depend on hashing).
    pub ordered: Vec<&'a str>,
    /// Names declared more than once (already reported), to avoid follow-up errors.
    pub duplicated: HashSet<&'a str>,
    pub model_name: &'a str,
    /// "Did you mean" among `ordered`, made at the first unknown name.
    pub suggestions: RefCell<Option<Suggestions<'a>>>,
    /// "Did you mean" among the built-in functions, made at the first unknown function.
    pub function_suggestions: RefCell<Option<Suggestions<'static>>>,
}

/// How to call each function, for hints.
fn signature(f: Func) -> String {
    match f {
        Func::Atan2 => "atan2(y, x)".into(),
        Func::Pow => "pow(a, b)".into(),
        Func::Min | Func::Max => format!("{}(a, b)", f.name()),
        _ => format!("{}(x)", f.name()),
    }
}

impl Scope<'_> {
    /// Resolves `e`, pushing a diagnostic for every error; `None` if there was one.
    pub(super) fn resolve(
        &self,
        e: &Expr,
        ctx: Ctx<'_>,
        diags: &mut Vec<Diagnostic>,
    ) -> Option<RExpr> {
        match &e.kind {
            ExprKind::Num(v) => Some(RExpr::Num(*v)),
            ExprKind::Time => self.time(e.span, ctx, diags),
            ExprKind::Name(n) => self.name(n, e.span, ctx, diags),
            ExprKind::Neg(a) => Some(RExpr::Neg(Box::new(self.resolve(a, ctx, diags)?))),
            ExprKind::Binary(op, a, b) => {
                let a = self.resolve(a, ctx, diags);
                let b = self.resolve(b, ctx, diags);
                Some(RExpr::Binary(*op, Box::new(a?), Box::new(b?)))
            }
            ExprKind::Call(f, args) => {
                let resolved: Vec<Option<RExpr>> =
                    args.iter().map(|a| self.resolve(a, ctx, diags)).collect();
                let func = self.function(&f.name, f.span, args.len(), e.span, diags)?;
                resolved
                    .into_iter()
                    .collect::<Option<Vec<_>>>()
                    .map(|a| RExpr::Call(func, a))
            }
            // Version-2 forms (`ExprKind::is_version_2`) never reach the version-1
            // checker (`uses_version_2`).
            _ => None,
        }
    }

    fn time(&self, span: Span, ctx: Ctx<'_>, diags: &mut Vec<Diagnostic>) -> Option<RExpr> {
        let (message, hint) = match ctx {
            Ctx::Equation => return Some(RExpr::Var(VarRef::Time)),
            Ctx::ParamDefault { name, .. } => (
                format!("the default of parameter `{name}` uses time `t`"),
                "parameters are constants: use numbers and parameters declared before it",
            ),
            Ctx::Init { name } => (
                format!("the initial value of `{name}` uses time `t`"),
                "initial values are computed before the simulation starts: use numbers and \
                 parameters",
            ),
        };
        diags.push(Diagnostic::new(message, span, "time is not allowed here").hint(hint));
        None
    }

    fn name(
        &self,
        n: &str,
        span: Span,
        ctx: Ctx<'_>,
        diags: &mut Vec<Diagnostic>,
    ) -> Option<RExpr> {
        let Some(entry) = self.names.get(n) else {
            diags.push(self.unknown_name(n, span));
            return None;
        };
        let resolved = match entry.kind {
            Kind::Param => RExpr::Var(VarRef::Param(ParamId::new(entry.index))),
            Kind::State => RExpr::Var(VarRef::State(StateId::new(entry.index))),
            Kind::Alg => RExpr::Var(VarRef::Alg(AlgId::new(entry.index))),
            Kind::Let => RExpr::Let(LetId::new(entry.index)),
        };
        match ctx {
            Ctx::Equation => Some(resolved),
            Ctx::ParamDefault { index, name } => {
                if entry.kind != Kind::Param {
                    diags.push(
                        Diagnostic::new(
                            format!("the default of parameter `{name}` uses `{n}`, {}", entry.kind.words()),
                            span,
                            entry.kind.words(),
                        )
                        .hint("a parameter default may use only numbers and parameters declared before it"),
                    );
                    None
                } else if entry.index >= index {
                    let d = if n == name {
                        Diagnostic::new(
                            format!("parameter `{name}` is defined in terms of itself"),
                            span,
                            "used in its own default",
                        )
                        .hint("give the parameter a value made of numbers and earlier parameters")
                    } else {
                        Diagnostic::new(
                            format!("the default of parameter `{name}` uses `{n}`, which is declared after it"),
                            span,
                            "declared later",
                        )
                        .related(entry.span, format!("`{n}` is declared here"))
                        .hint(format!("declare `{n}` before `{name}`"))
                    };
                    diags.push(d);
                    None
                } else {
                    Some(resolved)
                }
            }
            Ctx::Init { name } => {
                if entry.kind == Kind::Param {
                    Some(resolved)
                } else {
                    diags.push(
                        Diagnostic::new(
                            format!(
                                "the initial value of `{name}` uses `{n}`, {}",
                                entry.kind.words()
                            ),
                            span,
                            entry.kind.words(),
                        )
                        .hint("initial values may use only numbers and parameters"),
                    );
                    None
                }
            }
        }
    }

    /// The diagnostic for a name that is not declared.
    pub(super) fn unknown_name(&self, n: &str, span: Span) -> Diagnostic {
        if let Some(f) = Func::from_name(n) {
            return Diagnostic::new(
                format!("function `{n}` used without arguments"),
                span,
                "a function",
            )
            .hint(format!("call it: `{}`", signature(f)));
        }
        if KEYWORDS.contains(&n) {
            return Diagnostic::new(
                format!("reserved word `{n}` cannot be used in an expression"),
                span,
                "reserved word",
            )
            .hint("reserved words are `model param state alg let der constraint t` and the function names");
        }
        let d = Diagnostic::new(
            format!("unknown name `{n}`"),
            span,
            format!("not declared in model `{}`", self.model_name),
        );
        let suggestion = self
            .suggestions
            .borrow_mut()
            .get_or_insert_with(|| Suggestions::new(self.ordered.iter().copied()))
            .suggest(n);
        match suggestion {
            Some(s) => d.hint(format!("did you mean `{s}`?")),
            None => d.hint("declare it with `param`, `state`, `alg` or `let`"),
        }
    }

    /// The function called `name` with `nargs` arguments, or a diagnostic.
    fn function(
        &self,
        name: &str,
        name_span: Span,
        nargs: usize,
        call_span: Span,
        diags: &mut Vec<Diagnostic>,
    ) -> Option<Func> {
        if let Some(f) = Func::from_name(name) {
            if f.arity() == nargs {
                return Some(f);
            }
            let plural = |k: usize| if k == 1 { "argument" } else { "arguments" };
            diags.push(
                Diagnostic::new(
                    format!(
                        "function `{name}` takes {} {} but {nargs} {} given",
                        f.arity(),
                        plural(f.arity()),
                        if nargs == 1 { "was" } else { "were" }
                    ),
                    call_span,
                    format!("{nargs} {}", plural(nargs)),
                )
                .hint(format!("call it as `{}`", signature(f))),
            );
            return None;
        }
        let d = if let Some(entry) = self.names.get(name) {
            Diagnostic::new(
                format!("`{name}` is not a function"),
                name_span,
                entry.kind.words(),
            )
            .hint(format!("to multiply, write `{name} * (...)`"))
        } else if name == "t" {
            Diagnostic::new("`t` (time) is not a function", name_span, "time")
                .hint("to multiply, write `t * (...)`")
        } else if name == "der" {
            Diagnostic::new(
                "`der` is allowed only at the start of an equation",
                name_span,
                "here",
            )
            .hint("write `der(x) = ...;` as an item of its own")
        } else if KEYWORDS.contains(&name) {
            Diagnostic::new(
                format!("reserved word `{name}` is not a function"),
                name_span,
                "reserved word",
            )
            .hint("see docs/language.md for the built-in functions")
        } else {
            let d = Diagnostic::new(
                format!("unknown function `{name}`"),
                name_span,
                "unknown function",
            );
            let suggestion = self
                .function_suggestions
                .borrow_mut()
                .get_or_insert_with(|| Suggestions::new(Func::ALL.map(Func::name)))
                .suggest(name);
            match suggestion {
                Some(s) => d.hint(format!("did you mean `{s}`?")),
                None => d.hint(
                    "the functions are sin cos tan asin acos atan sinh cosh tanh exp ln sqrt abs \
                     sign atan2 pow min max",
                ),
            }
        };
        diags.push(d);
        None
    }
}
