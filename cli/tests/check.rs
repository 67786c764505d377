//! `daec check` run as a process: summaries, JSON, and user errors (exit status 1, all
//! diagnostics on stderr, no panic).

mod common;

use common::{daec, example};

use std::path::PathBuf;
use std::process::{Command, Output};

/// A file in a fresh temporary directory of this test process.
fn temp_file(name: &str, contents: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("daec-check-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write temp file");
    path
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn every_example_checks_with_a_summary() {
    for name in [
        "double_pendulum_planar.dae",
        "double_pendulum_3d.dae",
        "circuit_index1.dae",
        "tank_level_index2.dae",
        "integrator_chain_index4.dae",
    ] {
        let o = daec(&["check", &example(name)]);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
        assert!(stdout(&o).contains("1 model OK"), "{}", stdout(&o));
        assert!(stderr(&o).is_empty(), "{}", stderr(&o));
    }
    let o = daec(&["check", &example("double_pendulum_planar.dae")]);
    let text = stdout(&o);
    assert!(text.contains("model DoublePendulum\n"), "{text}");
    assert!(
        text.contains("states      (8): x1, y1, vx1, vy1, x2, y2, vx2, vy2"),
        "{text}"
    );
    assert!(text.contains("algebraics  (2): z1, z2"), "{text}");
    assert!(
        text.contains("parameters  (5): m1 = 0.1, m2 = 0.1, L1 = 2, L2 = 2, g = 9.8"),
        "{text}"
    );
    assert!(
        text.contains(
            "  constraints (2):\n    name   index  depends on\n    link1      3  z1, z2\n    link2      3  z1, z2\n"
        ),
        "{text}"
    );
}

#[test]
fn json_of_one_model_is_an_object_in_declaration_order() {
    let o = daec(&["check", "--json", &example("double_pendulum_3d.dae")]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    assert_eq!(v["model"], "DoublePendulum3D");
    let states: Vec<&str> = v["states"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert_eq!(
        states,
        [
            "p1x", "p1y", "p1z", "p2x", "p2y", "p2z", "v1x", "v1y", "v1z", "v2x", "v2y", "v2z"
        ]
    );
    assert_eq!(v["algebraics"], serde_json::json!(["z1", "z2"]));
    assert_eq!(
        v["parameters"],
        serde_json::json!({"m1": 0.1, "m2": 0.1, "L1": 2.0, "L2": 2.0, "g": 9.8})
    );
    assert_eq!(
        v["constraints"],
        serde_json::json!([
            {"name": "link1", "index": 3, "depends_on": ["z1", "z2"]},
            {"name": "link2", "index": 3, "depends_on": ["z1", "z2"]}
        ])
    );
    assert_eq!(v["jacobian"]["nonsingular"], true);
    // Exactly these keys, and parameters in declaration order (not sorted).
    let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
    assert_eq!(keys.len(), 6);
    let text = stdout(&o);
    let pos = |k: &str| text.find(&format!("\"{k}\":")).unwrap();
    assert!(pos("m1") < pos("m2") && pos("m2") < pos("L1") && pos("L2") < pos("g"));
}

#[test]
fn json_of_several_models_is_an_array() {
    let path = temp_file(
        "two.dae",
        b"model A { state x = 1; der(x) = -x; }\nmodel B { param k = 3; alg z = 0; constraint z = k; }\n",
    );
    let o = daec(&["check", "--json", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    let arr = v.as_array().expect("an array");
    assert_eq!(arr.len(), 2);
    assert_eq!(arr[0]["model"], "A");
    assert_eq!(arr[1]["parameters"], serde_json::json!({"k": 3.0}));
    assert_eq!(arr[1]["constraints"][0]["name"], "c1");
    let o = daec(&["check", path.to_str().unwrap()]);
    assert!(stdout(&o).contains("2 models OK"), "{}", stdout(&o));
}

#[test]
fn errors_are_all_rendered_on_stderr_with_exit_status_1() {
    let path = temp_file(
        "bad.dae",
        b"model M {\n  state x = 0, v = 0;\n  der(x) = vv;\n  der(q) = 1;\n}\n",
    );
    let name = path.display().to_string();
    for args in [
        vec!["check", name.as_str()],
        vec!["check", "--json", name.as_str()],
    ] {
        let o = daec(&args);
        assert_eq!(o.status.code(), Some(1));
        if args.contains(&"--json") {
            // The failure as JSON on stdout, every diagnostic with its place.
            let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
            assert_eq!(v["status"], "error");
            let d = v["diagnostics"].as_array().unwrap();
            assert_eq!(d.len(), 3, "{v}");
            assert!(
                d.iter().any(|d| d["message"] == "unknown name `vv`"
                    && (d["line"].as_u64(), d["column"].as_u64()) == (Some(3), Some(12))),
                "{v}"
            );
        } else {
            assert!(o.stdout.is_empty(), "nothing on stdout: {}", stdout(&o));
        }
        let err = stderr(&o);
        assert!(err.contains(&format!("{name}:3:12")), "{err}");
        assert!(err.contains("unknown name `vv`"), "{err}");
        assert!(err.contains("Help: did you mean `v`?"), "{err}");
        assert!(err.contains("unknown name `q`"), "{err}");
        assert!(
            err.contains("state `v` has no equation `der(v) = ...`"),
            "{err}"
        );
        assert!(err.contains("error: 3 errors in"), "{err}");
        assert!(
            !err.contains('\u{1b}'),
            "no colour when stderr is not a terminal: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn syntax_error_is_reported_with_its_place() {
    let path = temp_file(
        "syntax.dae",
        b"model M {\n  state x = 0\n  der(x) = 1;\n}\n",
    );
    let o = daec(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("expected `,`, `;` or an operator (`+ - * / ^`), found `der`"),
        "{err}"
    );
    assert!(err.contains("syntax.dae:3:3"), "{err}");
    assert!(
        err.contains("is one missing at the end of line 2?"),
        "{err}"
    );
}

#[test]
fn unreadable_or_binary_files_are_errors_not_panics() {
    let o = daec(&["check", "/nonexistent/dir/model.dae"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("error: cannot read `/nonexistent/dir/model.dae`"),
        "{}",
        stderr(&o)
    );

    let dir = temp_file("placeholder", b"")
        .parent()
        .unwrap()
        .to_path_buf();
    let o = daec(&["check", dir.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("error: cannot read"), "{}", stderr(&o));

    let path = temp_file("binary.dae", &[0x6d, 0xff, 0xfe, 0x00]);
    let o = daec(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("is not UTF-8 text: byte 0xFF at "),
        "{}",
        stderr(&o)
    );

    let path = temp_file("empty.dae", b"");
    let o = daec(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("expected `model`, found the end of the file"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn missing_argument_is_a_usage_error() {
    let o = daec(&["check"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("FILE"), "{}", stderr(&o));
}

#[test]
fn the_rendered_error_in_the_user_docs_is_what_daec_prints() {
    let blocks = common::user_docs_code_blocks();
    let model = blocks
        .iter()
        .find(|b| b.starts_with("model Spring"))
        .expect("the Spring example");
    let shown = blocks
        .iter()
        .find(|b| b.starts_with("Error: unknown name `xx`"))
        .expect("its rendering");
    let path = temp_file("spring.dae", model.as_bytes());
    let o = Command::new(env!("CARGO_BIN_EXE_daec"))
        .current_dir(path.parent().unwrap())
        .args(["check", "spring.dae"])
        .output()
        .expect("daec runs");
    assert_eq!(o.status.code(), Some(1));
    // The docs drop the trailing spaces ariadne leaves on some lines.
    let trim = |s: &str| s.lines().map(str::trim_end).collect::<Vec<_>>().join("\n");
    assert_eq!(trim(&stderr(&o)), trim(shown));
}

#[test]
fn the_first_model_in_the_user_docs_checks_as_shown() {
    let blocks = common::user_docs_code_blocks();
    let model = blocks
        .iter()
        .find(|b| b.starts_with("// Planar pendulum"))
        .expect("the first model");
    let summary = blocks
        .iter()
        .find(|b| b.starts_with("pend.dae: 1 model OK"))
        .expect("its summary");
    let json = blocks
        .iter()
        .find(|b| b.contains("\"model\": \"Pendulum\""))
        .expect("its JSON");
    let path = temp_file("pend.dae", model.as_bytes());
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_daec"))
            .current_dir(path.parent().unwrap())
            .args(args)
            .output()
            .expect("daec runs")
    };
    let o = run(&["check", "pend.dae"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), *summary);
    let o = run(&["check", "--json", "pend.dae"]);
    let got: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    let want: serde_json::Value = serde_json::from_str(json).expect("the docs show valid JSON");
    assert_eq!(got, want);
}

/// `0/0`, `0 * (1/0)`, `(1/0) - (1/0)` and `0 * ln(x - 1)` (with x = 0 at the start) used
/// to be folded to 0 and accepted; each is now an error at the operation that fails.
#[test]
fn operations_without_a_finite_value_are_errors_where_written() {
    for (rhs, message, col) in [
        (
            "0/0 + x",
            "zero divided by zero: an expression of numbers only that is NaN",
            12,
        ),
        (
            "x + 0 * (1/0)",
            "division by zero: an expression of numbers only that is inf",
            20,
        ),
        (
            "x + (1/0) - (1/0)",
            "division by zero: an expression of numbers only that is inf",
            16,
        ),
        (
            "0 * ln(x - 1)",
            "`ln` of a negative number (-1) at the initial point",
            16,
        ),
    ] {
        let src = format!("model M {{\n  state x = 0;\n  der(x) = {rhs};\n}}\n");
        let path = temp_file("nan.dae", src.as_bytes());
        let o = daec(&["check", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1), "{rhs}: {}", stdout(&o));
        let err = stderr(&o);
        assert!(err.contains(message), "{rhs}: {err}");
        assert!(err.contains(&format!("nan.dae:3:{col}")), "{rhs}: {err}");
        assert!(stdout(&o).is_empty());
    }
}
