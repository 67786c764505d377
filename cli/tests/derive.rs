//! `daec derive` and the analysis part of `daec check` run as processes: the derive text
//! is the library's, JSON snapshots of every example, condition numbers against closed
//! forms, and analysis errors reported like the other diagnostics.

mod common;

use common::daec;

use std::path::{Path, PathBuf};
use std::process::Command;

const EXAMPLES: [&str; 5] = [
    "circuit_index1.dae",
    "double_pendulum_3d.dae",
    "double_pendulum_planar.dae",
    "integrator_chain_index4.dae",
    "tank_level_index2.dae",
];

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/models")
        .join(name)
}

fn temp_file(name: &str, contents: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("daec-derive-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write temp file");
    path
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn derive_prints_the_library_derive_text_of_every_example() {
    for name in EXAMPLES {
        let path = example(name);
        let o = daec(&["derive", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", text(&o.stderr));
        let src = std::fs::read_to_string(&path).unwrap();
        let model = dae_lang::check_source(&src).unwrap().remove(0);
        let a = dae_lang::analyze(&model, &dae_lang::AnalysisOptions::default()).unwrap();
        assert_eq!(text(&o.stdout), a.derive_text(), "{name}");
    }
}

#[test]
fn check_json_of_every_example() {
    for name in EXAMPLES {
        let o = daec(&["check", "--json", example(name).to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", text(&o.stderr));
        insta::assert_snapshot!(name.trim_end_matches(".dae"), text(&o.stdout));
    }
}

fn condition(path: &Path) -> f64 {
    let o = daec(&["check", "--json", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["jacobian"]["nonsingular"], true);
    v["jacobian"]["condition"].as_f64().expect("a number")
}

#[test]
fn condition_numbers_match_closed_forms() {
    // 3-D double pendulum at R1 = (-1, 0, 0), R2 = (-5, 0, 0), m1 = m2 = 0.1:
    // J = [[-1/m1, 1/m1], [1/m1, -(1/m1 + 1/m2)]] = [[-10, 10], [10, -20]], symmetric with
    // eigenvalues -15 -+ 5 sqrt 5, so cond = (15 + 5 sqrt 5)/(15 - 5 sqrt 5).
    let s5 = 5f64.sqrt();
    let want = (15.0 + 5.0 * s5) / (15.0 - 5.0 * s5);
    let got = condition(&example("double_pendulum_3d.dae"));
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    // The planar one starts from the same configuration.
    let got = condition(&example("double_pendulum_planar.dae"));
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    // Mixed indices 1, 2, 3: J = [[1, 0, 0], [0, 1, 0], [1, 0, 1]]; J^T J has eigenvalues 1
    // and (3 +- sqrt 5)/2, so cond = sqrt((3 + sqrt 5)/(3 - sqrt 5)) = (3 + sqrt 5)/2.
    let mixed = temp_file(
        "mixed.dae",
        "model Mixed {
    state a = 0, p = 0, v = 0;
    alg z1 = 0, z2 = 1, z3 = 0;
    der(a) = z2;
    der(p) = v;
    der(v) = z3 + z1;
    constraint c_alg: z1 = a;
    constraint c_vel: a = t;
    constraint c_pos: p = 0;
}
",
    );
    let want = (3.0 + s5) / 2.0;
    let got = condition(&mixed);
    assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    let o = daec(&["check", mixed.to_str().unwrap()]);
    let out = text(&o.stdout);
    assert!(
        out.contains(
            "    name   index  depends on\n    c_alg      1  z1\n    c_vel      2  z2\n    c_pos      3  z1, z3\n"
        ),
        "{out}"
    );
    assert!(
        out.contains("J_Omega at t = 0: nonsingular, condition number 2.618034\n"),
        "{out}"
    );
}

#[test]
fn analysis_errors_are_rendered_with_exit_status_1() {
    let singular = temp_file(
        "singular.dae",
        "model Singular {
    state x = 0, y = 0;
    alg z1 = 0, z2 = 0;
    der(x) = z1 + z2;
    der(y) = 2 * (z1 + z2);
    constraint a: x = t;
    constraint b: y = 2 * t;
}
",
    );
    let no_index = temp_file(
        "noindex.dae",
        "model NoIndex {
    state x = 1, y = 0;
    alg z = 0;
    der(x) = -x;
    der(y) = z;
    constraint stuck: x = 1;
}
",
    );
    for (path, place, what) in [
        (&singular, "singular.dae:6:5", "J_Omega is"),
        (
            &no_index,
            "noindex.dae:6:5",
            "constraint `stuck` has no index",
        ),
    ] {
        for cmd in [vec!["check"], vec!["check", "--json"], vec!["derive"]] {
            let mut args = cmd.clone();
            args.push(path.to_str().unwrap());
            let o = daec(&args);
            assert_eq!(o.status.code(), Some(1), "{args:?}");
            if args.contains(&"--json") {
                // The failure as JSON on stdout.
                let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
                assert_eq!(v["status"], "error");
                assert!(v["error"].as_str().unwrap().contains(what), "{v}");
            } else {
                assert!(o.stdout.is_empty(), "{}", text(&o.stdout));
            }
            let err = text(&o.stderr);
            assert!(err.contains(place), "{err}");
            assert!(err.contains(what), "{err}");
            assert!(err.contains("error: 1 error in"), "{err}");
            assert!(!err.contains("panicked"), "{err}");
        }
    }
    let err = text(&daec(&["check", singular.to_str().unwrap()]).stderr);
    assert!(err.contains("`a`") && err.contains("`b`"), "{err}");
    assert!(err.contains("condition number"), "{err}");
}

#[test]
fn the_index_analysis_outputs_in_the_user_docs_are_what_daec_prints() {
    let blocks = common::user_docs_code_blocks();
    let find = |start: &str| {
        blocks
            .iter()
            .find(|b| b.starts_with(start))
            .unwrap_or_else(|| panic!("a block starting with {start}"))
            .clone()
    };
    let run = |file: &Path, args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_daec"))
            .current_dir(file.parent().unwrap())
            .args(args)
            .arg(file.file_name().unwrap())
            .output()
            .expect("daec runs")
    };
    let pend = temp_file("pend.dae", &find("// Planar pendulum"));
    let o = run(&pend, &["derive"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(text(&o.stdout), find("// model Pendulum:"));
    let o = run(&pend, &["check"]);
    assert!(
        text(&o.stdout).ends_with(&find("  constraints (1):\n    name  index")),
        "{}",
        text(&o.stdout)
    );
    let twice = temp_file("twice.dae", &find("model Twice"));
    let o = run(&twice, &["check"]);
    assert_eq!(o.status.code(), Some(1));
    let trim = |s: &str| s.lines().map(str::trim_end).collect::<Vec<_>>().join("\n");
    assert_eq!(
        trim(&text(&o.stderr)),
        trim(&find("Error: J_Omega is singular"))
    );
}

/// A sum over the set of the constraint's own element: the condition compares the sum's
/// element with the constraint's (not with itself), and a sum inside it takes a name of
/// its own. The lines are `w` and its derivative written out by hand.
#[test]
fn a_sum_over_the_constraint_s_own_set_keeps_the_outer_element_in_its_condition() {
    let src = "model Ring {
    size N = 4;
    set P = N;
    map nxt[p in P] -> P = if p == N - 1 then 0 else p + 1;
    state x[p in P] = p;
    alg z[p in P] = 0;
    der(x[p]) = z[p] + sum(q in P where nxt[q] == p) x[q];
    constraint c[p in P]: x[p] + sum(q in P where nxt[q] == p) x[q] = 1;
}
";
    let path = temp_file("ring.dae", src);
    let o = daec(&["derive", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(
        out.contains("\nw_c[p] = x[p] + (sum(p' in P where nxt[p'] == p) x[p']) - 1\n"),
        "{out}"
    );
    assert!(
        out.contains(
            "\nOmega_c[p] = z[p] + (sum(p' in P where nxt[p'] == p) x[p']) + (sum(p' in P where nxt[p'] == p) (z[p'] + (sum(p'' in P where nxt[p''] == p') x[p''])))\n"
        ),
        "{out}"
    );
}
