//! `dae-codegen`: Rust code generation for DAE models, on top of `dae-lang`.
//!
//! `dae-lang` compiles a `.dae` model into a [`CompiledModel`](dae_lang::CompiledModel): one straight-line program
//! (tape) per function of the runtime's `Model` trait. This crate prints those tapes as
//! Rust ([`generate`], [`emit_rust`]): one type per model, a struct whose public fields
//! are the model's parameters, implementing `::dae_runtime::Model` with straight-line
//! code on fixed-size arrays (no allocation, shared sub-expressions computed once).
//!
//! It also holds everything that turns Rust tokens or files into that code, so that the
//! proc-macro crate `dae-macros` stays a thin shim (as `pest_derive` over
//! `pest_generator`):
//!
//! * [`TokenSource`]: the second front door, model text given as Rust tokens (`dae!`);
//! * [`expand_dae`], [`expand_dae_file`]: the expansions of `dae!` and `dae_file!`,
//!   errors as `compile_error!` at the offending tokens;
//! * [`compile_file_to_out_dir`]: the build-script entry point.
//!
//! ```
//! let src = "
//!     model Tracking {
//!         param a = 1.0;
//!         state x = 0.0;
//!         alg z = 1.0;
//!         der(x) = z - x;
//!         constraint follow: x = a * sin(t);
//!     }";
//! let models = dae_lang::compile_source(src).expect("a valid model");
//! let rust = dae_codegen::emit_rust(&models[0]);
//! assert!(rust.contains("pub struct Tracking"));
//! assert!(rust.contains("Model for Tracking")); // `impl ::dae_runtime::Model for ...`
//! ```
//!
//! # Features
//!
//! * `pretty`: [`emit_rust`] (and so [`compile_file_to_out_dir`]) formats the code with
//!   `prettyplease`, for code that people read (`daec emit`). Without it the code is the
//!   tokens' text, which compiles the same; the macros leave it off, so that a crate
//!   using `dae!` does not compile `syn` and `prettyplease`.
#![warn(missing_docs)]

mod construction;
mod expand;
mod family;
mod rust;
mod tokens;

pub use expand::{compile_file_to_out_dir, expand_dae, expand_dae_file};
pub use rust::{emit_rust, generate, rust_ident};
pub use tokens::TokenSource;
