//! `daec emit` run as a process: the generated Rust of every model on stdout (the same
//! text as `dae_codegen::emit_rust`), user errors on stderr with exit status 1.

mod common;

use common::daec;

use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/models")
        .join(name)
}

#[test]
fn emit_prints_the_generated_rust_of_the_model() {
    let path = example("tank_level_index2.dae");
    let out = daec(&["emit", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let src = std::fs::read_to_string(&path).unwrap();
    let expected = dae_codegen::emit_rust(&dae_lang::compile_source(&src).unwrap()[0]);
    assert_eq!(text, expected);
    assert!(text.contains("impl ::dae_runtime::Model for TankLevel"));
}

#[test]
fn emit_prints_every_model_of_a_file() {
    let dir = std::env::temp_dir().join(format!("daec-emit-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("two.dae");
    std::fs::write(
        &path,
        "model A { state x = 1; der(x) = -x; }\nmodel B { state y = 2; der(y) = -2 * y; }\n",
    )
    .unwrap();
    let out = daec(&["emit", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("pub struct A {"), "{text}");
    assert!(text.contains("pub struct B {"), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn emit_reports_analysis_errors_with_exit_status_1() {
    let dir = std::env::temp_dir().join(format!("daec-emit-err-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("singular.dae");
    // Passes `daec check` (the syntax and names are fine) but not the analysis.
    std::fs::write(
        &path,
        "model S {\n  state x = 0;\n  alg z = 0;\n  der(x) = z^2;\n  constraint c: x = t;\n}\n",
    )
    .unwrap();
    let out = daec(&["emit", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty(), "no code for a bad model");
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("J_Omega is singular"), "{err}");
    assert!(err.contains("singular.dae:5:3"), "{err}");
    assert!(err.contains("error: 1 error in"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn emit_reports_a_missing_file() {
    let out = daec(&["emit", "/nonexistent/model.dae"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.starts_with("error: cannot read `/nonexistent/model.dae`"),
        "{err}"
    );
}
