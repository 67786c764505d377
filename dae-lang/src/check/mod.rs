//! The checker: from a parsed model ([`ModelAst`]) to a checked [`Model`].
//!
//! It resolves names over the whole model, evaluates parameter defaults, orders the
//! `let` definitions and checks the structure. It goes on after an error so that one
//! run reports every error of a model; an expression in error is dropped (`None`)
//! rather than reported again where it is used.

mod domain;
mod eval;
mod family;
mod lets;
pub(crate) mod mass;
mod names;
mod resolve;

use crate::ast::{Binder, Decl, Expr, File, Item, ModelAst, Span};
use crate::diag::Diagnostic;
use crate::model::{
    ConstraintDef, DerDef, Family, LetDef, MassDef, Model, ParamDef, RExpr, VarDef,
};
use resolve::{Ctx, Entry, Kind, Scope};
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

/// The declarations of one model, by kind, in source order (first declarations only).
#[derive(Default)]
struct Decls<'a> {
    params: Vec<&'a Decl>,
    states: Vec<&'a Decl>,
    algs: Vec<&'a Decl>,
    lets: Vec<&'a Decl>,
}

/// Checks one model: a model that uses anything of version 2 (families, vectors,
/// construction-time forms) goes to the family checker; any other model is checked
/// exactly as in version 1.
pub(crate) fn check_model(m: &ModelAst) -> Result<Model, Vec<Diagnostic>> {
    check_model_with(m, true)
}

/// Checks one model; `at_start`: with the values of the equations at the initial point
/// (see `domain`). Without, only for tests of the syntax and the printer, whose
/// expressions need not be defined at any particular point. A model that uses anything
/// of version 2 goes to the family checker (with its own checks at the default sizes).
pub(crate) fn check_model_with(m: &ModelAst, at_start: bool) -> Result<Model, Vec<Diagnostic>> {
    if family::uses_version_2(m) {
        return family::check_model(m);
    }
    let mut diags = Vec::new();
    if names::is_reserved(&m.name.name) {
        let (message, hint) = names::reserved_message(&m.name.name);
        diags.push(Diagnostic::new(message, m.name.span, "reserved word").hint(hint));
    }
    let (scope, decls) = declare(m, &mut diags);

    // Parameters, in order: each default may use the ones before it.
    let mut values: Vec<Option<f64>> = Vec::with_capacity(decls.params.len());
    let mut param_exprs: Vec<Option<RExpr>> = Vec::with_capacity(decls.params.len());
    for (i, d) in decls.params.iter().enumerate() {
        let ctx = Ctx::ParamDefault {
            index: i,
            name: &d.name.name,
        };
        let resolved = scope.resolve(&d.value, ctx, &mut diags);
        let value = resolved.as_ref().and_then(|e| eval::eval(e, &values));
        param_exprs.push(resolved);
        let value = value.filter(|v| {
            let finite = v.is_finite();
            if !finite {
                diags.push(not_finite(
                    &format!("the default of parameter `{}`", d.name.name),
                    *v,
                    d,
                ));
            }
            finite
        });
        values.push(value);
    }

    let init = |list: &[&Decl], diags: &mut Vec<Diagnostic>| -> Vec<Option<RExpr>> {
        list.iter()
            .map(|d| {
                let e = scope.resolve(&d.value, Ctx::Init { name: &d.name.name }, diags)?;
                match eval::eval(&e, &values) {
                    Some(v) if !v.is_finite() => {
                        let what = format!("the initial value of `{}`", d.name.name);
                        diags.push(not_finite(&what, v, d));
                        None
                    }
                    _ => Some(e),
                }
            })
            .collect()
    };
    let state_inits = init(&decls.states, &mut diags);
    let alg_inits = init(&decls.algs, &mut diags);

    let let_exprs: Vec<Option<RExpr>> = decls
        .lets
        .iter()
        .map(|d| scope.resolve(&d.value, Ctx::Equation, &mut diags))
        .collect();
    let let_order = order_lets(&decls.lets, &let_exprs, &mut diags);

    let ders = ders(m, &scope, &decls.states, &mut diags);
    let mass = mass::mass_matrices(m, &scope, &mut diags);
    let constraints = constraints(m, &scope, &mut diags);
    if decls.algs.len() != constraints.len() {
        diags.push(count_mismatch(m, decls.algs.len(), constraints.len()));
    }

    if diags.is_empty() && at_start {
        // Every operation of the equations at the initial point (see `domain`).
        let at_start = |inits: &[Option<RExpr>]| -> Vec<Option<f64>> {
            inits
                .iter()
                .map(|e| e.as_ref().and_then(|e| eval::eval(e, &values)))
                .collect()
        };
        let start = domain::Start {
            params: &values,
            states: at_start(&state_inits),
            algs: at_start(&alg_inits),
        };
        domain::check(m, &scope, start, &decls.lets, &let_order, &mut diags);
    }
    if !diags.is_empty() {
        diags.sort_by_key(|d| d.span.start);
        return Err(diags);
    }
    // No error was reported, so every `Option` below is `Some`: each `None` comes with a
    // diagnostic. `flatten` keeps this free of panicking unwraps all the same.
    let var_defs = |list: &[&Decl], inits: Vec<Option<RExpr>>| -> Vec<VarDef> {
        list.iter()
            .zip(inits)
            .filter_map(|(d, e)| {
                Some(VarDef {
                    name: d.name.name.clone(),
                    init: e?,
                    span: d.span,
                    family: Family::SCALAR,
                })
            })
            .collect()
    };
    let mut new_index = vec![0; decls.lets.len()];
    for (new, &old) in let_order.iter().enumerate() {
        new_index[old] = new;
    }
    let mut let_exprs = let_exprs;
    let lets_out = let_order
        .iter()
        .filter_map(|&i| {
            let mut expr = let_exprs[i].take()?;
            lets::renumber(&mut expr, &new_index);
            Some(LetDef {
                name: decls.lets[i].name.name.clone(),
                expr,
                span: decls.lets[i].span,
                family: Family::SCALAR,
            })
        })
        .collect();
    let mut ders_out: Vec<DerDef> = ders.into_iter().flatten().collect();
    let mut constraints_out: Vec<ConstraintDef> = constraints.into_iter().flatten().collect();
    ders_out
        .iter_mut()
        .for_each(|d| lets::renumber(&mut d.expr, &new_index));
    constraints_out
        .iter_mut()
        .for_each(|c| lets::renumber(&mut c.residual, &new_index));
    let mut mass_out: Vec<MassDef> = mass.into_iter().flatten().collect();
    mass_out
        .iter_mut()
        .flat_map(|m| &mut m.entries)
        .for_each(|e| lets::renumber(e, &new_index));
    let model = Model {
        name: m.name.name.clone(),
        span: m.name.span,
        params: decls
            .params
            .iter()
            .zip(values)
            .zip(param_exprs)
            .filter_map(|((d, v), e)| {
                Some(ParamDef {
                    name: d.name.name.clone(),
                    default: v?,
                    span: d.span,
                    value: e?,
                    family: Family::SCALAR,
                })
            })
            .collect(),
        states: var_defs(&decls.states, state_inits),
        algs: var_defs(&decls.algs, alg_inits),
        lets: lets_out,
        ders: ders_out,
        mass: mass_out,
        constraints: constraints_out,
        sizes: Vec::new(),
        sets: Vec::new(),
        maps: Vec::new(),
        inputs: Vec::new(),
    };
    mass::algebraic_entries(&model, &mut diags);
    if diags.is_empty() {
        Ok(model)
    } else {
        Err(diags)
    }
}

/// Registers every declared name; reports reserved words and names declared twice.
fn declare<'a>(m: &'a ModelAst, diags: &mut Vec<Diagnostic>) -> (Scope<'a>, Decls<'a>) {
    let mut scope = Scope {
        names: HashMap::new(),
        ordered: Vec::new(),
        duplicated: HashSet::new(),
        model_name: &m.name.name,
        suggestions: Default::default(),
        function_suggestions: Default::default(),
    };
    let mut decls = Decls::default();
    for item in &m.items {
        let (kind, list): (Kind, Vec<&Decl>) = match item {
            Item::Param(ds, _) => (Kind::Param, ds.iter().collect()),
            Item::State(ds, _) => (Kind::State, ds.iter().collect()),
            Item::Alg(ds, _) => (Kind::Alg, ds.iter().collect()),
            Item::Let(d, _) => (Kind::Let, vec![d]),
            // Version-2 items never reach this checker (see `check_model`).
            _ => continue,
        };
        for d in list {
            let name = d.name.name.as_str();
            if names::is_reserved(name) {
                let (message, hint) = names::reserved_message(name);
                diags.push(Diagnostic::new(message, d.name.span, "reserved word").hint(hint));
            }
            if let Some(first) = scope.names.get(name) {
                diags.push(names::declared_twice(
                    name,
                    d.name.span,
                    kind.words(),
                    first.span,
                    first.kind.words(),
                ));
                scope.duplicated.insert(name);
                continue;
            }
            let list = match kind {
                Kind::Param => &mut decls.params,
                Kind::State => &mut decls.states,
                Kind::Alg => &mut decls.algs,
                Kind::Let => &mut decls.lets,
            };
            scope.names.insert(
                name,
                Entry {
                    kind,
                    index: list.len(),
                    span: d.name.span,
                },
            );
            scope.ordered.push(name);
            list.push(d);
        }
    }
    (scope, decls)
}

fn not_finite(what: &str, v: f64, d: &Decl) -> Diagnostic {
    Diagnostic::new(format!("{what} is not finite"), d.value.span, format!("evaluates to {v}"))
        .hint("look for a division by zero, an overflow, or a function outside its domain (ln, sqrt, asin, acos)")
}

/// Orders the `let`s so that each follows those it uses; reports cycles.
fn order_lets(decls: &[&Decl], exprs: &[Option<RExpr>], diags: &mut Vec<Diagnostic>) -> Vec<usize> {
    let uses: Vec<Vec<usize>> = exprs
        .iter()
        .map(|e| {
            let mut out = Vec::new();
            if let Some(e) = e {
                lets::let_uses(e, &mut out);
            }
            out
        })
        .collect();
    let order = lets::order(&uses);
    for cycle in &order.cycles {
        diags.push(lets::cycle_error(cycle, decls));
    }
    order.order
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

/// The state `name` names (in `der(name)` or a `mass` item), or `None` with the error
/// reported (nothing more for a name declared twice, already reported).
fn state_named(
    scope: &Scope<'_>,
    name: &crate::ast::Ident,
    diags: &mut Vec<Diagnostic>,
) -> Option<resolve::Entry> {
    let (text, at) = (name.name.as_str(), name.span);
    match scope.names.get(text) {
        Some(e) if e.kind == Kind::State => Some(*e),
        Some(_) if scope.duplicated.contains(text) => None,
        Some(e) => {
            diags.push(der_of_non_state(text, at, e.kind.words(), e.span));
            None
        }
        None => {
            diags.push(if text == "t" {
                der_of_time(at)
            } else {
                scope.unknown_name(text, at)
            });
            None
        }
    }
}

/// The `der` equations, one per state (indexed like `states`).
fn ders(
    m: &ModelAst,
    scope: &Scope<'_>,
    states: &[&Decl],
    diags: &mut Vec<Diagnostic>,
) -> Vec<Option<DerDef>> {
    let mut out: Vec<Option<DerDef>> = vec![None; states.len()];
    let mut first_span: Vec<Option<Span>> = vec![None; states.len()];
    for item in &m.items {
        let Item::Der {
            target, rhs, span, ..
        } = item
        else {
            continue;
        };
        let expr = scope.resolve(rhs, Ctx::Equation, diags);
        let name = target.name.as_str();
        let Some(entry) = state_named(scope, target, diags) else {
            continue;
        };
        if let Some(first) = first_span[entry.index] {
            diags.push(
                Diagnostic::new(
                    format!("state `{name}` has two equations `der({name}) = ...`"),
                    *span,
                    "second equation",
                )
                .related(first, "first equation")
                .hint("keep one of them: each state has exactly one `der` equation"),
            );
            continue;
        }
        first_span[entry.index] = Some(*span);
        out[entry.index] = expr.map(|expr| DerDef { expr, span: *span });
    }
    for (i, d) in states.iter().enumerate() {
        if first_span[i].is_none() {
            let name = &d.name.name;
            diags.push(
                Diagnostic::new(format!("state `{name}` has no equation `der({name}) = ...`"), d.name.span, "declared here")
                    .hint(format!("add `der({name}) = ...;`, or declare `{name}` with `alg` if it has no derivative")),
            );
        }
    }
    out
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

/// The constraints in order, named ([`named_constraints`]); reports duplicate names,
/// a generated name equal to a written one included.
fn constraints(
    m: &ModelAst,
    scope: &Scope<'_>,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Option<ConstraintDef>> {
    let mut out = Vec::new();
    // name -> (span, written by the user)
    let mut seen: HashMap<String, (Span, bool)> = HashMap::new();
    for constraint in named_constraints(m) {
        let NamedConstraint {
            name: cname,
            name_span: cspan,
            written,
            lhs,
            rhs,
            span,
            ..
        } = constraint;
        if written && names::is_reserved(&cname) {
            let (message, hint) = names::reserved_message(&cname);
            diags.push(Diagnostic::new(message, cspan, "reserved word").hint(hint));
        }
        if let Some(&(first, first_written)) = seen.get(&cname) {
            let hint = if written && first_written {
                "rename one of them: constraint names are unique in a model".to_string()
            } else {
                format!(
                    "an unnamed constraint is named `c<k>` after its position k among the \
                     constraints, here `{cname}`: give it a name or rename the other one"
                )
            };
            let label = if written {
                "second use of the name"
            } else {
                "named automatically"
            };
            let first_label = if first_written {
                "first use of the name"
            } else {
                "named automatically"
            };
            diags.push(
                Diagnostic::new(format!("two constraints named `{cname}`"), cspan, label)
                    .related(first, first_label)
                    .hint(hint),
            );
        } else {
            seen.insert(cname.clone(), (cspan, written));
        }
        let l = scope.resolve(lhs, Ctx::Equation, diags);
        let r = scope.resolve(rhs, Ctx::Equation, diags);
        let residual = l
            .zip(r)
            .map(|(l, r)| RExpr::Binary(crate::ast::BinOp::Sub, Box::new(l), Box::new(r)));
        out.push(residual.map(|residual| ConstraintDef {
            name: cname,
            residual,
            span,
            over: None,
        }));
    }
    out
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

#[cfg(test)]
mod tests;
