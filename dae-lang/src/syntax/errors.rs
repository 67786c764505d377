//! Syntax errors: pest's error (a position and the rules it tried there) translated
//! into a [`Diagnostic`] in words a model author knows, with a hint.

use super::Rule;
use crate::ast::Span;
use crate::diag::{Diagnostic, line_col};
use pest::error::{Error, ErrorVariant, InputLocation};

/// What the parser expected, in the order the message lists them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Expected {
    Model,
    Item,
    Keyword(&'static str),
    Name,
    Integer,
    Expression,
    Token(&'static str),
    Operator,
    EndOfFile,
}

impl Expected {
    fn words(self) -> String {
        match self {
            Expected::Model => "`model`".into(),
            Expected::Item => {
                "an item (`param`, `state`, `alg`, `let`, `der` or `constraint`)".into()
            }
            Expected::Keyword(k) => format!("`{k}`"),
            Expected::Name => "a name".into(),
            Expected::Integer => "a whole number".into(),
            Expected::Expression => "an expression".into(),
            Expected::Token(t) => format!("`{t}`"),
            Expected::Operator => "an operator (`+ - * / ^`)".into(),
            Expected::EndOfFile => "the end of the file".into(),
        }
    }
}

const ITEM_KEYWORDS: [Rule; 6] = [
    Rule::kw_param,
    Rule::kw_state,
    Rule::kw_alg,
    Rule::kw_let,
    Rule::kw_der,
    Rule::kw_constraint,
];

/// The other item keywords (`mass`, and those of version 2): folded into "an item" with
/// the six above (the message names those; the hint lists these too).
const OTHER_ITEM_KEYWORDS: [Rule; 5] = [
    Rule::kw_mass,
    Rule::kw_size,
    Rule::kw_set,
    Rule::kw_map,
    Rule::kw_input,
];

fn expected_of(rule: Rule) -> Option<Expected> {
    Some(match rule {
        Rule::model | Rule::kw_model => Expected::Model,
        Rule::param_item | Rule::kw_param => Expected::Keyword("param"),
        Rule::state_item | Rule::kw_state => Expected::Keyword("state"),
        Rule::alg_item | Rule::kw_alg => Expected::Keyword("alg"),
        Rule::let_item | Rule::kw_let => Expected::Keyword("let"),
        Rule::der_item | Rule::kw_der => Expected::Keyword("der"),
        Rule::constraint_item | Rule::kw_constraint => Expected::Keyword("constraint"),
        Rule::mass_item | Rule::kw_mass => Expected::Keyword("mass"),
        Rule::size_item | Rule::kw_size => Expected::Keyword("size"),
        Rule::set_item | Rule::kw_set => Expected::Keyword("set"),
        Rule::map_item | Rule::kw_map => Expected::Keyword("map"),
        Rule::input_item | Rule::kw_input => Expected::Keyword("input"),
        Rule::kw_in => Expected::Keyword("in"),
        Rule::kw_where => Expected::Keyword("where"),
        Rule::with_clause | Rule::kw_with => Expected::Keyword("with"),
        Rule::kw_derivatives | Rule::kw_derivative => Expected::Keyword("derivatives"),
        Rule::kw_then => Expected::Keyword("then"),
        Rule::kw_else => Expected::Keyword("else"),
        Rule::ident | Rule::decl | Rule::input_decl | Rule::mass_state => Expected::Name,
        Rule::integer => Expected::Integer,
        Rule::expr
        | Rule::if_expr
        | Rule::kw_if
        | Rule::disj
        | Rule::conj
        | Rule::negation
        | Rule::kw_not
        | Rule::comparison
        | Rule::arith
        | Rule::product
        | Rule::unary
        | Rule::sum_expr
        | Rule::kw_sum
        | Rule::power
        | Rule::number
        | Rule::name
        | Rule::call
        | Rule::neg
        | Rule::mass_row => Expected::Expression,
        Rule::lbrace => Expected::Token("{"),
        Rule::rbrace => Expected::Token("}"),
        Rule::lparen => Expected::Token("("),
        Rule::rparen => Expected::Token(")"),
        Rule::comma => Expected::Token(","),
        Rule::semi => Expected::Token(";"),
        Rule::colon => Expected::Token(":"),
        Rule::assign => Expected::Token("="),
        Rule::lbracket | Rule::binder | Rule::der_elem | Rule::index => Expected::Token("["),
        Rule::rbracket => Expected::Token("]"),
        Rule::dot | Rule::field => Expected::Token("."),
        Rule::arrow => Expected::Token("->"),
        Rule::type_ann => Expected::Token(":"),
        Rule::add_op | Rule::mul_op | Rule::pow_op | Rule::cmp_op | Rule::kw_and | Rule::kw_or => {
            Expected::Operator
        }
        Rule::EOI => Expected::EndOfFile,
        _ => return None,
    })
}

/// The list of expected things, deduplicated, in a fixed order, with the six item
/// keywords merged into "an item".
fn expected_list(positives: &[Rule]) -> Vec<Expected> {
    let mut list: Vec<Expected> = positives.iter().filter_map(|&r| expected_of(r)).collect();
    let is_item_kw = |e: &Expected| ITEM_KEYWORDS.iter().any(|&k| expected_of(k) == Some(*e));
    if ITEM_KEYWORDS
        .iter()
        .all(|&k| list.contains(&expected_of(k).unwrap_or(Expected::Item)))
    {
        let is_other_kw = |e: &Expected| {
            OTHER_ITEM_KEYWORDS
                .iter()
                .any(|&k| expected_of(k) == Some(*e))
        };
        list.retain(|e| !is_item_kw(e) && !is_other_kw(e));
        list.push(Expected::Item);
    }
    // After a name, `(` would start a call, `[` an element access and `.` a component;
    // listing them next to the operators only confuses ("expected `(`, `;` or an
    // operator").
    if list.contains(&Expected::Operator) {
        list.retain(|e| !matches!(e, Expected::Token("(" | "[" | ".")));
    }
    list.sort();
    list.dedup();
    list
}

fn join_or(parts: &[String]) -> String {
    match parts {
        [] => "something else".into(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// The token found at `pos`, as shown to the user, and its span.
fn found_at(src: &str, pos: usize) -> (String, Span) {
    let rest = &src[pos..];
    let Some(first) = rest.chars().next() else {
        return ("the end of the file".into(), Span::new(pos, pos));
    };
    let len = if rest.starts_with("/*") {
        2
    } else if first.is_ascii_alphabetic() || first == '_' {
        rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len())
    } else if first.is_ascii_digit() {
        rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '.'))
            .unwrap_or(rest.len())
    } else {
        first.len_utf8()
    };
    let text = &rest[..len];
    let shown = match text {
        "\n" | "\r" => "a line break".to_string(),
        "\t" => "a tab".to_string(),
        _ if first.is_control() => format!("the character U+{:04X}", first as u32),
        _ => format!("`{text}`"),
    };
    (shown, Span::new(pos, pos + len))
}

/// The end of the last token before `pos` (skipping only white space).
fn previous_token_end(src: &str, pos: usize) -> usize {
    src[..pos].trim_end().len()
}

/// Whether `text` starts with an item keyword (as a whole word).
fn starts_with_keyword(text: &str) -> bool {
    let word = text
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .next();
    matches!(
        word,
        Some(
            "model"
                | "param"
                | "state"
                | "alg"
                | "let"
                | "der"
                | "constraint"
                | "size"
                | "set"
                | "map"
                | "input"
        )
    )
}

/// The last item keyword written before `pos` (a rough scan, used only for hints).
fn last_keyword(src: &str, pos: usize) -> Option<&str> {
    src[..pos]
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .rev()
        .find(|w| starts_with_keyword(w))
}

/// The text of the current item up to `pos` (from the last `;`, `{` or `}` before it).
fn item_text(src: &str, pos: usize) -> &str {
    let start = src[..pos].rfind([';', '{', '}']).map_or(0, |i| i + 1);
    &src[start..pos]
}

/// A hint for the most common mistakes at this place; a general one otherwise.
fn hint(src: &str, pos: usize, expected: &[Expected]) -> String {
    let rest = &src[pos..];
    let prev_end = previous_token_end(src, pos);
    let prev = src[..prev_end].chars().next_back();
    let expects = |e: Expected| expected.contains(&e);
    if rest.starts_with("/*") {
        return "this block comment is never closed: end it with `*/`".into();
    }
    if rest.starts_with('.') && prev.is_some_and(|c| c.is_ascii_digit()) {
        return "write digits on both sides of a decimal point, e.g. `0.5` or `2.0`".into();
    }
    if rest.starts_with('=') && prev == Some('=') {
        return "equations use a single `=`".into();
    }
    if expects(Expected::Token("=")) && item_text(src, pos).contains("==") {
        return "equations use a single `=` (`==` compares, in construction-time expressions)"
            .into();
    }
    if expects(Expected::Operator)
        && prev_end == pos
        && prev.is_some_and(|c| c.is_ascii_digit())
        && rest.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
    {
        return "to multiply, write `*` between a number and a name: `2 * x`".into();
    }
    if expects(Expected::Token(";"))
        && rest.starts_with(',')
        && last_keyword(src, pos) == Some("let")
    {
        return "a `let` defines one name: write each definition as its own `let ...;`".into();
    }
    if expects(Expected::Token(";")) && src[prev_end..pos].contains('\n') {
        let (line, _) = line_col(src, Span::new(prev_end, prev_end));
        return format!("every item ends with `;`: is one missing at the end of line {line}?");
    }
    if expects(Expected::Token(";")) && starts_with_keyword(rest) {
        return "every item ends with `;`: is one missing before this word?".into();
    }
    if expects(Expected::Operator)
        && rest.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == '(')
    {
        return "two terms need an operator between them, e.g. `a * b`".into();
    }
    if expects(Expected::Token(";")) {
        return "every item ends with `;`".into();
    }
    if expects(Expected::Token(")")) {
        return "a `(` is not closed: add `)`, or a `,` between the arguments of a call".into();
    }
    if rest.is_empty() && expects(Expected::Token("}")) {
        return "the model is not closed: end it with `}`".into();
    }
    if expects(Expected::Item) {
        return "a model holds items that start with `param`, `state`, `alg`, `let`, `der`, \
                `mass` or `constraint` (and, for families, `size`, `set`, `map` or `input`), each \
                ending with `;`"
            .into();
    }
    if expects(Expected::Model) {
        return "a file holds one or more models: `model Name { ... }`".into();
    }
    if expects(Expected::Expression) {
        return "an expression is a number, a name, `t`, a call such as `sin(x)`, or an \
                expression in parentheses"
            .into();
    }
    if expects(Expected::Name) {
        return "a name starts with a letter or `_` followed by letters, digits or `_`".into();
    }
    "see docs/language.md for the syntax of `.dae` models".into()
}

/// Translates a pest error into a diagnostic.
pub(super) fn translate(e: &Error<Rule>, src: &str) -> Diagnostic {
    let pos = match e.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    let pos = pos.min(src.len());
    let (found, found_span) = found_at(src, pos);
    match &e.variant {
        ErrorVariant::ParsingError { positives, .. } => {
            let expected = expected_list(positives);
            let words: Vec<String> = expected.iter().map(|x| x.words()).collect();
            let message = format!("expected {}, found {found}", join_or(&words));
            let label = if found_span.start == found_span.end {
                "the file ends here".to_string()
            } else {
                "unexpected here".to_string()
            };
            Diagnostic::new(message, found_span, label).hint(hint(src, pos, &expected))
        }
        ErrorVariant::CustomError { message } => {
            // pest's only custom errors are its call and stack limits, reached by
            // expressions nested absurdly deep.
            Diagnostic::new(
                format!("the parser gave up here ({message}): expression nested too deeply"),
                found_span,
                "here",
            )
            .hint("split the expression into several `let` definitions")
        }
    }
}

/// The error for a successful parse that produced no tree (not expected to happen).
pub(super) fn empty_parse(src: &str) -> Diagnostic {
    Diagnostic::new(
        "internal error: the parser produced no tree",
        Span::new(0, src.len()),
        "",
    )
    .hint("please report this model as a bug of the `.dae` parser")
}
