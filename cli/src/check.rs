//! `daec check FILE [--json]`: parse and check the models of a file.

use crate::Reported;
use dae_lang::model::Model;
use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Arguments of `daec check`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.dae` file to check.
    file: PathBuf,
    /// Print the result as JSON (one object per model; an array if the file holds
    /// several models).
    #[arg(long)]
    json: bool,
}

/// Reads, parses and checks the file; prints the summary on stdout or every error on
/// stderr.
pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    let (name, source) = read_source(&args.file)?;
    let models = dae_lang::compile_models(&source).map_err(|d| report(&name, &source, &d))?;
    if args.json {
        println!("{}", json(&models));
    } else {
        print!("{}", summary(&name, &models));
    }
    Ok(())
}

/// Reads a `.dae` file as UTF-8 text; returns its display name and contents, or reports
/// why it cannot (shared by the subcommands that take a file).
pub(crate) fn read_source(path: &Path) -> Result<(String, String), Reported> {
    let name = path.display().to_string();
    match std::fs::read(path) {
        Ok(bytes) => match String::from_utf8(bytes) {
            Ok(s) => Ok((name, s)),
            Err(e) => {
                eprintln!(
                    "error: `{name}` is not UTF-8 text (invalid byte at offset {})",
                    e.utf8_error().valid_up_to()
                );
                Err(Reported)
            }
        },
        Err(e) => {
            eprintln!("error: cannot read `{name}`: {e}");
            Err(Reported)
        }
    }
}

/// Renders every diagnostic of `source` on stderr (in colour on a terminal unless
/// `NO_COLOR` is set), then a count line.
pub(crate) fn report(name: &str, source: &str, diags: &[dae_lang::Diagnostic]) -> Reported {
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

/// The JSON form of a model. `index` and `depends_on` of a constraint are filled by the
/// index analysis, which `check` does not run: `null` and `[]` here.
#[derive(Serialize)]
struct ModelJson<'a> {
    model: &'a str,
    states: Vec<&'a str>,
    algebraics: Vec<&'a str>,
    parameters: Params<'a>,
    constraints: Vec<ConstraintJson<'a>>,
}

#[derive(Serialize)]
struct ConstraintJson<'a> {
    name: &'a str,
    index: Option<usize>,
    depends_on: Vec<&'a str>,
}

/// Parameters as a JSON object in declaration order (a map type would sort them).
struct Params<'a>(&'a Model);

impl Serialize for Params<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.0.params.len()))?;
        for p in &self.0.params {
            map.serialize_entry(&p.name, &p.default)?;
        }
        map.end()
    }
}

fn model_json(m: &Model) -> ModelJson<'_> {
    ModelJson {
        model: &m.name,
        states: m.states.iter().map(|s| s.name.as_str()).collect(),
        algebraics: m.algs.iter().map(|a| a.name.as_str()).collect(),
        parameters: Params(m),
        constraints: m
            .constraints
            .iter()
            .map(|c| ConstraintJson {
                name: &c.name,
                index: None,
                depends_on: Vec::new(),
            })
            .collect(),
    }
}

/// One object for one model, an array for several.
fn json(models: &[Model]) -> String {
    let all: Vec<ModelJson<'_>> = models.iter().map(model_json).collect();
    let value = match all.as_slice() {
        [one] => serde_json::to_string_pretty(one),
        _ => serde_json::to_string_pretty(&all),
    };
    // Serialising these plain structs (finite numbers, string keys) cannot fail.
    value.unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

/// The text summary: per model its states, algebraics, parameters and constraints.
fn summary(file: &str, models: &[Model]) -> String {
    let mut out = String::new();
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    out.push_str(&format!(
        "{file}: {} model{} OK\n",
        models.len(),
        plural(models.len())
    ));
    for m in models {
        out.push_str(&format!("\nmodel {}\n", m.name));
        let names = |v: Vec<&str>| {
            if v.is_empty() {
                "(none)".to_string()
            } else {
                v.join(", ")
            }
        };
        out.push_str(&format!(
            "  states      ({}): {}\n",
            m.states.len(),
            names(m.states.iter().map(|s| s.name.as_str()).collect())
        ));
        out.push_str(&format!(
            "  algebraics  ({}): {}\n",
            m.algs.len(),
            names(m.algs.iter().map(|a| a.name.as_str()).collect())
        ));
        let params: Vec<String> = m
            .params
            .iter()
            .map(|p| format!("{} = {}", p.name, p.default))
            .collect();
        out.push_str(&format!(
            "  parameters  ({}): {}\n",
            m.params.len(),
            names(params.iter().map(String::as_str).collect())
        ));
        out.push_str(&format!(
            "  definitions ({}): {}\n",
            m.lets.len(),
            names(m.lets.iter().map(|l| l.name.as_str()).collect())
        ));
        out.push_str(&format!(
            "  constraints ({}): {}\n",
            m.constraints.len(),
            names(m.constraints.iter().map(|c| c.name.as_str()).collect())
        ));
    }
    out
}
