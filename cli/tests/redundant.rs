//! A singular `J_Omega` from redundant constraints is reported with its rank, the
//! constraints the ones before them imply (by family, at the lines of their
//! declarations) and one dependency written out: by `daec check` at the default sizes,
//! and by `daec run` at the start.

mod common;

use std::path::Path;

use common::{daec, fixture};

/// Runs `daec`, returns (status, stderr).
fn run(args: &[&str]) -> (Option<i32>, String) {
    let o = daec(args);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Each link of the chain is constrained twice, `again` being `link` times two: rank 5
/// of 10, every `again` implied, `again[l]`'s row exactly twice `link[l]`'s. The chain
/// starts straight along x, so the tensions act on the 5 x-velocities alone.
#[test]
fn check_names_the_implied_family_at_its_line_with_the_counts() {
    let file = fixture("chain_twice.dae");
    let (code, err) = run(&["check", &file]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("J_Omega of `ChainTwice` is singular at t = 0 with the default sizes (N = 5): rank 5 of 10 (10 constraints on the 5 state derivatives the algebraic unknowns act on): 5 constraints are implied by the ones before them"),
        "{err}"
    );
    // Underlined at `again`'s declaration (line 30), `link`'s (line 29) beside it.
    assert!(err.contains("chain_twice.dae:30:5"), "{err}");
    assert!(
        err.contains("`again`: 5 of its 5 constraints implied (`again[0]`, `again[1]`, `again[2]`, `again[3]`, `again[4]`)"),
        "{err}"
    );
    assert!(err.contains("`link`: 5 constraints, none implied"), "{err}");
    assert!(err.contains("row `again[0]` = 2 row `link[0]`"), "{err}");
}

#[test]
fn check_json_keeps_the_diagnostic() {
    let (code, out) = {
        let o = daec(&["check", "--json", &fixture("chain_twice.dae")]);
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        )
    };
    assert_eq!(code, Some(1));
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON on stdout");
    let text = v.to_string();
    assert!(text.contains("rank 5 of 10"), "{text}");
    assert!(text.contains("\"line\":30"), "{text}");
}

#[test]
fn run_reports_the_redundancy_at_the_start() {
    let (code, err) = run(&[
        "run",
        &fixture("chain_twice.dae"),
        "--t-end",
        "0.1",
        "--eps",
        "1e-3",
    ]);
    assert_ne!(code, Some(0), "{err}");
    assert!(
        err.contains("rank 5 of 10 (10 constraints on the 5 state derivatives the algebraic unknowns act on): 5 constraints are implied"),
        "{err}"
    );
    assert!(
        err.contains("`again`: 5 of its 5 constraints implied"),
        "{err}"
    );
    assert!(err.contains("row `again[0]` = 2 row `link[0]`"), "{err}");
}

/// The cloth with rigid diagonals: the links (declared first) are independent, the
/// diagonals are what the others imply.
#[test]
fn check_finds_the_rigid_diagonals_of_a_cloth_implied_by_its_links() {
    let (code, err) = run(&["check", &fixture("cloth_rigid_shear.dae")]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("rank 32 of 42 (42 constraints on the 34 state derivatives the algebraic unknowns act on): 10 constraints are implied by the ones before them"),
        "{err}"
    );
    assert!(
        err.contains("`link`: 24 constraints, none implied"),
        "{err}"
    );
    assert!(
        err.contains("`shear`: 10 of its 18 constraints implied"),
        "{err}"
    );
}

/// The samples of a `--csv` trace: the header and the rows.
fn trace(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).expect("the trace");
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect());
    let header: Vec<String> = lines.next().expect("a header");
    (header, lines.collect())
}

/// With `--redundant drop`, the chain whose links are constrained twice runs as the chain
/// constrained once: every state at every sample equal to the bit, and the summary says
/// that the implied constraints were set aside.
#[test]
fn run_with_redundant_drop_is_the_chain_without_its_repeated_constraints() {
    let dir = std::env::temp_dir().join(format!("daec-redundant-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (once, twice) = (dir.join("once.csv"), dir.join("twice.csv"));
    let common = ["--t-end", "0.5", "--eps", "1e-3"];
    let o = daec(
        &[
            &["run", &fixture("chain_once.dae")][..],
            &common,
            &["--csv", once.to_str().unwrap()],
        ]
        .concat(),
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let t = daec(
        &[
            &[
                "run",
                &fixture("chain_twice_same.dae"),
                "--redundant",
                "drop",
            ][..],
            &common,
            &["--csv", twice.to_str().unwrap()],
        ]
        .concat(),
    );
    let out = String::from_utf8_lossy(&t.stdout);
    assert_eq!(
        t.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&t.stderr)
    );
    assert!(
        out.contains("the constraints the others imply set aside (at most 5)"),
        "{out}"
    );
    let ((ha, ra), (hb, rb)) = (trace(&once), trace(&twice));
    assert_eq!(ra.len(), rb.len());
    let states: Vec<&String> = ha
        .iter()
        .filter(|c| *c == "t" || c.starts_with("x."))
        .collect();
    assert_eq!(states.len(), 1 + 36);
    for c in states {
        let (i, j) = (
            ha.iter().position(|h| h == c).unwrap(),
            hb.iter().position(|h| h == c).unwrap(),
        );
        for (a, b) in ra.iter().zip(&rb) {
            assert_eq!(a[i], b[j], "column {c}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
