//! The equations evaluated at the initial point as written, operation by operation.
//!
//! Later stages simplify the equations, and a simplification may remove an operation
//! whose value is not a number: `0 * ln(x - 1)` becomes `0`, `x / x` becomes `1`. They
//! are exact wherever every operation has a finite value (the contract of the symbolic
//! core), so the checker makes sure that this holds at the one point the compiler knows,
//! the initial point (parameters at their defaults, states at their initial values,
//! algebraic variables at their guesses, `t = 0`): every operation of every `let`, `der`
//! and `constraint` must have a finite value there. An expression of numbers only has
//! the same value everywhere, so one that is not finite (`0/0`, `1/0`) is an error of
//! the model, not only of its start.

use crate::Func;
use crate::ast::{BinOp, Decl, Expr, ExprKind, Item, ModelAst, Span};
use crate::diag::Diagnostic;

/// A finite value, and whether it is made of numbers only.
#[derive(Clone, Copy)]
struct Val {
    v: f64,
    constant: bool,
}

/// What a declared name is, with its position among the declarations of its kind.
#[derive(Clone, Copy)]
pub(super) enum Named {
    Param(usize),
    State(usize),
    Alg(usize),
    Let(usize),
}

/// The values of the declared names at the initial point (`None`: unknown or not
/// finite, and already reported).
pub(super) struct Start<'a> {
    pub params: &'a [Option<f64>],
    pub states: Vec<Option<f64>>,
    pub algs: Vec<Option<f64>>,
}

/// A `let`'s value at the initial point, computed on first use.
#[derive(Clone, Copy)]
enum LetValue {
    Todo,
    Done(Option<Val>),
}

/// Reports every operation of the model's equations whose value at the initial point is
/// not finite, with its operands all finite (the first operation that fails, not those
/// that inherit its value). `names` tells what a name declares (every name is resolved
/// already); `lets` are the `let` declarations, each evaluated once, before its first
/// use.
pub(super) fn check(
    m: &ModelAst,
    names: &dyn Fn(&str) -> Option<Named>,
    start: Start<'_>,
    lets: &[&Decl],
    diags: &mut Vec<Diagnostic>,
) {
    let mut w = Walk {
        names,
        start,
        decls: lets,
        lets: vec![LetValue::Todo; lets.len()],
        diags,
    };
    for i in 0..lets.len() {
        w.let_value(i);
    }
    for item in &m.items {
        match item {
            Item::Der { rhs, .. } => {
                w.eval(rhs);
            }
            Item::Mass { states, rows, span } => {
                let values: Option<Vec<f64>> = rows
                    .iter()
                    .flatten()
                    .map(|e| w.eval(e).map(|v| v.v))
                    .collect();
                if let Some(k) = values.and_then(|a| super::mass::zero_pivot(a, states.len())) {
                    w.diags
                        .push(singular_mass(states[k].0.name.as_str(), k, *span));
                }
            }
            Item::Constraint { lhs, rhs, span, .. } => {
                if let (Some(l), Some(r)) = (w.eval(lhs), w.eval(rhs)) {
                    let residual = l.v - r.v;
                    if !residual.is_finite() {
                        w.report(
                            *span,
                            l.constant && r.constant,
                            format!(
                                "the constraint's residual `left - right` overflows ({residual})"
                            ),
                            residual,
                        );
                    }
                }
            }
            _ => {}
        }
    }
}

struct Walk<'n, 'p, 'l, 'd> {
    names: &'n dyn Fn(&str) -> Option<Named>,
    start: Start<'p>,
    decls: &'l [&'l Decl],
    /// Values of the lets, by declaration.
    lets: Vec<LetValue>,
    diags: &'d mut Vec<Diagnostic>,
}

impl Walk<'_, '_, '_, '_> {
    /// The value of `let` declaration `i`, evaluated on first use (the checker has
    /// ruled out cycles).
    fn let_value(&mut self, i: usize) -> Option<Val> {
        if let LetValue::Done(v) = *self.lets.get(i)? {
            return v;
        }
        let decls = self.decls;
        let v = self.eval(&decls[i].value);
        self.lets[i] = LetValue::Done(v);
        v
    }

    fn eval(&mut self, e: &Expr) -> Option<Val> {
        let variable = |v: Option<f64>| v.map(|v| Val { v, constant: false });
        match &e.kind {
            ExprKind::Num(v) => Some(Val {
                v: *v,
                constant: true,
            }),
            ExprKind::Time => variable(Some(0.0)),
            ExprKind::Name(n) => {
                // Resolved by the checker already; an unknown name is not reached.
                match (self.names)(n.as_str())? {
                    Named::Param(i) => variable(*self.start.params.get(i)?),
                    Named::State(i) => variable(*self.start.states.get(i)?),
                    Named::Alg(i) => variable(*self.start.algs.get(i)?),
                    Named::Let(i) => self.let_value(i),
                }
            }
            ExprKind::Neg(a) => {
                let a = self.eval(a)?;
                Some(Val { v: -a.v, ..a })
            }
            ExprKind::Binary(op, a, b) => {
                let (a, b) = (self.eval(a), self.eval(b));
                let (a, b) = (a?, b?);
                let v = match op {
                    BinOp::Add => a.v + b.v,
                    BinOp::Sub => a.v - b.v,
                    BinOp::Mul => a.v * b.v,
                    BinOp::Div => a.v / b.v,
                    BinOp::Pow => a.v.powf(b.v),
                };
                let constant = a.constant && b.constant;
                if v.is_finite() {
                    return Some(Val { v, constant });
                }
                let what = match op {
                    BinOp::Div if a.v == 0.0 && b.v == 0.0 => "zero divided by zero".to_string(),
                    BinOp::Div if b.v == 0.0 => "division by zero".to_string(),
                    BinOp::Pow => power_failure(a.v, b.v),
                    _ => format!("the value overflows ({v})"),
                };
                self.report(e.span, constant, what, v)
            }
            ExprKind::Call(f, args) => {
                let func = Func::from_name(&f.name)?;
                let vals: Vec<Option<Val>> = args.iter().map(|a| self.eval(a)).collect();
                let vals: Vec<Val> = vals.into_iter().collect::<Option<_>>()?;
                let constant = vals.iter().all(|a| a.constant);
                let x = vals.first()?.v;
                let v = match vals.get(1) {
                    Some(y) => func.apply2(x, y.v),
                    None => func.apply1(x),
                };
                if v.is_finite() {
                    return Some(Val { v, constant });
                }
                let name = func.name();
                let what = match func {
                    Func::Ln if x == 0.0 => "`ln` of zero".to_string(),
                    Func::Ln => format!("`ln` of a negative number ({x})"),
                    Func::Sqrt => format!("`sqrt` of a negative number ({x})"),
                    Func::Asin | Func::Acos => format!("`{name}` of {x}, outside [-1, 1]"),
                    Func::Pow => power_failure(x, vals.get(1).map_or(f64::NAN, |y| y.v)),
                    _ => format!("`{name}` overflows ({v})"),
                };
                self.report(e.span, constant, what, v)
            }
            // The forms of version 2 (element access, sums, vectors, `if`): the checker
            // walks only models without them.
            _ => None,
        }
    }

    /// Records that the operation at `span` has the value `v`, not finite; `None`, so
    /// that the operations using it are not reported again.
    fn report(&mut self, span: Span, constant: bool, what: String, v: f64) -> Option<Val> {
        let (message, hint) = if constant {
            (
                format!("{what}: an expression of numbers only that is {v}"),
                "an expression of numbers only has the same value everywhere, and this one is \
                 not a number: correct it"
                    .to_string(),
            )
        } else {
            (
                format!("{what} at the initial point"),
                "every operation must have a finite value at the initial point (parameter \
                 defaults, initial values, t = 0), also one that the compiler would simplify \
                 away, like `0 * ln(x - 1)`: change the start or the expression"
                    .to_string(),
            )
        };
        self.diags
            .push(Diagnostic::new(message, span, format!("this is {v}")).hint(hint));
        None
    }
}

/// The mass matrix's elimination in the written order meets pivot `k` (of `state`).
fn singular_mass(state: &str, k: usize, at: Span) -> Diagnostic {
    Diagnostic::new(
        format!(
            "the mass matrix is singular at the initial point: eliminated in the order \
             written, its pivot {} (the row of `der({state})`) is zero",
            k + 1
        ),
        at,
        "singular here",
    )
    .hint(
        "the matrix must be invertible wherever the model runs; it is eliminated without \
         row exchanges, so list the states in an order whose leading blocks are invertible \
         (any order serves a symmetric positive definite matrix)",
    )
}

/// Why `a ^ b` is not finite.
fn power_failure(a: f64, b: f64) -> String {
    if a == 0.0 && b < 0.0 {
        format!("zero to a negative power ({b}), a division by zero")
    } else if a < 0.0 && b.fract() != 0.0 {
        format!("a negative number ({a}) to a non-integer power ({b})")
    } else {
        format!("the power overflows ({a}^{b})")
    }
}

#[cfg(test)]
mod tests {
    use crate::check_source;
    use crate::diag::line_col;

    /// Every error as (message, label, line, column).
    fn errors(src: &str) -> Vec<(String, String, (usize, usize))> {
        match check_source(src) {
            Ok(m) => panic!("expected errors for {src}, got {m:?}"),
            Err(d) => d
                .iter()
                .map(|x| {
                    assert!(x.hint.is_some(), "{x:?}");
                    (x.message.clone(), x.label.clone(), line_col(src, x.span))
                })
                .collect(),
        }
    }

    fn one(src: &str) -> (String, String, (usize, usize)) {
        let mut e = errors(src);
        assert_eq!(e.len(), 1, "{e:#?}");
        e.remove(0)
    }

    fn der(rhs: &str) -> String {
        format!("model M {{\n  param k = 1;\n  state x = 0;\n  der(x) = {rhs};\n}}")
    }

    /// `0/0`, `0 * (1/0)`, `(1/0) - (1/0)` were folded to 0 inside equations: an
    /// expression of numbers only that is not a number is an error, at the operation
    /// that fails.
    #[test]
    fn constants_that_are_not_finite_are_errors() {
        let (message, label, at) = one(&der("0/0 + x"));
        assert_eq!(
            message,
            "zero divided by zero: an expression of numbers only that is NaN"
        );
        assert_eq!((label.as_str(), at), ("this is NaN", (4, 12)));
        let (message, _, at) = one(&der("x + 0 * (1/0)"));
        assert_eq!(
            message,
            "division by zero: an expression of numbers only that is inf"
        );
        assert_eq!(at, (4, 20), "the parenthesised `(1/0)`");
        // Each `1/0` is its own error; their difference is not reported again.
        let e = errors(&der("(1/0) - (1/0)"));
        let places: Vec<_> = e.iter().map(|x| x.2).collect();
        assert_eq!(places, [(4, 12), (4, 20)], "{e:#?}");
        let (message, _, _) = one(&der("(x + 1) * 1e200 * 1e200"));
        assert_eq!(message, "the value overflows (inf) at the initial point");
        let (message, _, _) = one(&der("1e200 * 1e200 * x"));
        assert_eq!(
            message,
            "the value overflows (inf): an expression of numbers only that is inf"
        );
    }

    /// `0 * ln(x - 1)` is simplified to 0, which is exact only where `ln(x - 1)` is
    /// finite: at the initial point x = 0 it is not, and that is reported.
    #[test]
    fn a_domain_error_at_the_initial_point_is_reported_where_it_is_written() {
        let (message, label, at) = one(&der("0 * ln(x - 1)"));
        assert_eq!(
            message,
            "`ln` of a negative number (-1) at the initial point"
        );
        assert_eq!((label.as_str(), at), ("this is NaN", (4, 16)));
        // Where the start is inside the domain, the model is accepted.
        let ok = der("0 * ln(x - 1)").replace("state x = 0", "state x = 2");
        assert!(check_source(&ok).is_ok());
        for (rhs, message, col) in [
            (
                "sqrt(x - k)",
                "`sqrt` of a negative number (-1) at the initial point",
                12,
            ),
            (
                "asin(x + 2*k)",
                "`asin` of 2, outside [-1, 1] at the initial point",
                12,
            ),
            ("k / x", "division by zero at the initial point", 12),
            ("x / x", "zero divided by zero at the initial point", 12),
            ("ln(x)", "`ln` of zero at the initial point", 12),
            (
                "(x - k)^0.5",
                "a negative number (-1) to a non-integer power (0.5) at the initial point",
                12,
            ),
            (
                "pow(x, -1)",
                "zero to a negative power (-1), a division by zero at the initial point",
                12,
            ),
            (
                "1 + exp(1000 * k)",
                "`exp` overflows (inf) at the initial point",
                16,
            ),
            ("x - t / x", "zero divided by zero at the initial point", 16),
            (
                "x - (t + 1) / x",
                "division by zero at the initial point",
                16,
            ),
        ] {
            let (m, _, at) = one(&der(rhs));
            assert_eq!((m.as_str(), at), (message, (4, col)), "{rhs}");
        }
    }

    #[test]
    fn lets_and_constraints_are_checked_and_a_failed_let_is_reported_once() {
        let src = "model M {\n  state x = 0;\n  alg z = 0;\n  let r = sqrt(x - 1);\n  \
                   let q = 2 * r;\n  der(x) = z + q;\n  constraint c: x = ln(t);\n}";
        let e = errors(src);
        assert_eq!(
            e,
            [
                (
                    "`sqrt` of a negative number (-1) at the initial point".to_string(),
                    "this is NaN".to_string(),
                    (4, 11)
                ),
                (
                    "`ln` of zero at the initial point".to_string(),
                    "this is -inf".to_string(),
                    (7, 21)
                ),
            ]
        );
        // Lets are evaluated in the order they depend on each other, not as written.
        let src =
            "model M {\n  state x = 1;\n  let b = 1 / a;\n  let a = x - 1;\n  der(x) = -b;\n}";
        let (m, _, at) = one(src);
        assert_eq!(
            (m.as_str(), at),
            ("division by zero at the initial point", (3, 11))
        );
    }
}
