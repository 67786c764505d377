//! dae-lang's parser is generated from its grammar (`dae-lang/src/syntax/dae.pest`) by
//! pest's generator and checked in (`dae-lang/src/syntax/parser.rs`), so that dae-lang
//! itself pulls no proc-macro toolchain (syn, quote) into the builds of its users, as
//! pest_meta does for its own grammar. This test regenerates it and fails if the
//! checked-in file is stale; `DAE_REGENERATE_PARSER=1 cargo test -p dae-tests --test
//! parser` rewrites it.

use std::path::Path;

const HEADER: &str = "\
// @generated from dae.pest by pest_generator: do not edit.
// Regenerate with `DAE_REGENERATE_PARSER=1 cargo test -p dae-tests --test parser`.
";

fn generate(grammar: &str) -> String {
    let input: proc_macro2::TokenStream =
        format!("#[derive(Parser)] #[grammar_inline = {grammar:?}] pub(crate) struct DaeParser;")
            .parse()
            .expect("derive input tokens");
    let tokens = pest_generator::derive_parser(input, false);
    let file: syn::File = syn::parse2(tokens).expect("pest_generator emits a valid Rust file");
    format!(
        "{HEADER}\n/// The parser of the `.dae` grammar.\npub(crate) struct DaeParser;\n\n{}",
        prettyplease::unparse(&file)
    )
}

#[test]
fn checked_in_parser_matches_the_grammar() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../dae-lang/src/syntax");
    let grammar = std::fs::read_to_string(dir.join("dae.pest")).expect("read dae.pest");
    let fresh = generate(&grammar);
    let path = dir.join("parser.rs");
    if std::env::var_os("DAE_REGENERATE_PARSER").is_some() {
        std::fs::write(&path, &fresh).expect("write parser.rs");
        return;
    }
    let current = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        current == fresh,
        "dae-lang/src/syntax/parser.rs is not the parser of dae.pest: after changing the \
         grammar, run `DAE_REGENERATE_PARSER=1 cargo test -p dae-tests --test parser` and \
         commit the result"
    );
}
