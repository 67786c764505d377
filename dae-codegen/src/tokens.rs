//! The second front door: model text given as Rust tokens (the `dae!` macro).
//!
//! Rust has already split the text into tokens (and dropped the comments). We print
//! them back as text, one token after another with a space between, and remember
//! which byte range of that text each token came from. Punctuation that Rust marks as
//! joined to the next character (`==`, `<=`, `->`: each is two `Punct`s, the first with
//! `Spacing::Joint`) is printed without the space, so that multi-character operators of
//! the language come back whole. The text then goes through the
//! same parser as a `.dae` file, so both front ends produce the same AST by
//! construction, and any diagnostic's byte span maps back to the token it points at.

use proc_macro2::{Delimiter, Spacing, Span, TokenStream, TokenTree};

use dae_lang::ast;

/// Model text rebuilt from tokens, with the way back from byte offsets to token spans.
#[derive(Debug)]
pub struct TokenSource {
    text: String,
    /// `(start, end, span)` of each token's text, in increasing `start` order.
    spans: Vec<(usize, usize, Span)>,
    /// The last token was punctuation joined to the next one (no space follows).
    joint: bool,
}

impl TokenSource {
    /// Rebuild the text of `tokens`.
    pub fn new(tokens: TokenStream) -> Self {
        let mut src = TokenSource {
            text: String::new(),
            spans: Vec::new(),
            joint: false,
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

    /// The spans of the first and the last token that `span` covers, for an error that
    /// underlines the whole range (a proc macro cannot join spans on stable Rust, but
    /// an error whose tokens start at one span and end at another covers both).
    pub fn span_range(&self, span: ast::Span) -> (Span, Span) {
        let first = self.span_of(span);
        let last_byte = span.end.max(span.start + 1) - 1;
        let last = self.span_of(ast::Span::new(last_byte, last_byte + 1));
        (first, last)
    }

    fn push_token(&mut self, text: &str, span: Span) {
        if !self.text.is_empty() && !self.joint {
            self.text.push(' ');
        }
        self.joint = false;
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
                TokenTree::Punct(p) => {
                    self.push_token(&p.as_char().to_string(), p.span());
                    self.joint = p.spacing() == Spacing::Joint;
                }
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
    fn joined_punctuation_comes_back_whole() {
        let ts: TokenStream = "map a[l in L] -> P = l; x == y; a <= b; c*-d"
            .parse()
            .unwrap();
        let src = TokenSource::new(ts);
        assert_eq!(
            src.text(),
            "map a [ l in L ] -> P = l ; x == y ; a <= b ; c *- d"
        );
        // Every byte of a joined operator maps to a token of it.
        let at = src.text().find("->").unwrap();
        let col = |b| src.span_of(ast::Span::new(b, b + 1)).start().column;
        assert_eq!(col(at), 14);
        assert_eq!(col(at + 1), 15);
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

    #[test]
    fn a_range_maps_to_its_first_and_last_token() {
        let ts: TokenStream = "a + bcd ; e".parse().unwrap();
        let src = TokenSource::new(ts);
        let cols = |a, b| {
            let (first, last) = src.span_range(ast::Span::new(a, b));
            (first.start().column, last.start().column)
        };
        assert_eq!(cols(0, 7), (0, 4), "`a + bcd`");
        assert_eq!(cols(4, 5), (4, 4), "inside one token");
        assert_eq!(cols(8, 8), (8, 8), "an empty span at `;`");
    }
}
