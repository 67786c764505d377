//! `daec check --set NAME=VALUE --topology FILE`: the check reports for the given sizes,
//! parameters and topology; a name the model cannot take is an error naming what it can.

mod common;

use common::daec;

use std::path::Path;
use std::process::Output;

fn file(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(path)
        .display()
        .to_string()
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn failed(o: &Output) -> String {
    assert_eq!(o.status.code(), Some(1));
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    String::from_utf8(o.stderr.clone()).unwrap()
}

#[test]
fn a_family_model_is_checked_at_the_sizes_of_set() {
    let chain = file("../examples/models/chain.dae");
    let out = ok(&daec(&["check", &chain, "--set", "N=50"]));
    assert!(
        out.contains("  at the given sizes (N = 50): 306 states, 50 constraints;"),
        "{out}"
    );
    let v: serde_json::Value =
        serde_json::from_slice(&daec(&["check", "--json", &chain, "--set", "N=50"]).stdout)
            .unwrap();
    let at = &v["jacobian"]["at_default_sizes"];
    assert_eq!(at["constraints"], 50);
    assert_eq!(at["given"], true);
    assert_eq!(at["sizes"], "N = 50");
}

#[test]
fn a_version_1_model_is_checked_with_its_parameters_set() {
    let planar = file("../examples/models/double_pendulum_planar.dae");
    let default = ok(&daec(&["check", &planar]));
    assert!(default.contains("condition number 6.854102"), "{default}");
    let out = ok(&daec(&[
        "check", &planar, "--set", "m1=3", "--set", "L1=1.5",
    ]));
    assert!(
        out.contains("  parameters  (5): m1 = 3, m2 = 0.1, L1 = 1.5, L2 = 2, g = 9.8"),
        "{out}"
    );
    // J_Omega at the initial point depends on the masses and lengths.
    assert!(out.contains("condition number 32.102183"), "{out}");
    let v: serde_json::Value =
        serde_json::from_slice(&daec(&["check", "--json", &planar, "--set", "m1=3"]).stdout)
            .unwrap();
    assert_eq!(v["parameters"]["m1"], 3.0);
}

#[test]
fn an_unknown_name_in_set_names_what_the_model_can_take() {
    let chain = file("../examples/models/chain.dae");
    let err = failed(&daec(&["check", &chain, "--set", "X=5"]));
    assert!(
        err.contains("error: --set X=5: the model `Chain` has no size or scalar parameter `X`"),
        "{err}"
    );
    assert!(
        err.contains("hint: --set takes the sizes (N) and the scalar parameters (g, m_end, L0)"),
        "{err}"
    );
    let planar = file("../examples/models/double_pendulum_planar.dae");
    let err = failed(&daec(&["check", &planar, "--set", "N=5"]));
    assert!(
        err.contains("has no parameter `N` (a version-1 model has no sizes)"),
        "{err}"
    );
    assert!(
        err.contains("hint: its parameters: m1, m2, L1, L2, g"),
        "{err}"
    );
    let err = failed(&daec(&["check", &chain, "--set", "N=2.5"]));
    assert!(err.contains("`N` is a size, a whole number >= 0"), "{err}");
}

#[test]
fn a_topology_builds_the_family_model_that_check_reports() {
    let star = file("tests/fixtures/star.dae");
    let without = ok(&daec(&["check", &star]));
    assert!(
        without.contains("sets or maps given at run time"),
        "{without}"
    );
    let topo = file("tests/fixtures/star.topo");
    let out = ok(&daec(&["check", &star, "--topology", &topo]));
    assert!(
        out.contains("  at the given sizes: 30 states, 4 constraints; J_Omega with 16 entries, structural rank 4, nonsingular at t = 0"),
        "{out}"
    );
    // A version-1 model has no sets to give.
    let planar = file("../examples/models/double_pendulum_planar.dae");
    let err = failed(&daec(&["check", &planar, "--topology", &topo]));
    assert!(err.contains("has no sets (a version-1 model)"), "{err}");
}
