//! Library side of `daec`: `.dae` models run through the runtime without compiling
//! Rust, by the runtime's interpreter ([`Interpreted`] for a version-1 model,
//! `dae_runtime::family::Interpreter` for a family model). The command line itself is
//! the `daec` binary.
#![warn(missing_docs)]

use dae_runtime::family::Interpreted;

/// Parse, check, analyse and compile every model of a source text into interpreted
/// models (the interpreter's counterpart of the generated Rust types).
pub fn interpret_source(src: &str) -> Result<Vec<Interpreted>, Vec<dae_lang::Diagnostic>> {
    Ok(dae_lang::compile_source(src)?
        .into_iter()
        .map(Interpreted::new)
        .collect())
}
