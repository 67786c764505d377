//! The `daec derive` text of a family model: its templates, one equation a line, the
//! same for any sizes.
//!
//! ```text
//! // model Chain: 1 constraint family, indices (3); templates for any sizes
//! // sizes: N = 10
//! // sets: P = N + 1 (element p), L = N (element l)
//! // maps: a[l in L] -> P = l, b[l in L] -> P = l + 1
//!
//! // definitions (the model's lets, in terms of earlier ones)
//! let d[l].x = x[b[l]].x - x[a[l]].x
//!
//! // constraint link[l in L]: index 3, Omega = w_link'', depends on z, mu_link = realization parameter
//! w_link[l] = ...
//! w_link'[l] = ...
//! Omega_link[l] = ...
//! J(link[l], z[k]) = u[l].x*u[k].x*free[b[l]]/m[b[l]] + ...  when b[l] == a[k]
//! beta_link[l] = ...
//! s_link[l] = ...
//! alpha_link[l] = ...
//! alpha_hat_link[l] = ...
//! ```
//!
//! A family variable prints at the element bound to its set (`x[b[l]].x`: the
//! component `x` of `x` at particle `b[l]`); input derivatives print with primes
//! (`pin''[p].x`). `J(c[l], z[k])` is the kernel of one coupling: the entry of row `l`
//! of `c` and column `k` of `z` exists where the condition after `when` holds, and its
//! value is the sum of the kernels of all couplings that hold there.

use std::fmt::Write;

use super::Analysis;
use super::text::{condition_text, wname};
use crate::model::MapKind;
use crate::sym::{Arena, Id, Names};
use crate::{SetId, VarRef};

/// The name of the element of a set other than `avoid` (for the columns of a kernel).
fn column_elem(names: &Names, set: SetId, avoid: &str) -> String {
    let own = names.elem(set);
    if own != avoid {
        return own;
    }
    ["k", "j", "i", "q"]
        .into_iter()
        .find(|c| *c != avoid)
        .unwrap_or("k")
        .to_string()
}

/// `name[e]` (or `name` for a scalar), with a component after: `d.x` -> `d[l].x`.
fn named(name: &str, set: Option<SetId>, elem: &str) -> String {
    match set {
        None => name.to_string(),
        Some(_) => match name.find('.') {
            Some(i) => format!("{}[{elem}]{}", &name[..i], &name[i..]),
            None => format!("{name}[{elem}]"),
        },
    }
}

/// A product of two printed factors (`1` dropped).
fn times(a: &str, b: &str) -> String {
    let wrap = |s: &str| {
        if s.contains(" + ") || s.contains(" - ") || s.starts_with("sum(") {
            format!("({s})")
        } else {
            s.to_string()
        }
    };
    match (a, b) {
        ("1", b) => b.to_string(),
        (a, "1") => a.to_string(),
        (a, b) => format!("{}*{}", wrap(a), wrap(b)),
    }
}

impl Analysis {
    /// The templates as text (see the module documentation of `text_family`).
    pub(super) fn family_text(&self) -> String {
        let sym = &self.symbolic;
        let names = &sym.names;
        let arena = &sym.arena;
        let model = self.compiled.family.as_ref().map(|f| &f.construction);
        let mut out = String::new();
        let indices: Vec<String> = self.indices().iter().map(|r| r.to_string()).collect();
        let _ = writeln!(
            out,
            "// model {}: {} constraint declaration{}, indices ({}); templates for any sizes",
            self.model_name,
            self.constraints.len(),
            if self.constraints.len() == 1 { "" } else { "s" },
            indices.join(", "),
        );
        if let Some(c) = model {
            let sizes: Vec<String> = c
                .sizes
                .iter()
                .map(|s| format!("{} = {}", s.name, s.default))
                .collect();
            let _ = writeln!(
                out,
                "// sizes: {}",
                if sizes.is_empty() {
                    "(none)".into()
                } else {
                    sizes.join(", ")
                }
            );
            let sets: Vec<String> = c
                .sets
                .iter()
                .map(|s| match &s.size {
                    Some(f) => format!(
                        "{} = {} (element {})",
                        s.name,
                        arena.formula_text(f, "", names),
                        s.elem
                    ),
                    None => format!("{} given (element {})", s.name, s.elem),
                })
                .collect();
            let _ = writeln!(out, "// sets: {}", sets.join(", "));
            let maps: Vec<String> = c
                .maps
                .iter()
                .filter(|m| crate::maps::is_named(m))
                .map(|m| {
                    let dom = names.set(m.domain);
                    let elem = m.domain.map_or(String::new(), |s| names.elem(s));
                    let head = format!("{}[{elem} in {dom}] -> {}", m.name, names.set(m.codomain));
                    match &m.kind {
                        MapKind::Formula(f) => {
                            format!("{head} = {}", arena.formula_text(f, &elem, names))
                        }
                        _ => format!("{head} given"),
                    }
                })
                .collect();
            if !maps.is_empty() {
                let _ = writeln!(out, "// maps: {}", maps.join(", "));
            }
        }
        let _ = writeln!(
            out,
            "// J(c[l], z[k]) = dOmega_c(l)/dz(k) where the condition after `when` holds (the values of the couplings that hold add)"
        );
        let abbrev = |n: usize| -> Vec<(Id, String)> {
            sym.lets
                .iter()
                .zip(&sym.let_names)
                .take(n)
                .filter(|(id, _)| !arena.children(**id).is_empty())
                .map(|(id, name)| (*id, name.clone()))
                .collect()
        };
        let all = abbrev(sym.lets.len());
        if !sym.lets.is_empty() {
            out.push_str("\n// definitions (the model's lets, in terms of earlier ones)\n");
        }
        for (j, (&id, name)) in sym.lets.iter().zip(&sym.let_names).enumerate() {
            let own: Vec<(Id, String)> = abbrev(j).into_iter().filter(|(a, _)| *a != id).collect();
            let text = arena.display_in(&[id], names, &own, &[]);
            let set = arena.ctx(id);
            let elem = set.map_or(String::new(), |s| names.elem(s));
            let _ = writeln!(out, "let {} = {}", named(name, set, &elem), text[0]);
        }
        for (i, (c, e)) in self.constraints.iter().zip(&sym.constraints).enumerate() {
            let set = arena.leaf_sets().constraint(crate::ConstraintId::new(i));
            let elem = set.map_or(String::new(), |s| names.elem(s));
            let r = c.index;
            let head = match set {
                Some(s) => format!("{}[{elem} in {}]", c.name, names.set(Some(s))),
                None => c.name.clone(),
            };
            let mu = names.var(VarRef::Mu(crate::ConstraintId::new(i)));
            let _ = writeln!(
                out,
                "\n// constraint {head}: index {r}, Omega = {}, depends on {}, {mu} = realization parameter",
                wname(&c.name, r - 1, r + 1),
                c.depends_on.join(", "),
            );
            let mut ids: Vec<Id> = e.w.clone();
            ids.extend([e.beta, e.s, e.alpha, e.alpha_hat]);
            let printed = arena.display_in(&ids, names, &all, &[]);
            let row = |what: String| named(&what, set, &elem);
            for (j, text) in printed.iter().take(r).enumerate() {
                let _ = writeln!(out, "{} = {}", row(wname(&c.name, j, r)), text);
            }
            for k in &e.kernels {
                let _ = writeln!(
                    out,
                    "{}",
                    kernel_line(arena, names, &all, &c.name, set, &elem, k)
                );
            }
            let _ = writeln!(out, "{} = {}", row(format!("beta_{}", c.name)), printed[r]);
            let _ = writeln!(out, "{} = {}", row(format!("s_{}", c.name)), printed[r + 1]);
            let _ = writeln!(
                out,
                "{} = {}",
                row(format!("alpha_{}", c.name)),
                printed[r + 2]
            );
            let _ = writeln!(
                out,
                "{} = {}",
                row(format!("alpha_hat_{}", c.name)),
                printed[r + 3]
            );
        }
        if self.condition_number.is_finite() {
            let _ = writeln!(
                out,
                "// cond(J_Omega) = {}",
                condition_text(self.condition_number)
            );
        }
        out
    }
}

/// `J(link[l], z[k]) = ... when b[l] == a[k]`.
fn kernel_line(
    arena: &Arena,
    names: &Names,
    abbrev: &[(Id, String)],
    constraint: &str,
    row_set: Option<SetId>,
    row_elem: &str,
    k: &super::Kernel,
) -> String {
    let col_set = arena.leaf_sets().of(VarRef::Alg(k.alg));
    let col_elem = col_set.map_or(String::new(), |s| column_elem(names, s, row_elem));
    let mut bind = Vec::new();
    if let Some(s) = col_set {
        bind.push((s, col_elem.clone()));
    }
    let rows: Vec<Id> = k.terms.iter().map(|t| t.0).collect();
    let cols: Vec<Id> = k.terms.iter().map(|t| t.1).collect();
    let r_text = arena.display_in(&rows, names, abbrev, &[]);
    let c_text = arena.display_in(&cols, names, abbrev, &bind);
    let mut value = String::new();
    for (n, (r, c)) in r_text.iter().zip(&c_text).enumerate() {
        let term = times(r, c);
        match (n, term.strip_prefix('-')) {
            (0, _) => value.push_str(&term),
            (_, Some(rest)) => {
                let _ = write!(value, " - {rest}");
            }
            (_, None) => {
                let _ = write!(value, " + {term}");
            }
        }
    }
    let z = names.var(VarRef::Alg(k.alg));
    let z = named(&z, col_set, &col_elem);
    let row = named(constraint, row_set, row_elem);
    let lhs = arena.path_text(k.row_map, row_elem, names);
    let rhs = arena.path_text(k.col_map, &col_elem, names);
    let when = if lhs == rhs && lhs == "0" {
        String::new()
    } else {
        format!("  when {lhs} == {rhs}")
    };
    format!("J({row}, {z}) = {value}{when}")
}
