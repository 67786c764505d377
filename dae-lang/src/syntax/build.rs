//! From the pest parse tree to the AST: models and items (expressions are in
//! `build_expr.rs`).
//!
//! The grammar already guarantees the shape of every pair, so the functions here only
//! walk it; the few things the grammar cannot check (a literal too large for `f64`, an
//! expression nested too deeply) become diagnostics. All of them are collected.

use super::Rule;
use crate::ast::{Binder, Decl, Expr, ExprKind, File, Ident, InputDecl, Item, ModelAst, Span};
use crate::diag::Diagnostic;
use pest::iterators::Pair;

/// Collects the diagnostics found while building.
#[derive(Default)]
pub(super) struct Builder {
    pub(super) diags: Vec<Diagnostic>,
}

pub(super) fn file(pair: Pair<'_, Rule>) -> Result<File, Vec<Diagnostic>> {
    let mut b = Builder::default();
    let models = pair
        .into_inner()
        .filter(|p| p.as_rule() == Rule::model)
        .map(|p| b.model(p))
        .collect();
    if b.diags.is_empty() {
        Ok(File { models })
    } else {
        Err(b.diags)
    }
}

pub(super) fn span(p: &Pair<'_, Rule>) -> Span {
    let s = p.as_span();
    Span::new(s.start(), s.end())
}

pub(super) fn ident(p: Pair<'_, Rule>) -> Ident {
    Ident {
        name: p.as_str().to_string(),
        span: span(&p),
    }
}

/// The pairs of a node without its keywords and punctuation.
pub(super) fn significant<'i>(p: Pair<'i, Rule>) -> impl Iterator<Item = Pair<'i, Rule>> {
    p.into_inner().filter(|c| {
        !matches!(
            c.as_rule(),
            Rule::kw_model
                | Rule::kw_param
                | Rule::kw_state
                | Rule::kw_alg
                | Rule::kw_let
                | Rule::kw_der
                | Rule::kw_constraint
                | Rule::kw_mass
                | Rule::kw_size
                | Rule::kw_set
                | Rule::kw_map
                | Rule::kw_input
                | Rule::kw_in
                | Rule::kw_with
                | Rule::kw_derivatives
                | Rule::kw_derivative
                | Rule::kw_sum
                | Rule::kw_where
                | Rule::kw_if
                | Rule::kw_then
                | Rule::kw_else
                | Rule::lbrace
                | Rule::rbrace
                | Rule::lparen
                | Rule::rparen
                | Rule::lbracket
                | Rule::rbracket
                | Rule::comma
                | Rule::semi
                | Rule::colon
                | Rule::assign
                | Rule::arrow
                | Rule::dot
        )
    })
}

/// A placeholder for an expression that could not be built; the diagnostic explaining
/// why has already been recorded, so the result is discarded.
pub(super) fn error_expr(span: Span) -> (Expr, usize) {
    (
        Expr {
            kind: ExprKind::Num(0.0),
            span,
        },
        1,
    )
}

impl Builder {
    fn model(&mut self, p: Pair<'_, Rule>) -> ModelAst {
        let model_span = span(&p);
        let mut name = None;
        let mut items = Vec::new();
        for c in significant(p) {
            match c.as_rule() {
                Rule::ident => name = Some(ident(c)),
                _ => items.push(self.item(c)),
            }
        }
        let name = name.unwrap_or(Ident {
            name: String::new(),
            span: model_span,
        });
        ModelAst {
            name,
            items,
            span: model_span,
        }
    }

    fn item(&mut self, p: Pair<'_, Rule>) -> Item {
        let item_span = span(&p);
        let rule = p.as_rule();
        let mut parts: Vec<Pair<'_, Rule>> = significant(p).collect();
        match rule {
            Rule::param_item | Rule::state_item | Rule::alg_item => {
                let decls = parts.into_iter().map(|d| self.decl(d)).collect();
                match rule {
                    Rule::param_item => Item::Param(decls, item_span),
                    Rule::state_item => Item::State(decls, item_span),
                    _ => Item::Alg(decls, item_span),
                }
            }
            Rule::let_item => {
                let decl = match parts.pop() {
                    Some(d) => self.decl(d),
                    None => self.missing(item_span),
                };
                Item::Let(decl, item_span)
            }
            Rule::der_item => {
                let mut it = parts.into_iter().peekable();
                let target = it.next().map(ident);
                let elem = match it.peek() {
                    Some(e) if e.as_rule() == Rule::der_elem => {
                        it.next().and_then(|e| significant(e).next()).map(ident)
                    }
                    _ => None,
                };
                let rhs = it.next().map(|e| self.expr(e).0);
                match (target, rhs) {
                    (Some(target), Some(rhs)) => Item::Der {
                        target,
                        elem,
                        rhs,
                        span: item_span,
                    },
                    _ => Item::Let(self.missing(item_span), item_span),
                }
            }
            Rule::constraint_item => {
                // An optional name (with an optional binder), then lhs and rhs.
                let name = match parts.first() {
                    Some(first) if first.as_rule() == Rule::ident => Some(ident(parts.remove(0))),
                    _ => None,
                };
                let binder = match parts.first() {
                    Some(first) if first.as_rule() == Rule::binder => Some(binder(parts.remove(0))),
                    _ => None,
                };
                let mut it = parts.into_iter();
                let lhs = it.next().map(|e| self.expr(e).0);
                let rhs = it.next().map(|e| self.expr(e).0);
                match (lhs, rhs) {
                    (Some(lhs), Some(rhs)) => Item::Constraint {
                        name,
                        binder,
                        lhs,
                        rhs,
                        span: item_span,
                    },
                    _ => Item::Let(self.missing(item_span), item_span),
                }
            }
            Rule::mass_item => {
                let mut states = Vec::new();
                let mut rows = Vec::new();
                for part in parts {
                    match part.as_rule() {
                        Rule::mass_state => {
                            let mut it = significant(part);
                            let name = it.next().map(ident);
                            let elem = it.next().and_then(|e| significant(e).next()).map(ident);
                            if let Some(name) = name {
                                states.push((name, elem));
                            }
                        }
                        _ => rows.push(significant(part).map(|e| self.expr(e).0).collect()),
                    }
                }
                Item::Mass {
                    states,
                    rows,
                    span: item_span,
                }
            }
            Rule::size_item => {
                let mut it = parts.into_iter();
                match (it.next(), it.next()) {
                    (Some(name), Some(value)) => Item::Size {
                        name: ident(name),
                        value: self.expr(value).0,
                        span: item_span,
                    },
                    _ => Item::Let(self.missing(item_span), item_span),
                }
            }
            Rule::set_item => {
                let mut it = parts.into_iter();
                match it.next() {
                    Some(name) => Item::Set {
                        name: ident(name),
                        size: it.next().map(|e| self.expr(e).0),
                        span: item_span,
                    },
                    None => Item::Let(self.missing(item_span), item_span),
                }
            }
            Rule::map_item => {
                let mut it = parts.into_iter();
                match (it.next(), it.next(), it.next()) {
                    (Some(name), Some(b), Some(codomain)) => Item::Map {
                        name: ident(name),
                        binder: binder(b),
                        codomain: ident(codomain),
                        formula: it.next().map(|e| self.expr(e).0),
                        span: item_span,
                    },
                    _ => Item::Let(self.missing(item_span), item_span),
                }
            }
            Rule::input_item => {
                let decls = parts.into_iter().map(|d| self.input_decl(d)).collect();
                Item::Input(decls, item_span)
            }
            _ => Item::Let(self.missing(item_span), item_span),
        }
    }

    /// Records that the parse tree lacked a part the grammar requires. It cannot happen
    /// with the grammar as written; it is reported instead of panicking all the same.
    pub(super) fn missing(&mut self, at: Span) -> Decl {
        self.diags.push(
            Diagnostic::new("internal error: incomplete parse tree", at, "here")
                .hint("please report this model as a bug of the `.dae` parser"),
        );
        let name = Ident {
            name: String::new(),
            span: at,
        };
        Decl {
            name,
            binder: None,
            ty: None,
            value: error_expr(at).0,
            span: at,
        }
    }

    fn decl(&mut self, p: Pair<'_, Rule>) -> Decl {
        let decl_span = span(&p);
        let mut name = None;
        let mut binder_ = None;
        let mut ty = None;
        let mut value = None;
        for c in significant(p) {
            match c.as_rule() {
                Rule::ident => name = Some(ident(c)),
                Rule::binder => binder_ = Some(binder(c)),
                Rule::type_ann => ty = significant(c).next().map(ident),
                _ => value = Some(self.expr(c).0),
            }
        }
        match (name, value) {
            (Some(name), Some(value)) => Decl {
                name,
                binder: binder_,
                ty,
                value,
                span: decl_span,
            },
            _ => self.missing(decl_span),
        }
    }

    fn input_decl(&mut self, p: Pair<'_, Rule>) -> InputDecl {
        let decl_span = span(&p);
        let mut name = None;
        let mut binder_ = None;
        let mut ty = None;
        let mut value = None;
        let mut derivatives = None;
        for c in significant(p) {
            match c.as_rule() {
                Rule::ident => name = Some(ident(c)),
                Rule::binder => binder_ = Some(binder(c)),
                Rule::type_ann => ty = significant(c).next().map(ident),
                Rule::with_clause => derivatives = Some(self.with_clause(c)),
                _ => value = Some(self.expr(c).0),
            }
        }
        let decl = match (name, value) {
            (Some(name), Some(value)) => Decl {
                name,
                binder: binder_,
                ty,
                value,
                span: decl_span,
            },
            _ => self.missing(decl_span),
        };
        InputDecl { decl, derivatives }
    }

    /// `with K derivatives`: K (too large a K is reported) and the clause's span.
    fn with_clause(&mut self, p: Pair<'_, Rule>) -> (u32, Span) {
        let s = span(&p);
        let text = significant(p)
            .find(|c| c.as_rule() == Rule::integer)
            .map(|c| c.as_str().to_string())
            .unwrap_or_default();
        match text.parse::<u32>() {
            Ok(k) => (k, s),
            Err(_) => {
                self.diags.push(
                    Diagnostic::new(
                        format!("`{text}` derivatives is too many"),
                        s,
                        "too large",
                    )
                    .hint("an input gives at most a few time derivatives (the index needs at most 8)"),
                );
                (0, s)
            }
        }
    }
}

/// `[e in S]` or `[S]`.
fn binder(p: Pair<'_, Rule>) -> Binder {
    let s = span(&p);
    let ids: Vec<Ident> = significant(p).map(ident).collect();
    match ids.as_slice() {
        [elem, set] => Binder {
            elem: Some(elem.clone()),
            set: set.clone(),
            span: s,
        },
        [set] => Binder {
            elem: None,
            set: set.clone(),
            span: s,
        },
        // The grammar allows nothing else; an empty set name is reported by the checker.
        _ => Binder {
            elem: None,
            set: Ident {
                name: String::new(),
                span: s,
            },
            span: s,
        },
    }
}
