//! Reading a `.dae` file and reporting its diagnostics, shared by the subcommands.

use crate::{Reported, failure};
use dae_lang::Diagnostic;
use std::io::IsTerminal;
use std::path::Path;

/// The file's display name and its text; a missing, too long or non-UTF-8 file is
/// reported on stderr.
///
/// At most [`dae_lang::MAX_SOURCE_BYTES`] bytes and one more are read, so that a file
/// over the limit, or one that never ends (`/dev/urandom`, a pipe), is refused without
/// reading it all.
pub(crate) fn read(path: &Path) -> Result<(String, String), Reported> {
    use std::io::Read;
    let name = path.display().to_string();
    let limit = dae_lang::MAX_SOURCE_BYTES;
    let mut bytes = Vec::new();
    let read =
        std::fs::File::open(path).and_then(|f| f.take(limit as u64 + 1).read_to_end(&mut bytes));
    if let Err(e) = read {
        error!("cannot read `{name}`: {e}");
        return Err(Reported);
    }
    if bytes.len() > limit {
        error!(
            "`{name}` is longer than 16 MiB ({limit} bytes), the limit for a `.dae` file\n  \
             hint: split the models over several files"
        );
        return Err(Reported);
    }
    match String::from_utf8(bytes) {
        Ok(s) => Ok((name, s)),
        Err(e) => {
            error!("{}", not_utf8(&name, e.as_bytes(), e.utf8_error()));
            Err(Reported)
        }
    }
}

/// The error for a file that is not UTF-8: the first invalid byte, with its line and
/// column (counted in the valid text before it) and its byte offset.
fn not_utf8(name: &str, bytes: &[u8], e: std::str::Utf8Error) -> String {
    let at = e.valid_up_to();
    // Valid by definition of `valid_up_to`; the fallback is never taken.
    let before = std::str::from_utf8(&bytes[..at]).unwrap_or_default();
    let (line, col) = dae_lang::line_col(before, dae_lang::ast::Span::new(at, at));
    let byte = bytes.get(at).copied().unwrap_or_default();
    format!(
        "`{name}` is not UTF-8 text: byte 0x{byte:02X} at {name}:{line}:{col} \
         (byte offset {at}) is not valid UTF-8\n  \
         hint: save the file as UTF-8 (the language is ASCII; other characters may appear \
         in comments)"
    )
}

/// Renders every diagnostic with source context on stderr (coloured on a terminal
/// unless `NO_COLOR` is set), then a count line; keeps them for the JSON object of
/// `--json` (`failure::diagnostics`).
pub(crate) fn report(name: &str, source: &str, diags: &[Diagnostic]) -> Reported {
    let color = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    let renderer = dae_lang::Renderer::new(name, source, color);
    for d in diags {
        eprint!("{}", renderer.render(d));
    }
    let n = diags.len();
    eprintln!(
        "error: {n} error{} in `{name}`",
        if n == 1 { "" } else { "s" }
    );
    failure::diagnostics(name, source, diags);
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
                Some(w) => error!("`{name}` has no model `{w}` (it has: {})", names.join(", ")),
                None if names.is_empty() => error!("`{name}` holds no model"),
                None => error!(
                    "`{name}` holds {} models ({}); choose one with --model",
                    names.len(),
                    names.join(", ")
                ),
            }
            Err(Reported)
        }
    }
}
