//! Both front ends (the pest parser over a `.dae` file, and the token front end behind
//! `dae!` which rebuilds text from Rust tokens) give the same syntax tree for every
//! example model, up to spans (and comments, which Rust's tokenizer drops).

use dae_codegen::TokenSource;
use dae_tests::example_sources;
use proc_macro2::TokenStream;

#[test]
fn token_front_end_gives_the_same_ast_as_the_file_parser_for_every_example() {
    let sources = example_sources();
    assert!(
        sources.len() >= 6,
        "example models found: {}",
        sources.len()
    );
    for (name, text) in &sources {
        let mut from_file = dae_lang::parse(text).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let tokens: TokenStream = text
            .parse()
            .unwrap_or_else(|e| panic!("{name}: not Rust tokens: {e}"));
        let rebuilt = TokenSource::new(tokens);
        let mut from_tokens = dae_lang::parse(rebuilt.text())
            .unwrap_or_else(|e| panic!("{name}: token text does not parse: {e:?}"));
        assert!(!from_file.models.is_empty(), "{name}: no model");
        from_file.erase_spans();
        from_tokens.erase_spans();
        assert_eq!(from_file, from_tokens, "{name}: the front ends disagree");
    }
}
