//! From the pest parse tree to the AST: expressions.
//!
//! Every level of the grammar that holds a single child (a version-1 expression has no
//! comparison, `and`, `or` or `if`) returns that child unchanged, so a version-1
//! expression gets exactly the tree (and spans) it always had.

use super::MAX_DEPTH;
use super::Rule;
use super::build::{Builder, error_expr, ident, significant, span};
use crate::ast::{BinOp, CmpOp, Expr, ExprKind, LogicOp, Span};
use crate::diag::Diagnostic;
use pest::iterators::Pair;

impl Builder {
    /// Builds an expression and returns it with its depth (a leaf has depth 1).
    pub(super) fn expr(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        match p.as_rule() {
            Rule::expr => match p.into_inner().next() {
                Some(inner) => self.expr(inner),
                None => self.broken(s),
            },
            Rule::arith | Rule::product => self.chain(p),
            Rule::disj | Rule::conj => self.logic(p),
            Rule::negation => self.negation(p),
            Rule::comparison => self.comparison(p),
            Rule::if_expr => self.if_expr(p),
            Rule::sum_expr => self.sum(p),
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
            _ => self.broken(s),
        }
    }

    fn broken(&mut self, s: Span) -> (Expr, usize) {
        self.missing(s);
        error_expr(s)
    }

    /// `a op b op c ...`, folded to the left.
    fn chain(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut it = p.into_inner();
        let Some(first) = it.next() else {
            return self.broken(s);
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

    /// `a or b or c`, `a and b`: folded to the left.
    fn logic(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let op = if p.as_rule() == Rule::disj {
            LogicOp::Or
        } else {
            LogicOp::And
        };
        let mut it = p
            .into_inner()
            .filter(|c| !matches!(c.as_rule(), Rule::kw_and | Rule::kw_or));
        let Some(first) = it.next() else {
            return self.broken(s);
        };
        let (mut acc, mut depth) = self.expr(first);
        for rhs in it {
            let (rhs, rdepth) = self.expr(rhs);
            depth = depth.max(rdepth) + 1;
            let span = acc.span.join(rhs.span);
            acc = Expr {
                kind: ExprKind::Logic(op, Box::new(acc), Box::new(rhs)),
                span,
            };
            if depth > MAX_DEPTH {
                return self.too_deep(s);
            }
        }
        (acc, depth)
    }

    /// `not a` (a `not` in front of a negation, or a comparison).
    fn negation(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut not_at = None;
        let mut operand = None;
        for c in p.into_inner() {
            if c.as_rule() == Rule::kw_not {
                not_at = Some(span(&c).start);
            } else {
                operand = Some(self.expr(c));
            }
        }
        let Some((e, depth)) = operand else {
            return self.broken(s);
        };
        match not_at {
            None => (e, depth),
            Some(start) => {
                if depth + 1 > MAX_DEPTH {
                    return self.too_deep(s);
                }
                let span = Span::new(start, e.span.end);
                let kind = ExprKind::Not(Box::new(e));
                (Expr { kind, span }, depth + 1)
            }
        }
    }

    /// `a` or `a op b` for a comparison operator.
    fn comparison(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut it = p.into_inner();
        let Some(first) = it.next() else {
            return self.broken(s);
        };
        let (lhs, ldepth) = self.expr(first);
        let (Some(op), Some(rhs)) = (it.next(), it.next()) else {
            return (lhs, ldepth);
        };
        let op = match op.as_str() {
            "==" => CmpOp::Eq,
            "!=" => CmpOp::Ne,
            "<=" => CmpOp::Le,
            ">=" => CmpOp::Ge,
            "<" => CmpOp::Lt,
            _ => CmpOp::Gt,
        };
        let (rhs, rdepth) = self.expr(rhs);
        let depth = ldepth.max(rdepth) + 1;
        if depth > MAX_DEPTH {
            return self.too_deep(s);
        }
        let span = lhs.span.join(rhs.span);
        let kind = ExprKind::Compare(op, Box::new(lhs), Box::new(rhs));
        (Expr { kind, span }, depth)
    }

    /// `if c then a else b`.
    fn if_expr(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let parts: Vec<(Expr, usize)> = significant(p).map(|c| self.expr(c)).collect();
        let [c, a, b]: [(Expr, usize); 3] = match parts.try_into() {
            Ok(x) => x,
            Err(_) => return self.broken(s),
        };
        let depth = c.1.max(a.1).max(b.1) + 1;
        if depth > MAX_DEPTH {
            return self.too_deep(s);
        }
        let kind = ExprKind::If(Box::new(c.0), Box::new(a.0), Box::new(b.0));
        (Expr { kind, span: s }, depth)
    }

    /// `sum(k in K where c) body` or `sum(k in K) body`.
    fn sum(&mut self, p: Pair<'_, Rule>) -> (Expr, usize) {
        let s = span(&p);
        let mut idents = Vec::new();
        let mut exprs = Vec::new();
        let mut saw_where = false;
        for c in p.into_inner() {
            match c.as_rule() {
                Rule::ident => idents.push(ident(c)),
                Rule::kw_where => saw_where = true,
                Rule::kw_sum | Rule::kw_in | Rule::lparen | Rule::rparen => {}
                _ => exprs.push(self.expr(c)),
            }
        }
        let (cond, body) = match (saw_where, exprs.len()) {
            (true, 2) => {
                let body = exprs.pop();
                (exprs.pop(), body)
            }
            (false, 1) => (None, exprs.pop()),
            _ => (None, None),
        };
        let (Ok([elem, set]), Some((body, bdepth))) =
            (<[crate::ast::Ident; 2]>::try_from(idents), body)
        else {
            return self.broken(s);
        };
        let cdepth = cond.as_ref().map_or(0, |c| c.1);
        let depth = bdepth.max(cdepth) + 1;
        if depth > MAX_DEPTH {
            return self.too_deep(s);
        }
        let span = s.join(body.span);
        let kind = ExprKind::Sum {
            elem,
            set,
            cond: cond.map(|c| Box::new(c.0)),
            body: Box::new(body),
        };
        (Expr { kind, span }, depth)
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
            return self.broken(s);
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

    /// `atom`, `atom[i].x ...` or either `^ unary`, where `atom` may be `( expr )`.
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
                Rule::index | Rule::field => {
                    let Some((e, depth)) = base.take() else {
                        return self.broken(s);
                    };
                    base = Some(self.postfix(e, depth, c));
                }
                _ if after_pow => exponent = Some(self.expr(c)),
                _ => base = Some(self.expr(c)),
            }
        }
        let Some((base, bdepth)) = base else {
            return self.broken(s);
        };
        if bdepth > MAX_DEPTH {
            return self.too_deep(s);
        }
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

    /// `e[i]` or `e.x` applied to `e`.
    fn postfix(&mut self, e: Expr, depth: usize, op: Pair<'_, Rule>) -> (Expr, usize) {
        let end = span(&op).end;
        let span = Span::new(e.span.start, end);
        match op.as_rule() {
            Rule::index => {
                let Some(i) = significant(op).next() else {
                    return self.broken(span);
                };
                let (i, idepth) = self.expr(i);
                let kind = ExprKind::Index(Box::new(e), Box::new(i));
                (Expr { kind, span }, depth.max(idepth) + 1)
            }
            _ => {
                let Some(f) = significant(op).next() else {
                    return self.broken(span);
                };
                let kind = ExprKind::Field(Box::new(e), ident(f));
                (Expr { kind, span }, depth + 1)
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
            None => self.broken(s),
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
