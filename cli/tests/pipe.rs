//! Closing stdout early (`daec derive big.dae | head`) must not panic the process.

use std::io::Read;
use std::process::{Command, Stdio};

/// A planar chain of `n` links: its derive text is far longer than a pipe's buffer.
fn chain(n: usize) -> String {
    let mut s = String::from("model Chain {\n    param m = 0.1, L = 0.5, g = 9.8;\n");
    for k in 1..=n {
        let x = k as f64 * 0.5;
        s += &format!("    state x{k} = {x}, y{k} = 0.0, vx{k} = 0.0, vy{k} = 0.0;\n");
        s += &format!("    alg z{k} = 0.0;\n");
    }
    for k in 1..=n {
        let (px, py) = if k == 1 {
            ("0".to_string(), "0".to_string())
        } else {
            (format!("x{}", k - 1), format!("y{}", k - 1))
        };
        s += &format!("    let dx{k} = x{k} - {px};\n    let dy{k} = y{k} - {py};\n");
        s += &format!("    let l{k} = sqrt(dx{k}^2 + dy{k}^2);\n");
        s += &format!("    constraint link{k}: l{k} = L;\n");
        let next = if k < n {
            format!(" + z{} * dx{} / l{}", k + 1, k + 1, k + 1)
        } else {
            String::new()
        };
        let next_y = if k < n {
            format!(" + z{} * dy{} / l{}", k + 1, k + 1, k + 1)
        } else {
            String::new()
        };
        s += &format!("    der(x{k}) = vx{k};\n    der(y{k}) = vy{k};\n");
        s += &format!("    der(vx{k}) = (-z{k} * dx{k} / l{k}{next}) / m;\n");
        s += &format!("    der(vy{k}) = (-z{k} * dy{k} / l{k}{next_y}) / m - g;\n");
    }
    s + "}\n"
}

#[test]
fn closed_stdout_ends_quietly() {
    let dir = std::env::temp_dir().join(format!("daec-pipe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("chain.dae");
    std::fs::write(&file, chain(30)).unwrap();

    let mut child = Command::new(env!("CARGO_BIN_EXE_daec"))
        .arg("derive")
        .arg(&file)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut head = [0u8; 100];
    child.stdout.take().unwrap().read_exact(&mut head).unwrap();
    // Dropping the read end closes the pipe while daec is still writing.
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "daec panicked: {stderr}");
    assert!(
        out.status.success(),
        "status {:?}, stderr: {stderr}",
        out.status
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_chain_fixture_is_a_valid_model_with_long_output() {
    // Guards the test above: the output must exceed any pipe buffer (64 KiB on Linux).
    let text = dae_lang::analyze_source(&chain(30)).unwrap()[0]
        .1
        .derive_text();
    assert!(
        text.len() > 96 * 1024,
        "derive text is only {} bytes",
        text.len()
    );
}
