//! Helpers shared by the tests that run the `daec` binary.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Run `daec` with `args` and collect its output.
pub fn daec(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_daec"))
        .args(args)
        .output()
        .expect("daec runs")
}

/// The path of the example model `name` (`examples/models/`).
pub fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/models")
        .join(name)
        .display()
        .to_string()
}

/// The path of the test fixture `name` (`cli/tests/fixtures/`).
pub fn fixture(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
        .display()
        .to_string()
}

/// The code blocks of `docs/language.md`, in order (the user docs that the tests hold
/// to what `daec` really prints).
pub fn user_docs_code_blocks() -> Vec<String> {
    let md =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/language.md"))
            .expect("docs/language.md");
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in md.lines() {
        if line.starts_with("```") {
            match current.take() {
                Some(b) => blocks.push(b),
                None => current = Some(String::new()),
            }
        } else if let Some(b) = current.as_mut() {
            b.push_str(line);
            b.push('\n');
        }
    }
    blocks
}
