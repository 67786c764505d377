//! `mass [v1, ..., vn] = [m11, ..., m1n; ...; mn1, ..., mnn];`: the derivatives of the
//! listed states solve `M der(v) = rhs`, `rhs` being the right-hand sides of their
//! `der` items. Checked here: the names are distinct states in at most one matrix,
//! the matrix is n x n, and no entry depends on an algebraic unknown (directly or
//! through a `let`), so that `J_Omega`, `beta` and `alpha` stay what docs/method.md
//! derives through `M^-1`. The family checker lists its states at an element and
//! shares the rest.

use super::resolve::{Ctx, Scope};
use super::state_named;
use crate::ast::{Expr, Ident, Item, ModelAst, Span};
use crate::diag::Diagnostic;
use crate::model::{MassDef, Model, RExpr};
use crate::{StateId, VarRef};
use std::collections::HashMap;

/// The mass matrices of a version-1 model, in the order written (`None` where one is
/// in error, already reported). That no entry reads an algebraic unknown is checked on
/// the built model ([`algebraic_entries`]).
pub(super) fn mass_matrices(
    m: &ModelAst,
    scope: &Scope<'_>,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Option<MassDef>> {
    let mut listed = Listed::default();
    let mut out = Vec::new();
    for item in &m.items {
        let Item::Mass { states, rows, span } = item else {
            continue;
        };
        let before = diags.len();
        let mut ids = Vec::with_capacity(states.len());
        for (s, _) in states {
            let Some(entry) = state_named(scope, s, diags) else {
                continue;
            };
            if listed.first_time(entry.index, s, diags) {
                ids.push(StateId::new(entry.index));
            }
        }
        let shape_ok = check_shape(states.len(), rows, *span, diags);
        let mut entries = Vec::new();
        let mut entry_spans = Vec::new();
        for e in rows.iter().flatten() {
            if let Some(r) = scope.resolve(e, Ctx::Equation, diags) {
                entries.push(r);
                entry_spans.push(e.span);
            }
        }
        out.push((shape_ok && diags.len() == before).then_some(MassDef {
            states: ids,
            entries,
            entry_spans,
            span: *span,
        }));
    }
    out
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
