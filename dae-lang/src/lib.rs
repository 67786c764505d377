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
//! [`compile_source`] runs the whole pipeline: [`analyze`] finds each constraint's index,
//! differentiates symbolically and builds the realization (`s`, `J_Omega`, `beta`,
//! `alpha`, `alpha_hat`; the method is in `docs/method.md`), and compiles it into a
//! [`CompiledModel`]: for every model the four programs over sets
//! ([`family::FamilyModel`]: `rhs`, `sliding`, `jacobian` and the rate `Omega'`, with the
//! data construction needs), which the runtime's interpreter runs at any sizes and the
//! `dae-codegen` crate prints as the Rust type implementing `dae_runtime::Model` that
//! `dae!`, `dae_file!` and build scripts compile (for a family model a `Kernels` type).
//! The initial values of every model are the construction's formulas over the
//! parameters ([`family::Construction`]).
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
//! let m = &models[0];
//! assert_eq!(m.indices, [2]); // x' holds z: differentiate once to reach it
//!
//! // J_Omega = dOmega/dz at t = 0, x = 0, z = 1: Omega = w' = z - x - a cos(t), so 1.
//! // The jacobian program at the model's sizes (a model without sets has none to give).
//! use dae_lang::family::{Scratch, Spec, Values, construct};
//! let inst = construct(&m.programs.construction, &Spec::default()).expect("built");
//! let at = Values {
//!     params: &[1.0],
//!     states: &[0.0],
//!     algs: &[1.0],
//!     alg_rates: &[],
//!     mu: &[0.1],
//!     inputs: &[],
//!     t: 0.0,
//! };
//! let jacobian = &m.programs.jacobian;
//! let mut j = [0.0];
//! jacobian.eval(&inst, &at, &mut Scratch::new(jacobian, &inst), &mut [&mut j]);
//! assert_eq!(j, [1.0]);
//! ```
//!
//! # Features
//!
//! * `internals`: the symbolic intermediate representation (the hash-consed `Arena` of
//!   expressions, its `Node`s and `Id`s, `lower`, `Analysis::symbolic`) as public API,
//!   for the test crate and for tools that inspect a derivation. Not a stable interface.
//! * `fixtures`: models built in code (module `fixtures`) for tests and benchmarks.
#![warn(missing_docs)]

pub mod ast;
pub mod family;
pub mod model;
pub mod tape;

mod compile;
mod compiled;
mod diag;

mod check;
mod func;
mod ids;
mod maps;
mod syntax;

pub use diag::{Diagnostic, Renderer, line_col};
pub use func::Func;
pub use ids::{
    AlgId, ArrayId, ConstraintId, InputId, LetId, MapId, ParamId, SetId, SizeId, StateId, VarRef,
};
pub use maps::MapTable;
pub use syntax::MAX_SOURCE_BYTES;

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
// The arena's API is whole for the `internals` feature; the compiler uses part of it.
#[cfg_attr(not(feature = "internals"), allow(dead_code))]
mod sym;

#[cfg(any(test, feature = "fixtures"))]
pub use analysis::fixtures;
pub use analysis::{Analysis, AnalysisOptions, ConstraintAnalysis, InitialPoint};
#[cfg(feature = "internals")]
pub use analysis::{ConstraintExprs, Kernel, Lowered, SymbolicModel, lower};
#[cfg(feature = "internals")]
pub use sym::{
    Arena, DiffContext, FamilyNames, Id, LeafSets, Names, Node, Num, Point, Term, TwoHop,
    jacobian_terms,
};

pub use compiled::{CompiledModel, DENSE_JACOBIAN_MAX};

/// Analyse a checked model: index, `J_Omega`, `beta`, `s`, `alpha`, `alpha_hat`, its
/// compiled form, and the checks at the initial point. Every problem found is returned,
/// each as a diagnostic with the span of the item concerned.
pub fn analyze(model: &model::Model, opts: &AnalysisOptions) -> Result<Analysis, Vec<Diagnostic>> {
    let (constraints, symbolic) = analysis::derive(model, opts)?;
    let compiled = compile::compile(model, &constraints, &symbolic);
    Analysis::checked(model, constraints, symbolic, compiled, opts)
}

/// The compiled form of an analysed model: its programs (the input of the code generator
/// and of the interpreter).
///
/// The analysis compiled them from its expressions and, for a model without sets,
/// evaluated them at the initial point, so what runs is what was checked; this hands
/// them over.
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
///
/// Each model's analysis (its symbolic expressions) is dropped as soon as its programs
/// are made, so that the memory held is that of the programs, not of every derivation.
pub fn compile_source(src: &str) -> Result<Vec<CompiledModel>, Vec<Diagnostic>> {
    let models = check_source(src)?;
    let opts = AnalysisOptions::default();
    let mut out = Vec::with_capacity(models.len());
    let mut errors = Vec::new();
    for m in models {
        match analyze(&m, &opts) {
            Ok(a) => out.push(a.compiled),
            Err(mut e) => errors.append(&mut e),
        }
    }
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(errors)
    }
}
