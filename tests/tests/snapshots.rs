//! The generated Rust of every example model without families, pinned (one snapshot per
//! model). These are the code users compile: review a changed snapshot as you would
//! review code.

use dae_tests::scalar_example_sources;

#[test]
fn generated_code_of_every_example_model() {
    for (stem, text) in scalar_example_sources() {
        let models = dae_lang::compile_source(&text).unwrap_or_else(|e| panic!("{stem}: {e:?}"));
        let code: Vec<String> = models.iter().map(dae_codegen::emit_rust).collect();
        insta::assert_snapshot!(stem, code.join("\n"));
    }
}
