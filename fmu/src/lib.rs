//! `dae-fmu`: a `.dae` model as an FMI 2.0 co-simulation FMU that other tools run
//! (Modelica tools, Simulink, Python through FMPy, hardware-in-the-loop rigs).
//!
//! The crate is two things. Built as a `cdylib` it is the FMU's library: the C
//! functions of the standard, which compile the model from the FMU's resources when
//! instantiated and run it on the runtime's interpreter, with the online design of
//! `daec run` (the same settings, so the same trajectory at the same cut points). Used as
//! a Rust library it is the packager, [`export`], behind `daec fmu`:
//!
//! ```no_run
//! use dae_fmu::{Config, export, find_library};
//! let src = std::fs::read_to_string("double_pendulum.dae").unwrap();
//! let config = Config::new("DoublePendulum", 1e-3, 10.0);
//! let lib = find_library().expect("libdae_fmu.so: cargo build --release -p dae-fmu");
//! let fmu = export(&src, config, &lib, "DoublePendulum.fmu".as_ref()).unwrap();
//! println!("{} variables", fmu.variables.len());
//! ```
//!
//! What the FMU offers (its `modelDescription.xml` says it to importers):
//! - variables: `eps` (the layer of every constraint) and the model's parameters as fixed
//!   parameters; the states, the algebraic unknowns and each constraint's error
//!   `error.<name>` (its `w = g(t, x)`) as outputs; a family model's inputs as inputs,
//!   their derivatives through `fmi2SetRealInputDerivatives`.
//! - `fmi2DoStep` runs DBSMC from the current time to the end of the communication step
//!   and cuts the run there (explicit steps; the work follows the model's state, never
//!   the wall clock). A run that leaves its layer returns `fmi2Warning` once, with a log
//!   message naming when, which constraint and by how much; a failed run returns
//!   `fmi2Error` with the reason, and only `fmi2Reset` brings the instance back.
//! - `fmi2Reset` goes back to the state after `fmi2Instantiate`. The FMU state
//!   (`fmi2Get/SetFMUstate`) and directional derivatives are not offered.
#![warn(missing_docs)]

pub mod abi;
mod archive;
mod config;
mod description;
mod export;
mod instance;
mod model;
mod variables;

pub use config::Config;
pub use export::{Exported, LIBRARY_FILE, export, find_library, model_identifier, unpack};
pub use variables::{Kind, Variable};
