//! The second front door: model text given as Rust tokens (the `dae!` macro).
//!
//! Rust has already split the text into tokens (and dropped the comments). We print
//! them back as text, one token after another with a space between, and remember
//! which byte range of that text each token came from. The text then goes through the
//! same parser as a `.dae` file, so both front ends produce the same AST by
//! construction, and any diagnostic's byte span maps back to the token it points at.

use proc_macro2::{Delimiter, Span, TokenStream, TokenTree};

use crate::ast;

/// Model text rebuilt from tokens, with the way back from byte offsets to token spans.
#[derive(Debug)]
pub struct TokenSource {
    text: String,
    /// `(start, end, span)` of each token's text, in increasing `start` order.
    spans: Vec<(usize, usize, Span)>,
}

impl TokenSource {
    /// Rebuild the text of `tokens`.
    pub fn new(tokens: TokenStream) -> Self {
        let mut src = TokenSource {
            text: String::new(),
            spans: Vec::new(),
        };
        src.push_stream(tokens);
        src
    }

    /// The rebuilt text, ready for the parser.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The span of the token that contains byte `span.start` (or the nearest token
    /// before it, for a span that starts in the space between two tokens or at the end).
    pub fn span_of(&self, span: ast::Span) -> Span {
        let k = self
            .spans
            .partition_point(|(start, _, _)| *start <= span.start);
        match k.checked_sub(1).and_then(|k| self.spans.get(k)) {
            Some((_, _, s)) => *s,
            None => Span::call_site(),
        }
    }

    fn push_token(&mut self, text: &str, span: Span) {
        if !self.text.is_empty() {
            self.text.push(' ');
        }
        let start = self.text.len();
        self.text.push_str(text);
        self.spans.push((start, self.text.len(), span));
    }

    fn push_stream(&mut self, tokens: TokenStream) {
        for tree in tokens {
            match tree {
                TokenTree::Group(g) => {
                    let (open, close) = match g.delimiter() {
                        Delimiter::Parenthesis => ("(", ")"),
                        Delimiter::Brace => ("{", "}"),
                        Delimiter::Bracket => ("[", "]"),
                        Delimiter::None => ("", ""),
                    };
                    if !open.is_empty() {
                        self.push_token(open, g.span_open());
                    }
                    self.push_stream(g.stream());
                    if !close.is_empty() {
                        self.push_token(close, g.span_close());
                    }
                }
                TokenTree::Ident(i) => self.push_token(&i.to_string(), i.span()),
                TokenTree::Punct(p) => self.push_token(&p.as_char().to_string(), p.span()),
                TokenTree::Literal(l) => self.push_token(&l.to_string(), l.span()),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rebuilds_text_token_by_token() {
        let ts: TokenStream = "model M { der(x) = -x^2 * 1e-3; }".parse().unwrap();
        let src = TokenSource::new(ts);
        assert_eq!(src.text(), "model M { der ( x ) = - x ^ 2 * 1e-3 ; }");
    }

    #[test]
    fn byte_offsets_map_to_the_token_that_holds_them() {
        let ts: TokenStream = "a + bcd".parse().unwrap();
        let src = TokenSource::new(ts);
        // "a + bcd": `bcd` starts at byte 4; every offset inside it maps to its span.
        let col = |b| src.span_of(ast::Span::new(b, b + 1)).start().column;
        assert_eq!(col(4), 4);
        assert_eq!(col(6), 4);
        assert_eq!(col(2), 2);
        assert_eq!(col(0), 0);
    }
}
