//! The report of a singular `J_Omega` at a point: its rank, the constraints that the
//! ones before them imply (grouped by constraint family), and one dependency written
//! out, so that a user sees which constraints to remove (or to make forces) and why.

use dae_runtime::Model;
use dae_runtime::model::{constraint_families, constraint_family};
use dae_runtime::solve::Redundancy;

/// At most this many names are listed per family, and terms per combination.
const LISTED: usize = 6;

/// `J_Omega` at a point analysed for redundancy; see the module documentation.
pub(crate) struct Redundant {
    /// Constraints (rows).
    pub(crate) m: usize,
    /// Its numerical rank.
    pub(crate) rank: usize,
    /// The constraints implied by the ones before them (ascending).
    pub(crate) implied: Vec<usize>,
    /// Whether "before" is in the order of the families (see [`Redundancy::by_class`]).
    pub(crate) by_family: bool,
    /// The state derivatives the algebraic unknowns act on (the degrees of freedom the
    /// constraints hold), counted by one evaluation of `f` with every unknown moved.
    pub(crate) reached: usize,
    /// The dependency of the first implied constraint: rows and coefficients `y` with
    /// `y^T J_Omega = 0`, its own coefficient 1.
    pub(crate) first: Vec<(usize, f64)>,
    /// Per constraint family, in the order of first appearance: its name, how many
    /// constraints it has, and its implied constraints.
    pub(crate) families: Vec<(String, usize, Vec<usize>)>,
}

impl Redundant {
    /// `J_Omega` of `model` at `(t, x, z)`; `None` when it has full rank there (then the
    /// caller's own message stands).
    pub(crate) fn at(model: &dyn Model, t: f64, x: &[f64], z: &[f64]) -> Option<Redundant> {
        let m = model.n_constraints();
        let pattern = model.jacobian_pattern();
        let mut values = vec![0.0; pattern.len()];
        model.jacobian(t, x, z, &mut values);
        // Families in the order of their first constraint: name, size, implied rows.
        let class = constraint_families(model);
        let mut families: Vec<(String, usize, Vec<usize>)> = Vec::new();
        for (i, &k) in class.iter().enumerate() {
            if k == families.len() {
                let name = constraint_family(model.constraint_name(i));
                families.push((name.to_string(), 0, Vec::new()));
            }
            families[k].1 += 1;
        }
        let r = Redundancy::of(m, pattern, &values, &class).ok()?;
        if r.rank() == m {
            return None;
        }
        // Every unknown moved by a different amount, so that no derivative it reaches
        // can stay put by cancellation but by accident.
        let n = model.n_states();
        let (mut f0, mut f1) = (vec![0.0; n], vec![0.0; n]);
        model.rhs(t, x, z, &mut f0);
        let moved: Vec<f64> = z
            .iter()
            .enumerate()
            .map(|(k, v)| v + (1.0 + v.abs()) * 1e-3 * (1.0 + 0.618 * k as f64).fract().max(0.1))
            .collect();
        model.rhs(t, x, &moved, &mut f1);
        let reached = f0.iter().zip(&f1).filter(|(a, b)| a != b).count();
        for &i in r.implied() {
            families[class[i]].2.push(i);
        }
        let first = r.combination(r.implied()[0]);
        Some(Redundant {
            m,
            rank: r.rank(),
            implied: r.implied().to_vec(),
            by_family: r.by_class(),
            reached,
            first,
            families,
        })
    }

    /// `rank 29 of 42 (42 constraints on the 42 state derivatives ...): 13 constraints
    /// are implied by the ones before them` (the families
    /// declared before, and the constraints of its own family taken before it).
    pub(crate) fn counts(&self) -> String {
        let d = self.implied.len();
        let by = match (self.by_family, d == 1) {
            (true, true) => "the ones before it",
            (true, false) => "the ones before them",
            (false, _) => "the others",
        };
        format!(
            "rank {} of {} ({} constraints on the {} state derivatives the algebraic unknowns act on): {d} constraint{} implied by {by}",
            self.rank,
            self.m,
            self.m,
            self.reached,
            if d == 1 { " is" } else { "s are" },
        )
    }

    /// The names of some rows, `a, b, c and 4 more`.
    pub(crate) fn names(model: &dyn Model, rows: &[usize]) -> String {
        let shown: Vec<String> = rows
            .iter()
            .take(LISTED)
            .map(|&r| format!("`{}`", model.constraint_name(r)))
            .collect();
        let more = rows.len().saturating_sub(shown.len());
        if more > 0 {
            format!("{} and {more} more", shown.join(", "))
        } else {
            shown.join(", ")
        }
    }

    /// The first dependency as an equation between rows of `J_Omega`:
    /// `` row `shear[1]` = 0.707 row `link[0]` - 0.707 row `link[4]` + ... ``.
    pub(crate) fn dependency(&self, model: &dyn Model) -> String {
        let own = self.implied[0];
        let others: Vec<(usize, f64)> = self
            .first
            .iter()
            .filter(|&&(r, _)| r != own)
            .map(|&(r, c)| (r, -c))
            .collect();
        let mut text = format!("row `{}` =", model.constraint_name(own));
        if others.is_empty() {
            text.push_str(" 0");
        }
        for (k, &(r, c)) in others.iter().take(LISTED).enumerate() {
            let sign = match (k, c < 0.0) {
                (0, false) => " ",
                (0, true) => " -",
                (_, false) => " + ",
                (_, true) => " - ",
            };
            text.push_str(&format!(
                "{sign}{} row `{}`",
                coefficient(c.abs()),
                model.constraint_name(r)
            ));
        }
        if others.len() > LISTED {
            text.push_str(&format!(" + {} more", others.len() - LISTED));
        }
        text
    }

    /// One line per family: `` `shear`: 13 of its 18 constraints implied (`shear[1]`, ...) ``.
    pub(crate) fn family_lines(&self, model: &dyn Model) -> Vec<(String, String)> {
        self.families
            .iter()
            .map(|(name, total, implied)| {
                let text = if implied.is_empty() {
                    format!(
                        "`{name}`: {total} constraint{}, none implied",
                        plural(*total)
                    )
                } else {
                    format!(
                        "`{name}`: {} of its {total} constraint{} implied ({})",
                        implied.len(),
                        plural(*total),
                        Self::names(model, implied)
                    )
                };
                (name.clone(), text)
            })
            .collect()
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// `1`, `0.5`, `0.707`, `1.41`, `2.5e-3`: three significant digits, no trailing zeros.
fn coefficient(c: f64) -> String {
    if c < 0.01 {
        return format!("{c:.2e}");
    }
    let digits = if c >= 100.0 {
        0
    } else if c >= 10.0 {
        1
    } else if c >= 1.0 {
        2
    } else {
        3
    };
    let s = format!("{c:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
