//! The parser's work on nested forms that fail: a form that starts with `if` or `not`
//! and fails late is not parsed again as a call, so nested failures cost the length of
//! the input, not 2^depth. Found by fuzzing (`cargo fuzz run run`): a 1.9 KB file of
//! nested `(if(` took 5 s to reject in a release build, 44 s under the fuzzer.
//!
//! Each case runs on its own thread with a deadline far above its cost when the work is
//! linear (microseconds) and far below it when it doubles per level (2^60 parses): the
//! deadline turns a hang into a failure, it does not measure speed. The depths stay
//! within the 64 levels of nesting the parser accepts (deeper input is refused before
//! parsing).

use std::sync::mpsc;
use std::time::Duration;

/// A model whose one equation opens `open` `depth` times and never closes it.
fn nested(open: &str, depth: usize) -> String {
    format!(
        "model m {{\n  state x = 0;\n  der(x) = {}x;\n}}\n",
        open.repeat(depth)
    )
}

fn rejected_in_time(what: &str, src: String) -> String {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let result = dae_lang::check_source(&src);
        let _ = tx.send(result.map(|_| ()).map_err(|d| d[0].message.clone()));
    });
    match rx.recv_timeout(Duration::from_secs(60)) {
        Ok(Err(message)) => message,
        Ok(Ok(())) => panic!("{what}: accepted"),
        Err(_) => panic!("{what}: not rejected within 60 s (exponential backtracking)"),
    }
}

#[test]
fn nested_ifs_without_then_are_rejected_without_backtracking() {
    // `if(` 30 times (60 levels of the 64 accepted), never closed, no `then`. Before the
    // fix the work grew 4x per two levels (release build: 0.08 s at 14, 0.29 s at 16,
    // 1.18 s at 18), about 5 hours at 30.
    let message = rejected_in_time("if", nested("if(", 30));
    assert!(!message.contains("nested too deeply"), "{message}");
}

#[test]
fn nested_nots_that_fail_are_rejected_without_backtracking() {
    // `not(` 26 times, never closed. Before the fix: 0.28 s at 16, 1.18 s at 18, 4.62 s
    // at 20 (release build), about 5 minutes at 26.
    let message = rejected_in_time("not", nested("not(", 26));
    assert!(!message.contains("nested too deeply"), "{message}");
}

#[test]
fn if_and_not_are_not_names_or_calls_in_expressions() {
    for src in [
        "model m {\n  state x = 0;\n  der(x) = if(x);\n}\n",
        "model m {\n  state x = 0;\n  der(x) = x + not;\n}\n",
    ] {
        assert!(dae_lang::check_source(src).is_err(), "{src}");
    }
}
