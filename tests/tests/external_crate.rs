//! Acceptance of issue 10: a crate outside the workspace (`tests/external/family_chain`)
//! compiles `examples/models/chain.dae` with `dae_file!` once and runs it at N = 10 and
//! N = 10,000 from the same binary: the size is chosen at run time.
//!
//! Ignored by default (a cold build of the crate and its dependencies, about a minute on
//! two cores). Run it with
//! `cargo test -p dae-tests --test external_crate -- --ignored`.

use std::path::PathBuf;
use std::process::Command;

#[test]
#[ignore = "cold build of an external crate (about a minute): run with --ignored"]
fn external_crate_runs_the_chain_at_any_size_without_recompiling() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let manifest = root.join("tests/external/family_chain/Cargo.toml");
    // Its own target directory inside the workspace's, so that it is built once.
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map_or_else(|| root.join("target"), PathBuf::from)
        .join("external");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let build = || {
        let o = Command::new(&cargo)
            .args(["build", "--manifest-path"])
            .arg(&manifest)
            .env("CARGO_TARGET_DIR", &target)
            .output()
            .expect("cargo runs");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    build();
    let exe = target.join("debug/family-chain-user");
    let stamp = || {
        std::fs::metadata(&exe)
            .and_then(|m| m.modified())
            .expect("binary")
    };
    let before = stamp();
    for (n, states, entries) in [(10, 66, 28), (10_000, 60_006, 29_998)] {
        let o = Command::new(&exe)
            .arg(n.to_string())
            .output()
            .expect("runs");
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "N = {n}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            out.contains(&format!(
                "N = {n}: {states} states, {n} constraints, {entries} entries of J_Omega"
            )),
            "{out}"
        );
        assert!(out.contains("10 steps"), "{out}");
    }
    // A second build compiles nothing: the one binary served both sizes.
    let log = build();
    assert!(!log.contains("Compiling"), "{log}");
    assert_eq!(stamp(), before);
    // A bad size is a clear error, not a panic.
    let o = Command::new(&exe).arg("0").output().expect("runs");
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("set `L` has 0 elements"));
}
