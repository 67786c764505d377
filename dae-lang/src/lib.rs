//! `dae-lang`: the compiler for DAE models written in the `.dae` language.
#![warn(missing_docs)]

pub mod ast;
pub mod diag;
pub mod model;

mod check;
mod syntax;

pub use diag::{Diagnostic, line_col};

/// Parses a `.dae` source text into its syntax tree.
pub fn parse(src: &str) -> Result<ast::File, Vec<Diagnostic>> {
    syntax::parse(src)
}

/// Checks one model: resolves names, evaluates parameter defaults, orders the `let`
/// definitions and verifies the structure (one `der` per state, as many constraints
/// as algebraic variables, ...). Returns every error found, not only the first.
pub fn check(model: &ast::ModelAst) -> Result<model::Model, Vec<Diagnostic>> {
    check::check_model(model)
}

/// Parses and checks every model of a source text.
///
/// On failure returns all the errors: the syntax error, or the errors of every model,
/// in source order.
pub fn compile_models(src: &str) -> Result<Vec<model::Model>, Vec<Diagnostic>> {
    check::check_file(&parse(src)?)
}
