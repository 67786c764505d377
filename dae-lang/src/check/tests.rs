//! Checker tests: what a valid model becomes, and one test per class of error (message
//! and place), plus a test that all errors of a model are reported together.

use crate::ast::BinOp;
use crate::diag::line_col;
use crate::model::{Model, RExpr};
use crate::{AlgId, Func, LetId, ParamId, StateId, VarRef};
use crate::{check_source, parse};

fn model(src: &str) -> Model {
    match check_source(src) {
        Ok(mut ms) => ms.remove(0),
        Err(d) => panic!("check failed for {src}: {d:#?}"),
    }
}

/// Every error as (message, line, column).
fn errors(src: &str) -> Vec<(String, (usize, usize))> {
    match check_source(src) {
        Ok(m) => panic!("expected errors for {src}, got {m:?}"),
        Err(d) => {
            for x in &d {
                assert!(x.hint.is_some(), "every error has a hint: {x:?}");
                assert!(!x.label.is_empty(), "every error has a label: {x:?}");
            }
            d.iter()
                .map(|x| (x.message.clone(), line_col(src, x.span)))
                .collect()
        }
    }
}

/// The only error of `src`.
fn error(src: &str) -> (String, (usize, usize)) {
    let mut e = errors(src);
    assert_eq!(e.len(), 1, "expected exactly one error: {e:#?}");
    e.remove(0)
}

fn bin(op: BinOp, a: RExpr, b: RExpr) -> RExpr {
    RExpr::Binary(op, Box::new(a), Box::new(b))
}

fn param(i: usize) -> RExpr {
    RExpr::Var(VarRef::Param(ParamId::new(i)))
}

fn state(i: usize) -> RExpr {
    RExpr::Var(VarRef::State(StateId::new(i)))
}

fn alg(i: usize) -> RExpr {
    RExpr::Var(VarRef::Alg(AlgId::new(i)))
}

fn let_(i: usize) -> RExpr {
    RExpr::Let(LetId::new(i))
}

fn time() -> RExpr {
    RExpr::Var(VarRef::Time)
}

#[test]
fn names_resolve_over_the_whole_model() {
    let m = model(
        "model M {
            der(x) = v;             // uses names declared below
            der(v) = -k * x + z + t;
            param k = 2;
            state x = 1, v = 0;
            alg z = 0;
            constraint x + e = 1;
            let e = v * 2;
        }",
    );
    assert_eq!(m.name, "M");
    assert_eq!(m.ders[0].expr, state(1));
    let rhs = bin(
        BinOp::Add,
        bin(
            BinOp::Add,
            bin(BinOp::Mul, RExpr::Neg(Box::new(param(0))), state(0)),
            alg(0),
        ),
        time(),
    );
    assert_eq!(m.ders[1].expr, rhs);
    // The residual is lhs - rhs.
    let residual = bin(
        BinOp::Sub,
        bin(BinOp::Add, state(0), let_(0)),
        RExpr::Num(1.0),
    );
    assert_eq!(m.constraints[0].residual, residual);
    assert_eq!(m.lets[0].expr, bin(BinOp::Mul, state(1), RExpr::Num(2.0)));
}

#[test]
fn ders_are_indexed_like_states_whatever_their_order() {
    let m = model("model M { state a = 0, b = 0, c = 0; der(c) = 3; der(a) = 1; der(b) = 2; }");
    let rhs: Vec<&RExpr> = m.ders.iter().map(|d| &d.expr).collect();
    assert_eq!(rhs, [&RExpr::Num(1.0), &RExpr::Num(2.0), &RExpr::Num(3.0)]);
}

#[test]
fn params_evaluate_from_numbers_and_earlier_params() {
    let m = model(
        "model M {
            param a = 2, b = a^3 - 1;
            param c = sqrt(b + 2) * -1, d = atan2(0, -1), e = max(a, b) / min(a, b), f = 2^-1;
        }",
    );
    let values: Vec<(&str, f64)> = m
        .params
        .iter()
        .map(|p| (p.name.as_str(), p.default))
        .collect();
    assert_eq!(
        values,
        [
            ("a", 2.0),
            ("b", 7.0),
            ("c", -3.0),
            ("d", std::f64::consts::PI),
            ("e", 3.5),
            ("f", 0.5)
        ]
    );
}

#[test]
fn initial_values_stay_expressions_over_params() {
    let m = model(
        "model M { param L = 2; state x = -L / 2; alg z = L; der(x) = 0; constraint z = L; }",
    );
    assert_eq!(
        m.states[0].init,
        bin(BinOp::Div, RExpr::Neg(Box::new(param(0))), RExpr::Num(2.0))
    );
    assert_eq!(m.algs[0].init, param(0));
}

#[test]
fn lets_are_ordered_so_that_each_uses_only_earlier_ones() {
    let m = model(
        "model M {
            state x = 0;
            let c = b + a;
            let a = x;
            let d = 1;
            let b = a * 2;
            der(x) = c + d;
        }",
    );
    let names: Vec<&str> = m.lets.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["a", "b", "c", "d"]);
    for (i, l) in m.lets.iter().enumerate() {
        let mut uses = Vec::new();
        super::lets::let_uses(&l.expr, &mut uses);
        assert!(
            uses.iter().all(|&u| u < i),
            "{} uses a later let: {uses:?}",
            l.name
        );
    }
    // References were renumbered to the new order: c = b + a.
    assert_eq!(m.lets[2].expr, bin(BinOp::Add, let_(1), let_(0)));
    assert_eq!(m.ders[0].expr, bin(BinOp::Add, let_(2), let_(3)));
}

#[test]
fn unnamed_constraints_are_named_by_their_position() {
    let m = model(
        "model M {
            alg a = 0, b = 0, c = 0;
            constraint a = 1;
            constraint named: b = 2;
            constraint c = 3;
        }",
    );
    let names: Vec<&str> = m.constraints.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["c1", "named", "c3"]);
}

#[test]
fn calls_resolve_to_functions() {
    let m = model("model M { state x = 0; der(x) = pow(sign(x), 2) + ln(abs(x) + 1); }");
    let RExpr::Binary(BinOp::Add, a, b) = &m.ders[0].expr else {
        panic!("{:?}", m.ders[0].expr)
    };
    assert!(
        matches!(a.as_ref(), RExpr::Call(Func::Pow, args) if matches!(args[0], RExpr::Call(Func::Sign, _)))
    );
    assert!(matches!(b.as_ref(), RExpr::Call(Func::Ln, _)));
}

#[test]
fn error_syntax() {
    assert_eq!(
        error("model M {\n  state x = 0\n}"),
        (
            "expected `,`, `;` or an operator (`+ - * / ^`), found `}`".into(),
            (3, 1)
        )
    );
}

#[test]
fn error_unknown_name_with_suggestion() {
    let src = "model M {\n  state speed = 0;\n  der(speed) = -sped;\n}";
    assert_eq!(error(src), ("unknown name `sped`".into(), (3, 17)));
    let d = check_source(src).unwrap_err();
    assert_eq!(d[0].hint.as_deref(), Some("did you mean `speed`?"));
    assert_eq!(d[0].label, "not declared in model `M`");
    let d = check_source("model M { state x = 0; der(x) = omega; }").unwrap_err();
    assert_eq!(
        d[0].hint.as_deref(),
        Some("declare it with `param`, `state`, `alg` or `let`")
    );
}

#[test]
fn error_name_declared_twice() {
    let src = "model M {\n  param g = 9.8;\n  state x = 0, g = 1;\n  der(x) = 0;\n  der(g) = 0;\n}";
    assert_eq!(error(src), ("`g` is declared twice".into(), (3, 16)));
    let d = check_source(src).unwrap_err();
    assert_eq!(d[0].related.len(), 1);
    assert_eq!(line_col(src, d[0].related[0].0), (2, 9));
    assert_eq!(d[0].related[0].1, "first declared here, as a parameter");
}

#[test]
fn error_state_without_der() {
    let src = "model M {\n  state x = 0, v = 0;\n  der(x) = v;\n}";
    assert_eq!(
        error(src),
        ("state `v` has no equation `der(v) = ...`".into(), (2, 16))
    );
}

#[test]
fn error_state_with_two_ders() {
    let src = "model M {\n  state x = 0;\n  der(x) = 1;\n  der(x) = 2;\n}";
    assert_eq!(
        error(src),
        ("state `x` has two equations `der(x) = ...`".into(), (4, 3))
    );
    let d = check_source(src).unwrap_err();
    assert_eq!(line_col(src, d[0].related[0].0), (3, 3));
}

#[test]
fn error_der_of_non_state() {
    let src = "model M {\n  alg z = 0;\n  der(z) = 1;\n  constraint z = 0;\n}";
    assert_eq!(
        error(src),
        (
            "`der(z)`: `z` is an algebraic variable, not a state".into(),
            (3, 7)
        )
    );
    let src = "model M {\n  param p = 1;\n  let e = p;\n  der(e) = 1;\n  der(p) = 1;\n  der(t) = 1;\n  der(y) = 1;\n}";
    let e = errors(src);
    assert_eq!(
        e,
        [
            (
                "`der(e)`: `e` is a `let` definition, not a state".to_string(),
                (4, 7)
            ),
            (
                "`der(p)`: `p` is a parameter, not a state".to_string(),
                (5, 7)
            ),
            ("`der(t)`: `t` is time, not a state".to_string(), (6, 7)),
            ("unknown name `y`".to_string(), (7, 7)),
        ]
    );
}

#[test]
fn error_cycle_among_lets() {
    let src =
        "model M {\n  state x = 0;\n  let a = b + x;\n  let b = c;\n  let c = a;\n  der(x) = a;\n}";
    assert_eq!(
        error(src),
        (
            "the definitions form a cycle: a -> b -> c -> a".into(),
            (3, 7)
        )
    );
    let src = "model M {\n  state x = 0;\n  let a = a;\n  der(x) = a;\n}";
    assert_eq!(
        error(src),
        ("the definitions form a cycle: a -> a".into(), (3, 7))
    );
}

#[test]
fn error_alg_and_constraint_counts_differ() {
    let src = "model Two {\n  alg a = 0, b = 0;\n  constraint a = 1;\n}";
    assert_eq!(
        error(src),
        (
            "model `Two` has 2 algebraic variables but 1 constraint".into(),
            (1, 7)
        )
    );
    let src = "model M {\n  state x = 0;\n  der(x) = 1;\n  constraint x = 1;\n}";
    assert_eq!(
        error(src),
        (
            "model `M` has 0 algebraic variables but 1 constraint".into(),
            (1, 7)
        )
    );
}

#[test]
fn error_reserved_word_as_name() {
    let src = "model M {\n  param sin = 1;\n  state t = 0;\n  der(t) = 1;\n  alg model = 0;\n  constraint let: model = 0;\n}";
    let e = errors(src);
    assert_eq!(
        e,
        [
            ("reserved word `sin` cannot be used as a name (`sin` is the name of a built-in function)".to_string(), (2, 9)),
            ("reserved word `t` cannot be used as a name (`t` is reserved for time)".to_string(), (3, 9)),
            ("reserved word `model` cannot be used as a name (`model` is a keyword)".to_string(), (5, 7)),
            ("reserved word `let` cannot be used as a name (`let` is a keyword)".to_string(), (6, 14)),
        ]
    );
    assert_eq!(
        error("model der {}"),
        (
            "reserved word `der` cannot be used as a name (`der` is a keyword)".into(),
            (1, 7)
        )
    );
    // Used as a value without being declared.
    assert_eq!(
        error("model M {\n  state x = 0;\n  der(x) = state;\n}"),
        (
            "reserved word `state` cannot be used in an expression".into(),
            (3, 12)
        )
    );
}

#[test]
fn error_unknown_function() {
    let src = "model M {\n  state x = 0;\n  der(x) = sine(x);\n}";
    assert_eq!(error(src), ("unknown function `sine`".into(), (3, 12)));
    assert_eq!(
        check_source(src).unwrap_err()[0].hint.as_deref(),
        Some("did you mean `sin`?")
    );
    assert_eq!(
        error("model M {\n  state x = 0;\n  der(x) = x(x + 1);\n}"),
        ("`x` is not a function".into(), (3, 12))
    );
    assert_eq!(
        error("model M {\n  state x = 0;\n  der(x) = der(x);\n}"),
        (
            "`der` is allowed only at the start of an equation".into(),
            (3, 12)
        )
    );
    assert_eq!(
        error("model M {\n  state x = 0;\n  der(x) = cos;\n}"),
        ("function `cos` used without arguments".into(), (3, 12))
    );
}

#[test]
fn error_wrong_number_of_arguments() {
    let src = "model M {\n  state x = 0;\n  der(x) = atan2(x) + sin(x, 1) + max();\n}";
    assert_eq!(
        errors(src),
        [
            (
                "function `atan2` takes 2 arguments but 1 was given".to_string(),
                (3, 12)
            ),
            (
                "function `sin` takes 1 argument but 2 were given".to_string(),
                (3, 23)
            ),
            (
                "function `max` takes 2 arguments but 0 were given".to_string(),
                (3, 35)
            ),
        ]
    );
}

#[test]
fn error_param_default_uses_a_variable_or_time() {
    let src = "model M {\n  state x = 0;\n  param p = 2 * x, q = t;\n  der(x) = p + q;\n}";
    assert_eq!(
        errors(src),
        [
            (
                "the default of parameter `p` uses `x`, a state".to_string(),
                (3, 17)
            ),
            (
                "the default of parameter `q` uses time `t`".to_string(),
                (3, 24)
            ),
        ]
    );
}

#[test]
fn error_param_default_uses_a_later_param() {
    let src = "model M {\n  param a = b + 1;\n  param b = 2, c = c;\n}";
    assert_eq!(
        errors(src),
        [
            (
                "the default of parameter `a` uses `b`, which is declared after it".to_string(),
                (2, 13)
            ),
            (
                "parameter `c` is defined in terms of itself".to_string(),
                (3, 20)
            ),
        ]
    );
    let d = check_source(src).unwrap_err();
    assert_eq!(line_col(src, d[0].related[0].0), (3, 9));
}

#[test]
fn error_initial_value_uses_a_variable_or_time() {
    let src = "model M {\n  state x = 0, y = x;\n  alg z = e;\n  let e = 1;\n  der(x) = 0;\n  der(y) = 0;\n  constraint z = t + 1 / 0 * 0;\n  state w = t;\n  der(w) = 0;\n}";
    assert_eq!(
        errors(src),
        [
            (
                "the initial value of `y` uses `x`, a state".to_string(),
                (2, 20)
            ),
            (
                "the initial value of `z` uses `e`, a `let` definition".to_string(),
                (3, 11)
            ),
            (
                "the initial value of `w` uses time `t`".to_string(),
                (8, 13)
            ),
        ]
    );
}

#[test]
fn error_non_finite_values() {
    let src = "model M {\n  param a = 0;\n  param p = 1 / a, q = ln(a), r = 1e200 * 1e200;\n}";
    assert_eq!(
        errors(src),
        [
            (
                "the default of parameter `p` is not finite".to_string(),
                (3, 13)
            ),
            (
                "the default of parameter `q` is not finite".to_string(),
                (3, 24)
            ),
            (
                "the default of parameter `r` is not finite".to_string(),
                (3, 35)
            ),
        ]
    );
    let d = check_source(src).unwrap_err();
    assert_eq!(d[0].label, "evaluates to inf");
    assert_eq!(d[1].label, "evaluates to -inf");
    let src = "model M {\n  param a = -1;\n  state x = sqrt(a);\n  der(x) = 0;\n}";
    assert_eq!(
        error(src),
        ("the initial value of `x` is not finite".into(), (3, 13))
    );
    assert_eq!(check_source(src).unwrap_err()[0].label, "evaluates to NaN");
}

#[test]
fn error_two_models_with_one_name() {
    let src = "model A {}\nmodel B {}\nmodel A {}";
    assert_eq!(
        error(src),
        ("two models named `A` in one file".into(), (3, 7))
    );
}

#[test]
fn error_generated_constraint_name_collides_with_a_written_one() {
    let src = "model M {\n  alg a = 0, b = 0;\n  constraint c2: a = 1;\n  constraint b = 2;\n}";
    assert_eq!(error(src), ("two constraints named `c2`".into(), (4, 3)));
    let src = "model M {\n  alg a = 0, b = 0;\n  constraint k: a = 1;\n  constraint k: b = 2;\n}";
    assert_eq!(error(src), ("two constraints named `k`".into(), (4, 14)));
}

#[test]
fn all_errors_of_all_models_are_reported_in_source_order() {
    let src = "model A {\n  state x = 0;\n  der(x) = y;\n  der(q) = 1;\n}\nmodel B {\n  param p = 1 / 0;\n  alg z = 0;\n}";
    let e = errors(src);
    let places: Vec<(usize, usize)> = e.iter().map(|x| x.1).collect();
    assert_eq!(places, [(3, 12), (4, 7), (6, 7), (7, 13)], "{e:#?}");
}

#[test]
fn check_takes_one_parsed_model() {
    let file = parse("model A { state x = 1; der(x) = -x; } model B { alg z = 0; }").unwrap();
    assert!(crate::check(&file.models[0]).is_ok());
    let d = crate::check(&file.models[1]).unwrap_err();
    assert_eq!(
        d[0].message,
        "model `B` has 1 algebraic variable but 0 constraints"
    );
}
