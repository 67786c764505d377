//! `daec check FILE [--json] [--set NAME=VALUE] [--topology FILE]`: parse, check and
//! analyse the models of a file (at the given sizes and parameters).

use crate::check_family::{self, FamilyCheck};
use crate::{Reported, check_set, source};
use dae_lang::Analysis;
use dae_lang::model::Model;
use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};
use std::path::PathBuf;

/// Arguments of `daec check`.
///
/// Besides the front-end checks, runs the index analysis: a constraint without an index,
/// a singular or ill-conditioned J_Omega (condition number above 1e12) at the initial
/// point, or a non-finite value there is an error (rendered on stderr, exit status 1;
/// with `--json` also a JSON failure object on stdout). So a successful check always reports a nonsingular J_Omega.
#[derive(clap::Args)]
#[command(
    after_help = "A singular J_Omega at the initial point is an error (exit status 1): it names the \
                  constraints whose rows are dependent and the condition number. A successful check \
                  therefore always prints `\"nonsingular\": true` in its JSON."
)]
pub(crate) struct Args {
    /// The `.dae` file to check.
    file: PathBuf,
    /// The model to check when the file holds several [default: every model].
    #[arg(long)]
    model: Option<String>,
    /// A size or a scalar parameter of the model, checked at this value instead of the
    /// one declared: `--set N=1000 --set m_end=10` (repeatable; for a version-1 model,
    /// its parameters).
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = crate::family::parse_assignment)]
    set: Vec<(String, f64)>,
    /// The sets and maps of a family model given at construction, as for `daec run`
    /// (docs/language.md, "Topology files"): `J_Omega` is checked on the model built
    /// with them.
    #[arg(long, value_name = "FILE")]
    topology: Option<PathBuf>,
    /// Print the result as JSON (one object per model; an array if the file holds
    /// several models).
    #[arg(long)]
    pub(crate) json: bool,
}

/// Reads, parses, checks and analyses the file; prints the summary on stdout or every
/// error on stderr.
pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    let (name, src) = source::read(&args.file)?;
    let given = !args.set.is_empty() || args.topology.is_some();
    let analysed = if given || args.model.is_some() {
        check_set::analysed(&name, &src, args.model.as_deref(), &args.set)?
    } else {
        dae_lang::analyze_source(&src).map_err(|d| source::report(&name, &src, &d))?
    };
    let topology = match &args.topology {
        None => None,
        Some(path) => {
            if let Some((m, _)) = analysed.iter().find(|(m, _)| !m.is_family()) {
                error!(
                    "--topology {}: `{}` has no sets (a version-1 model); a topology gives the sets and maps of a family model",
                    path.display(),
                    m.name
                );
                return Err(Reported);
            }
            Some(crate::family::read_topology(path)?)
        }
    };
    let families = analysed
        .iter()
        .map(|(m, a)| {
            m.is_family()
                .then(|| check_family::check(a, topology.as_ref(), given))
                .transpose()
        })
        .collect::<Result<Vec<_>, Reported>>()?;
    if args.json {
        println!("{}", json(&analysed, &families));
    } else {
        print!("{}", summary(&name, &analysed, &families));
    }
    Ok(())
}

/// The JSON form of a version-1 model (fields in this order) or of a family model.
#[derive(Serialize)]
#[serde(untagged)]
enum AnyJson<'a> {
    Scalar(ModelJson<'a>),
    Family(serde_json::Value),
}

/// The JSON form of a model.
#[derive(Serialize)]
struct ModelJson<'a> {
    model: &'a str,
    states: Vec<&'a str>,
    algebraics: Vec<&'a str>,
    parameters: Params<'a>,
    constraints: Vec<ConstraintJson<'a>>,
    jacobian: JacobianJson,
}

#[derive(Serialize)]
struct ConstraintJson<'a> {
    name: &'a str,
    index: usize,
    depends_on: &'a [String],
}

/// `J_Omega` at the initial point. `nonsingular` is always true in printed output (a
/// singular J_Omega is an error); it is there so that consumers need not know that rule.
#[derive(Serialize)]
struct JacobianJson {
    nonsingular: bool,
    condition: f64,
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

fn model_json<'a>(m: &'a Model, a: &'a Analysis) -> ModelJson<'a> {
    ModelJson {
        model: &m.name,
        states: m.states.iter().map(|s| s.name.as_str()).collect(),
        algebraics: m.algs.iter().map(|a| a.name.as_str()).collect(),
        parameters: Params(m),
        constraints: a
            .constraints
            .iter()
            .map(|c| ConstraintJson {
                name: &c.name,
                index: c.index,
                depends_on: &c.depends_on,
            })
            .collect(),
        jacobian: JacobianJson {
            nonsingular: a.condition_number.is_finite(),
            condition: a.condition_number,
        },
    }
}

/// One object for one model, an array for several.
fn json(models: &[(Model, Analysis)], families: &[Option<FamilyCheck>]) -> String {
    let all: Vec<AnyJson<'_>> = models
        .iter()
        .zip(families)
        .map(|((m, a), f)| match f {
            Some(f) => AnyJson::Family(check_family::json(m, a, f)),
            None => AnyJson::Scalar(model_json(m, a)),
        })
        .collect();
    let value = match all.as_slice() {
        [one] => serde_json::to_string_pretty(one),
        _ => serde_json::to_string_pretty(&all),
    };
    // The analysis only succeeds with finite values, and the keys are strings, so
    // serialising cannot fail.
    value.unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

/// The text summary: per model its states, algebraics, parameters, definitions, and a
/// table of the constraints with their index and the algebraic unknowns in their `Omega`.
fn summary(file: &str, models: &[(Model, Analysis)], families: &[Option<FamilyCheck>]) -> String {
    let mut out = String::new();
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    out.push_str(&format!(
        "{file}: {} model{} OK\n",
        models.len(),
        plural(models.len())
    ));
    for ((m, a), f) in models.iter().zip(families) {
        if let Some(f) = f {
            out.push_str(&check_family::text(m, a, f));
            continue;
        }
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
        out.push_str(&format!("  constraints ({}):", a.constraints.len()));
        if a.constraints.is_empty() {
            out.push_str(" (none)\n");
            continue;
        }
        out.push('\n');
        let width = a
            .constraints
            .iter()
            .map(|c| c.name.len())
            .chain(["name".len()])
            .max()
            .unwrap_or(4);
        out.push_str(&format!("    {:<width$}  index  depends on\n", "name"));
        for c in &a.constraints {
            out.push_str(&format!(
                "    {:<width$}  {:>5}  {}\n",
                c.name,
                c.index,
                c.depends_on.join(", ")
            ));
        }
        out.push_str(&format!(
            "  J_Omega at t = 0: nonsingular, condition number {}\n",
            condition_text(a.condition_number)
        ));
    }
    out
}

/// A condition number with 7 significant digits: `6.854102` below 1e6, `3.162278e7` above.
fn condition_text(c: f64) -> String {
    if c < 1e6 {
        format!("{c:.6}")
    } else {
        format!("{c:.6e}")
    }
}
