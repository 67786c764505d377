//! `mass [v1, ..., vn] = [m11, ..., m1n; ...; mn1, ..., mnn];`: the derivatives of the
//! listed states solve `M der(v) = rhs`, `rhs` being the right-hand sides of their
//! `der` items. Checked here: the names are distinct states in at most one matrix,
//! the matrix is n x n, and no entry depends on an algebraic unknown (directly or
//! through a `let`), so that `J_Omega`, `beta` and `alpha` stay what docs/method.md
//! derives through `M^-1`.

use super::resolve::{Ctx, Kind, Scope};
use super::state_named;
use crate::StateId;
use crate::ast::{Expr, Item, ModelAst, Span};
use crate::diag::Diagnostic;
use crate::model::{MassDef, RExpr};

/// The mass matrices of a model, in the order written (`None` where one is in error,
/// already reported). `let_uses_alg[j]`: whether `let` number `j` (by declaration)
/// depends on an algebraic unknown.
pub(super) fn mass_matrices(
    m: &ModelAst,
    scope: &Scope<'_>,
    let_uses_alg: &[bool],
    diags: &mut Vec<Diagnostic>,
) -> Vec<Option<MassDef>> {
    // The matrix that lists each state, with the span of its name there.
    let mut owner: Vec<Option<Span>> = Vec::new();
    let mut out = Vec::new();
    for item in &m.items {
        let Item::Mass { states, rows, span } = item else {
            continue;
        };
        let before = diags.len();
        let mut ids = Vec::with_capacity(states.len());
        for s in states {
            let name = s.name.as_str();
            let Some(entry) = state_named(scope, s, diags) else {
                continue;
            };
            if owner.len() <= entry.index {
                owner.resize(entry.index + 1, None);
            }
            if let Some(first) = owner[entry.index] {
                diags.push(
                    Diagnostic::new(
                        format!("state `{name}` is listed twice in mass matrices"),
                        s.span,
                        "listed again",
                    )
                    .related(first, "first listed here")
                    .hint("each state's derivative is multiplied by one row of one mass matrix"),
                );
                continue;
            }
            owner[entry.index] = Some(s.span);
            ids.push(StateId::new(entry.index));
        }
        let n = states.len();
        let shape_ok = check_shape(n, rows, *span, diags);
        let mut entries = Vec::with_capacity(n * n);
        for e in rows.iter().flatten() {
            let Some(r) = scope.resolve(e, Ctx::Equation, diags) else {
                continue;
            };
            if let Some(what) = alg_use(&r, scope, let_uses_alg) {
                diags.push(
                    Diagnostic::new(
                        format!("a mass matrix entry depends on {what}"),
                        e.span,
                        "depends on an algebraic unknown",
                    )
                    .hint(
                        "the mass matrix may depend on the parameters, the states and t: \
                         move the terms with algebraic unknowns to the right-hand side of \
                         the `der` items",
                    ),
                );
                continue;
            }
            entries.push(r);
        }
        if shape_ok && diags.len() == before {
            out.push(Some(MassDef {
                states: ids,
                entries,
                span: *span,
            }));
        } else {
            out.push(None);
        }
    }
    out
}

/// Reports a matrix that is not `n x n`.
fn check_shape(n: usize, rows: &[Vec<Expr>], at: Span, diags: &mut Vec<Diagnostic>) -> bool {
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

/// The first algebraic unknown `e` reads, directly or through a `let`, in words.
fn alg_use(e: &RExpr, scope: &Scope<'_>, let_uses_alg: &[bool]) -> Option<String> {
    let mut found = None;
    e.visit(&mut |x| {
        if found.is_some() {
            return;
        }
        match x {
            RExpr::Var(crate::VarRef::Alg(k)) => {
                found = Some(format!(
                    "the algebraic unknown `{}`",
                    alg_name(scope, k.index())
                ));
            }
            RExpr::Let(l) if let_uses_alg.get(l.index()).copied().unwrap_or(false) => {
                found = Some(format!(
                    "the `let` `{}`, which reads an algebraic unknown",
                    let_name(scope, l.index())
                ));
            }
            _ => {}
        }
    });
    found
}

fn alg_name(scope: &Scope<'_>, index: usize) -> String {
    name_of(scope, Kind::Alg, index)
}

fn let_name(scope: &Scope<'_>, index: usize) -> String {
    name_of(scope, Kind::Let, index)
}

fn name_of(scope: &Scope<'_>, kind: Kind, index: usize) -> String {
    scope
        .ordered
        .iter()
        .find(|n| {
            scope
                .names
                .get(**n)
                .is_some_and(|e| e.kind == kind && e.index == index)
        })
        .map_or_else(|| "?".to_string(), |n| n.to_string())
}

/// Whether each `let` (by declaration) reads an algebraic unknown, directly or through
/// earlier lets; `order` lists the lets so that each comes after those it reads.
pub(super) fn lets_using_algs(exprs: &[Option<RExpr>], order: &[usize]) -> Vec<bool> {
    let mut uses = vec![false; exprs.len()];
    for &i in order {
        let mut found = false;
        if let Some(e) = &exprs[i] {
            e.visit(&mut |x| match x {
                RExpr::Var(crate::VarRef::Alg(_)) => found = true,
                RExpr::Let(l) => found |= uses.get(l.index()).copied().unwrap_or(false),
                _ => {}
            });
        }
        uses[i] = found;
    }
    uses
}

/// The elimination of `M x = b` in the written order without row exchanges, on the
/// values of `M` (row-major, `n x n`): the first pivot (0-based) that is not finite or
/// zero to round-off (at most `1e-14` of the largest entry), or `None`. This is the
/// elimination the compiler writes symbolically (a symmetric positive definite matrix,
/// as the mass matrices of mechanics are, has positive pivots in any order).
pub(super) fn zero_pivot(mut a: Vec<f64>, n: usize) -> Option<usize> {
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
