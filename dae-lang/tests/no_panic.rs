//! Robustness: whatever the input, parsing and checking return a value (a model or
//! diagnostics) and never panic; diagnostics point inside the source and render;
//! accepted models satisfy the invariants of `Model`.
//!
//! Inputs: random bytes, random text over the language's characters, and random byte
//! and token mutations of the example models (which reach the checker far more often
//! than random text does).

use dae_lang::model::{Model, RExpr};
use proptest::prelude::*;
use std::path::PathBuf;

fn examples() -> Vec<String> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples/models");
    let mut out: Vec<(PathBuf, String)> = std::fs::read_dir(&dir)
        .expect("examples/models exists")
        .filter_map(|e| {
            let path = e.ok()?.path();
            let text = std::fs::read_to_string(&path).ok()?;
            path.extension()
                .is_some_and(|x| x == "dae")
                .then_some((path, text))
        })
        .collect();
    out.sort();
    assert!(out.len() >= 5);
    out.into_iter().map(|(_, t)| t).collect()
}

fn max_let(e: &RExpr) -> Option<usize> {
    let mut max = None;
    e.visit(&mut |x| {
        if let RExpr::Let(i) = x {
            max = max.max(Some(i.index()));
        }
    });
    max
}

fn check_invariants(m: &Model) {
    assert_eq!(m.ders.len(), m.states.len());
    if m.is_family() {
        // Counts of family models are checked at construction (they need sizes); the
        // defaults of scalar parameters are evaluated at the default sizes when possible.
        assert!(
            m.params
                .iter()
                .all(|p| p.family.over.is_some() || !p.default.is_infinite())
        );
    } else {
        assert_eq!(m.constraints.len(), m.algs.len());
        assert!(m.params.iter().all(|p| p.default.is_finite()));
    }
    // Each mass matrix is square over distinct states of the model, each in one matrix.
    let mut listed = std::collections::HashSet::new();
    for mass in &m.mass {
        let n = mass.states.len();
        assert_eq!(mass.entries.len(), n * n, "a mass matrix over {n} states");
        assert_eq!(mass.entry_spans.len(), n * n);
        for s in &mass.states {
            assert!(s.index() < m.states.len() && listed.insert(s.index()));
        }
    }
    for (i, l) in m.lets.iter().enumerate() {
        assert!(
            max_let(&l.expr).is_none_or(|j| j < i),
            "let {} uses a later let",
            l.name
        );
    }
}

/// Compiles `src`; on error, every diagnostic must point inside it and render.
fn run(src: &str) {
    match dae_lang::check_source(src) {
        Ok(models) => models.iter().for_each(check_invariants),
        Err(diags) => {
            assert!(!diags.is_empty());
            for d in &diags {
                assert!(
                    d.span.start <= d.span.end && d.span.end <= src.len(),
                    "{d:?}"
                );
                for (s, _) in &d.related {
                    assert!(s.start <= s.end && s.end <= src.len(), "{d:?}");
                }
                let text = d.render("fuzz.dae", src, false);
                assert!(text.contains(&d.message), "{text}");
            }
        }
    }
}

/// The text without its comments (block comments become a space).
fn strip_comments(src: &str) -> String {
    let mut out = String::new();
    let mut rest = src;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix("//") {
            rest = after.find('\n').map_or("", |k| &after[k..]);
        } else if let Some(after) = rest.strip_prefix("/*") {
            rest = after.find("*/").map_or("", |k| &after[k + 2..]);
            out.push(' ');
        } else {
            let c = rest.chars().next().unwrap_or(' ');
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    out
}

/// Splits a model into tokens (comments dropped): names and numbers (with exponents), single other
/// characters; white space
/// is dropped (tokens are re-joined with spaces, which the language ignores).
fn tokens(src: &str) -> Vec<String> {
    let src = strip_comments(src);
    let src = src.as_str();
    let mut out = Vec::new();
    let mut chars = src.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if c.is_whitespace() {
            continue;
        }
        let mut end = i + c.len_utf8();
        if c.is_ascii_alphanumeric() || c == '_' || c == '.' {
            while let Some(&(j, d)) = chars.peek() {
                let token = &src[i..end];
                let exponent_sign = matches!(d, '+' | '-')
                    && token.starts_with(|c: char| c.is_ascii_digit())
                    && token.ends_with(['e', 'E']);
                if d.is_ascii_alphanumeric() || d == '_' || d == '.' || exponent_sign {
                    end = j + 1;
                    chars.next();
                } else {
                    break;
                }
            }
        } else if let Some(&(j, d)) = chars.peek() {
            // The operators of two characters (version 2) are one token.
            if matches!(
                (c, d),
                ('-', '>') | ('=', '=') | ('!', '=') | ('<', '=') | ('>', '=')
            ) {
                end = j + d.len_utf8();
                chars.next();
            }
        }
        out.push(src[i..end].to_string());
    }
    out
}

const VOCABULARY: &[&str] = &[
    "model",
    "param",
    "state",
    "alg",
    "let",
    "der",
    "constraint",
    "t",
    "sin",
    "atan2",
    "pow",
    "x",
    "z1",
    "l1",
    "(",
    ")",
    "{",
    "}",
    ";",
    ",",
    ":",
    "=",
    "+",
    "-",
    "*",
    "/",
    "^",
    "0",
    "1e-3",
    "2.5E+4",
    "1e999",
    "//",
    "/*",
    "*/",
    "\n",
    "é",
];

#[derive(Clone, Debug)]
enum Edit {
    Delete(usize, usize),
    Insert(usize, Vec<u8>),
    Replace(usize, u8),
    Duplicate(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 1usize..12).prop_map(|(p, n)| Edit::Delete(p, n)),
        (any::<usize>(), prop::sample::select(VOCABULARY))
            .prop_map(|(p, v)| Edit::Insert(p, v.as_bytes().to_vec())),
        (any::<usize>(), any::<u8>()).prop_map(|(p, b)| Edit::Replace(p, b)),
        (any::<usize>(), 1usize..40).prop_map(|(p, n)| Edit::Duplicate(p, n)),
    ]
}

fn apply(bytes: &mut Vec<u8>, e: &Edit) {
    let len = bytes.len().max(1);
    match e {
        Edit::Delete(p, n) => {
            let p = p % len;
            let end = (p + n).min(bytes.len());
            if p < end {
                bytes.drain(p..end);
            }
        }
        Edit::Insert(p, v) => {
            let p = p % (bytes.len() + 1);
            bytes.splice(p..p, v.iter().copied());
        }
        Edit::Replace(p, b) => {
            if !bytes.is_empty() {
                let p = p % bytes.len();
                bytes[p] = *b;
            }
        }
        Edit::Duplicate(p, n) => {
            let p = p % len;
            let end = (p + n).min(bytes.len());
            if p < end {
                let copy = bytes[p..end].to_vec();
                bytes.splice(end..end, copy);
            }
        }
    }
}

#[derive(Clone, Debug)]
enum TokenEdit {
    Delete(usize),
    Insert(usize, &'static str),
    Swap(usize, usize),
    Copy(usize, usize),
}

fn token_edit() -> impl Strategy<Value = TokenEdit> {
    prop_oneof![
        any::<usize>().prop_map(TokenEdit::Delete),
        (any::<usize>(), prop::sample::select(VOCABULARY))
            .prop_map(|(p, v)| TokenEdit::Insert(p, v)),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| TokenEdit::Swap(a, b)),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| TokenEdit::Copy(a, b)),
    ]
}

fn apply_token(toks: &mut Vec<String>, e: &TokenEdit) {
    if toks.is_empty() {
        return;
    }
    let n = toks.len();
    match e {
        TokenEdit::Delete(p) => {
            toks.remove(p % n);
        }
        TokenEdit::Insert(p, v) => toks.insert(p % (n + 1), (*v).to_string()),
        TokenEdit::Swap(a, b) => toks.swap(a % n, b % n),
        TokenEdit::Copy(a, b) => {
            let t = toks[a % n].clone();
            toks.insert(b % (n + 1), t);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        run(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn random_text_over_the_alphabet_never_panics(
        src in "(model|state|param|alg|let|der|constraint|[a-z]{1,3}|[0-9.eE+-]{1,4}|[(){};:,=+*/^-]|//|/\\*|\\*/|[ \n]){0,80}"
    ) {
        run(&src);
    }

    #[test]
    fn byte_mutations_of_the_examples_never_panic(
        which in 0usize..64,
        edits in prop::collection::vec(edit(), 1..6),
    ) {
        let models = examples();
        let mut bytes = models[which % models.len()].clone().into_bytes();
        for e in &edits {
            apply(&mut bytes, e);
        }
        run(&String::from_utf8_lossy(&bytes));
    }

    /// Replacing names by other names (of the same model, reserved words, unknown ones)
    /// keeps the syntax valid, so these cases exercise the checker.
    #[test]
    fn name_substitutions_in_the_examples_never_panic(
        which in 0usize..64,
        swaps in prop::collection::vec((any::<usize>(), any::<usize>()), 1..6),
    ) {
        let models = examples();
        let mut toks = tokens(&models[which % models.len()]);
        let is_name = |t: &str| t.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_');
        let mut pool: Vec<String> = toks.iter().filter(|t| is_name(t)).cloned().collect();
        pool.extend(["t", "der", "sin", "atan2", "model", "unknown_name"].map(String::from));
        // Item keywords stay: replacing them breaks the syntax, which other tests cover.
        let keyword = |t: &str| matches!(t, "model" | "param" | "state" | "alg" | "let" | "der" | "constraint");
        let sites: Vec<usize> = (0..toks.len()).filter(|&i| is_name(&toks[i]) && !keyword(&toks[i])).collect();
        for (site, pick) in swaps {
            toks[sites[site % sites.len()]] = pool[pick % pool.len()].clone();
        }
        run(&toks.join(" "));
    }

    #[test]
    fn token_mutations_of_the_examples_never_panic(
        which in 0usize..64,
        edits in prop::collection::vec(token_edit(), 1..3),
    ) {
        let models = examples();
        let mut toks = tokens(&models[which % models.len()]);
        for e in &edits {
            apply_token(&mut toks, e);
        }
        run(&toks.join(" "));
    }
}

#[test]
fn token_round_trip_keeps_the_examples_valid() {
    // The token tests start from text that checks: the tokens of an example, re-joined
    // with spaces, give the same models.
    for src in examples() {
        let a = dae_lang::check_source(&src).expect("example checks");
        let b = dae_lang::check_source(&tokens(&src).join(" ")).expect("tokens re-joined check");
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.name, y.name);
            // Bits: a per-element parameter's default is NaN, which `==` never equals.
            assert_eq!(
                x.params
                    .iter()
                    .map(|p| p.default.to_bits())
                    .collect::<Vec<_>>(),
                y.params
                    .iter()
                    .map(|p| p.default.to_bits())
                    .collect::<Vec<_>>()
            );
            assert_eq!(
                x.ders.iter().map(|d| &d.expr).collect::<Vec<_>>(),
                y.ders.iter().map(|d| &d.expr).collect::<Vec<_>>()
            );
            assert_eq!(
                x.constraints
                    .iter()
                    .map(|c| &c.residual)
                    .collect::<Vec<_>>(),
                y.constraints
                    .iter()
                    .map(|c| &c.residual)
                    .collect::<Vec<_>>()
            );
        }
    }
    assert_eq!(strip_comments("a // b\nc /* d\n */ e"), "a \nc   e");
}
