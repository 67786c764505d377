//! `daec derive FILE`: the index analysis of every model, one equation per line.

use crate::{Reported, source};
use std::path::PathBuf;

/// Arguments of `daec derive`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.dae` file to analyse.
    file: PathBuf,
}

/// Prints, per model, the lets, then per constraint `w^(j)`, `Omega`, the non-zero entries
/// of its row of `J_Omega`, `beta`, `s`, `alpha` and `alpha_hat`, each right-hand side an
/// expression of the language. Models of one file are separated by a blank line.
pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    let (name, src) = source::read(&args.file)?;
    let analysed = dae_lang::analyze_source(&src).map_err(|d| source::report(&name, &src, &d))?;
    for (k, (_, a)) in analysed.iter().enumerate() {
        if k > 0 {
            println!();
        }
        print!("{}", a.derive_text());
    }
    Ok(())
}
