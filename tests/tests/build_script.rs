//! `dae_codegen::compile_file_to_out_dir`, the build-script entry point: it writes
//! formatted Rust into `OUT_DIR` that parses and defines the model's type, and reports
//! a bad file as rendered diagnostics. One test in this binary, because it sets the
//! process-wide `OUT_DIR`.

use dae_codegen::compile_file_to_out_dir;
use dae_tests::models_dir;

#[test]
fn compile_file_to_out_dir_writes_parsable_rust_defining_the_model_type_or_reports_errors() {
    let out = std::env::temp_dir().join(format!("dae-tests-build-script-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    // SAFETY: this test binary holds only this test, so no other thread reads the
    // environment meanwhile.
    unsafe { std::env::set_var("OUT_DIR", &out) };

    let written = compile_file_to_out_dir(models_dir().join("tank_level_index2.dae"))
        .expect("a valid model compiles");
    assert_eq!(written, out.join("tank_level_index2.rs"));
    let code = std::fs::read_to_string(&written).unwrap();
    let file = syn::parse_file(&code).expect("the written file is Rust");
    let has_struct = file
        .items
        .iter()
        .any(|i| matches!(i, syn::Item::Struct(s) if s.ident == "TankLevel"));
    assert!(has_struct, "no `struct TankLevel` in:\n{code}");
    let implements_model = file.items.iter().any(|i| match i {
        syn::Item::Impl(imp) => imp
            .trait_
            .as_ref()
            .is_some_and(|(_, path, _)| path.segments.last().is_some_and(|s| s.ident == "Model")),
        _ => false,
    });
    assert!(implements_model, "no `impl Model` in:\n{code}");

    let bad = out.join("bad.dae");
    std::fs::write(&bad, "model M {\n  state x = 0;\n  der(x) = -k * x;\n}\n").unwrap();
    let err = compile_file_to_out_dir(&bad).expect_err("an unknown name is an error");
    assert!(err.contains("unknown name `k`"), "{err}");
    assert!(err.contains("bad.dae:3:13"), "position of `k` in: {err}");
    assert!(
        !out.join("bad.rs").exists(),
        "nothing written for a bad model"
    );

    let missing = compile_file_to_out_dir(out.join("missing.dae")).expect_err("no such file");
    assert!(missing.starts_with("cannot read"), "{missing}");

    std::fs::remove_dir_all(&out).unwrap();
}
