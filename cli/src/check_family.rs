//! `daec check` of a family model: its templates (sizes, sets, maps, declarations over
//! sets, constraint families with their index, the cases of the `J_Omega` kernels) and
//! the model built at its default sizes (structural rank and a factorisation of
//! `J_Omega` at the initial point). Nothing here grows with the sizes but the check at
//! the default sizes, which is linear in them.

use crate::Reported;
use crate::family::{DefaultSizes, Topology, at_default_sizes, template_lines};
use dae_lang::Analysis;
use dae_lang::model::{Family, Model};
use serde_json::{Value, json};

/// Everything printed about one family model.
pub(crate) struct FamilyCheck {
    header: Vec<String>,
    kernels: Vec<(String, Vec<String>)>,
    default: Option<DefaultSizes>,
}

/// Checks a family model (see the module documentation); a singular `J_Omega` at the
/// default sizes is an error.
pub(crate) fn check(
    a: &Analysis,
    topology: Option<&Topology>,
    given: bool,
) -> Result<FamilyCheck, Reported> {
    let (header, kernels) = template_lines(&a.derive_text());
    let default = at_default_sizes(dae_lang::compile(a), topology, given)?;
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
        let over = f.over.map(|s| {
            let set = &m.sets[s.index()];
            format!("[{} in {}]", set.elem, set.name)
        });
        let ty = match f.dim {
            2 => ": vec2",
            3 => ": vec3",
            _ => "",
        };
        out.push(format!("{base}{}{ty}", over.unwrap_or_default()));
    }
    out
}

fn list(v: &[String]) -> String {
    if v.is_empty() {
        "(none)".into()
    } else {
        v.join(", ")
    }
}

struct Sections {
    states: Vec<String>,
    algs: Vec<String>,
    inputs: Vec<String>,
    params: Vec<String>,
    lets: Vec<String>,
    constraints: Vec<String>,
}

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
            .map(|c| {
                let over = c.over.map(|s| {
                    let set = &m.sets[s.index()];
                    format!("[{} in {}]", set.elem, set.name)
                });
                format!("{}{}", c.name, over.unwrap_or_default())
            })
            .collect(),
    }
}

/// The text summary of a family model.
pub(crate) fn text(m: &Model, a: &Analysis, c: &FamilyCheck) -> String {
    let s = sections(m);
    let mut out = format!("\nmodel {} (families: templates for any sizes)\n", m.name);
    for h in &c.header {
        out.push_str(&format!("  {h}\n"));
    }
    for (what, v) in [
        ("states     ", &s.states),
        ("algebraics ", &s.algs),
        ("inputs     ", &s.inputs),
        ("parameters ", &s.params),
        ("definitions", &s.lets),
    ] {
        out.push_str(&format!("  {what} ({}): {}\n", v.len(), list(v)));
    }
    out.push_str(&format!("  constraints ({}):\n", s.constraints.len()));
    let width = s
        .constraints
        .iter()
        .map(String::len)
        .chain(["name".len()])
        .max()
        .unwrap_or(4);
    out.push_str(&format!("    {:<width$}  index  depends on\n", "name"));
    for (name, k) in s.constraints.iter().zip(&a.constraints) {
        out.push_str(&format!(
            "    {name:<width$}  {:>5}  {}\n",
            k.index,
            k.depends_on.join(", ")
        ));
    }
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

/// The JSON form of a family model.
pub(crate) fn json(m: &Model, a: &Analysis, c: &FamilyCheck) -> Value {
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
