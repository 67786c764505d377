//! `mass [v1, ..., vn] = [m11, ..., m1n; ...; mn1, ..., mnn];`: the derivatives of the
//! listed states solve `M der(v) = rhs`, `rhs` being the right-hand sides of their
//! `der` items. Checked here: the names are distinct states in at most one matrix,
//! the matrix is n x n, and no entry depends on an algebraic unknown (directly or
//! through a `let`), so that `J_Omega`, `beta` and `alpha` stay what docs/method.md
//! derives through `M^-1`. In a model over sets a matrix is one per element of the set
//! its listed states are families over (a vector state lists its components in order),
//! its entries resolved in that element's context.

use super::Checker;
use super::expr::{Binding, Env, Ty, Via, Where};
use crate::ast::{Expr, Ident, Item, Span};
use crate::diag::Diagnostic;
use crate::model::{MassDef, Model, RExpr};
use crate::{StateId, VarRef};
use std::collections::HashMap;

impl Checker<'_> {
    /// The mass matrices, in the order written (the ones in error reported and left out).
    pub(super) fn mass_matrices(&mut self) -> Vec<MassDef> {
        let mut listed = Listed::default();
        let mut out = Vec::new();
        for item in &self.m.items {
            let Item::Mass { states, rows, span } = item else {
                continue;
            };
            let before = self.diags.len();
            let mut env = Env {
                ctx: None,
                binders: Vec::new(),
                place: Where::Equation,
                owner: "the mass matrix".to_string(),
            };
            let mut ids = Vec::new();
            for (k, (name, elem)) in states.iter().enumerate() {
                let Some((first, dim, over)) = self.mass_state(name, elem.as_ref()) else {
                    continue;
                };
                if k == 0 {
                    env.ctx = over;
                } else if over != env.ctx {
                    self.diags.push(
                        Diagnostic::new(
                            format!("`{}` is not over the set of the first state listed", name.name),
                            name.span,
                            "another set",
                        )
                        .hint("the states of one mass matrix are families over one set (one matrix per element), or all scalars"),
                    );
                    continue;
                }
                if let (Some(set), Some(e)) = (over, elem) {
                    env.binders.push(Binding {
                        name: e.name.clone(),
                        set,
                        via: Via::Here,
                    });
                }
                for c in 0..dim {
                    if listed.first_time(first + c, name, &mut self.diags) {
                        ids.push(StateId::new(first + c));
                    }
                }
            }
            // In a version-1 model the shape is checked against the names written and the
            // entries' own errors are reported, whatever the names.
            let listed_ok = self.diags.len() == before;
            let n = if listed_ok { ids.len() } else { states.len() };
            let shape_ok =
                (listed_ok || self.version1) && check_shape(n, rows, *span, &mut self.diags);
            if !(listed_ok && shape_ok) {
                if self.version1 {
                    for e in rows.iter().flatten() {
                        self.expr(e, &env);
                    }
                }
                continue;
            }
            let mut entries = Vec::new();
            let mut entry_spans = Vec::new();
            for e in rows.iter().flatten() {
                let Some(v) = self.expr(e, &env) else {
                    continue;
                };
                if v.dim() != 1 || v.ty == Ty::Bool {
                    self.diags.push(
                        Diagnostic::new(
                            format!("a mass matrix entry is {}", v.ty.words()),
                            e.span,
                            "not a number",
                        )
                        .hint("each entry is one number: a vector state lists its components as rows and columns of their own"),
                    );
                    continue;
                }
                entries.extend(v.comps);
                entry_spans.push(e.span);
            }
            if self.diags.len() == before {
                out.push(MassDef {
                    states: ids,
                    entries,
                    entry_spans,
                    span: *span,
                });
            }
        }
        out
    }

    /// The first component, dimension and set of the state `name` listed in a mass
    /// matrix at the element `elem` (which a family must name and a scalar must not).
    fn mass_state(
        &mut self,
        name: &Ident,
        elem: Option<&Ident>,
    ) -> Option<(usize, usize, Option<crate::SetId>)> {
        let text = name.name.as_str();
        let entry = self.state_named(name)?;
        match (entry.over, elem) {
            (Some(set), None) => {
                let s = &self.sets[set.index()];
                self.diags.push(
                    Diagnostic::new(
                        format!("`{text}` is a family over `{}`", s.name),
                        name.span,
                        "which element?",
                    )
                    .hint(format!(
                        "name the element: `mass [{text}[{}]] = ...;`",
                        s.elem
                    )),
                );
                None
            }
            (None, Some(e)) => {
                self.diags.push(
                    Diagnostic::new(
                        format!("`{text}[{}]`: `{text}` is not a family", e.name),
                        e.span,
                        "no element",
                    )
                    .hint(format!("write `{text}` alone")),
                );
                None
            }
            _ => Some((entry.first, entry.dim as usize, entry.over)),
        }
    }
}

/// The states listed so far in the mass matrices of a model, with where.
#[derive(Default)]
pub(super) struct Listed(HashMap<usize, Span>);

impl Listed {
    /// Records state `index` listed at `name`; reports it listed before.
    pub(super) fn first_time(
        &mut self,
        index: usize,
        name: &Ident,
        diags: &mut Vec<Diagnostic>,
    ) -> bool {
        if let Some(&first) = self.0.get(&index) {
            diags.push(
                Diagnostic::new(
                    format!("state `{}` is listed twice in mass matrices", name.name),
                    name.span,
                    "listed again",
                )
                .related(first, "first listed here")
                .hint("each state's derivative is multiplied by one row of one mass matrix"),
            );
            return false;
        }
        self.0.insert(index, name.span);
        true
    }
}

/// Reports a matrix that is not `n x n`.
pub(super) fn check_shape(
    n: usize,
    rows: &[Vec<Expr>],
    at: Span,
    diags: &mut Vec<Diagnostic>,
) -> bool {
    let mut ok = true;
    if rows.len() != n {
        diags.push(
            Diagnostic::new(
                format!(
                    "the mass matrix over {n} state{} has {} row{}",
                    plural(n),
                    rows.len(),
                    plural(rows.len())
                ),
                at,
                "not square",
            )
            .hint("write one row per listed state, rows separated by `;`"),
        );
        ok = false;
    }
    for row in rows {
        if let (Some(first), Some(last)) = (row.first(), row.last())
            && row.len() != n
        {
            let (first, last) = (first.span, last.span);
            diags.push(
                Diagnostic::new(
                    format!(
                        "a row of the mass matrix over {n} state{} has {} entr{}",
                        plural(n),
                        row.len(),
                        if row.len() == 1 { "y" } else { "ies" }
                    ),
                    Span::new(first.start, last.end),
                    "this row",
                )
                .hint("write one entry per listed state in every row, separated by `,`"),
            );
            ok = false;
        }
    }
    ok
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// Reports every mass matrix entry of a checked model that reads an algebraic unknown,
/// directly or through a `let` (the model's lets each use only earlier ones).
pub(crate) fn algebraic_entries(model: &Model, diags: &mut Vec<Diagnostic>) {
    if model.mass.is_empty() {
        return;
    }
    let mut let_alg: Vec<bool> = Vec::with_capacity(model.lets.len());
    for l in &model.lets {
        let found = first_alg(&l.expr, model, &let_alg).is_some();
        let_alg.push(found);
    }
    for m in &model.mass {
        for (e, &at) in m.entries.iter().zip(&m.entry_spans) {
            if let Some(what) = first_alg(e, model, &let_alg) {
                diags.push(
                    Diagnostic::new(
                        format!("a mass matrix entry depends on {what}"),
                        at,
                        "depends on an algebraic unknown",
                    )
                    .hint(
                        "the mass matrix may depend on the parameters, the states and t: \
                         move the terms with algebraic unknowns to the right-hand side of \
                         the `der` items",
                    ),
                );
            }
        }
    }
}

/// The first algebraic unknown `e` reads, in words: directly, or through a `let` that
/// reads one (`let_alg`, by the model's let order).
fn first_alg(e: &RExpr, model: &Model, let_alg: &[bool]) -> Option<String> {
    let mut found = None;
    e.visit(&mut |x| {
        if found.is_some() {
            return;
        }
        match x {
            RExpr::Var(VarRef::Alg(k)) => {
                let name = model.algs.get(k.index()).map_or("?", |a| a.name.as_str());
                found = Some(format!("the algebraic unknown `{}`", family_name(name)));
            }
            RExpr::Let(l) if let_alg.get(l.index()).copied().unwrap_or(false) => {
                let name = model.lets.get(l.index()).map_or("?", |d| d.name.as_str());
                found = Some(format!(
                    "the `let` `{}`, which reads an algebraic unknown",
                    family_name(name)
                ));
            }
            _ => {}
        }
    });
    found
}

/// `pin` for the component `pin.x`.
fn family_name(name: &str) -> &str {
    name.split('.').next().unwrap_or(name)
}

/// The elimination of `M x = b` in the written order without row exchanges, on the
/// values of `M` (row-major, `n x n`): the first pivot (0-based) that is not finite or
/// zero to round-off (at most `1e-14` of the largest entry), or `None`. This is the
/// elimination the compiler writes symbolically (a symmetric positive definite matrix,
/// as the mass matrices of mechanics are, has positive pivots in any order).
pub(crate) fn zero_pivot(mut a: Vec<f64>, n: usize) -> Option<usize> {
    if a.len() != n * n {
        return None;
    }
    let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    for k in 0..n {
        let p = a[k * n + k];
        if !p.is_finite() || p.abs() <= 1e-14 * scale {
            return Some(k);
        }
        for i in k + 1..n {
            let l = a[i * n + k] / p;
            if l != 0.0 {
                for j in k + 1..n {
                    a[i * n + j] -= l * a[k * n + j];
                }
            }
        }
    }
    None
}
