//! Parser tests: every construct, the precedence rules, spans and syntax errors.

use super::parse;
use crate::ast::{BinOp, Expr, ExprKind, File, Item, Span};
use crate::diag::line_col;

/// An expression as an S-expression, e.g. `(+ a (* b c))`.
fn sx(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Num(v) => format!("{v}"),
        ExprKind::Time => "t".into(),
        ExprKind::Name(n) => n.clone(),
        ExprKind::Neg(a) => format!("(neg {})", sx(a)),
        ExprKind::Binary(op, a, b) => {
            let op = match op {
                BinOp::Add => "+",
                BinOp::Sub => "-",
                BinOp::Mul => "*",
                BinOp::Div => "/",
                BinOp::Pow => "^",
            };
            format!("({op} {} {})", sx(a), sx(b))
        }
        ExprKind::Call(f, args) => {
            let args: Vec<String> = args.iter().map(sx).collect();
            format!("({} {})", f.name, args.join(" "))
        }
        ExprKind::Index(a, i) => format!("([] {} {})", sx(a), sx(i)),
        ExprKind::Field(a, f) => format!("(. {} {})", sx(a), f.name),
        ExprKind::Sum {
            elem,
            set,
            cond,
            body,
        } => match cond {
            Some(c) => format!("(sum {} {} {} {})", elem.name, set.name, sx(c), sx(body)),
            None => format!("(sum {} {} {})", elem.name, set.name, sx(body)),
        },
        ExprKind::Compare(op, a, b) => format!("({} {} {})", op.symbol(), sx(a), sx(b)),
        ExprKind::Logic(op, a, b) => {
            let w = if *op == crate::ast::LogicOp::And {
                "and"
            } else {
                "or"
            };
            format!("({w} {} {})", sx(a), sx(b))
        }
        ExprKind::Not(a) => format!("(not {})", sx(a)),
        ExprKind::If(c, a, b) => format!("(if {} {} {})", sx(c), sx(a), sx(b)),
    }
}

fn file(src: &str) -> File {
    match parse(src) {
        Ok(f) => f,
        Err(d) => panic!("parse failed for {src:?}: {d:?}"),
    }
}

/// The right-hand side of `der(x) = <expr>;` as an S-expression.
fn expr(text: &str) -> String {
    let src = format!("model M {{ der(x) = {text}; }}");
    let f = file(&src);
    match &f.models[0].items[0] {
        Item::Der { rhs, .. } => sx(rhs),
        other => panic!("not a der item: {other:?}"),
    }
}

/// The first syntax error: message and 1-based line and column.
fn syntax_error(src: &str) -> (String, (usize, usize)) {
    match parse(src) {
        Ok(f) => panic!("expected a syntax error for {src:?}, got {f:?}"),
        Err(d) => {
            assert_eq!(d.len(), 1, "{d:?}");
            assert!(d[0].hint.is_some(), "every syntax error has a hint: {d:?}");
            (d[0].message.clone(), line_col(src, d[0].span))
        }
    }
}

#[test]
fn numbers_in_every_form() {
    assert_eq!(expr("2"), "2");
    assert_eq!(expr("0.1"), "0.1");
    assert_eq!(expr("1e-3"), "0.001");
    assert_eq!(expr("2.5E+4"), "25000");
    assert_eq!(expr("3e2"), "300");
    assert_eq!(expr("007"), "7");
}

#[test]
fn time_names_and_calls() {
    assert_eq!(expr("t"), "t");
    assert_eq!(expr("time_1"), "time_1");
    assert_eq!(expr("_x"), "_x");
    assert_eq!(expr("tt"), "tt");
    assert_eq!(expr("sin(t)"), "(sin t)");
    assert_eq!(expr("atan2(y, x)"), "(atan2 y x)");
    assert_eq!(expr("sqrt ( a )"), "(sqrt a)");
    // Arity is the checker's business: the parser accepts any number of arguments.
    assert_eq!(expr("f()"), "(f )");
    assert_eq!(expr("max(a, min(b, c))"), "(max a (min b c))");
}

#[test]
fn additive_and_multiplicative_operators_are_left_associative() {
    assert_eq!(expr("a - b - c"), "(- (- a b) c)");
    assert_eq!(expr("a + b - c + d"), "(+ (- (+ a b) c) d)");
    assert_eq!(expr("a / b / c"), "(/ (/ a b) c)");
    assert_eq!(expr("a * b / c * d"), "(* (/ (* a b) c) d)");
}

#[test]
fn multiplication_binds_tighter_than_addition() {
    assert_eq!(expr("a + b * c"), "(+ a (* b c))");
    assert_eq!(expr("a * b + c"), "(+ (* a b) c)");
    assert_eq!(expr("a - b / c"), "(- a (/ b c))");
    assert_eq!(expr("(a + b) * c"), "(* (+ a b) c)");
}

#[test]
fn unary_minus_binds_tighter_than_products() {
    assert_eq!(expr("-a * b"), "(* (neg a) b)");
    assert_eq!(expr("a * -b"), "(* a (neg b))");
    assert_eq!(expr("a - -b"), "(- a (neg b))");
    assert_eq!(expr("--a"), "(neg (neg a))");
    assert_eq!(expr("-a + b"), "(+ (neg a) b)");
}

#[test]
fn power_is_right_associative_and_binds_tighter_than_unary_minus() {
    assert_eq!(expr("-x^2"), "(neg (^ x 2))");
    assert_eq!(expr("-2^2"), "(neg (^ 2 2))");
    assert_eq!(expr("a^b^c"), "(^ a (^ b c))");
    assert_eq!(expr("a * b^2"), "(* a (^ b 2))");
    assert_eq!(expr("(-x)^2"), "(^ (neg x) 2)");
    assert_eq!(expr("x^2^-1"), "(^ x (^ 2 (neg 1)))");
}

#[test]
fn exponent_may_be_negated() {
    // The exponent of `^` is a unary expression: `2^-x` is `2^(-x)`, and the `^` inside
    // it still binds tighter: `2^-x^2` is `2^(-(x^2))`.
    assert_eq!(expr("2^-x"), "(^ 2 (neg x))");
    assert_eq!(expr("2^-x^2"), "(^ 2 (neg (^ x 2)))");
    assert_eq!(expr("2^--x"), "(^ 2 (neg (neg x)))");
}

#[test]
fn comments_of_both_kinds_anywhere() {
    let src = "// head\nmodel /* a */ M { // line\n state /* mid */ x = 1 /* in expr */ + 2; /* multi\nline */\n der(x) = 0; } // end";
    let f = file(src);
    assert_eq!(f.models.len(), 1);
    match &f.models[0].items[0] {
        Item::State(ds, _) => assert_eq!(sx(&ds[0].value), "(+ 1 2)"),
        other => panic!("{other:?}"),
    }
    // `/* */` does not nest and `//` inside a block comment is plain text.
    let f = file("model M { /* // } */ }");
    assert!(f.models[0].items.is_empty());
}

#[test]
fn every_item_kind() {
    let src = "model M {
        param a = 1, b = a;
        state x = 0, v = b;
        alg z = 0;
        let e = x + v;
        der(x) = v;
        constraint named: x = 1;
        constraint z * 2 = e;
    }";
    let f = file(src);
    let items = &f.models[0].items;
    assert_eq!(items.len(), 7);
    match &items[0] {
        Item::Param(ds, _) => {
            let names: Vec<&str> = ds.iter().map(|d| d.name.name.as_str()).collect();
            assert_eq!(names, ["a", "b"]);
            assert_eq!(sx(&ds[1].value), "a");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(&items[1], Item::State(ds, _) if ds.len() == 2 && ds[1].name.name == "v"));
    assert!(matches!(&items[2], Item::Alg(ds, _) if ds.len() == 1 && ds[0].name.name == "z"));
    assert!(
        matches!(&items[3], Item::Let(d, _) if d.name.name == "e" && sx(&d.value) == "(+ x v)")
    );
    assert!(
        matches!(&items[4], Item::Der { target, rhs, .. } if target.name == "x" && sx(rhs) == "v")
    );
    match &items[5] {
        Item::Constraint {
            name: Some(n),
            lhs,
            rhs,
            ..
        } => {
            assert_eq!(n.name, "named");
            assert_eq!((sx(lhs), sx(rhs)), ("x".to_string(), "1".to_string()));
        }
        other => panic!("{other:?}"),
    }
    match &items[6] {
        Item::Constraint {
            name: None,
            lhs,
            rhs,
            ..
        } => {
            assert_eq!((sx(lhs), sx(rhs)), ("(* z 2)".to_string(), "e".to_string()));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn several_models_and_empty_ones() {
    let f = file("model A { } model B { state x = 1; der(x) = -x; }\nmodel C {}");
    let names: Vec<&str> = f.models.iter().map(|m| m.name.name.as_str()).collect();
    assert_eq!(names, ["A", "B", "C"]);
    assert_eq!(f.models[1].items.len(), 2);
}

#[test]
fn keywords_need_a_word_boundary_and_names_may_contain_them() {
    // `statex` is not `state x`; names that merely start with a keyword are names.
    let f = file("model M { state state_1 = 0, models = 1, tx = 2; }");
    match &f.models[0].items[0] {
        Item::State(ds, _) => {
            let names: Vec<&str> = ds.iter().map(|d| d.name.name.as_str()).collect();
            assert_eq!(names, ["state_1", "models", "tx"]);
        }
        other => panic!("{other:?}"),
    }
    let (msg, _) = syntax_error("model M { statex = 1; }");
    assert!(msg.starts_with("expected an item"), "{msg}");
}

#[test]
fn spans_cover_the_source_text() {
    let src = "model Mo {\n  state x = 1 + 2, y = 3;\n  der(x) = -(a + b) * c;\n  constraint k: x = y;\n}\n";
    let f = file(src);
    let text = |s: Span| &src[s.start..s.end];
    let m = &f.models[0];
    assert_eq!(text(m.name.span), "Mo");
    assert_eq!(text(m.span), src.trim_end());
    match &m.items[0] {
        Item::State(ds, s) => {
            assert_eq!(text(*s), "state x = 1 + 2, y = 3;");
            assert_eq!(text(ds[0].span), "x = 1 + 2");
            assert_eq!(text(ds[0].name.span), "x");
            assert_eq!(text(ds[0].value.span), "1 + 2");
            assert_eq!(text(ds[1].value.span), "3");
        }
        other => panic!("{other:?}"),
    }
    match &m.items[1] {
        Item::Der {
            target, rhs, span, ..
        } => {
            assert_eq!(text(*span), "der(x) = -(a + b) * c;");
            assert_eq!(text(target.span), "x");
            assert_eq!(text(rhs.span), "-(a + b) * c");
            let ExprKind::Binary(BinOp::Mul, neg, c) = &rhs.kind else {
                panic!("{rhs:?}")
            };
            assert_eq!(text(neg.span), "-(a + b)");
            assert_eq!(text(c.span), "c");
            let ExprKind::Neg(inner) = &neg.kind else {
                panic!("{neg:?}")
            };
            // Parentheses belong to the span of what they enclose.
            assert_eq!(text(inner.span), "(a + b)");
        }
        other => panic!("{other:?}"),
    }
    match &m.items[2] {
        Item::Constraint {
            name,
            lhs,
            rhs,
            span,
            ..
        } => {
            assert_eq!(text(*span), "constraint k: x = y;");
            assert_eq!(name.as_ref().map(|n| text(n.span)), Some("k"));
            assert_eq!((text(lhs.span), text(rhs.span)), ("x", "y"));
        }
        other => panic!("{other:?}"),
    }
    let f = file("model M { der(x) = sin(a, b^2); }");
    let Item::Der { rhs, .. } = &f.models[0].items[0] else {
        panic!()
    };
    let ExprKind::Call(name, args) = &rhs.kind else {
        panic!("{rhs:?}")
    };
    assert_eq!(
        (rhs.span, name.span, args[1].span),
        (Span::new(19, 30), Span::new(19, 22), Span::new(26, 29))
    );
}

#[test]
fn syntax_error_missing_semicolon() {
    let (msg, at) = syntax_error("model M {\n  state x = 0\n  der(x) = 1;\n}");
    assert_eq!(
        msg,
        "expected `,`, `;` or an operator (`+ - * / ^`), found `der`"
    );
    assert_eq!(at, (3, 3));
}

#[test]
fn syntax_error_missing_expression() {
    let (msg, at) = syntax_error("model M {\n  der(x) = 1 + ;\n}");
    assert_eq!(msg, "expected an expression, found `;`");
    assert_eq!(at, (2, 16));
}

#[test]
fn syntax_error_not_an_item() {
    let (msg, at) = syntax_error("model M {\n  x = 1;\n}");
    assert_eq!(
        msg,
        "expected an item (`param`, `state`, `alg`, `let`, `der` or `constraint`) or `}`, found `x`"
    );
    assert_eq!(at, (2, 3));
}

#[test]
fn syntax_error_unclosed_model_and_comment() {
    let (msg, at) = syntax_error("model M {\n  state x = 0;\n");
    assert!(msg.ends_with("found the end of the file"), "{msg}");
    assert_eq!(at, (3, 1));
    let (msg, at) = syntax_error("model M {\n  /* never closed\n}");
    assert!(msg.ends_with("found `/*`"), "{msg}");
    assert_eq!(at, (2, 3));
}

#[test]
fn syntax_error_bad_numbers_and_tokens() {
    assert_eq!(
        syntax_error("model M { der(x) = 2.; }").0,
        "expected `;` or an operator (`+ - * / ^`), found `.`"
    );
    assert_eq!(
        syntax_error("model M { der(x) = .5; }").0,
        "expected an expression, found `.`"
    );
    assert_eq!(syntax_error("model M { der(x) = 2x; }").1, (1, 21));
    assert_eq!(
        syntax_error("model M { der(x) = +x; }").0,
        "expected an expression, found `+`"
    );
    assert_eq!(
        syntax_error("model M { der(x) = x $ 1; }").0,
        "expected `;` or an operator (`+ - * / ^`), found `$`"
    );
    assert_eq!(
        syntax_error("model M { der(x) = (x; }").0,
        "expected `)` or an operator (`+ - * / ^`), found `;`"
    );
    assert_eq!(
        syntax_error("model M { state 1x = 0; }").0,
        "expected a name, found `1x`"
    );
    assert_eq!(
        syntax_error("model M { der(x) = 1; } junk").0,
        "expected `model` or the end of the file, found `junk`"
    );
    assert_eq!(
        syntax_error("").0,
        "expected `model`, found the end of the file"
    );
    assert_eq!(syntax_error("model M { state x = é; }").1, (1, 21));
}

#[test]
fn syntax_error_hints_name_the_usual_mistakes() {
    let hint = |src: &str| parse(src).unwrap_err()[0].hint.clone().unwrap_or_default();
    assert!(hint("model M { der(x) = 2x; }").contains("`2 * x`"));
    assert!(hint("model M { der(x) = 2.; }").contains("`2.0`"));
    assert!(hint("model M { let a = 1, b = 2; }").contains("its own `let"));
    assert!(hint("model M { /* x }").contains("`*/`"));
    assert!(hint("model M { state x = 0;").contains("end it with `}`"));
    assert!(hint("model M {\n state x = 0\n der(x) = 1; }").contains("end of line 2"));
    assert!(hint("model M { param a == 1; }").contains("single `=`"));
}

#[test]
fn numbers_too_large_for_f64_are_errors() {
    let src = "model M {\n  param a = 1e999;\n}";
    let d = parse(src).unwrap_err();
    assert_eq!(d[0].message, "number `1e999` is too large");
    assert_eq!(line_col(src, d[0].span), (2, 13));
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let deep = |open: &str, close: &str, n: usize| {
        format!(
            "model M {{ der(x) = {}x{}; }}",
            open.repeat(n),
            close.repeat(n)
        )
    };
    let sum = |n: usize| format!("model M {{ der(x) = {}1; }}", "1 + ".repeat(n));
    // Within the limits: accepted. 64 levels, as docs/language.md says.
    for src in [
        deep("(", ")", 64),
        deep("sin(", ")", 64),
        deep("2^", "", 64),
        deep("(2^", ")", 32),
        deep("-", "", 250),
        sum(250),
    ] {
        assert!(parse(&src).is_ok(), "{src}");
    }
    // A chain of `^` counts, separate powers do not: `x^2 + x^2 + ...` is shallow.
    assert!(
        parse(&format!(
            "model M {{ der(x) = {}1; }}",
            "x^2 + ".repeat(200)
        ))
        .is_ok()
    );
    // Beyond: exactly one diagnostic, at the place the limit is crossed.
    for (src, col) in [
        // The 65th `(`, at column 20 + 64.
        (deep("(", ")", 65), 84),
        (deep("sin(", ")", 5000), 20 + 4 * 64 + 3),
        (deep("2^", "", 3000), 20 + 2 * 64 + 1),
        // `(2^` is two levels: the 33rd `(` is the 65th level.
        (deep("(2^", ")", 40), 20 + 3 * 32),
        // The sign of an exponent does not end a chain of `^`: the 65th `^`.
        (deep("2^1e-1^", "", 100), 21 + 7 * 32),
    ] {
        let d = parse(&src).unwrap_err();
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(
            d[0].message.starts_with("expression nested too deeply"),
            "{}",
            d[0].message
        );
        assert_eq!(line_col(&src, d[0].span), (1, col));
    }
    for src in [deep("-", "", 5000), sum(300)] {
        let d = parse(&src).unwrap_err();
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(
            d[0].message,
            "expression too deep (more than 256 levels of operations)"
        );
    }
    // Parentheses in comments do not count.
    let commented = format!(
        "model M {{ /* {} */ // {}\n der(x) = 1; }}",
        "(".repeat(100),
        "(".repeat(100)
    );
    assert!(parse(&commented).is_ok());
}

#[test]
fn a_byte_order_mark_at_the_start_is_skipped() {
    let src = "\u{feff}model M {\n  state x = 1;\n  der(x) = -x;\n}\n";
    let file = parse(src).expect("a BOM is not an error");
    assert_eq!(file.models[0].name.name, "M");
    // Spans stay byte offsets into the text as given; columns do not count the BOM,
    // which editors do not show.
    let name = file.models[0].name.span;
    assert_eq!(&src[name.start..name.end], "M");
    assert_eq!(line_col(src, name), (1, 7));
    let bad = "\u{feff}model M { state x = 1 }";
    let d = parse(bad).unwrap_err();
    assert_eq!(line_col(bad, d[0].span), (1, 23), "{d:?}");
    // Anywhere else it is a character the language does not have.
    assert!(parse("model M {\u{feff} state x = 1; der(x) = -x; }").is_err());
}

#[test]
fn a_source_longer_than_the_limit_is_one_error() {
    use super::MAX_SOURCE_BYTES;
    assert_eq!(MAX_SOURCE_BYTES, 16 * 1024 * 1024);
    let model = "model M { state x = 1; der(x) = -x; }\n";
    let mut src = model.to_string();
    src.push_str(&" ".repeat(MAX_SOURCE_BYTES - src.len()));
    assert!(parse(&src).is_ok(), "exactly the limit is accepted");
    src.push(' ');
    let d = parse(&src).unwrap_err();
    assert_eq!(d.len(), 1);
    assert_eq!(
        d[0].message,
        "the source text is 16777217 bytes long, more than the limit of 16 MiB (16777216 bytes)"
    );
    assert_eq!(d[0].span, Span::new(MAX_SOURCE_BYTES, MAX_SOURCE_BYTES + 1));
}
