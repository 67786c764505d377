//! The `daec derive` text: one equation per line, right-hand sides in the language syntax.
//!
//! A version-1 model and a family model share the printer: a version-1 model is one
//! without sets, whose constraints print at no element and whose `J_Omega` entries are
//! numbered; a family model prints its templates, the same for any sizes:
//!
//! ```text
//! // model Chain: 1 constraint declaration, indices (3); templates for any sizes
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

use super::{Analysis, ConstraintExprs, Kernel};
use crate::family::Construction;
use crate::model::MapKind;
use crate::sym::{Arena, Id, Names};
use crate::{ConstraintId, SetId, VarRef};

/// The name of `w^(j)` of a constraint; the last one (`j = r - 1`) is called `Omega`.
pub(super) fn wname(c: &str, j: usize, index: usize) -> String {
    if j + 1 == index {
        return format!("Omega_{c}");
    }
    match j {
        0..=3 => format!("w_{c}{}", "'".repeat(j)),
        _ => format!("w_{c}^({j})"),
    }
}

impl Analysis {
    /// The lets as abbreviations, skipping lets that are a bare leaf or number.
    fn abbreviations(&self) -> Vec<(Id, String)> {
        let sym = &self.symbolic;
        sym.lets
            .iter()
            .zip(&sym.let_names)
            .filter(|(id, _)| is_abbreviated(&sym.arena, **id))
            .map(|(id, name)| (*id, name.clone()))
            .collect()
    }

    /// The derivation as text, one equation per line:
    ///
    /// ```text
    /// // constraint link1: index 3, Omega = w_link1'', depends on z1, z2
    /// w_link1 = ...
    /// w_link1' = ...
    /// Omega_link1 = ...
    /// J(0, 0) = ...  // link1 / z1
    /// beta_link1 = ...
    /// s_link1 = ...
    /// alpha_link1 = ...
    /// alpha_hat_link1 = ...
    /// ```
    ///
    /// The model's lets come first (`let l1 = ...`), each in terms of earlier ones; every
    /// right-hand side after them is an expression of the language over the model's names
    /// (parameters, states, algebraic unknowns, lets) and `t`, plus the realization
    /// parameters `mu1, mu2, ...`. A let is written by name wherever its node occurs whole
    /// (after simplification a let may also be merged into a larger term, e.g. `l^2`
    /// becomes the sum it squares). `J(i, k)` is `dOmega_i/dz_k` (row = constraint,
    /// column = algebraic unknown, both from 0), followed by a comment naming the
    /// constraint and the unknown; only structurally non-zero entries appear.
    ///
    /// For a family model, the templates: the same equations per constraint family,
    /// written at its element (`w_link[l] = ...`), with `J_Omega` as kernels and the
    /// conditions they hold in (`J(link[l], z[k]) = ... when b[l] == a[k]`).
    pub fn derive_text(&self) -> String {
        let sym = &self.symbolic;
        let family = self
            .compiled
            .is_family()
            .then_some(&self.compiled.programs.construction);
        let mut out = String::new();
        let indices: Vec<String> = self.indices().iter().map(|r| r.to_string()).collect();
        let (noun, tail) = match family {
            None => (
                "constraint",
                format!(
                    ", cond(J_Omega) = {} at t = 0",
                    condition_text(self.condition_number)
                ),
            ),
            Some(_) => ("constraint declaration", "; templates for any sizes".into()),
        };
        let _ = writeln!(
            out,
            "// model {}: {} {noun}{}, indices ({}){tail}",
            self.model_name,
            self.constraints.len(),
            if self.constraints.len() == 1 { "" } else { "s" },
            indices.join(", "),
        );
        match family {
            None => {
                let cols: Vec<String> = (sym.names.algs.iter().enumerate())
                    .map(|(k, n)| format!("{k} = {n}"))
                    .collect();
                let _ = writeln!(
                    out,
                    "// J(i, k) = dOmega_i/dz_k, columns: {}",
                    cols.join(", ")
                );
            }
            Some(c) => {
                construction_text(&mut out, &sym.arena, &sym.names, c);
                let _ = writeln!(
                    out,
                    "// J(c[l], z[k]) = dOmega_c(l)/dz(k) where the condition after `when` holds (the values of the couplings that hold add)"
                );
            }
        }
        self.definitions_text(&mut out);
        let all = self.abbreviations();
        for (i, e) in sym.constraints.iter().enumerate() {
            self.constraint_text(&mut out, &all, i, e);
        }
        if family.is_some() && self.condition_number.is_finite() {
            let _ = writeln!(
                out,
                "// cond(J_Omega) = {}",
                condition_text(self.condition_number)
            );
        }
        out
    }

    /// `let name = ...` for each let, in terms of the earlier ones.
    fn definitions_text(&self, out: &mut String) {
        let sym = &self.symbolic;
        let (arena, names) = (&sym.arena, &sym.names);
        if !sym.lets.is_empty() {
            out.push_str("\n// definitions (the model's lets, in terms of earlier ones)\n");
        }
        let defs: Vec<(Id, &str, bool)> = sym
            .lets
            .iter()
            .zip(&sym.let_names)
            .map(|(&id, name)| (id, name.as_str(), is_abbreviated(arena, id)))
            .collect();
        let texts = arena.display_definitions(&defs, names);
        for ((id, name, _), text) in defs.iter().zip(texts) {
            let set = arena.ctx(*id);
            let elem = set.map_or(String::new(), |s| names.elem(s));
            let _ = writeln!(out, "let {} = {text}", named(name, set, &elem));
        }
    }

    /// The equations of constraint `i`, at its element if it is a family.
    fn constraint_text(
        &self,
        out: &mut String,
        all: &[(Id, String)],
        i: usize,
        e: &ConstraintExprs,
    ) {
        let (arena, names) = (&self.symbolic.arena, &self.symbolic.names);
        let c = &self.constraints[i];
        let set = arena.leaf_sets().constraint(ConstraintId::new(i));
        let elem = set.map_or(String::new(), |s| names.elem(s));
        let r = c.index;
        let head = match set {
            Some(s) => format!("{}[{elem} in {}]", c.name, names.set(Some(s))),
            None => c.name.clone(),
        };
        let mu = names.var(VarRef::Mu(ConstraintId::new(i)));
        let _ = writeln!(
            out,
            "\n// constraint {head}: index {r}, Omega = {}, depends on {}, {mu} = realization parameter",
            wname(&c.name, r - 1, r + 1),
            c.depends_on.join(", "),
        );
        let mut ids: Vec<Id> = e.w.clone();
        ids.extend(e.jacobian_row.iter().map(|(_, id)| *id));
        ids.extend([e.beta, e.s, e.alpha, e.alpha_hat]);
        let printed = arena.display_in(&ids, names, all, &[]);
        let row = |what: String| named(&what, set, &elem);
        for (j, text) in printed.iter().take(r).enumerate() {
            let _ = writeln!(out, "{} = {}", row(wname(&c.name, j, r)), text);
        }
        let entries = e.jacobian_row.iter().zip(&printed[r..]);
        for ((k, _), text) in entries {
            let z = super::alg_name(names, *k);
            let col = k.index();
            let _ = writeln!(out, "J({i}, {col}) = {text}  // {} / {z}", c.name);
        }
        // A version-1 model's kernels are its entries again (printed above).
        for k in e.kernels.iter().filter(|_| names.family.is_some()) {
            let line = kernel_line(arena, names, all, &c.name, set, &elem, k);
            let _ = writeln!(out, "{line}");
        }
        let rest = &printed[r + e.jacobian_row.len()..];
        for (what, text) in ["beta", "s", "alpha", "alpha_hat"].iter().zip(rest) {
            let _ = writeln!(out, "{} = {text}", row(format!("{what}_{}", c.name)));
        }
    }
}

/// The sizes, sets and named maps of a family model, one comment line each.
fn construction_text(out: &mut String, arena: &Arena, names: &Names, c: &Construction) {
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

/// Whether a let's name is written for its node: not for a bare leaf or number (writing
/// `x` for a let `a = x` would only obscure the text).
fn is_abbreviated(arena: &Arena, id: Id) -> bool {
    !arena.children(id).is_empty()
}

/// A condition number with 7 significant digits: `6.854102` below 1e6, `3.162278e7` above.
pub(super) fn condition_text(c: f64) -> String {
    if c < 1e6 {
        format!("{c:.6}")
    } else {
        format!("{c:.6e}")
    }
}

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

/// `J(link[l], z[k]) = ... when b[l] == a[k]`.
fn kernel_line(
    arena: &Arena,
    names: &Names,
    abbrev: &[(Id, String)],
    constraint: &str,
    row_set: Option<SetId>,
    row_elem: &str,
    k: &Kernel,
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
