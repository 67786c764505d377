//! The checker: from a parsed model ([`ModelAst`]) to a checked [`Model`].
//!
//! One checker for every model; a model that uses nothing of version 2 is the case
//! without sets (its diagnostics worded as version 1 words them, and its start checked
//! operation by operation, `start.rs`). It runs in passes over one model: declare every
//! name (with its set, vector type and component ids; `decl.rs`), resolve the sizes of
//! the sets and the formulas of the maps, the parameter values and initial values
//! (construction-time expressions), the `let`s (lazily, so that a `let`'s vector type is
//! known where it is used, whatever the order), the `der` equations, the mass matrices
//! and the constraints; order the `let`s (`finish.rs`); and evaluate the construction at
//! the default sizes when nothing is given at construction, which reports a set without
//! elements, a map pointing outside its set, a particle in no link or a count mismatch
//! while the model is checked. Expressions are resolved by `expr.rs` (types and
//! vectors), `resolve.rs` (names, variables, `let`s) and `access.rs` (element access,
//! maps, sums). It goes on after an error so that one run reports every error of a
//! model; an expression in error is dropped (`None`) rather than reported again where
//! it is used.

mod access;
mod decl;
mod domain;
pub(crate) mod eval;
mod expr;
mod finish;
mod lets;
pub(crate) mod mass;
mod names;
mod resolve;
mod start;

use crate::ast::{Binder, Decl, Expr, ExprKind, File, Item, ModelAst, Span};
use crate::diag::Diagnostic;
use crate::maps::MapTable;
use crate::model::{Family, Model, RExpr, SetDef, SizeDef};
use crate::{MapId, SetId};
use std::collections::{HashMap, HashSet};

/// Checks every model of a file and that no two have the same name.
pub(crate) fn check_file(file: &File) -> Result<Vec<Model>, Vec<Diagnostic>> {
    let mut diags = Vec::new();
    let mut models = Vec::new();
    let mut seen: HashMap<&str, Span> = HashMap::new();
    for m in &file.models {
        if let Some(&first) = seen.get(m.name.name.as_str()) {
            diags.push(
                Diagnostic::new(
                    format!("two models named `{}` in one file", m.name.name),
                    m.name.span,
                    "second model with this name",
                )
                .related(first, "first model with this name")
                .hint("rename one of the models"),
            );
        } else {
            seen.insert(&m.name.name, m.name.span);
        }
        match check_model(m) {
            Ok(model) => models.push(model),
            Err(mut d) => diags.append(&mut d),
        }
    }
    if diags.is_empty() {
        Ok(models)
    } else {
        diags.sort_by_key(|d| d.span.start);
        Err(diags)
    }
}

/// Checks one model.
pub(crate) fn check_model(m: &ModelAst) -> Result<Model, Vec<Diagnostic>> {
    check_model_at(m, true)
}

/// Checks one model; `at_start`: with the values of the equations at the initial point
/// (see `domain`). Without, only for tests of the syntax and the printer, whose
/// expressions need not be defined at any particular point.
#[cfg(test)]
pub(crate) fn check_model_with(m: &ModelAst, at_start: bool) -> Result<Model, Vec<Diagnostic>> {
    check_model_at(m, at_start)
}

fn not_finite(what: &str, v: f64, d: &Decl) -> Diagnostic {
    Diagnostic::new(format!("{what} is not finite"), d.value.span, format!("evaluates to {v}"))
        .hint("look for a division by zero, an overflow, or a function outside its domain (ln, sqrt, asin, acos)")
}

/// `der(name)` of a name declared as something other than a state.
fn der_of_non_state(name: &str, at: Span, what: &str, declared: Span) -> Diagnostic {
    Diagnostic::new(
        format!("`der({name})`: `{name}` is {what}, not a state"),
        at,
        what,
    )
    .related(declared, format!("`{name}` is declared here"))
    .hint(format!(
        "only states have a derivative: declare `{name}` with `state`"
    ))
}

/// `der(t)`.
fn der_of_time(at: Span) -> Diagnostic {
    Diagnostic::new("`der(t)`: `t` is time, not a state", at, "time")
        .hint("`der` takes a state declared with `state`")
}

/// A constraint item with its name: the written one, or `c<k>`, `k` being its position
/// among all the constraints of the model (1-based): the third constraint is `c3`
/// whether or not the first two have names.
struct NamedConstraint<'a> {
    name: String,
    /// Where the name is written (the whole constraint for a generated name).
    name_span: Span,
    written: bool,
    binder: Option<&'a Binder>,
    lhs: &'a Expr,
    rhs: &'a Expr,
    /// The whole constraint.
    span: Span,
}

/// The constraints of a model in order, named.
fn named_constraints(m: &ModelAst) -> impl Iterator<Item = NamedConstraint<'_>> {
    let items = m.items.iter().filter_map(|item| match item {
        Item::Constraint {
            name,
            binder,
            lhs,
            rhs,
            span,
        } => Some((name, binder, lhs, rhs, *span)),
        _ => None,
    });
    items
        .enumerate()
        .map(|(i, (name, binder, lhs, rhs, span))| {
            let (name, name_span, written) = match name {
                Some(n) => (n.name.clone(), n.span, true),
                None => (format!("c{}", i + 1), span, false),
            };
            NamedConstraint {
                name,
                name_span,
                written,
                binder: binder.as_ref(),
                lhs,
                rhs,
                span,
            }
        })
}

fn count_mismatch(m: &ModelAst, algs: usize, constraints: usize) -> Diagnostic {
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let a = plural(algs, "algebraic variable", "algebraic variables");
    let c = plural(constraints, "constraint", "constraints");
    Diagnostic::new(
        format!("model `{}` has {a} but {c}", m.name.name),
        m.name.span,
        format!("{a}, {c}"),
    )
    .hint(
        "each constraint determines one algebraic variable: declare as many `alg` as `constraint`",
    )
}

/// Whether a model uses anything of version 2.
pub(crate) fn uses_version_2(m: &ModelAst) -> bool {
    m.items.iter().any(|item| match item {
        Item::Size { .. } | Item::Set { .. } | Item::Map { .. } | Item::Input(..) => true,
        Item::Param(ds, _) | Item::State(ds, _) | Item::Alg(ds, _) => ds.iter().any(decl_v2),
        Item::Let(d, _) => decl_v2(d),
        Item::Mass { states, rows, .. } => {
            states.iter().any(|(_, elem)| elem.is_some()) || rows.iter().flatten().any(expr_v2)
        }
        Item::Der { elem, rhs, .. } => elem.is_some() || expr_v2(rhs),
        Item::Constraint {
            binder, lhs, rhs, ..
        } => binder.is_some() || expr_v2(lhs) || expr_v2(rhs),
    })
}

fn decl_v2(d: &Decl) -> bool {
    d.binder.is_some() || d.ty.is_some() || expr_v2(&d.value)
}

/// Functions of version 2 (vectors and integer formulas), resolved by the checker.
const FAMILY_FUNCTIONS: [&str; 7] = ["vec2", "vec3", "dot", "norm", "cross", "div", "mod"];

fn expr_v2(e: &Expr) -> bool {
    e.kind.is_version_2()
        || match &e.kind {
            ExprKind::Neg(a) => expr_v2(a),
            ExprKind::Binary(_, a, b) => expr_v2(a) || expr_v2(b),
            ExprKind::Call(f, args) => {
                FAMILY_FUNCTIONS.contains(&f.name.as_str()) || args.iter().any(expr_v2)
            }
            _ => false,
        }
}

/// What a declared name is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Size,
    Set,
    Map,
    Param,
    State,
    Alg,
    Let,
    Input,
}

impl Kind {
    pub(super) fn words(self) -> &'static str {
        match self {
            Kind::Size => "a size",
            Kind::Set => "a set",
            Kind::Map => "a map",
            Kind::Param => "a parameter",
            Kind::State => "a state",
            Kind::Alg => "an algebraic variable",
            Kind::Let => "a `let` definition",
            Kind::Input => "an input",
        }
    }
}

/// A declared name.
#[derive(Clone, Copy, Debug)]
struct Entry {
    pub kind: Kind,
    /// Position among the declarations of its kind (source order).
    pub decl: usize,
    /// Id of its first component (params, states, algs, inputs), of the size, set or
    /// named map; for a `let`, its declaration number (components are numbered later).
    pub first: usize,
    /// The set of a family.
    pub over: Option<SetId>,
    /// Vector dimension (1 for a number).
    pub dim: u8,
    /// Where the name was declared.
    pub span: Span,
}

/// One component of a declaration (`x.y` of `state x[p in P]: vec3`).
struct Component<'a> {
    pub decl: &'a Decl,
    pub name: String,
    pub family: Family,
    /// Time derivatives given (inputs only).
    pub derivatives: u8,
}

/// A `let` declaration, resolved on first use.
enum LetState {
    Todo,
    InProgress,
    /// The components (provisional let ids inside), or `None` after an error.
    Done(Option<Vec<RExpr>>),
}

/// A named map: its declaration and id.
struct NamedMap<'a> {
    pub name: &'a str,
    pub formula: Option<&'a Expr>,
    pub id: MapId,
}

/// The state of checking one model.
struct Checker<'a> {
    pub m: &'a ModelAst,
    pub diags: Vec<Diagnostic>,
    pub names: HashMap<&'a str, Entry>,
    /// Declared names in source order (for suggestions).
    pub ordered: Vec<&'a str>,
    /// "Did you mean" among `ordered`, built on the first unknown name (with the number
    /// of names it was built from).
    pub suggestions: Option<(usize, crate::check::names::Suggestions<'a>)>,
    /// Names declared more than once (already reported).
    pub duplicated: HashSet<&'a str>,
    pub sizes: Vec<SizeDef>,
    pub sets: Vec<SetDef>,
    /// Set size formulas (resolved later).
    pub set_exprs: Vec<Option<&'a Expr>>,
    pub maps: MapTable,
    pub named_maps: Vec<NamedMap<'a>>,
    pub params: Vec<Component<'a>>,
    /// Declaration number of each parameter component (for "declared after it").
    pub param_decl: Vec<usize>,
    pub states: Vec<Component<'a>>,
    pub algs: Vec<Component<'a>>,
    pub inputs: Vec<Component<'a>>,
    /// `let` declarations in source order, their sets, and their resolution.
    pub lets: Vec<&'a Decl>,
    pub let_sets: Vec<Option<SetId>>,
    pub let_state: Vec<LetState>,
    /// The `let` declarations being resolved, outermost first (a cycle's path).
    pub let_stack: Vec<usize>,
    /// The model uses nothing of version 2: its diagnostics are worded as in version 1
    /// and its start is checked operation by operation (`start.rs`).
    pub version1: bool,
    /// Check the equations at the initial point (a model without sets only).
    pub at_start: bool,
}

/// Provisional `let` ids: declaration `d`, component `c` is `3 d + c` until the `let`s
/// are ordered and numbered.
const LET_STRIDE: usize = 3;

/// Checks one model; `at_start`: with the values of the equations of a version-1 model
/// at its initial point (see `start.rs`; off only for tests of the syntax and the
/// printer, whose expressions need not be defined at any particular point).
fn check_model_at(m: &ModelAst, at_start: bool) -> Result<Model, Vec<Diagnostic>> {
    let mut c = Checker {
        m,
        diags: Vec::new(),
        names: HashMap::new(),
        ordered: Vec::new(),
        suggestions: None,
        duplicated: HashSet::new(),
        sizes: Vec::new(),
        sets: Vec::new(),
        set_exprs: Vec::new(),
        maps: MapTable::default(),
        named_maps: Vec::new(),
        params: Vec::new(),
        param_decl: Vec::new(),
        states: Vec::new(),
        algs: Vec::new(),
        inputs: Vec::new(),
        lets: Vec::new(),
        let_sets: Vec::new(),
        let_state: Vec::new(),
        let_stack: Vec::new(),
        version1: !uses_version_2(m),
        at_start,
    };
    c.declare();
    c.finish()
}

#[cfg(test)]
mod tests;
