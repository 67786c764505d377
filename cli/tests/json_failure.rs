//! With `--json`, a failure of `daec run`, `daec design` or `daec check` is one JSON
//! object on stdout (`status`, `command`, `error`, `hint` and what the error carries),
//! with the same exit status and the text on stderr.

mod common;

use common::{daec, example};

use serde_json::Value;
use std::path::PathBuf;
use std::process::Output;

fn temp_file(name: &str, contents: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("daec-json-failure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write temp file");
    path
}

/// The failure object on stdout of a run that exited with status 1.
fn failure(o: &Output, command: &str) -> Value {
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("not JSON ({e}): {}", String::from_utf8_lossy(&o.stdout)));
    assert_eq!(v["status"], "error", "{v}");
    assert_eq!(v["command"], command, "{v}");
    // The text stays on stderr.
    let err = String::from_utf8_lossy(&o.stderr);
    let message = v["error"].as_str().expect("error is a string");
    assert!(err.contains("error: "), "{err}");
    assert!(!message.is_empty());
    v
}

#[test]
fn a_bad_flag_value_of_run_is_a_json_failure() {
    let o = daec(&[
        "run",
        &example("double_pendulum_3d.dae"),
        "--t-end",
        "1",
        "--eps",
        "-0.2",
        "--json",
    ]);
    let v = failure(&o, "run");
    assert_eq!(v["error"], "--eps -0.2: must be a finite number > 0");
    assert!(v["hint"].is_null(), "{v}");
    // Without --json nothing goes to stdout.
    let o = daec(&[
        "run",
        &example("double_pendulum_3d.dae"),
        "--t-end",
        "1",
        "--eps",
        "-0.2",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(o.stdout.is_empty());
}

#[test]
fn a_simulation_failure_says_when_and_which_constraints() {
    let o = daec(&[
        "run",
        &example("double_pendulum_3d.dae"),
        "--t-end",
        "1",
        "--eps",
        "0.2",
        "--mu",
        "0.076,0.066",
        "--gain",
        "0.01",
        "--step",
        "1e-4",
        "--reaching-limit",
        "0.01",
        "--json",
    ]);
    let v = failure(&o, "run");
    assert_eq!(v["kind"], "reaching_timeout", "{v}");
    assert!(
        v["error"]
            .as_str()
            .unwrap()
            .starts_with("simulation of `DoublePendulum3D` failed: reaching phase not finished"),
        "{v}"
    );
    assert_eq!(v["hint"], "increase the gains or the layers");
    let t = v["t"].as_f64().unwrap();
    assert!((0.01..0.0102).contains(&t), "{v}");
    assert_eq!(v["limit"], 0.01);
    assert_eq!(v["constraints"], serde_json::json!(["link1", "link2"]));
}

#[test]
fn a_nan_in_a_run_names_the_variable_and_the_time() {
    let model = temp_file(
        "blowup.dae",
        "model Blowup {\n  state x = 0.0, y = 0.0;\n  alg z = 0.0;\n  der(x) = sqrt(1 - t);\n  der(y) = z;\n  constraint c: y = 0;\n}\n",
    );
    let o = daec(&[
        "run",
        model.to_str().unwrap(),
        "--t-end",
        "2",
        "--eps",
        "0.01",
        "--mu",
        "1",
        "--gain",
        "1",
        "--step",
        "1e-3",
        "--json",
    ]);
    let v = failure(&o, "run");
    assert_eq!(v["kind"], "non_finite", "{v}");
    assert_eq!(v["variable"], "x", "{v}");
    assert_eq!(v["quantity"], "state", "{v}");
    assert_eq!(v["value"], "NaN", "{v}");
    assert!((v["t"].as_f64().unwrap() - 1.001).abs() < 1e-9, "{v}");
    assert!(
        v["hint"].as_str().unwrap().contains("is NaN, not infinite"),
        "{v}"
    );
}

#[test]
fn a_malformed_model_is_a_json_failure_with_its_diagnostics() {
    let model = temp_file("bad.dae", "model A {\n  state x = 1;\n  der(x) = y;\n}\n");
    for command in ["check", "run", "design"] {
        let mut args = vec![command, model.to_str().unwrap(), "--json"];
        if command != "check" {
            args.extend(["--eps", "0.1"]);
        }
        match command {
            "run" => args.extend(["--t-end", "1"]),
            "design" => args.extend(["--pilot", "1"]),
            _ => {}
        }
        let v = failure(&daec(&args), command);
        assert_eq!(
            v["error"],
            format!("unknown name `y` (1 error in `{}`)", model.display())
        );
        assert_eq!(
            v["hint"],
            "declare it with `param`, `state`, `alg` or `let`"
        );
        let d = &v["diagnostics"][0];
        assert_eq!(d["message"], "unknown name `y`");
        assert_eq!(
            (d["line"].as_u64(), d["column"].as_u64()),
            (Some(3), Some(12))
        );
    }
}

#[test]
fn a_failed_design_is_a_json_failure() {
    let o = daec(&[
        "design", "--index", "2", "--bound", "index3", "--eps", "0.2", "--beta", "1e3", "--m",
        "9e4", "--json",
    ]);
    let v = failure(&o, "design");
    assert_eq!(
        v["error"],
        "--bound index3 (T 4.6) holds for index 3 only, got --index 2; use --bound general"
    );
    let o = daec(&["check", &example("chain.dae"), "--set", "X=1", "--json"]);
    let v = failure(&o, "check");
    assert_eq!(
        v["hint"],
        "--set takes the sizes (N) and the scalar parameters (g, m_end, L0)"
    );
}
