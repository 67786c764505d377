//! `daec check FILE [--json] [--set NAME=VALUE] [--topology FILE]`: parse, check and
//! analyse the models of a file (at the given sizes and parameters).
//!
//! A family model is reported by its templates (sizes, sets, maps, declarations over
//! sets, constraint families with their index, the cases of the `J_Omega` kernels) and
//! by the model built at its default sizes (structural rank and a factorisation of
//! `J_Omega` at the initial point); nothing but that build grows with the sizes. A
//! version-1 model is the case without sets, whose `J_Omega` is checked at its initial
//! point by the analysis.

use crate::family::{DefaultSizes, Topology, at_default_sizes, template_lines};
use crate::{Reported, check_set, source};
use dae_lang::model::{Family, Model};
use dae_lang::{Analysis, SetId};
use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};
use serde_json::{Value, json};
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
                .then(|| check_family(a, topology.as_ref(), given, (&name, &src)))
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
    Family(Value),
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
            Some(f) => AnyJson::Family(family_json(m, a, f)),
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

/// The text summary: per model its declarations, and a table of the constraints with
/// their index and the algebraic unknowns in their `Omega`.
fn summary(file: &str, models: &[(Model, Analysis)], families: &[Option<FamilyCheck>]) -> String {
    let plural = if models.len() == 1 { "" } else { "s" };
    let mut out = format!("{file}: {} model{plural} OK\n", models.len());
    for ((m, a), f) in models.iter().zip(families) {
        out.push_str(&text(m, a, f.as_ref()));
    }
    out
}

/// The text summary of one model (`c` for a family model).
fn text(m: &Model, a: &Analysis, c: Option<&FamilyCheck>) -> String {
    let s = sections(m);
    let mut out = format!("\nmodel {}", m.name);
    let mut lists = vec![("states     ", &s.states), ("algebraics ", &s.algs)];
    if let Some(c) = c {
        out.push_str(" (families: templates for any sizes)");
        for h in &c.header {
            out.push_str(&format!("\n  {h}"));
        }
        lists.push(("inputs     ", &s.inputs));
    }
    out.push('\n');
    lists.extend([("parameters ", &s.params), ("definitions", &s.lets)]);
    for (what, v) in lists {
        out.push_str(&format!("  {what} ({}): {}\n", v.len(), list(v)));
    }
    out.push_str(&format!("  constraints ({}):", s.constraints.len()));
    if c.is_none() && s.constraints.is_empty() {
        out.push_str(" (none)\n");
        return out;
    }
    out.push('\n');
    out.push_str(&constraint_table(&s.constraints, a));
    let Some(c) = c else {
        out.push_str(&format!(
            "  J_Omega at t = 0: nonsingular, condition number {}\n",
            condition_text(a.condition_number)
        ));
        return out;
    };
    for (lhs, cases) in &c.kernels {
        out.push_str(&format!(
            "  J_Omega kernel {lhs}: {} case{} ({})\n",
            cases.len(),
            if cases.len() == 1 { "" } else { "s" },
            cases
                .iter()
                .map(|c| format!("when {c}"))
                .collect::<Vec<_>>()
                .join("; ")
        ));
    }
    match &c.default {
        Some(d) => out.push_str(&format!(
            "  at the {} sizes{}: {} states, {} constraints; J_Omega with {} entries, structural rank {}, nonsingular at t = 0 ({} solver)\n",
            if d.given { "given" } else { "default" },
            if d.sizes.is_empty() {
                String::new()
            } else {
                format!(" ({})", d.sizes)
            },
            d.states,
            d.constraints, d.entries, d.structural_rank, d.solver
        )),
        None => out.push_str(
            "  sets or maps given at run time: J_Omega is checked when the model is built (--topology FILE, of daec check or daec run)\n",
        ),
    }
    out
}

/// The table of the constraints: name, index and the algebraic unknowns in `Omega`.
fn constraint_table(names: &[String], a: &Analysis) -> String {
    let width = names
        .iter()
        .map(String::len)
        .chain(["name".len()])
        .max()
        .unwrap_or(4);
    let mut out = format!("    {:<width$}  index  depends on\n", "name");
    for (name, k) in names.iter().zip(&a.constraints) {
        out.push_str(&format!(
            "    {name:<width$}  {:>5}  {}\n",
            k.index,
            k.depends_on.join(", ")
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

/// Everything printed about one family model.
struct FamilyCheck {
    header: Vec<String>,
    kernels: Vec<(String, Vec<String>)>,
    default: Option<DefaultSizes>,
}

/// Checks a family model (see the module documentation); a singular `J_Omega` at the
/// default sizes is an error.
fn check_family(
    a: &Analysis,
    topology: Option<&Topology>,
    given: bool,
    file: (&str, &str),
) -> Result<FamilyCheck, Reported> {
    let (header, kernels) = template_lines(&a.derive_text());
    let default = at_default_sizes(dae_lang::compile(a), topology, given, file)?;
    Ok(FamilyCheck {
        header,
        kernels,
        default,
    })
}

/// `x[p in P]: vec3` for each declaration, its component families (`x.x`, `x.y`, `x.z`)
/// taken together.
fn decls<'a>(m: &Model, items: impl Iterator<Item = (&'a str, Family)>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut last = String::new();
    for (name, f) in items {
        let base = if f.dim > 1 {
            name.rsplit_once('.').map_or(name, |(b, _)| b)
        } else {
            name
        };
        if f.dim > 1 && f.component > 0 && base == last {
            continue;
        }
        last = base.to_string();
        let ty = match f.dim {
            2 => ": vec2",
            3 => ": vec3",
            _ => "",
        };
        out.push(format!("{base}{}{ty}", binder(m, f.over)));
    }
    out
}

/// `[p in P]` after the name of a declaration over `P` (nothing for a scalar).
fn binder(m: &Model, over: Option<SetId>) -> String {
    over.map_or(String::new(), |s| {
        let set = &m.sets[s.index()];
        format!("[{} in {}]", set.elem, set.name)
    })
}

/// A list of names, `(none)` when empty.
fn list(v: &[String]) -> String {
    if v.is_empty() {
        "(none)".into()
    } else {
        v.join(", ")
    }
}

/// The declarations of a model as `daec check` lists them.
struct Sections {
    states: Vec<String>,
    algs: Vec<String>,
    inputs: Vec<String>,
    params: Vec<String>,
    lets: Vec<String>,
    constraints: Vec<String>,
}

/// The declarations of a model: over their sets and with their vector types, the inputs
/// with their derivatives, the scalar parameters with their defaults.
fn sections(m: &Model) -> Sections {
    let inputs = decls(m, m.inputs.iter().map(|i| (i.name.as_str(), i.family)));
    let inputs = inputs
        .into_iter()
        .map(|text| {
            let base = text.split(['[', ':']).next().unwrap_or("");
            let k = m
                .inputs
                .iter()
                .find(|i| i.name.split('.').next() == Some(base))
                .map_or(0, |i| i.derivatives);
            format!("{text} with {k} derivatives")
        })
        .collect();
    let mut params = Vec::new();
    for p in decls(m, m.params.iter().map(|p| (p.name.as_str(), p.family))) {
        let scalar = m
            .params
            .iter()
            .find(|q| q.name == p && q.family.over.is_none());
        params.push(match scalar {
            Some(q) => format!("{} = {}", q.name, q.default),
            None => p,
        });
    }
    Sections {
        states: decls(m, m.states.iter().map(|s| (s.name.as_str(), s.family))),
        algs: decls(m, m.algs.iter().map(|s| (s.name.as_str(), s.family))),
        inputs,
        params,
        lets: decls(m, m.lets.iter().map(|s| (s.name.as_str(), s.family))),
        constraints: m
            .constraints
            .iter()
            .map(|c| format!("{}{}", c.name, binder(m, c.over)))
            .collect(),
    }
}

/// The JSON form of a family model.
fn family_json(m: &Model, a: &Analysis, c: &FamilyCheck) -> Value {
    let s = sections(m);
    json!({
        "model": m.name,
        "family": true,
        "sizes": m.sizes.iter().map(|z| json!({"name": z.name, "default": z.default})).collect::<Vec<_>>(),
        "templates": c.header,
        "states": s.states,
        "algebraics": s.algs,
        "inputs": s.inputs,
        "parameters": s.params,
        "definitions": s.lets,
        "constraints": s.constraints.iter().zip(&a.constraints).map(|(name, k)| json!({
            "name": name,
            "index": k.index,
            "depends_on": k.depends_on,
        })).collect::<Vec<_>>(),
        "jacobian": {
            "kernels": c.kernels.iter().map(|(lhs, cases)| json!({"entry": lhs, "cases": cases})).collect::<Vec<_>>(),
            "at_default_sizes": c.default,
            "nonsingular": c.default.as_ref().map(|d| d.nonsingular),
        },
    })
}
