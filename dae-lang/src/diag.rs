//! Diagnostics: one type for every user error the compiler reports.

use crate::ast::Span;
use ariadne::{CharSet, Color, Config, IndexType, Label, Report, ReportKind, Source};

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

impl Diagnostic {
    /// An error at `span` with a message and the label shown under the underline.
    pub(crate) fn new(message: impl Into<String>, span: Span, label: impl Into<String>) -> Self {
        Diagnostic {
            message: message.into(),
            span,
            label: label.into(),
            hint: None,
            related: Vec::new(),
        }
    }

    /// Adds the one-line hint.
    pub(crate) fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    /// Adds a related place with its own label.
    pub(crate) fn related(mut self, span: Span, label: impl Into<String>) -> Self {
        self.related.push((span, label.into()));
        self
    }

    /// Renders the diagnostic with its source context: a `file:line:col` header, the
    /// source lines involved with the spans underlined and labelled, and the hint.
    ///
    /// `color` adds ANSI colours (for a terminal); without it the text is plain, for
    /// files and tests. Spans outside `source` are clamped to it, so rendering never
    /// fails.
    ///
    /// ```
    /// let src = "model M {\n    state x = 0;\n    der(x) = y;\n}\n";
    /// let errors = dae_lang::check_source(src).unwrap_err();
    /// let text = errors[0].render("m.dae", src, false);
    /// assert!(text.contains("m.dae:3:14"));
    /// assert!(text.contains("unknown name `y`"));
    /// ```
    pub fn render(&self, file_name: &str, source: &str, color: bool) -> String {
        let clamp = |s: Span| {
            let end = floor_char_boundary(source, s.end.min(source.len()));
            let start = floor_char_boundary(source, s.start.min(end));
            start..end
        };
        let primary = clamp(self.span);
        let config = Config::default()
            .with_color(color)
            .with_index_type(IndexType::Byte)
            .with_char_set(CharSet::Unicode);
        // ariadne starts a new snippet (with a misleading header) whenever a label lies
        // on an earlier line than the previous one; ordering labels by position keeps
        // all of them in one snippet.
        let mut labels: Vec<(std::ops::Range<usize>, &str, Color)> =
            vec![(primary.clone(), &self.label, Color::Red)];
        labels.extend(
            self.related
                .iter()
                .map(|(s, l)| (clamp(*s), l.as_str(), Color::Blue)),
        );
        labels.sort_by_key(|(r, _, _)| r.start);
        let mut report = Report::build(ReportKind::Error, (file_name, primary))
            .with_config(config)
            .with_message(&self.message);
        for (i, (range, label, color)) in labels.into_iter().enumerate() {
            report = report.with_label(
                Label::new((file_name, range))
                    .with_message(label)
                    .with_color(color)
                    .with_order(i32::try_from(i).unwrap_or(i32::MAX)),
            );
        }
        if let Some(hint) = &self.hint {
            report = report.with_help(hint);
        }
        let mut out = Vec::new();
        // Writing into a Vec cannot fail; should ariadne ever fail, fall back to a
        // one-line rendering rather than losing the error.
        if report
            .finish()
            .write((file_name, Source::from(source)), &mut out)
            .is_err()
        {
            let (line, col) = line_col(source, self.span);
            return format!("error: {}\n --> {file_name}:{line}:{col}\n", self.message);
        }
        String::from_utf8_lossy(&out).into_owned()
    }
}

/// The 1-based line and column of the start of `span` in `source`.
///
/// Columns count characters (not bytes), so they match what an editor shows. Positions
/// past the end of `source` are clamped to its end.
pub fn line_col(source: &str, span: Span) -> (usize, usize) {
    let pos = floor_char_boundary(source, span.start.min(source.len()));
    let before = &source[..pos];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let col = before[line_start..].chars().count() + 1;
    (line, col)
}

/// The largest char boundary of `s` at or below `i` (`i <= s.len()`).
fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_is_one_based_and_counts_chars() {
        let src = "ab\ncdé f\n";
        assert_eq!(line_col(src, Span::new(0, 1)), (1, 1));
        assert_eq!(line_col(src, Span::new(3, 4)), (2, 1));
        // `é` is two bytes but one column.
        assert_eq!(line_col(src, Span::new(8, 9)), (2, 5));
        // Past the end: the end of the text.
        assert_eq!(line_col(src, Span::new(100, 100)), (3, 1));
    }

    #[test]
    fn render_without_color_has_header_underline_label_hint_and_related() {
        let src = "model M {\n    state x = 0, x = 1;\n}\n";
        let d = Diagnostic::new(
            "name `x` declared twice",
            Span::new(27, 28),
            "second declaration",
        )
        .hint("rename one of them")
        .related(Span::new(18, 19), "first declared here");
        let text = d.render("m.dae", src, false);
        assert!(
            !text.contains('\u{1b}'),
            "no escape codes without colour: {text}"
        );
        assert!(text.contains("Error: name `x` declared twice"), "{text}");
        assert!(text.contains("m.dae:2:18"), "{text}");
        assert!(text.contains("state x = 0, x = 1;"), "{text}");
        assert!(text.contains("second declaration"), "{text}");
        assert!(text.contains("first declared here"), "{text}");
        assert!(text.contains("Help: rename one of them"), "{text}");
        assert!(text.contains('─'), "underline drawn: {text}");
    }

    #[test]
    fn render_with_color_uses_escape_codes() {
        let src = "model M {}\n";
        let d = Diagnostic::new("bad", Span::new(6, 7), "here");
        assert!(d.render("m.dae", src, true).contains('\u{1b}'));
    }

    #[test]
    fn render_survives_spans_at_or_past_the_end_and_inside_chars() {
        let src = "model é";
        for span in [
            Span::new(7, 7),
            Span::new(9, 9),
            Span::new(7, 8),
            Span::new(50, 60),
        ] {
            let text = Diagnostic::new("m", span, "l").render("f", src, false);
            assert!(text.contains("Error: m"), "{text}");
        }
        let text = Diagnostic::new("m", Span::new(0, 0), "l").render("f", "", false);
        assert!(text.contains("Error: m"), "{text}");
        // Spans over line breaks, ends in the middle of a character.
        let src = "a\r\nbé\nc";
        for (s, e) in [
            (1, 2),
            (1, 3),
            (2, 3),
            (0, 5),
            (4, 6),
            (5, 6),
            (6, 7),
            (3, 9),
            (8, 9),
        ] {
            let d = Diagnostic::new("m", Span::new(s, e), "l").related(Span::new(e, s.max(e)), "r");
            assert!(d.render("f", src, false).contains("Error: m"));
        }
    }

    #[test]
    fn related_places_on_earlier_lines_share_the_snippet() {
        let src = "model M {\n    state x = 0;\n    der(x) = 1;\n    der(x) = 2;\n}\n";
        let d =
            Diagnostic::new("two", Span::new(47, 58), "second").related(Span::new(31, 42), "first");
        let text = d.render("m.dae", src, false);
        assert_eq!(text.matches("m.dae:").count(), 1, "{text}");
        assert!(text.contains("m.dae:4:5"), "{text}");
        let first = text.find("first").unwrap_or(usize::MAX);
        let second = text.find("second").unwrap_or(0);
        assert!(first < second, "labels in source order: {text}");
    }
}
