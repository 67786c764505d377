//! Library side of `daec`: the interpreter that runs `.dae` models through the runtime
//! without compiling Rust. The command line itself is the `daec` binary.
#![warn(missing_docs)]

mod interp;

pub use interp::Interpreted;

/// Parse, check, analyse and compile every model of a source text into interpreted
/// models (the interpreter's counterpart of the generated Rust types).
pub fn interpret_source(src: &str) -> Result<Vec<Interpreted>, Vec<dae_lang::Diagnostic>> {
    Ok(dae_lang::compile_source(src)?
        .into_iter()
        .map(Interpreted::new)
        .collect())
}
