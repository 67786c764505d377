//! `daec fmu` against a real importer: FMPy (from PyPI, in a virtual environment this
//! test makes under cargo's target folder) validates the FMUs of the double pendulum and
//! of the family chain at N = 10, simulates them, and sees a lost layer in its log. The
//! outputs at the communication points equal `daec run --every` (the same cuts).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The FMPy of the packages list, pinned so that a new release cannot change the test.
const FMPY: &str = "fmpy==0.3.32";

fn daec(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_daec"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "daec {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The FMU library, built by cargo into a target folder of this test's own (`cargo
/// test` builds dae-fmu only as an `rlib`, and holds the lock of its own folder).
fn library() -> PathBuf {
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fmu-library");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("../Cargo.toml");
    let built = Command::new(cargo)
        .args(["build", "--quiet", "-p", "dae-fmu", "--manifest-path"])
        .arg(&manifest)
        .arg("--target-dir")
        .arg(&target)
        .output()
        .unwrap();
    assert!(
        built.status.success(),
        "cargo build -p dae-fmu: {}",
        String::from_utf8_lossy(&built.stderr)
    );
    target.join("debug/libdae_fmu.so")
}

/// A Python with FMPy, made once per target folder.
fn python() -> PathBuf {
    let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fmpy-venv");
    let py = venv.join("bin/python");
    let has = |py: &Path| {
        Command::new(py)
            .args(["-c", "import fmpy"])
            .status()
            .is_ok_and(|s| s.success())
    };
    if !has(&py) {
        let made = Command::new("python3")
            .args(["-m", "venv"])
            .arg(&venv)
            .status();
        assert!(
            made.is_ok_and(|s| s.success()),
            "python3 -m venv {}",
            venv.display()
        );
        let pip = Command::new(&py)
            .args(["-m", "pip", "install", "--quiet", FMPY])
            .output()
            .unwrap();
        assert!(
            pip.status.success(),
            "pip install {FMPY}: {}",
            String::from_utf8_lossy(&pip.stderr)
        );
    }
    py
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (head, rows)
}

/// The largest difference between FMPy's outputs and `daec run --every`'s samples, on
/// the states at every point and on the algebraic unknowns at every point but the last
/// (`daec run` writes its last sample before the update it makes at the end time, the
/// FMU's output is the value after it: compared with `z_final` instead).
fn largest_difference(fmu: &Path, run: &Path, json: &serde_json::Value) -> f64 {
    let (fh, f) = read_csv(fmu);
    let (rh, r) = read_csv(run);
    assert_eq!(
        f.len(),
        r.len(),
        "rows of {} and {}",
        fmu.display(),
        run.display()
    );
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    for (j, name) in fh.iter().enumerate() {
        for (prefix, all_rows) in [("x.", true), ("z.", false)] {
            let Some(i) = rh.iter().position(|h| h == &format!("{prefix}{name}")) else {
                continue;
            };
            let n = if all_rows { r.len() } else { r.len() - 1 };
            for k in 0..n {
                assert_eq!(f[k][0], r[k][0], "times of row {k}");
                worst = worst.max((f[k][j] - r[k][i]).abs());
            }
            compared += 1;
        }
    }
    // The algebraic unknowns at the end, in the order of the run's `z.` columns.
    let z_final: Vec<f64> = serde_json::from_value(json["z_final"].clone()).unwrap();
    let z_names = rh.iter().filter_map(|h| h.strip_prefix("z."));
    let last = f.last().unwrap();
    for (name, z) in z_names.zip(&z_final) {
        let j = fh.iter().position(|h| h == name).unwrap();
        worst = worst.max((last[j] - z).abs());
    }
    assert!(
        compared > 0,
        "no column of {} in {}",
        run.display(),
        fmu.display()
    );
    worst
}

#[test]
fn fmpy_validates_runs_and_hears_of_a_lost_layer() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fmu-test");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/models");
    let dp_model = models.join("double_pendulum_3d.dae");
    let chain_model = models.join("chain.dae");
    let (dp, chain) = (dir.join("dp.fmu"), dir.join("chain.fmu"));
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let lib = s(&library());
    let common = ["--eps", "1e-3", "--stop-time", "2", "--library", &lib];
    let (dp_s, chain_s) = (s(&dp_model), s(&chain_model));
    daec(&[&["fmu", &dp_s][..], &common, &["-o", &s(&dp)]].concat());
    daec(
        &[
            &["fmu", &chain_s, "--set", "N=10"][..],
            &common,
            &["-o", &s(&chain)],
        ]
        .concat(),
    );

    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fmu/fmpy_check.py");
    let out = Command::new(python())
        .arg(&script)
        .args([&dp, &chain, &dir])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    for m in ["dp", "chain"] {
        assert_eq!(
            report["problems"][m],
            serde_json::json!([]),
            "validation of {m}"
        );
    }
    let log = report["jump_log"].as_array().unwrap();
    assert!(
        log.iter()
            .any(|e| e[0] == 1 && e[1].as_str().unwrap().contains("the layer was left")),
        "FMPy's log: {log:?}"
    );

    let every = format!("{}", 1.0 / 60.0);
    for (name, model, sets) in [
        ("dp", &dp_model, vec![]),
        ("chain", &chain_model, vec!["--set", "N=10"]),
    ] {
        let csv = dir.join(format!("{name}-run.csv"));
        let mut args = vec![
            "run",
            model.to_str().unwrap(),
            "--t-end",
            "2",
            "--eps",
            "1e-3",
        ];
        args.extend(sets);
        let csv_s = s(&csv);
        args.extend(["--every", &every, "--csv", &csv_s, "--json"]);
        let json: serde_json::Value = serde_json::from_str(&daec(&args)).unwrap();
        let d = largest_difference(&dir.join(format!("{name}.csv")), &csv, &json);
        assert!(
            d <= 1e-9,
            "{name}: FMPy's outputs differ from daec run's by {d:e}"
        );
    }
}
