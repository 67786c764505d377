//! What `daec` reads: a UTF-8 byte order mark is skipped, a byte that is not UTF-8 is
//! reported with its line and column, and a file longer than the 16 MiB limit, or one
//! that never ends, is refused after reading at most the limit.

mod common;

use common::daec;

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A file in a fresh temporary directory of this test process.
fn temp_file(name: &str, contents: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("daec-input-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write temp file");
    path
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn a_byte_order_mark_is_skipped() {
    let path = temp_file(
        "bom.dae",
        "\u{feff}model M {\n  state x = 1;\n  der(x) = -x;\n}\n".as_bytes(),
    );
    for cmd in ["check", "derive", "emit"] {
        let o = daec(&[cmd, path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{cmd}: {}", stderr(&o));
    }
    // An error in such a file has the column an editor shows.
    let path = temp_file(
        "bom_error.dae",
        "\u{feff}model M { der(x) = 1; }".as_bytes(),
    );
    let o = daec(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("bom_error.dae:1:15"), "{}", stderr(&o));
    assert!(!stderr(&o).contains('\u{feff}'), "{}", stderr(&o));
}

#[test]
fn a_byte_that_is_not_utf8_is_reported_with_line_and_column() {
    let path = temp_file(
        "latin1.dae",
        b"model M {\n  state x = 1;\n  // caf\xe9\n  der(x) = -x;\n}\n",
    );
    let o = daec(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("latin1.dae:3:9"), "{err}");
    assert!(err.contains("byte 0xE9"), "{err}");
    assert!(err.contains("byte offset 33"), "{err}");
    assert!(err.contains("not UTF-8"), "{err}");
}

#[test]
fn a_file_longer_than_the_limit_is_refused() {
    let mut text = b"model M { state x = 1; der(x) = -x; }\n".to_vec();
    text.resize(dae_lang::MAX_SOURCE_BYTES + 1, b' ');
    let path = temp_file("huge.dae", &text);
    let o = daec(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("is longer than 16 MiB (16777216 bytes), the limit for a `.dae` file"),
        "{err}"
    );
    text.pop();
    std::fs::write(&path, &text).unwrap();
    let o = daec(&["check", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// `/dev/urandom` never ends: `daec` must stop at the limit, not read forever. (A
/// deadline far above the time it takes, so that a hang fails instead of blocking.)
#[cfg(unix)]
#[test]
fn an_endless_file_is_refused_at_the_limit() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_daec"))
        .args(["check", "/dev/urandom"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("daec runs");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().expect("kill");
            panic!("`daec check /dev/urandom` still reading after 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let out = child.wait_with_output().expect("output");
    assert_eq!(status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("is longer than 16 MiB"), "{err}");
}
