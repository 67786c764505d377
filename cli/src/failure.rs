//! The errors of a command, in one place: every error is written on stderr as text
//! (`error: ...`, `  hint: ...`) and kept, so that with `--json` a failed `daec run`,
//! `daec design` or `daec check` also prints one JSON object on stdout:
//! `{"status": "error", "command", "error", "hint", ...}` with what the error carries
//! (the time and the constraints of a failed simulation, the places of a model's
//! diagnostics).

use serde_json::{Map, Value, json};
use std::sync::Mutex;

/// What went wrong, as the JSON object will say it.
#[derive(Default)]
struct Failure {
    json: bool,
    command: &'static str,
    /// The first error: the one that ended the command.
    error: Option<String>,
    hint: Option<String>,
    /// Errors after the first (a CSV that could not be flushed after a failed run).
    more: Vec<String>,
    notes: Vec<String>,
    fields: Map<String, Value>,
}

static FAILURE: Mutex<Option<Failure>> = Mutex::new(None);

/// Most names (of constraints) given in one field of the object.
const NAMES_MAX: usize = 256;

fn with<R>(f: impl FnOnce(&mut Failure) -> R) -> R {
    // A poisoned lock only means that another thread panicked while holding it; the
    // record is still usable.
    let mut guard = FAILURE.lock().unwrap_or_else(|e| e.into_inner());
    f(guard.get_or_insert_with(Failure::default))
}

/// The command that runs, and whether its failures are also JSON on stdout (`--json`).
pub(crate) fn start(command: &'static str, json: bool) {
    with(|f| {
        f.command = command;
        f.json = json;
    });
}

/// Whether the command's output is JSON (`--json`).
pub(crate) fn json() -> bool {
    with(|f| f.json)
}

/// Reports an error: `error: MESSAGE` on stderr, kept for the JSON object. A message
/// whose lines after the first start with `hint:` gives the hint (the first one kept).
pub(crate) fn error(message: &str) {
    eprintln!("error: {message}");
    let (text, hint) = match message.split_once("\n  hint: ") {
        Some((text, hint)) => (text, Some(hint)),
        None => (message, None),
    };
    with(|f| {
        if f.error.is_none() {
            f.error = Some(text.to_string());
            f.hint = hint.map(str::to_string);
        } else {
            f.more.push(text.to_string());
        }
    });
}

/// The hint of the error just reported, on a line of its own (`  hint: ...`).
pub(crate) fn hint(text: &str) {
    eprintln!("  hint: {text}");
    with(|f| {
        f.hint.get_or_insert_with(|| text.to_string());
    });
}

/// A note after an error (`  note: ...`).
pub(crate) fn note(text: &str) {
    eprintln!("  note: {text}");
    with(|f| f.notes.push(text.to_string()));
}

/// A field of the JSON object besides the message (`t`, `constraints`, ...).
pub(crate) fn field(key: &str, value: Value) {
    with(|f| {
        f.fields.insert(key.to_string(), value);
    });
}

/// Names as a JSON array, at most [`NAMES_MAX`] of them (then `names_total` says how
/// many there were).
pub(crate) fn names(key: &str, names: &[String]) {
    field(key, json!(names.iter().take(NAMES_MAX).collect::<Vec<_>>()));
    if names.len() > NAMES_MAX {
        field(&format!("{key}_total"), json!(names.len()));
    }
}

/// The diagnostics of a model's source as the failure: the first one's message and hint
/// as `error` and `hint`, and all of them (at most [`NAMES_MAX`]) under `diagnostics`
/// with their file, line and column.
pub(crate) fn diagnostics(file: &str, source: &str, diags: &[dae_lang::Diagnostic]) {
    let list: Vec<Value> = diags
        .iter()
        .take(NAMES_MAX)
        .map(|d| {
            let (line, column) = dae_lang::line_col(source, d.span);
            json!({
                "message": d.message,
                "file": file,
                "line": line,
                "column": column,
                "label": d.label,
                "hint": d.hint,
            })
        })
        .collect();
    with(|f| {
        if f.error.is_none() {
            if let Some(d) = diags.first() {
                f.error = Some(format!(
                    "{} ({} error{} in `{file}`)",
                    d.message,
                    diags.len(),
                    if diags.len() == 1 { "" } else { "s" }
                ));
                f.hint = d.hint.clone();
            }
        }
        f.fields.insert("diagnostics".into(), json!(list));
    });
}

/// A number as JSON: finite numbers as numbers, `NaN` and infinities as strings.
pub(crate) fn number(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        json!(v.to_string())
    }
}

/// With `--json`, the JSON object of the failure on stdout (called once, when the
/// command has failed).
pub(crate) fn print_json() {
    let Some(object) = with(|f| f.json.then(|| object(f))) else {
        return;
    };
    println!(
        "{}",
        serde_json::to_string_pretty(&object).unwrap_or_default()
    );
}

fn object(f: &Failure) -> Value {
    let mut o = Map::new();
    o.insert("status".into(), json!("error"));
    o.insert("command".into(), json!(f.command));
    o.insert(
        "error".into(),
        json!(
            f.error
                .as_deref()
                .unwrap_or("the command failed (stderr says why)")
        ),
    );
    o.insert("hint".into(), json!(f.hint));
    for (k, v) in &f.fields {
        o.insert(k.clone(), v.clone());
    }
    if !f.notes.is_empty() {
        o.insert("notes".into(), json!(f.notes));
    }
    if !f.more.is_empty() {
        o.insert("more_errors".into(), json!(f.more));
    }
    Value::Object(o)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_object_has_the_first_error_its_hint_and_the_fields() {
        let mut f = Failure {
            json: true,
            command: "run",
            ..Failure::default()
        };
        f.error = Some("--eps must be a finite number > 0, got -1".into());
        f.hint = Some("e.g. --eps 0.01".into());
        f.more.push("writing the CSV: disk full".into());
        f.fields.insert("t".into(), number(0.5));
        f.fields.insert("value".into(), number(f64::NAN));
        let v = object(&f);
        assert_eq!(v["status"], "error");
        assert_eq!(v["command"], "run");
        assert_eq!(v["error"], "--eps must be a finite number > 0, got -1");
        assert_eq!(v["hint"], "e.g. --eps 0.01");
        assert_eq!(v["t"], 0.5);
        assert_eq!(v["value"], "NaN");
        assert_eq!(v["more_errors"][0], "writing the CSV: disk full");
        let empty = object(&Failure::default());
        assert_eq!(empty["hint"], Value::Null);
        assert!(empty["error"].as_str().unwrap().contains("stderr"));
    }
}
