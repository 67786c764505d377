//! `dae-lang`: the compiler for DAE models written in the `.dae` language.
//!
//! The front end turns source text into checked models: [`parse`] gives the syntax tree
//! ([`ast`]), [`check`] resolves and verifies one model ([`model::Model`]), and
//! [`check_source`] does both for every model of a file. Errors are [`Diagnostic`]s,
//! rendered with their source context by [`Diagnostic::render`]. The language is
//! described in `docs/language.md`.
//!
//! ```
//! let src = "
//!     model Decay {
//!         param k = 0.5;
//!         state x = 2 * k;
//!         der(x) = -k * x;
//!     }";
//! let models = dae_lang::check_source(src).expect("a valid model");
//! assert_eq!(models[0].name, "Decay");
//! assert_eq!(models[0].params[0].default, 0.5);
//!
//! let bad = "model M { state x = 0; der(x) = -k * x; }";
//! let errors = dae_lang::check_source(bad).unwrap_err();
//! assert_eq!(errors[0].message, "unknown name `k`");
//! assert_eq!(dae_lang::line_col(bad, errors[0].span), (1, 34));
//! println!("{}", errors[0].render("bad.dae", bad, false));
//! ```
//!
//! [`compile_source`] runs the whole pipeline: it also finds each constraint's index,
//! differentiates symbolically and compiles every function of the model into a
//! straight-line program ([`CompiledModel`]); [`codegen::emit_rust`] prints the Rust
//! type implementing `dae_runtime::Model` that the `dae!` macro, `dae_file!` and build
//! scripts ([`expand::compile_file_to_out_dir`]) compile, and that `daec emit` shows.
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
//! assert_eq!(models[0].indices, [2]); // x' holds z: differentiate once to reach it
//! let rust = dae_lang::codegen::emit_rust(&models[0]);
//! assert!(rust.contains("pub struct Tracking"));
//! assert!(rust.contains("impl ::dae_runtime::Model for Tracking"));
//! ```
#![warn(missing_docs)]

pub mod ast;
pub mod codegen;
pub mod compiled;
pub mod diag;
pub mod expand;
pub mod model;
pub mod tape;
pub mod tokens;

mod compile;

mod check;
mod func;
mod ids;
mod syntax;

pub use diag::{Diagnostic, line_col};
pub use func::Func;
pub use ids::{AlgId, ConstraintId, LetId, ParamId, StateId, VarRef};

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
pub fn check_source(src: &str) -> Result<Vec<model::Model>, Vec<Diagnostic>> {
    check::check_file(&parse(src)?)
}

mod analysis;
mod sym;

/// Models built in code (3-D double pendulum, planar chains) for this crate's tests,
/// benches and examples; not part of the supported API.
#[doc(hidden)]
pub use analysis::fixtures;
pub use analysis::{
    Analysis, AnalysisOptions, ConstraintAnalysis, ConstraintExprs, InitialPoint, Lowered,
    SymbolicModel, analyze, lower,
};
pub use sym::{Arena, DiffContext, Id, Names, Node, Num, Point};

pub use compiled::CompiledModel;

/// The compiled form of an analysed model: its functions as straight-line programs (the
/// input of the code generator and of the interpreter).
///
/// The analysis emitted these tapes from its expressions and evaluated them at the
/// initial point, so what runs is what was checked; this hands them over.
pub fn compile(analysis: &Analysis) -> CompiledModel {
    analysis.compiled.clone()
}

/// Parse, check and analyse (with default [`AnalysisOptions`]) every model of a source
/// text. On failure, all the errors: the front end's, or the analysis errors of every
/// model in order.
pub fn analyze_source(src: &str) -> Result<Vec<(model::Model, Analysis)>, Vec<Diagnostic>> {
    let models = check_source(src)?;
    let opts = AnalysisOptions::default();
    let mut out = Vec::with_capacity(models.len());
    let mut errors = Vec::new();
    for m in models {
        match analyze(&m, &opts) {
            Ok(a) => out.push((m, a)),
            Err(mut e) => errors.append(&mut e),
        }
    }
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(errors)
    }
}

/// The whole pipeline for every model of a source text: parse, check, analyse (with
/// default [`AnalysisOptions`]) and compile. All errors of all models are returned.
pub fn compile_source(src: &str) -> Result<Vec<CompiledModel>, Vec<Diagnostic>> {
    Ok(analyze_source(src)?
        .into_iter()
        .map(|(_, a)| a.compiled)
        .collect())
}
