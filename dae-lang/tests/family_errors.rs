//! Every mistake of the family constructs is a located error: the message, the place
//! (line:col of the offending text, underlined when rendered) and a hint. The checker's,
//! the analysis' and construction's errors.

use dae_lang::family::{Spec, construct};
use dae_lang::{AnalysisOptions, Diagnostic, analyze, compile, line_col};

/// A chain model with `body` in place of its equations (sets P, L, maps a, b, x, v, z).
fn chain(body: &str) -> String {
    format!(
        "model C {{
    size N = 4;
    set P = N + 1;
    set L = N;
    map a[l in L] -> P = l;
    map b[l in L] -> P = l + 1;
    param m = 0.1, L0 = 0.25, g = 9.81;
    param free[p in P] = if p == 0 then 0 else 1;
    state x[p in P]: vec3 = vec3(p * L0, 0, 0);
    state v[p in P]: vec3 = vec3(0, 0, 0);
    alg z[l in L] = 0;
{body}
}}"
    )
}

/// The usual equations of the chain.
const EQUATIONS: &str = "
    let d[l in L] = x[b[l]] - x[a[l]];
    der(x[p]) = v[p];
    der(v[p]) = free[p] * ((sum(l in L where a[l] == p) z[l] * d[l] / norm(d[l])
                          - sum(l in L where b[l] == p) z[l] * d[l] / norm(d[l])) / m
                          + vec3(0, 0, -g));
    constraint link[l in L]: norm(d[l]) = L0;";

/// The first error of checking and analysing `src`, rendered; asserts it mentions
/// `message`, starts at `text` (the first occurrence of `text` at or after `after`),
/// renders with the file:line:col header and an underline, and has a hint.
fn error_at(src: &str, message: &str, text: &str, after: &str) -> Diagnostic {
    let result = dae_lang::check_source(src).and_then(|ms| {
        ms.iter()
            .map(|m| analyze(m, &AnalysisOptions::default()))
            .collect::<Result<Vec<_>, _>>()
    });
    let errors = match result {
        Ok(_) => panic!("expected an error mentioning {message:?}"),
        Err(e) => e,
    };
    let d = errors
        .iter()
        .find(|d| d.message.contains(message))
        .unwrap_or_else(|| panic!("no error mentions {message:?}: {errors:#?}"))
        .clone();
    located(src, &d, text, after);
    d
}

fn located(src: &str, d: &Diagnostic, text: &str, after: &str) {
    let from = src
        .find(after)
        .unwrap_or_else(|| panic!("{after:?} not in the source"));
    let at = from
        + src[from..]
            .find(text)
            .unwrap_or_else(|| panic!("{text:?} not after {after:?}"));
    assert_eq!(
        d.span.start,
        at,
        "{}: starts at {:?}, expected {text:?}",
        d.message,
        &src[d.span.start..]
    );
    let (line, col) = line_col(src, d.span);
    let rendered = d.render("m.dae", src, false);
    assert!(
        rendered.contains(&format!("m.dae:{line}:{col}")),
        "{rendered}"
    );
    assert!(rendered.contains('─'), "underlined: {rendered}");
    assert!(
        d.hint.as_ref().is_some_and(|h| !h.is_empty()),
        "a hint: {d:?}"
    );
}

#[test]
fn unknown_set() {
    let src = chain(&format!("    param k[q in Q] = 1;{EQUATIONS}"));
    let d = error_at(&src, "unknown set `Q`", "Q", "param k[q in ");
    assert!(d.hint.unwrap().contains("`P`"));
}

#[test]
fn unknown_map() {
    // A two-letter typo: a one-letter name gets no suggestion (every one-letter name is
    // one edit from it).
    let src = chain(&EQUATIONS.replace("x[b[l]] - x[a[l]]", "x[bb[l]] - x[a[l]]"));
    let d = error_at(&src, "unknown map or family `bb`", "bb[l]", "let d");
    let h = d.hint.unwrap();
    assert!(h.contains("did you mean `b`?"), "{h}");
}

#[test]
fn element_access_with_the_wrong_set() {
    let src = chain(&EQUATIONS.replace("x[b[l]] - x[a[l]]", "x[l] - x[a[l]]"));
    let d = error_at(
        &src,
        "takes an element of `P`, but `l` is an element of `L`",
        "l]",
        "x[l]",
    );
    assert!(d.hint.unwrap().contains("a[l]"), "suggests a map");
}

#[test]
fn map_applied_to_an_element_of_the_wrong_set() {
    let src = chain(&EQUATIONS.replace("der(x[p]) = v[p];", "der(x[p]) = v[a[p]];"));
    error_at(
        &src,
        "map `a` takes an element of `L`, but `p` is an element of `P`",
        "p]",
        "v[a[p]]",
    );
}

#[test]
fn bare_family_name() {
    let src = chain(&EQUATIONS.replace("der(x[p]) = v[p];", "der(x[p]) = v;"));
    let d = error_at(&src, "`v` is a family over `P`", "v;", "der(x[p]) = ");
    assert!(d.hint.unwrap().contains("v[p]"));
}

#[test]
fn vector_scalar_mismatch() {
    let src = chain(&EQUATIONS.replace("der(x[p]) = v[p];", "der(x[p]) = v[p] + 1;"));
    error_at(
        &src,
        "`+` of a vec3 and a number",
        "v[p] + 1",
        "der(x[p]) = ",
    );
    let src = chain(&EQUATIONS.replace(
        "let d[l in L] = x[b[l]] - x[a[l]];",
        "let d[l in L] = x[b[l]] * x[a[l]];",
    ));
    let d = error_at(
        &src,
        "`*` of a vec3 and a vec3",
        "x[b[l]] * x[a[l]]",
        "let d",
    );
    assert!(d.hint.unwrap().contains("dot"));
}

#[test]
fn vector_constraint_and_vector_alg() {
    let src = chain(&EQUATIONS.replace("norm(d[l]) = L0;", "d[l] = vec3(L0, 0, 0);"));
    error_at(
        &src,
        "constraint `link` is a vec3, not one equation",
        "constraint link",
        "",
    );
    let src =
        chain(EQUATIONS).replace("alg z[l in L] = 0;", "alg z[l in L]: vec3 = vec3(0, 0, 0);");
    error_at(&src, "algebraic unknown `z` is a vector", "vec3 =", "alg z");
}

#[test]
fn sum_over_an_unknown_set() {
    let src = chain(&EQUATIONS.replacen("sum(l in L where a[l]", "sum(l in K where a[l]", 1));
    error_at(&src, "unknown set `K`", "K where", "sum(l in ");
}

#[test]
fn malformed_sum_conditions() {
    let src = chain(&EQUATIONS.replacen("where a[l] == p", "where a[l] < p", 1));
    error_at(
        &src,
        "malformed sum condition: it is not an equality",
        "a[l] < p",
        "where ",
    );
    let src = chain(&EQUATIONS.replacen("where a[l] == p", "where p == 1", 1));
    error_at(
        &src,
        "malformed sum condition: it does not use the summation element",
        "p == 1",
        "where ",
    );
}

#[test]
fn if_and_comparisons_in_an_equation() {
    let src = chain(&EQUATIONS.replace(
        "der(x[p]) = v[p];",
        "der(x[p]) = if p == 0 then v[p] else 2 * v[p];",
    ));
    let d = error_at(&src, "`if` in an equation", "if p == 0", "der(x[p]) = ");
    assert!(d.hint.unwrap().contains("per-element parameter"));
}

#[test]
fn float_in_a_map_formula() {
    let src = chain(EQUATIONS).replace(
        "map b[l in L] -> P = l + 1;",
        "map b[l in L] -> P = l + 0.5;",
    );
    error_at(&src, "a float in a map formula", "0.5", "map b");
    let src =
        chain(EQUATIONS).replace("map b[l in L] -> P = l + 1;", "map b[l in L] -> P = l / 2;");
    let d = error_at(&src, "`/` in a map formula", "l / 2", "map b");
    assert!(d.hint.unwrap().contains("div"));
}

#[test]
fn der_of_a_family_without_its_element() {
    let src = chain(&EQUATIONS.replace("der(x[p]) = v[p];", "der(x) = v[p];"));
    let d = error_at(&src, "`der(x)`: `x` is a family over `P`", "x) =", "der(");
    assert!(d.hint.unwrap().contains("der(x[p])"));
}

#[test]
fn family_without_an_index() {
    // The tensions act on v, which the constraint does not see through any der.
    let body = EQUATIONS
        .replace(
            "norm(d[l]) = L0;",
            "norm(d[l]) + 0 * sum(q in P) free[q] = L0;",
        )
        .replace("der(x[p]) = v[p];", "der(x[p]) = vec3(1, 0, 0);");
    let src = chain(&body);
    error_at(
        &src,
        "constraint `link` has no index",
        "constraint link",
        "",
    );
}

#[test]
fn input_used_without_the_derivatives_the_index_needs() {
    let src = chain(
        "    input pin: vec3 with 2 derivatives = vec3(0, 0, 0);
    let X[p in P] = free[p] * x[p] + (1 - free[p]) * pin;
    let d[l in L] = X[b[l]] - X[a[l]];
    der(x[p]) = v[p];
    der(v[p]) = free[p] * ((sum(l in L where a[l] == p) z[l] * d[l] / norm(d[l])
                          - sum(l in L where b[l] == p) z[l] * d[l] / norm(d[l])) / m
                          + vec3(0, 0, -g));
    constraint link[l in L]: norm(d[l]) = L0;",
    );
    let d = error_at(
        &src,
        "input `pin` is used without the derivatives the index needs: beta_link reads its derivative 3, but it declares 2",
        "pin: vec3",
        "input ",
    );
    assert!(d.hint.unwrap().contains("with 3 derivatives"));
    assert_eq!(d.related.len(), 1, "points at the constraint that needs it");
}

#[test]
fn two_hop_coupling() {
    // The summand reads z at the next link, not at the summation element.
    let src = chain(
        "    map next[l in L] -> L = mod(l + 1, N);
    let d[l in L] = x[b[l]] - x[a[l]];
    der(x[p]) = v[p];
    der(v[p]) = free[p] * ((sum(l in L where a[l] == p) z[next[l]] * d[l]
                          - sum(l in L where b[l] == p) z[l] * d[l]) / m + vec3(0, 0, -g));
    constraint link[l in L]: dot(d[l], d[l]) = L0^2;",
    );
    let d = error_at(
        &src,
        "couples with `z` through two maps",
        "constraint link",
        "",
    );
    assert!(d.hint.unwrap().contains("z[k]"));
}

#[test]
fn counts_and_names() {
    // A family name used as a scalar; an element name that is a declared name.
    let src = chain(&EQUATIONS.replace("norm(d[l]) = L0;", "norm(d[l]) = m[l];"));
    error_at(&src, "`m` is not a family", "m[l]", "norm(d[l]) = ");
    let src = chain(EQUATIONS).replace("param free[p in P]", "param free[g in P]");
    error_at(
        &src,
        "the element name `g` is also declared as a parameter",
        "g in P",
        "free[",
    );
}

/// Construction's errors, located at the declaration concerned.
fn construct_error(src: &str, spec: Spec, message: &str, text: &str) {
    let models = dae_lang::check_source(src).unwrap_or_else(|e| panic!("{e:#?}"));
    let a = analyze(&models[0], &AnalysisOptions::default()).unwrap_or_else(|e| panic!("{e:#?}"));
    let c = compile(&a);
    let err = construct(&c.programs.construction, &spec).expect_err("a construction error");
    assert!(err.message.contains(message), "{err}");
    let d = err.to_diagnostic();
    located(src, &d, text, "");
}

#[test]
fn set_of_size_zero_at_construction() {
    let src = chain(EQUATIONS);
    construct_error(
        &src,
        Spec {
            sizes: vec![("N".into(), 0)],
            ..Spec::default()
        },
        "set `L` has 0 elements with N = 0",
        "set L",
    );
    // At the default sizes, the checker reports it.
    let src = chain(EQUATIONS).replace("size N = 4;", "size N = 0;");
    error_at(&src, "set `L` has 0 elements with N = 0", "set L", "");
}

#[test]
fn map_pointing_outside_its_set() {
    let src =
        chain(EQUATIONS).replace("map b[l in L] -> P = l + 1;", "map b[l in L] -> P = l + 2;");
    error_at(
        &src,
        "map `b` points outside its set: element 3 goes to 5, but `P` has 5 elements",
        "map b",
        "",
    );
    // A given map, at construction.
    let src = chain(EQUATIONS).replace("map b[l in L] -> P = l + 1;", "map b[l in L] -> P;");
    construct_error(
        &src,
        Spec {
            maps: vec![("b".into(), vec![1, 2, 3, 9])],
            ..Spec::default()
        },
        "map `b` points outside its set: element 3 goes to 9",
        "map b",
    );
}

#[test]
fn particle_in_no_link() {
    let src = chain(EQUATIONS).replace("set P = N + 1;", "set P = N + 2;");
    error_at(
        &src,
        "element 5 of `P` is in no sum: no element has a[l] or b[l] equal to 5",
        "der(v[p])",
        "",
    );
}

/// Found by the name-substitution property test: a `let` over a set that uses itself
/// (`u[l] = u[l] / norm(d[l])`) was accepted, and the equations that used it were
/// dropped without a word (3 `der`s for 6 state components).
#[test]
fn a_let_family_that_uses_itself() {
    let src = chain(
        "
    let d[l in L] = x[b[l]] - x[a[l]];
    let u[l in L] = u[l] / norm(d[l]);
    der(x[p]) = v[p];
    der(v[p]) = free[p] * ((sum(l in L where a[l] == p) z[l] * u[l]
                          - sum(l in L where b[l] == p) z[l] * u[l]) / m
                          + vec3(0, 0, -g));
    constraint link[l in L]: norm(d[l]) = L0;",
    );
    error_at(&src, "form a cycle: u -> u", "u[l in L]", "let u");
}

#[test]
fn der_of_something_other_than_a_state() {
    let src = chain(&format!("{EQUATIONS}\n    der(m) = 0;\n    der(t) = 1;"));
    let d = error_at(
        &src,
        "`der(m)`: `m` is a parameter, not a state",
        "m",
        "der(m)",
    );
    assert_eq!(d.label, "a parameter");
    let declared = src.find("m = 0.1").expect("the declaration of m");
    assert_eq!(d.related[0].0.start, declared, "{d:?}");
    let d = error_at(&src, "`der(t)`: `t` is time, not a state", "t", "der(t)");
    assert_eq!(d.label, "time");
}
