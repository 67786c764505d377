//! The `dae!` macro as users meet it: a model that compiles and simulates, and models
//! whose mistakes must be compile errors pointing at the offending tokens (the pinned
//! `.stderr` files under `tests/ui/` show where rustc puts the caret).

#[test]
fn dae_macro_compiles_good_models_and_points_at_mistakes() {
    let t = trybuild::TestCases::new();
    t.pass("ui/pass_simulate.rs");
    t.compile_fail("ui/syntax_error.rs");
    t.compile_fail("ui/unknown_name.rs");
    t.compile_fail("ui/no_index.rs");
    t.compile_fail("ui/singular_start.rs");
}
