//! Names of the slots of a sized family model, built at run time: `x[3].y` for
//! component `y` of element 3 of the state family `x`, `link[7]` for element 7 of a
//! constraint family, `g` or `pivot.x` for scalars.
//!
//! A table holds all names of one kind (states, parameters, ...) in one string with a
//! range per slot: two allocations, about 8 bytes per name beyond its text, so that
//! the names of 10^6 slots cost a few megabytes and are built only when asked for.

use dae_lang::family::{Instance, Slot};
use dae_lang::model::Family;

/// One declaration's component family as names see it: its name (`x.y`), set and
/// component, and where its elements live.
pub(crate) struct Decl<'a> {
    pub name: &'a str,
    pub family: Family,
    pub slot: Slot,
}

/// The names of `len` slots, looked up by slot.
#[derive(Debug, Default)]
pub(crate) struct NameTable {
    text: String,
    ranges: Vec<(u32, u32)>,
}

impl NameTable {
    /// The names of the slots of `decls` (every slot `0..len` is covered by exactly
    /// one declaration element).
    pub fn build(decls: &[Decl<'_>], inst: &Instance, len: usize) -> NameTable {
        use std::fmt::Write;
        let mut text = String::new();
        let mut ranges = vec![(0u32, 0u32); len];
        for d in decls {
            let n = inst.set_size(d.family.over);
            let (base, comp) = split_component(d.name, d.family);
            for e in 0..n {
                let start = text.len();
                // Writing into a String cannot fail.
                let _ = match (d.family.over, comp) {
                    (None, _) => write!(text, "{}", d.name),
                    (Some(_), Some(c)) => write!(text, "{base}[{e}].{c}"),
                    (Some(_), None) => write!(text, "{base}[{e}]"),
                };
                ranges[d.slot.at(e)] = (start as u32, text.len() as u32);
            }
        }
        NameTable { text, ranges }
    }

    /// The name of slot `i`.
    pub fn get(&self, i: usize) -> &str {
        let (a, b) = self.ranges[i];
        &self.text[a as usize..b as usize]
    }
}

/// `("x", Some("y"))` for the component `x.y` of a vector declaration, `("m", None)`
/// for a scalar-typed one.
fn split_component(name: &str, family: Family) -> (&str, Option<&str>) {
    match name.rsplit_once('.') {
        Some((base, comp)) if family.dim > 1 => (base, Some(comp)),
        _ => (name, None),
    }
}

/// The slot named `name` among `decls`: `g`, `pivot.x` (scalars), `free[3]`,
/// `x[3].y` (an element of a family), or `None` when no declaration element has
/// that name. Costs one pass over the declarations, not over the slots.
pub(crate) fn lookup(decls: &[Decl<'_>], inst: &Instance, name: &str) -> Option<usize> {
    let Some((base, rest)) = name.split_once('[') else {
        return decls
            .iter()
            .find(|d| d.family.over.is_none() && d.name == name)
            .map(|d| d.slot.offset);
    };
    let (elem, comp) = rest.split_once(']')?;
    let e: usize = elem.trim().parse().ok()?;
    let comp = match comp {
        "" => None,
        c => Some(c.strip_prefix('.')?),
    };
    lookup_at(decls, inst, base, comp, e)
}

/// The slot of element `e` of the family `base` (component `comp` of a vector one).
pub(crate) fn lookup_at(
    decls: &[Decl<'_>],
    inst: &Instance,
    base: &str,
    comp: Option<&str>,
    e: usize,
) -> Option<usize> {
    let d = decls.iter().find(|d| {
        d.family.over.is_some() && {
            let (b, c) = split_component(d.name, d.family);
            b == base && c == comp
        }
    })?;
    (e < inst.set_size(d.family.over)).then(|| d.slot.at(e))
}
