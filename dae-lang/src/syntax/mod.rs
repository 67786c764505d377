//! The `.dae` file front end: a pest grammar (`dae.pest`) and the translation of its
//! parse tree into the [`crate::ast`].

mod build;
mod errors;

use crate::ast::File;
use crate::diag::Diagnostic;
use pest::Parser as _;
use pest_derive::Parser;

#[derive(Parser)]
#[grammar = "syntax/dae.pest"]
struct DaeParser;

/// Deepest nesting of expressions accepted. Later stages walk expressions recursively;
/// the bound keeps them far from the end of the stack (and no model written by hand
/// comes close to it).
pub(crate) const MAX_DEPTH: usize = 200;

/// Parses a whole `.dae` source text.
pub(crate) fn parse(src: &str) -> Result<File, Vec<Diagnostic>> {
    match DaeParser::parse(Rule::file, src) {
        Ok(mut pairs) => match pairs.next() {
            Some(file) => build::file(file),
            // pest always yields the `file` pair on success; report rather than panic.
            None => Err(vec![errors::empty_parse(src)]),
        },
        Err(e) => Err(vec![errors::translate(&e, src)]),
    }
}

#[cfg(test)]
mod tests;
