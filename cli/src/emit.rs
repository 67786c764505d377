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
/// error on stderr (and nothing on stdout).
///
/// Every model is analysed before anything is printed, so that an error in the last one
/// leaves no partial output; then the code is generated and written one model at a time,
/// so that the memory held is that of the models' tapes, not of all the code.
///
/// The code is generated on a thread of its own. With glibc each thread allocates from
/// an arena of its own, and generating (quote, syn, prettyplease) makes many small
/// allocations: on the heap that the parse of a large file has left fragmented, the
/// allocator's free lists made the time per model grow with the file (55,000 models:
/// 61 s, against 28 s on a fresh arena, the rate of a file of 1,000 models).
pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    let (name, source) = read_source(&args.file)?;
    let models = dae_lang::compile_source(&source).map_err(|d| report(&name, &source, &d))?;
    std::thread::scope(|s| {
        s.spawn(|| {
            for (k, model) in models.iter().enumerate() {
                if k > 0 {
                    println!();
                }
                print!("{}", dae_codegen::emit_rust(model));
            }
        });
    });
    Ok(())
}
