//! From the pest parse tree to the AST.
//!
//! The grammar already guarantees the shape of every pair, so the functions here only
//! walk it; the few things the grammar cannot check (a literal too large for `f64`, an
//! expression nested too deeply) become diagnostics. All of them are collected.

use super::{MAX_DEPTH, Rule};
use crate::ast::{BinOp, Decl, Expr, ExprKind, File, Ident, Item, ModelAst, Span};
use crate::diag::Diagnostic;
use pest::iterators::Pair;

/// Collects the diagnostics found while building.
#[derive(Default)]
struct Builder {
    diags: Vec<Diagnostic>,
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

fn span(p: &Pair<'_, Rule>) -> Span {
    let s = p.as_span();
    Span::new(s.start(), s.end())
}

fn ident(p: Pair<'_, Rule>) -> Ident {
    Ident {
        name: p.as_str().to_string(),
        span: span(&p),
    }
}

/// The pairs of a node without its keywords and punctuation.
fn significant<'i>(p: Pair<'i, Rule>) -> impl Iterator<Item = Pair<'i, Rule>> {
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
                | Rule::lbrace
                | Rule::rbrace
                | Rule::lparen
                | Rule::rparen
                | Rule::comma
                | Rule::semi
                | Rule::colon
                | Rule::assign
        )
    })
}

/// A placeholder for an expression that could not be built; the diagnostic explaining
/// why has already been recorded, so the result is discarded.
fn error_expr(span: Span) -> (Expr, usize) {
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
                let mut it = parts.into_iter();
                let target = it.next().map(ident);
                let rhs = it.next().map(|e| self.expr(e).0);
                match (target, rhs) {
                    (Some(target), Some(rhs)) => Item::Der {
                        target,
                        rhs,
                        span: item_span,
                    },
                    _ => Item::Let(self.missing(item_span), item_span),
                }
            }
            _ => {
                // constraint_item: an optional name, then lhs and rhs.
                let name = match parts.first() {
                    Some(first) if first.as_rule() == Rule::ident => Some(ident(parts.remove(0))),
                    _ => None,
                };
                let mut it = parts.into_iter();
                let lhs = it.next().map(|e| self.expr(e).0);
                let rhs = it.next().map(|e| self.expr(e).0);
                match (lhs, rhs) {
                    (Some(lhs), Some(rhs)) => Item::Constraint {
                        name,
                        lhs,
                        rhs,
                        span: item_span,
                    },
                    _ => Item::Let(self.missing(item_span), item_span),
                }
            }
        }
    }

    /// Records that the parse tree lacked a part the grammar requires. It cannot happen
    /// with the grammar as written; it is reported instead of panicking all the same.
    fn missing(&mut self, at: Span) -> Decl {
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
            value: error_expr(at).0,
            span: at,
        }
    }

    fn decl(&mut self, p: Pair<'_, Rule>) -> Decl {
        let decl_span = span(&p);
        let mut it = significant(p);
        match (it.next(), it.next()) {
            (Some(name), Some(value)) => Decl {
                name: ident(name),
                value: self.expr(value).0,
                span: decl_span,
            },
            _ => self.missing(decl_span),
        }
    }

    /// Builds an expression and returns it with its depth (a leaf has depth 1).
    fn expr(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        match p.as_rule() {
            Rule::expr | Rule::product => self.chain(p),
            Rule::unary => self.unary(p),
            Rule::power => self.power(p),
            Rule::number => (self.number(&p), 1),
            Rule::name => {
                let text = p.as_str();
                let kind = if text == "t" {
                    ExprKind::Time
                } else {
                    ExprKind::Name(text.to_string())
                };
                (Expr { kind, span: s }, 1)
            }
            Rule::call => self.call(p),
            _ => {
                self.missing(s);
                error_expr(s)
            }
        }
    }

    /// `a op b op c ...`, folded to the left.
    fn chain(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut it = p.into_inner();
        let Some(first) = it.next() else {
            self.missing(s);
            return error_expr(s);
        };
        let (mut acc, mut depth) = self.expr(first);
        while let (Some(op), Some(rhs)) = (it.next(), it.next()) {
            let op = match op.as_str() {
                "+" => BinOp::Add,
                "-" => BinOp::Sub,
                "*" => BinOp::Mul,
                _ => BinOp::Div,
            };
            let (rhs, rdepth) = self.expr(rhs);
            depth = depth.max(rdepth) + 1;
            let span = acc.span.join(rhs.span);
            acc = Expr {
                kind: ExprKind::Binary(op, Box::new(acc), Box::new(rhs)),
                span,
            };
            if depth > MAX_DEPTH {
                return self.too_deep(s);
            }
        }
        (acc, depth)
    }

    /// `- - x`: the minus signs wrap the power expression, innermost last.
    fn unary(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut signs = Vec::new();
        let mut operand = None;
        for c in p.into_inner() {
            if c.as_rule() == Rule::neg {
                signs.push(span(&c).start);
            } else {
                operand = Some(self.expr(c));
            }
        }
        let Some((mut e, mut depth)) = operand else {
            self.missing(s);
            return error_expr(s);
        };
        if depth + signs.len() > MAX_DEPTH {
            return self.too_deep(s);
        }
        for start in signs.into_iter().rev() {
            let span = Span::new(start, e.span.end);
            e = Expr {
                kind: ExprKind::Neg(Box::new(e)),
                span,
            };
            depth += 1;
        }
        (e, depth)
    }

    /// `atom` or `atom ^ unary`, where `atom` may be `( expr )`.
    fn power(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut base: Option<(Expr, usize)> = None;
        let mut open = None;
        let mut exponent = None;
        let mut after_pow = false;
        for c in p.into_inner() {
            match c.as_rule() {
                Rule::lparen => open = Some(span(&c).start),
                Rule::rparen => {
                    // Parentheses widen the span of what they enclose.
                    if let (Some(start), Some((e, _))) = (open, base.as_mut()) {
                        e.span = Span::new(start, span(&c).end);
                    }
                }
                Rule::pow_op => after_pow = true,
                _ if after_pow => exponent = Some(self.expr(c)),
                _ => base = Some(self.expr(c)),
            }
        }
        let Some((base, bdepth)) = base else {
            self.missing(s);
            return error_expr(s);
        };
        match exponent {
            None => (base, bdepth),
            Some((exp, edepth)) => {
                let depth = bdepth.max(edepth) + 1;
                if depth > MAX_DEPTH {
                    return self.too_deep(s);
                }
                let span = base.span.join(exp.span);
                let kind = ExprKind::Binary(BinOp::Pow, Box::new(base), Box::new(exp));
                (Expr { kind, span }, depth)
            }
        }
    }

    fn call(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut func = None;
        let mut args = Vec::new();
        let mut depth = 1;
        for c in significant(p) {
            if c.as_rule() == Rule::ident {
                func = Some(ident(c));
            } else {
                let (arg, d) = self.expr(c);
                depth = depth.max(d + 1);
                args.push(arg);
            }
        }
        if depth > MAX_DEPTH {
            return self.too_deep(s);
        }
        match func {
            Some(f) => (
                Expr {
                    kind: ExprKind::Call(f, args),
                    span: s,
                },
                depth,
            ),
            None => {
                self.missing(s);
                error_expr(s)
            }
        }
    }

    fn number(&mut self, p: &Pair<'_, Rule>) -> Expr {
        let s = span(p);
        let value = p.as_str().parse::<f64>().unwrap_or(f64::INFINITY);
        if !value.is_finite() {
            self.diags.push(
                Diagnostic::new(
                    format!("number `{}` is too large", p.as_str()),
                    s,
                    "too large",
                )
                .hint("numbers must fit in a 64-bit float (at most about 1.8e308)"),
            );
        }
        Expr {
            kind: ExprKind::Num(value),
            span: s,
        }
    }

    fn too_deep(&mut self, s: Span) -> (Expr, usize) {
        // One report per expression: an enclosing expression that is also too deep
        // overlaps this span and is not reported again.
        if !self
            .diags
            .iter()
            .any(|d| d.span.start <= s.start && s.end <= d.span.end)
        {
            self.diags
                .retain(|d| !(s.start <= d.span.start && d.span.end <= s.end));
            self.diags.push(
                Diagnostic::new(
                    format!("expression too deep (more than {MAX_DEPTH} levels of operations)"),
                    s,
                    "this expression",
                )
                .hint("split it into several `let` definitions"),
            );
        }
        error_expr(s)
    }
}
