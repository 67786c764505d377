//! Library side of `daec`: `.dae` models run through the runtime without compiling
//! Rust, by the runtime's interpreter ([`Interpreted`]). The command line itself is the
//! `daec` binary.
#![warn(missing_docs)]

use dae_runtime::family::Interpreted;

/// Parse, check, analyse and compile every model of a source text into interpreted
/// models at their default sizes (the interpreter's counterpart of the generated Rust
/// types). A model that needs sets or maps given at construction is an error.
pub fn interpret_source(src: &str) -> Result<Vec<Interpreted>, Vec<dae_lang::Diagnostic>> {
    let spec = dae_lang::family::Spec::default();
    let mut models = Vec::new();
    let mut errors = Vec::new();
    for c in dae_lang::compile_source(src)? {
        match Interpreted::from_compiled(c, &spec) {
            Ok(m) => models.push(m),
            Err(e) => errors.push(e.to_diagnostic()),
        }
    }
    if errors.is_empty() {
        Ok(models)
    } else {
        Err(errors)
    }
}
