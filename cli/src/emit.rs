//! `daec emit FILE`: print the Rust code generated for every model of a file (the code
//! that `dae!`, `dae_file!` and build scripts compile).

use crate::Reported;
use crate::source::{read as read_source, report};
use std::path::PathBuf;

/// Arguments of `daec emit`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.dae` file to compile.
    file: PathBuf,
}

/// Reads, compiles and prints the formatted Rust of each model on stdout, or every
/// error on stderr.
pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    let (name, source) = read_source(&args.file)?;
    let models = dae_lang::compile_source(&source).map_err(|d| report(&name, &source, &d))?;
    let code: Vec<String> = models.iter().map(dae_codegen::emit_rust).collect();
    print!("{}", code.join("\n"));
    Ok(())
}
