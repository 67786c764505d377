//! `dae-lang`: the compiler for DAE models written in the `.dae` language.
#![warn(missing_docs)]

pub mod ast;
pub mod diag;
pub mod model;

mod analysis;
mod sym;

pub use analysis::{
    Analysis, AnalysisOptions, ConstraintAnalysis, InitialPoint, Lowered, analyze, fixtures, lower,
};
pub use sym::{Arena, Fun1, Fun2, Id, Names, Node, Num, Point};
