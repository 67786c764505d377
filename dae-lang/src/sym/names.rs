//! The names of a model's leaves as the printed text writes them: declared names, the
//! fallbacks `p<i>`, `x<i>`, `z<i>`, and for a family model the names of its sizes,
//! sets, elements, inputs and constraint families.

use crate::model::Model;
use crate::{SetId, VarRef};

/// Names of the leaves for printing. Missing names fall back to `p<i>`, `x<i>`, `z<i>`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Names {
    /// Parameter names by index.
    pub params: Vec<String>,
    /// State names.
    pub states: Vec<String>,
    /// Algebraic names.
    pub algs: Vec<String>,
    /// The names of a family model's sizes, sets, inputs and constraints (`None` for a
    /// version-1 model).
    pub family: Option<Box<FamilyNames>>,
}

impl Names {
    /// The names declared in a model.
    pub fn from_model(m: &Model) -> Names {
        Names {
            params: m.params.iter().map(|p| p.name.clone()).collect(),
            states: m.states.iter().map(|s| s.name.clone()).collect(),
            algs: m.algs.iter().map(|a| a.name.clone()).collect(),
            family: m.is_family().then(|| Box::new(FamilyNames::from_model(m))),
        }
    }

    /// The printed name of a variable: its declared name, `p<i>`, `x<i>` or `z<i>` when
    /// there is none, `t`, and `mu<i+1>` for the realization parameter of constraint `i`.
    pub fn var(&self, v: VarRef) -> String {
        let named = |list: &[String], prefix: &str, i: usize| {
            list.get(i)
                .cloned()
                .unwrap_or_else(|| format!("{prefix}{i}"))
        };
        match v {
            VarRef::Param(i) => named(&self.params, "p", i.index()),
            VarRef::State(i) => named(&self.states, "x", i.index()),
            VarRef::Alg(i) => named(&self.algs, "z", i.index()),
            VarRef::AlgRate(i) => format!("der({})", named(&self.algs, "z", i.index())),
            VarRef::Time => "t".into(),
            VarRef::Mu(i) => match &self.family {
                Some(f) if f.constraint_families.get(i.index()) == Some(&true) => {
                    format!("mu_{}", f.constraints[i.index()])
                }
                _ => format!("mu{}", i.index() + 1),
            },
            VarRef::Input(i, j) => {
                let name = self
                    .family
                    .as_ref()
                    .and_then(|f| f.inputs.get(i.index()).cloned())
                    .unwrap_or_else(|| format!("u{}", i.index()));
                let (base, comp) = split_component(&name);
                format!("{base}{}{comp}", primes(j as usize))
            }
            VarRef::Elem(s) => self.elem(s),
            VarRef::Size(i) => self
                .family
                .as_ref()
                .and_then(|f| f.sizes.get(i.index()).cloned())
                .unwrap_or_else(|| format!("n{}", i.index())),
        }
    }

    /// The element name of a set (`s<i>` without family names).
    pub fn elem(&self, s: SetId) -> String {
        self.family
            .as_ref()
            .and_then(|f| f.elems.get(s.index()).cloned())
            .unwrap_or_else(|| format!("s{}", s.index()))
    }

    /// The name of a set (`the unit` for `None`).
    pub fn set(&self, s: Option<SetId>) -> String {
        match s {
            None => "the unit".into(),
            Some(s) => self
                .family
                .as_ref()
                .and_then(|f| f.sets.get(s.index()).cloned())
                .unwrap_or_else(|| format!("S{}", s.index())),
        }
    }
}

/// The names printing needs for a family model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FamilyNames {
    /// Sizes.
    pub sizes: Vec<String>,
    /// Sets.
    pub sets: Vec<String>,
    /// The element name of each set (`p` for `P`).
    pub elems: Vec<String>,
    /// Input components (`pin.x`).
    pub inputs: Vec<String>,
    /// Constraints (for `mu_link`).
    pub constraints: Vec<String>,
    /// Whether each constraint is a family (its `mu` prints `mu_link[l]`).
    pub constraint_families: Vec<bool>,
}

impl FamilyNames {
    /// The names of a family model.
    pub fn from_model(m: &Model) -> FamilyNames {
        FamilyNames {
            sizes: m.sizes.iter().map(|s| s.name.clone()).collect(),
            sets: m.sets.iter().map(|s| s.name.clone()).collect(),
            elems: m.sets.iter().map(|s| s.elem.clone()).collect(),
            inputs: m.inputs.iter().map(|i| i.name.clone()).collect(),
            constraints: m.constraints.iter().map(|c| c.name.clone()).collect(),
            constraint_families: m.constraints.iter().map(|c| c.over.is_some()).collect(),
        }
    }
}

/// `x.y` -> (`x`, `.y`); `x` -> (`x`, ``).
pub(crate) fn split_component(name: &str) -> (&str, &str) {
    match name.find('.') {
        Some(i) => (&name[..i], &name[i..]),
        None => (name, ""),
    }
}

/// `'`, `''`, `'''`, then `^(j)`.
pub(crate) fn primes(j: usize) -> String {
    match j {
        0..=3 => "'".repeat(j),
        _ => format!("^({j})"),
    }
}
