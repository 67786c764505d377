//! Reading a `.dae` file and reporting diagnostics, shared by the subcommands.

use crate::Reported;
use dae_lang::model::Model;
use dae_lang::{Analysis, AnalysisOptions, Diagnostic};
use std::io::IsTerminal;
use std::path::Path;

/// The contents of a `.dae` file as text, or an error on stderr.
pub(crate) fn read(path: &Path) -> Result<String, Reported> {
    let name = path.display();
    match std::fs::read(path) {
        Ok(bytes) => String::from_utf8(bytes).map_err(|e| {
            eprintln!(
                "error: `{name}` is not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            );
            Reported
        }),
        Err(e) => {
            eprintln!("error: cannot read `{name}`: {e}");
            Err(Reported)
        }
    }
}

/// Render every diagnostic on stderr (in colour on a terminal unless `NO_COLOR` is set),
/// followed by a count.
pub(crate) fn report(name: &str, source: &str, diags: &[Diagnostic]) -> Reported {
    let color = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    for d in diags {
        eprint!("{}", d.render(name, source, color));
    }
    let n = diags.len();
    eprintln!(
        "error: {n} error{} in `{name}`",
        if n == 1 { "" } else { "s" }
    );
    Reported
}

/// Parse, check and analyse (default options) every model of a source text. On failure
/// all the errors: the front end's, or the analysis errors of every model in order.
pub(crate) fn analyse_all(source: &str) -> Result<Vec<(Model, Analysis)>, Vec<Diagnostic>> {
    let models = dae_lang::compile_models(source)?;
    let opts = AnalysisOptions::default();
    let mut out = Vec::with_capacity(models.len());
    let mut errors = Vec::new();
    for m in models {
        match dae_lang::analyze(&m, &opts) {
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
