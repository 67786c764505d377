//! `daec`: the command line of the DAE compiler.
//!
//! Each subcommand lives in a module of its own; `main` only parses the arguments and
//! maps the outcome to an exit status (0 success, 1 a user error, already reported on
//! stderr; clap uses 2 for bad arguments).

use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod check;
mod emit;

/// Compile DAE models written in the `.dae` language.
#[derive(Parser)]
#[command(name = "daec", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Parse and check a `.dae` file; print a summary of each model.
    Check(check::Args),
    /// Print the Rust code generated for each model of a `.dae` file.
    Emit(emit::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Check(args) => check::run(&args),
        Command::Emit(args) => emit::run(&args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(Reported) => ExitCode::FAILURE,
    }
}

/// A user error that has already been written to stderr.
#[derive(Debug)]
struct Reported;
