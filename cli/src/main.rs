//! `daec`: the command line of the DAE compiler.
//!
//! Each subcommand lives in a module of its own; `main` only parses the arguments and
//! maps the outcome to an exit status (0 success, 1 a user error, already reported on
//! stderr; clap uses 2 for bad arguments; `daec run` adds 3 for a layer left after
//! reaching and 4 for layers never reached).

use clap::{Parser, Subcommand};
use std::process::ExitCode;

// `print!` and `println!` for every subcommand: the std macros panic when stdout is
// closed early (`daec derive f.dae | head`); these end the process quietly instead.
// Defined before the `mod` lines so that the modules below see them.
macro_rules! print {
    ($($arg:tt)*) => { $crate::write_stdout(format_args!($($arg)*), false) };
}
macro_rules! println {
    () => { $crate::write_stdout(format_args!(""), true) };
    ($($arg:tt)*) => { $crate::write_stdout(format_args!($($arg)*), true) };
}

// `error!`, `hint!` and `note!`: a line on stderr, kept for the JSON object of a failure
// (`failure`).
macro_rules! error {
    ($($arg:tt)*) => { $crate::failure::error(&format!($($arg)*)) };
}
macro_rules! hint {
    ($($arg:tt)*) => { $crate::failure::hint(&format!($($arg)*)) };
}
macro_rules! note {
    ($($arg:tt)*) => { $crate::failure::note(&format!($($arg)*)) };
}

mod bounded;
mod check;
mod check_set;
mod derive;
mod design;
mod emit;
mod failure;
mod family;
mod fmu;
mod messages;
mod pilot;
mod progress;
mod redundant;
mod run;
mod source;

/// Compile DAE models written in the `.dae` language.
#[derive(Parser)]
#[command(name = "daec", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Parse, check and analyse a `.dae` file; print a summary of each model with the
    /// index of each constraint and the condition number of J_Omega.
    Check(check::Args),
    /// Simulate a model with DBSMC on the interpreter. Exit status: 0 the layers held,
    /// 1 an error, 2 bad arguments, 3 a layer was left after reaching, 4 the layers were
    /// not reached by --t-end.
    #[command(allow_negative_numbers = true)]
    Run(Box<run::Args>),
    /// Choose mu, gains and the guaranteed period from bounds or from a pilot run.
    Design(Box<design::Args>),
    /// Print the index analysis of each model: w-derivatives, Omega, J_Omega, beta, s,
    /// alpha and alpha_hat, one equation per line in the language's syntax.
    Derive(derive::Args),
    /// Print the Rust code generated for each model of a `.dae` file.
    Emit(emit::Args),
    /// Write an FMI 2.0 co-simulation FMU of a model (Linux x86-64), run by DBSMC with
    /// the online design of `daec run`.
    Fmu(fmu::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Check(args) => {
            failure::start("check", args.json);
            check::run(&args).map(|()| 0)
        }
        Command::Run(args) => {
            failure::start("run", args.json);
            run::run(&args).map(run::Outcome::code)
        }
        Command::Design(args) => {
            failure::start("design", args.json);
            design::run(&args).map(|()| 0)
        }
        Command::Derive(args) => derive::run(&args).map(|()| 0),
        Command::Emit(args) => emit::run(&args).map(|()| 0),
        Command::Fmu(args) => {
            failure::start("fmu", false);
            fmu::run(&args).map(|()| 0)
        }
    };
    match outcome {
        Ok(code) => ExitCode::from(code),
        Err(Reported) => {
            // With --json, the failure is also one JSON object on stdout.
            failure::print_json();
            ExitCode::FAILURE
        }
    }
}

/// A user error that has already been written to stderr (and kept by `failure` for
/// the JSON object of `--json`).
#[derive(Debug)]
struct Reported;

/// Write to stdout; a closed pipe ends the process with status 0 (the reader has all it
/// wanted), any other write error with status 1.
fn write_stdout(args: std::fmt::Arguments<'_>, newline: bool) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let written = out.write_fmt(args).and_then(|()| {
        if newline {
            out.write_all(b"\n")?;
        }
        Ok(())
    });
    if let Err(e) = written {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to stdout: {e}");
        std::process::exit(1);
    }
}
