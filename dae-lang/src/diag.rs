//! Diagnostics: one type for every user error the compiler reports.

use crate::ast::Span;

/// A user error with the place it was made and a hint on how to fix it.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// One line saying what is wrong.
    pub message: String,
    /// Where (primary span, underlined).
    pub span: Span,
    /// Text shown under the underline.
    pub label: String,
    /// One line saying how to fix it.
    pub hint: Option<String>,
    /// Other relevant places, e.g. the first declaration of a duplicate name.
    pub related: Vec<(Span, String)>,
}
