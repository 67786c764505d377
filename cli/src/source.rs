//! Reading a `.dae` file and reporting its diagnostics, shared by the subcommands.

use crate::Reported;
use dae_lang::Diagnostic;
use std::io::IsTerminal;
use std::path::Path;

/// The file's display name and its text; a missing or non-UTF-8 file is reported on
/// stderr.
pub(crate) fn read(path: &Path) -> Result<(String, String), Reported> {
    let name = path.display().to_string();
    match std::fs::read(path) {
        Ok(bytes) => match String::from_utf8(bytes) {
            Ok(s) => Ok((name, s)),
            Err(e) => {
                eprintln!(
                    "error: `{name}` is not UTF-8 text (invalid byte at offset {})",
                    e.utf8_error().valid_up_to()
                );
                Err(Reported)
            }
        },
        Err(e) => {
            eprintln!("error: cannot read `{name}`: {e}");
            Err(Reported)
        }
    }
}

/// Renders every diagnostic with source context on stderr (coloured on a terminal
/// unless `NO_COLOR` is set), then a count line.
pub(crate) fn report(name: &str, source: &str, diags: &[Diagnostic]) -> Reported {
    let color = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    for d in diags {
        eprint!("{}", d.render(name, source, color));
    }
    let n = diags.len();
    eprintln!(
        "error: {n} error{} in `{name}`",
        if n == 1 { "" } else { "s" }
    );
    Reported
}

/// The compiled model of a file (the one it holds, or the one called `wanted`), with
/// the file's display name and text (to render later diagnostics).
pub(crate) fn compiled(
    path: &Path,
    wanted: Option<&str>,
) -> Result<(String, String, dae_lang::CompiledModel), Reported> {
    let (name, source) = read(path)?;
    let mut models = dae_lang::compile_source(&source).map_err(|d| report(&name, &source, &d))?;
    let names: Vec<String> = models.iter().map(|m| m.name.clone()).collect();
    let pick = match (wanted, models.len()) {
        (Some(w), _) => names.iter().position(|n| n == w),
        (None, 1) => Some(0),
        (None, _) => None,
    };
    match pick {
        Some(i) => {
            let m = models.swap_remove(i);
            Ok((name, source, m))
        }
        None => {
            match wanted {
                Some(w) => eprintln!(
                    "error: `{name}` has no model `{w}` (it has: {})",
                    names.join(", ")
                ),
                None if names.is_empty() => eprintln!("error: `{name}` holds no model"),
                None => eprintln!(
                    "error: `{name}` holds {} models ({}); choose one with --model",
                    names.len(),
                    names.join(", ")
                ),
            }
            Err(Reported)
        }
    }
}
