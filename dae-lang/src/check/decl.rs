//! The declaration pass: every name with its kind, set, vector type and component ids.

use super::{Checker, Component, Entry, Kind, LetState, NamedMap};
use crate::SetId;
use crate::ast::{Binder, Decl, ExprKind, Ident, Item};
use crate::check::names::{self, suggest};
use crate::diag::Diagnostic;
use crate::model::{Family, MapDef, MapKind, SetDef, SizeDef};

/// Words that start or join the expression forms of version 2; reserved in version-2
/// models (besides the version-1 keywords and the function names).
pub(super) const FAMILY_KEYWORDS: [&str; 6] = ["if", "then", "else", "and", "or", "not"];

/// Whether `name` is a reserved word (`version1`: of a model that uses nothing of
/// version 2, where the words of version 2 are names like any other).
pub(super) fn is_reserved(name: &str, version1: bool) -> bool {
    names::is_reserved(name) || (!version1 && FAMILY_KEYWORDS.contains(&name))
}

pub(super) fn reserved_message(name: &str) -> (String, String) {
    if FAMILY_KEYWORDS.contains(&name) {
        (
            format!("reserved word `{name}` cannot be used as a name (`{name}` is a keyword)"),
            format!("choose another name, e.g. `{name}_` or `{name}1`"),
        )
    } else {
        names::reserved_message(name)
    }
}

impl<'a> Checker<'a> {
    pub(super) fn declare(&mut self) {
        let m = self.m;
        if is_reserved(&m.name.name, self.version1) {
            let (message, hint) = reserved_message(&m.name.name);
            self.diags
                .push(Diagnostic::new(message, m.name.span, "reserved word").hint(hint));
        }
        // Sizes and sets first: every other declaration may be over a set.
        for item in &m.items {
            match item {
                Item::Size { name, value, span } => {
                    let default = self.size_default(name, value);
                    let id = self.sizes.len();
                    if self.register(name, Kind::Size, id, id, None, 1) {
                        self.sizes.push(SizeDef {
                            name: name.name.clone(),
                            default,
                            span: *span,
                        });
                    }
                }
                Item::Set { name, size, span } => {
                    let id = self.sets.len();
                    if self.register(name, Kind::Set, id, id, None, 1) {
                        self.sets.push(SetDef {
                            name: name.name.clone(),
                            size: None,
                            elem: String::new(),
                            span: *span,
                        });
                        self.set_exprs.push(size.as_ref());
                    }
                }
                _ => {}
            }
        }
        for item in &m.items {
            match item {
                Item::Map {
                    name,
                    binder,
                    codomain,
                    formula,
                    span,
                } => self.declare_map(name, binder, codomain, formula.as_ref(), *span),
                Item::Param(ds, _) => {
                    for d in ds {
                        self.declare_var(d, Kind::Param, 0);
                    }
                }
                Item::State(ds, _) => {
                    for d in ds {
                        self.declare_var(d, Kind::State, 0);
                    }
                }
                Item::Alg(ds, _) => {
                    for d in ds {
                        self.declare_var(d, Kind::Alg, 0);
                    }
                }
                Item::Input(ds, _) => {
                    for d in ds {
                        let k = match d.derivatives {
                            Some((k, span)) if k > 32 => {
                                self.diags.push(
                                    Diagnostic::new(
                                        format!("input `{}` with {k} derivatives", d.decl.name.name),
                                        span,
                                        "too many",
                                    )
                                    .hint("an input gives at most 32 time derivatives (an index needs at most 9)"),
                                );
                                0
                            }
                            Some((k, _)) => k as u8,
                            None => 0,
                        };
                        self.declare_var(&d.decl, Kind::Input, k);
                    }
                }
                Item::Let(d, _) => self.declare_var(d, Kind::Let, 0),
                _ => {}
            }
        }
        self.name_elements();
    }

    /// `size N = 10;`: the default must be a whole number >= 0.
    fn size_default(&mut self, name: &Ident, value: &crate::ast::Expr) -> i64 {
        match value.kind {
            ExprKind::Num(v) if v.fract() == 0.0 && (0.0..9.0e15).contains(&v) => v as i64,
            _ => {
                self.diags.push(
                    Diagnostic::new(
                        format!("the default of size `{}` is not a whole number", name.name),
                        value.span,
                        "not a whole number >= 0",
                    )
                    .hint("a size is written as a whole number, e.g. `size N = 10;`"),
                );
                0
            }
        }
    }

    /// Registers a name; reports reserved words and names declared twice. Returns whether
    /// the name is new.
    pub(super) fn register(
        &mut self,
        name: &'a Ident,
        kind: Kind,
        decl: usize,
        first: usize,
        over: Option<SetId>,
        dim: u8,
    ) -> bool {
        let n = name.name.as_str();
        if is_reserved(n, self.version1) {
            let (message, hint) = reserved_message(n);
            self.diags
                .push(Diagnostic::new(message, name.span, "reserved word").hint(hint));
        }
        if let Some(first_decl) = self.names.get(n) {
            self.diags.push(names::declared_twice(
                n,
                name.span,
                kind.words(),
                first_decl.span,
                first_decl.kind.words(),
            ));
            self.duplicated.insert(n);
            return false;
        }
        self.names.insert(
            n,
            Entry {
                kind,
                decl,
                first,
                over,
                dim,
                span: name.span,
            },
        );
        self.ordered.push(n);
        true
    }

    /// The set of a binder (`None` inside: a scalar declaration); `Err` after an error.
    pub(super) fn binder_set(&mut self, b: Option<&Binder>) -> Result<Option<SetId>, ()> {
        let Some(b) = b else { return Ok(None) };
        self.set_named(&b.set).map(Some)
    }

    /// The set called `name`, or an "unknown set" error.
    pub(super) fn set_named(&mut self, name: &Ident) -> Result<SetId, ()> {
        match self.names.get(name.name.as_str()) {
            Some(e) if e.kind == Kind::Set => Ok(SetId::new(e.first)),
            Some(e) => {
                let e = *e;
                self.diags.push(
                    Diagnostic::new(
                        format!("`{}` is {}, not a set", name.name, e.kind.words()),
                        name.span,
                        e.kind.words(),
                    )
                    .related(e.span, format!("`{}` is declared here", name.name))
                    .hint("declare the set with `set NAME = SIZE;` (or `set NAME;` when given at construction)"),
                );
                Err(())
            }
            None => {
                let sets: Vec<&str> = self.sets.iter().map(|s| s.name.as_str()).collect();
                let hint = match suggest(&name.name, sets.iter().copied()) {
                    Some(s) => format!("did you mean `{s}`?"),
                    None if sets.is_empty() => {
                        "declare the set with `set NAME = SIZE;` (or `set NAME;` when given at construction)".to_string()
                    }
                    None => format!("the sets of this model are {}", quoted(&sets)),
                };
                self.diags.push(
                    Diagnostic::new(
                        format!("unknown set `{}`", name.name),
                        name.span,
                        format!("no set `{}` in model `{}`", name.name, self.m.name.name),
                    )
                    .hint(hint),
                );
                Err(())
            }
        }
    }

    /// The vector dimension of a type annotation (1 without one).
    fn dim_of(&mut self, ty: Option<&Ident>) -> u8 {
        match ty.map(|t| t.name.as_str()) {
            None => 1,
            Some("vec2") => 2,
            Some("vec3") => 3,
            Some(other) => {
                let t = ty.expect("matched Some");
                self.diags.push(
                    Diagnostic::new(format!("unknown type `{other}`"), t.span, "not a type")
                        .hint("the types are `vec2` and `vec3`; a number needs no type"),
                );
                1
            }
        }
    }

    fn declare_map(
        &mut self,
        name: &'a Ident,
        binder: &'a Binder,
        codomain: &'a Ident,
        formula: Option<&'a crate::ast::Expr>,
        span: crate::ast::Span,
    ) {
        let (Ok(domain), Ok(codomain)) = (self.set_named(&binder.set), self.set_named(codomain))
        else {
            return;
        };
        let kind = if formula.is_some() {
            // The formula is resolved later; it is a placeholder until then.
            MapKind::Formula(crate::model::RExpr::Num(f64::NAN))
        } else {
            MapKind::Given
        };
        // A named map is its own map, never merged with another (its name is part of
        // the model's interface).
        let id = self.named_maps.len();
        if self.register(name, Kind::Map, id, id, Some(domain), 1) {
            let map = self.maps.push(MapDef {
                name: name.name.clone(),
                domain: Some(domain),
                codomain: Some(codomain),
                kind,
                span,
            });
            self.named_maps.push(NamedMap {
                name: &name.name,
                formula,
                id: map,
            });
        }
    }

    fn declare_var(&mut self, d: &'a Decl, kind: Kind, derivatives: u8) {
        let Ok(over) = self.binder_set(d.binder.as_ref()) else {
            return;
        };
        let dim = self.dim_of(d.ty.as_ref());
        if kind == Kind::Alg && dim > 1 {
            self.diags.push(
                Diagnostic::new(
                    format!("algebraic unknown `{}` is a vector", d.name.name),
                    d.ty.as_ref().map_or(d.name.span, |t| t.span),
                    "a vector type",
                )
                .hint("an algebraic unknown is a number (one per constraint): declare one per component"),
            );
            return;
        }
        if kind == Kind::Let {
            let decl = self.lets.len();
            if self.register(&d.name, kind, decl, decl, over, dim) {
                self.lets.push(d);
                self.let_sets.push(over);
                self.let_state.push(LetState::Todo);
            }
            return;
        }
        let list = match kind {
            Kind::Param => &self.params,
            Kind::State => &self.states,
            Kind::Alg => &self.algs,
            _ => &self.inputs,
        };
        let first = list.len();
        // Parameters count their declarations (a default may use only earlier ones).
        let decl = match kind {
            Kind::Param => self.param_decl.last().map_or(0, |d| d + 1),
            _ => first,
        };
        if !self.register(&d.name, kind, decl, first, over, dim) {
            return;
        }
        let list = match kind {
            Kind::Param => &mut self.params,
            Kind::State => &mut self.states,
            Kind::Alg => &mut self.algs,
            _ => &mut self.inputs,
        };
        for c in 0..dim {
            list.push(Component {
                decl: d,
                name: component_name(&d.name.name, dim, c),
                family: Family {
                    over,
                    dim,
                    component: c,
                },
                derivatives,
            });
        }
        if kind == Kind::Param {
            self.param_decl
                .extend(std::iter::repeat_n(decl, dim as usize));
        }
    }

    /// The printing name of each set's element (the first binder written for it), and
    /// the check that no element name is also a declared name.
    fn name_elements(&mut self) {
        let m = self.m;
        let mut binders: Vec<&Binder> = Vec::new();
        for item in &m.items {
            match item {
                Item::Param(ds, _) | Item::State(ds, _) | Item::Alg(ds, _) => {
                    binders.extend(ds.iter().filter_map(|d| d.binder.as_ref()))
                }
                Item::Let(d, _) => binders.extend(d.binder.as_ref()),
                Item::Input(ds, _) => {
                    binders.extend(ds.iter().filter_map(|d| d.decl.binder.as_ref()))
                }
                Item::Map { binder, .. } => binders.push(binder),
                Item::Constraint {
                    binder: Some(b), ..
                } => binders.push(b),
                _ => {}
            }
        }
        for b in binders {
            let Some(elem) = &b.elem else { continue };
            if let Some(e) = self.names.get(elem.name.as_str()) {
                let e = *e;
                self.diags.push(
                    Diagnostic::new(
                        format!(
                            "the element name `{}` is also declared as {}",
                            elem.name,
                            e.kind.words()
                        ),
                        elem.span,
                        "element name",
                    )
                    .related(e.span, format!("`{}` is declared here", elem.name))
                    .hint("choose another element name, e.g. a single lower-case letter"),
                );
                continue;
            }
            if let Some(set) = self.names.get(b.set.name.as_str()) {
                if set.kind == Kind::Set && self.sets[set.first].elem.is_empty() {
                    self.sets[set.first].elem = elem.name.clone();
                }
            }
        }
        for s in &mut self.sets {
            if s.elem.is_empty() {
                s.elem = s.name.to_lowercase();
            }
        }
    }
}

/// `x` for a number, `x.x`, `x.y`, `x.z` for the components of a vector.
pub(super) fn component_name(name: &str, dim: u8, c: u8) -> String {
    if dim == 1 {
        name.to_string()
    } else {
        format!("{name}.{}", COMPONENTS[c as usize])
    }
}

/// The names of vector components.
pub(super) const COMPONENTS: [&str; 3] = ["x", "y", "z"];

pub(super) fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}
