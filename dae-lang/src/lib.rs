//! `dae-lang`: the compiler for DAE models written in the `.dae` language.
#![warn(missing_docs)]

pub mod ast;
pub mod codegen;
pub mod compiled;
pub mod diag;
pub mod model;
pub mod tape;
pub mod tokens;
