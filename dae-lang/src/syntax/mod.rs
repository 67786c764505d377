//! The `.dae` file front end: a pest grammar (`dae.pest`) and the translation of its
//! parse tree into the [`crate::ast`].

mod build;
mod build_expr;
mod errors;
// Generated from `dae.pest` and checked in (see its header), so that dae-lang needs no
// proc-macro toolchain; a test in dae-tests fails when it is stale.
#[rustfmt::skip]
#[allow(clippy::all, dead_code, missing_docs)]
mod parser;

use crate::ast::{File, Span};
use crate::diag::Diagnostic;
use parser::DaeParser;
pub(crate) use parser::Rule;
use pest::Parser as _;

/// Longest source text accepted, in bytes (16 MiB): far above any model written by hand
/// or generated for the families of the language, and a bound on the work and memory of
/// every later stage.
pub const MAX_SOURCE_BYTES: usize = 16 * 1024 * 1024;

/// Deepest nesting of parentheses, brackets, calls, `^` chains and `if`/`sum` forms
/// accepted (see [`too_deep`]).
/// The parser and the tree builder recurse through several frames per level; 64 levels
/// stay well inside a 2 MB thread stack even in an unoptimised build.
pub(crate) const MAX_NESTING: usize = 64;

/// Deepest expression tree accepted (a leaf has depth 1; `a + b + c` has depth 3).
/// Later stages walk expressions recursively, one small frame per level.
pub(crate) const MAX_DEPTH: usize = 256;

/// Parses a whole `.dae` source text.
pub(crate) fn parse(src: &str) -> Result<File, Vec<Diagnostic>> {
    if src.len() > MAX_SOURCE_BYTES {
        return Err(vec![too_long(src)]);
    }
    // A UTF-8 byte order mark, which some editors write at the start of a file, is read
    // as white space: three spaces in its place keep every byte offset (every span)
    // the same as in `src`.
    let without_bom;
    let src = match src.strip_prefix('\u{feff}') {
        Some(rest) => {
            without_bom = format!("   {rest}");
            without_bom.as_str()
        }
        None => src,
    };
    if let Some(at) = too_deep(src) {
        return Err(vec![
            Diagnostic::new(
                format!(
                    "expression nested too deeply (more than {MAX_NESTING} levels of \
                     parentheses, brackets, calls, `^`, `if` and `sum`)"
                ),
                at,
                "too deep here",
            )
            .hint("split the expression into several `let` definitions"),
        ]);
    }
    match DaeParser::parse(Rule::file, src) {
        Ok(mut pairs) => match pairs.next() {
            Some(file) => build::file(file),
            // pest always yields the `file` pair on success; report rather than panic.
            None => Err(vec![errors::empty_parse(src)]),
        },
        Err(e) => Err(vec![errors::translate(&e, src)]),
    }
}

/// The error for a source text longer than [`MAX_SOURCE_BYTES`], at the first byte past
/// the limit.
fn too_long(src: &str) -> Diagnostic {
    let mut at = MAX_SOURCE_BYTES;
    while !src.is_char_boundary(at) {
        at -= 1;
    }
    Diagnostic::new(
        format!(
            "the source text is {} bytes long, more than the limit of 16 MiB ({MAX_SOURCE_BYTES} bytes)",
            src.len()
        ),
        Span::new(at, at + 1),
        "the limit is reached here",
    )
    .hint("split the models over several files")
}

/// The place where the nesting of parentheses and `^` first exceeds [`MAX_NESTING`],
/// found by a scan of the text before parsing.
///
/// The parser and the tree builder recurse once per level of parentheses (calls
/// included) and brackets, and once per `^` of a chain such as `a^b^c` (right
/// associative); sums and chains of unary minus are handled by loops. The forms
/// `if ... then ... else ...`, `not ...` and `sum(...) body` recurse without brackets; each counts
/// as one level until the end of the item (a rough but safe bound: no model nests 64 of
/// them). Bounding these levels before pest runs keeps every recursion far from the end
/// of the stack, whatever the input.
fn too_deep(src: &str) -> Option<Span> {
    let bytes = src.as_bytes();
    // For each open parenthesis level, the `^` counted so far in its current chain.
    let mut pows: Vec<usize> = vec![0];
    // The levels open: one per open parenthesis (a call's included) and one per `^` of
    // the current chains. `((x))` is 2 levels, `2^2^x` is 2, `sin(2^x)` is 2.
    let mut depth = 0usize;
    let mut prev = b' '; // previous significant byte
    let mut keyword_levels = 0usize; // `if` and `sum` seen in the current item
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i = src[i..].find('\n').map_or(bytes.len(), |k| i + k);
                continue;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => match src[i + 2..].find("*/") {
                Some(k) => {
                    i += k + 4;
                    continue;
                }
                // An unclosed comment is the parser's error to report.
                None => return None,
            },
            // Names and numbers are skipped whole, so that the sign of an exponent
            // (`1e-3`) is not taken for a minus that ends a `^` chain.
            b'a'..=b'z' | b'A'..=b'Z' | b'_' => {
                let len = token_len(&bytes[i..], |c| c.is_ascii_alphanumeric() || c == b'_');
                if matches!(&src[i..i + len], "if" | "sum" | "not") {
                    keyword_levels += 1;
                    if depth + keyword_levels > MAX_NESTING {
                        return Some(Span::new(i, i + len));
                    }
                }
                i += len;
                prev = b'a';
                continue;
            }
            b'0'..=b'9' => {
                i += number_len(&bytes[i..]);
                prev = b'0';
                continue;
            }
            b'(' | b'[' => {
                pows.push(0);
                depth += 1;
            }
            b')' | b']' if pows.len() > 1 => depth -= 1 + pows.pop().unwrap_or(0),
            b'^' => {
                if let Some(p) = pows.last_mut() {
                    *p += 1;
                }
                depth += 1;
            }
            b'-' if !(prev.is_ascii_alphanumeric() || matches!(prev, b'_' | b'.' | b')')) => {}
            b'+' | b'-' | b'*' | b'/' | b',' | b';' | b'=' | b':' | b'{' | b'}' | b'<' | b'>'
            | b'!' => {
                if let Some(p) = pows.last_mut() {
                    depth -= *p;
                    *p = 0;
                }
                if matches!(b, b';' | b'{' | b'}') {
                    keyword_levels = 0;
                }
            }
            _ => {}
        }
        if !b.is_ascii_whitespace() {
            prev = b;
        }
        if depth + keyword_levels > MAX_NESTING {
            return Some(Span::new(i, i + 1));
        }
        i += 1;
    }
    None
}

/// The length of the leading run of bytes satisfying `f`.
fn token_len(bytes: &[u8], f: impl Fn(u8) -> bool) -> usize {
    bytes.iter().position(|&c| !f(c)).unwrap_or(bytes.len())
}

/// The length of the number at the start of `bytes` (which starts with a digit), as
/// the grammar reads it: digits, optionally `.` and digits, optionally an exponent.
fn number_len(bytes: &[u8]) -> usize {
    let digits = |from: usize| token_len(&bytes[from.min(bytes.len())..], |c| c.is_ascii_digit());
    let mut n = digits(0);
    if bytes.get(n) == Some(&b'.') && digits(n + 1) > 0 {
        n += 1 + digits(n + 1);
    }
    if matches!(bytes.get(n), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(bytes.get(n + 1), Some(b'+' | b'-')));
        let exp = digits(n + 1 + sign);
        if exp > 0 {
            n += 1 + sign + exp;
        }
    }
    n
}

#[cfg(test)]
mod tests;
