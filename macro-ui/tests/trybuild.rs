//! The `dae!` macro as users meet it: a model that compiles and simulates, and models
//! whose mistakes must be compile errors pointing at the offending tokens (the pinned
//! `.stderr` files under `tests/ui/` show where rustc puts the caret). Also the Rust
//! that `daec emit` prints (`dae_codegen::emit_rust`) for models whose names are Rust
//! keywords or types compiles: one test in this binary, because it sets the
//! process-wide `DAE_EMITTED_NAMES`.

use std::path::Path;

#[test]
fn dae_macro_compiles_good_models_and_points_at_mistakes() {
    let ui = Path::new(env!("CARGO_MANIFEST_DIR")).join("ui");
    let src = std::fs::read_to_string(ui.join("names.dae")).expect("tests/ui/names.dae");
    let models = dae_lang::compile_source(&src).expect("names.dae passes the checks");
    let code: String = models.iter().map(dae_codegen::emit_rust).collect();
    // Formatted, so `syn` accepted the code (`emit_rust` falls back to the raw tokens).
    assert!(code.contains("\npub struct Self_ {\n"), "{code}");
    let emitted = Path::new(env!("CARGO_TARGET_TMPDIR")).join("emitted_names.rs");
    std::fs::write(&emitted, code).expect("write the emitted code");
    // SAFETY: this test binary holds only this test, so no other thread reads the
    // environment meanwhile; the cargo run by trybuild inherits it.
    unsafe { std::env::set_var("DAE_EMITTED_NAMES", &emitted) };

    let t = trybuild::TestCases::new();
    t.pass("ui/pass_simulate.rs");
    t.pass("ui/pass_emitted_names.rs");
    t.compile_fail("ui/syntax_error.rs");
    t.compile_fail("ui/unknown_name.rs");
    t.compile_fail("ui/no_index.rs");
    t.compile_fail("ui/singular_start.rs");
}
