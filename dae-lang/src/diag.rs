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
        Renderer::new(file_name, source, color).render(self)
    }
}

/// Renders diagnostics of one source text as [`Diagnostic::render`] does, with the index
/// of the text's lines built once: rendering many diagnostics costs their number plus
/// the length of the text, not their number times it.
///
/// ```
/// let src = "model M {\n    state x = 0;\n    der(x) = y + w;\n}\n";
/// let errors = dae_lang::check_source(src).unwrap_err();
/// let renderer = dae_lang::Renderer::new("m.dae", src, false);
/// let texts: Vec<String> = errors.iter().map(|d| renderer.render(d)).collect();
/// assert!(texts[1].contains("m.dae:3:18"));
/// ```
pub struct Renderer<'a> {
    file_name: &'a str,
    /// The text as given (spans are byte offsets into it).
    full: &'a str,
    /// The text after a byte order mark, which is not shown.
    shown: &'a str,
    /// Bytes skipped at the start (3 after a byte order mark, else 0).
    shift: usize,
    lines: Source<&'a str>,
    color: bool,
}

impl<'a> Renderer<'a> {
    /// A renderer for diagnostics of `source`, a file called `file_name`; `color` adds
    /// ANSI colours.
    pub fn new(file_name: &'a str, source: &'a str, color: bool) -> Self {
        // A byte order mark is not shown: render the text after it, spans moved back.
        let shift = if source.starts_with('\u{feff}') { 3 } else { 0 };
        let shown = &source[shift..];
        Renderer {
            file_name,
            full: source,
            shown,
            shift,
            lines: Source::from(shown),
            color,
        }
    }

    /// One diagnostic with its source context (see [`Diagnostic::render`]).
    pub fn render(&self, d: &Diagnostic) -> String {
        let (file_name, source, shift) = (self.file_name, self.shown, self.shift);
        let clamp = |s: Span| {
            let end = floor_char_boundary(source, s.end.saturating_sub(shift).min(source.len()));
            let start = floor_char_boundary(source, s.start.saturating_sub(shift).min(end));
            start..end
        };
        let primary = clamp(d.span);
        let config = Config::default()
            .with_color(self.color)
            .with_index_type(IndexType::Byte)
            .with_char_set(CharSet::Unicode);
        // ariadne starts a new snippet (with a misleading header) whenever a label lies
        // on an earlier line than the previous one; ordering labels by position keeps
        // all of them in one snippet.
        let mut labels: Vec<(std::ops::Range<usize>, &str, Color)> =
            vec![(primary.clone(), &d.label, Color::Red)];
        labels.extend(
            d.related
                .iter()
                .map(|(s, l)| (clamp(*s), l.as_str(), Color::Blue)),
        );
        labels.sort_by_key(|(r, _, _)| r.start);
        let mut report = Report::build(ReportKind::Error, (file_name, primary))
            .with_config(config)
            .with_message(&d.message);
        for (i, (range, label, color)) in labels.into_iter().enumerate() {
            report = report.with_label(
                Label::new((file_name, range))
                    .with_message(label)
                    .with_color(color)
                    .with_order(i32::try_from(i).unwrap_or(i32::MAX)),
            );
        }
        if let Some(hint) = &d.hint {
            report = report.with_help(hint);
        }
        let mut out = Vec::new();
        // Writing into a Vec cannot fail; should ariadne ever fail, fall back to a
        // one-line rendering rather than losing the error.
        if report
            .finish()
            .write((file_name, &self.lines), &mut out)
            .is_err()
        {
            let (line, col) = line_col(self.full, d.span);
            return format!("error: {}\n --> {file_name}:{line}:{col}\n", d.message);
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
    let line_no = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    // A byte order mark at the start of the text is not shown by editors: not a column.
    let line = &before[line_start..];
    let line = if line_start == 0 {
        line.strip_prefix('\u{feff}').unwrap_or(line)
    } else {
        line
    };
    let col = line.chars().count() + 1;
    (line_no, col)
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

    #[test]
    fn a_byte_order_mark_is_neither_shown_nor_counted() {
        let src = "\u{feff}model M {\n    der(x) = y;\n}\n";
        let d = Diagnostic::new("m", Span::new(9, 10), "the name");
        let text = d.render("m.dae", src, false);
        assert!(text.contains("m.dae:1:7"), "{text}");
        assert!(!text.contains('\u{feff}'), "{text}");
        let d = Diagnostic::new("m", Span::new(26, 27), "y");
        assert!(d.render("m.dae", src, false).contains("m.dae:2:14"));
        assert_eq!(line_col(src, Span::new(26, 27)), (2, 14));
    }
}
