//! The `daec derive` text: one equation per line, right-hand sides in the language syntax.

use std::fmt::Write;

use super::Analysis;
use crate::sym::Id;

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
        if self.compiled.is_family() {
            return self.family_text();
        }
        let sym = &self.symbolic;
        let mut ids = Vec::new();
        for c in &sym.constraints {
            ids.extend(&c.w);
            ids.extend(c.jacobian_row.iter().map(|(_, id)| *id));
            ids.extend([c.beta, c.s, c.alpha, c.alpha_hat]);
        }
        let abbrev = self.abbreviations();
        let mut printed = sym
            .arena
            .display_all_abbreviated(&ids, &sym.names, &abbrev)
            .into_iter();
        let mut next = || printed.next().expect("one printed expression per id");
        let mut out = String::new();
        let indices: Vec<String> = self.indices().iter().map(|r| r.to_string()).collect();
        let _ = writeln!(
            out,
            "// model {}: {} constraint{}, indices ({}), cond(J_Omega) = {} at t = 0",
            self.model_name,
            self.constraints.len(),
            if self.constraints.len() == 1 { "" } else { "s" },
            indices.join(", "),
            condition_text(self.condition_number)
        );
        let cols: Vec<String> = sym
            .names
            .algs
            .iter()
            .enumerate()
            .map(|(k, n)| format!("{k} = {n}"))
            .collect();
        let _ = writeln!(
            out,
            "// J(i, k) = dOmega_i/dz_k, columns: {}",
            cols.join(", ")
        );
        if !sym.lets.is_empty() {
            out.push_str("\n// definitions (the model's lets, in terms of earlier ones)\n");
        }
        let defs: Vec<(Id, &str, bool)> = sym
            .lets
            .iter()
            .zip(&sym.let_names)
            .map(|(&id, name)| (id, name.as_str(), is_abbreviated(&sym.arena, id)))
            .collect();
        let texts = sym.arena.display_definitions(&defs, &sym.names);
        for ((_, name, _), text) in defs.iter().zip(texts) {
            let _ = writeln!(out, "let {name} = {text}");
        }
        for (i, (c, e)) in self.constraints.iter().zip(&sym.constraints).enumerate() {
            let r = c.index;
            let omega_is = if r == 1 {
                format!("w_{}", c.name)
            } else {
                format!(
                    "w_{}{}",
                    c.name,
                    if r - 1 <= 3 {
                        "'".repeat(r - 1)
                    } else {
                        format!("^({})", r - 1)
                    }
                )
            };
            let _ = writeln!(
                out,
                "\n// constraint {}: index {r}, Omega = {omega_is}, depends on {}, mu{} = realization parameter",
                c.name,
                c.depends_on.join(", "),
                i + 1
            );
            for j in 0..r {
                let _ = writeln!(out, "{} = {}", wname(&c.name, j, r), next());
            }
            for (k, _) in &e.jacobian_row {
                let z = super::alg_name(&sym.names, *k);
                let col = k.index();
                let _ = writeln!(out, "J({i}, {col}) = {}  // {} / {z}", next(), c.name);
            }
            let _ = writeln!(out, "beta_{} = {}", c.name, next());
            let _ = writeln!(out, "s_{} = {}", c.name, next());
            let _ = writeln!(out, "alpha_{} = {}", c.name, next());
            let _ = writeln!(out, "alpha_hat_{} = {}", c.name, next());
        }
        out
    }
}

/// Whether a let's name is written for its node: not for a bare leaf or number (writing
/// `x` for a let `a = x` would only obscure the text).
fn is_abbreviated(arena: &crate::sym::Arena, id: Id) -> bool {
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
