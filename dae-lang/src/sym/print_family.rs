//! Printing the templates of family models: leaves at the element bound to their set
//! (`x[b[l]].y`), gathers (the gathered node printed with its set bound to the image,
//! `b[l]`), sums (`sum(k in L where a[k] == p) z[k]*u[k].x`), and the integer formulas
//! of maps and sets.
//!
//! The text of a node depends on the element name bound to its context (the same `let`
//! prints `u[l].x` and `u[k].x`), so the printer's memo is keyed by the node and that
//! name. A version-1 model has no contexts: every node is printed once, as before.

use std::collections::HashMap;

use super::names::{Names, primes, split_component};
use super::print::{Abbreviations, Kind, Piece, Printer, number, wrap};
use super::{Arena, Id};
use crate::ast::{BinOp, LogicOp};
use crate::model::{IntOp, MapKind, RExpr};
use crate::{MapId, SetId, VarRef};

impl<'a> Printer<'a> {
    pub(super) fn new(arena: &'a Arena, names: &'a Names) -> Printer<'a> {
        let env = names
            .family
            .as_ref()
            .map_or(Vec::new(), |f| f.elems.clone());
        Printer {
            arena,
            names,
            memo: HashMap::new(),
            abbrev: Abbreviations::default(),
            defining: None,
            env,
            bindings: HashMap::new(),
        }
    }
}

impl Printer<'_> {
    /// The memo key of a node: its id and the element name bound to its context.
    pub(super) fn key(&mut self, id: Id) -> (Id, u32) {
        let Some(s) = self.arena.ctx(id) else {
            return (id, 0);
        };
        let b = self.env.get(s.index()).cloned().unwrap_or_default();
        let next = self.bindings.len() as u32 + 1;
        (id, *self.bindings.entry(b).or_insert(next))
    }

    /// The element name bound to a set.
    fn bound(&self, s: Option<SetId>) -> String {
        match s {
            None => "0".into(),
            Some(s) => self
                .env
                .get(s.index())
                .cloned()
                .unwrap_or_else(|| self.names.elem(s)),
        }
    }

    /// A name (a family variable's or a `let`'s) at the element bound to `set`:
    /// `x.y` -> `x[b[l]].y`.
    pub(super) fn at_element(&self, name: &str, set: Option<SetId>) -> String {
        match set {
            None => name.to_string(),
            Some(s) => {
                let (base, comp) = split_component(name);
                format!("{base}[{}]{comp}", self.bound(Some(s)))
            }
        }
    }

    pub(super) fn leaf(&self, v: VarRef) -> String {
        let set = self.arena.leaf_sets().of(v);
        match (v, set) {
            (VarRef::Elem(s), _) => self.bound(Some(s)),
            (_, None) => self.names.var(v),
            (VarRef::Mu(_), Some(_)) => format!("{}[{}]", self.names.var(v), self.bound(set)),
            (VarRef::Input(i, j), Some(_)) => {
                let name = self
                    .names
                    .family
                    .as_ref()
                    .and_then(|f| f.inputs.get(i.index()).cloned())
                    .unwrap_or_else(|| format!("u{}", i.index()));
                let (base, comp) = split_component(&name);
                format!("{base}{}[{}]{comp}", primes(j as usize), self.bound(set))
            }
            _ => self.at_element(&self.names.var(v), set),
        }
    }

    /// Element `elem` mapped by `m`, as text: `a[l]`, `b[a[l]]`, `l + 1`.
    pub(super) fn path(&self, m: MapId, elem: &str) -> String {
        let d = self.arena.maps().get(m);
        match &d.kind {
            MapKind::Identity => elem.to_string(),
            MapKind::ToUnit => "0".into(),
            MapKind::Chain(ms) => ms.iter().fold(elem.to_string(), |e, k| self.path(*k, &e)),
            MapKind::Formula(f) if d.name.is_empty() => self.formula(f, elem),
            _ => format!("{}[{elem}]", d.name),
        }
    }

    /// An integer formula (a map's or a set size's) with the element written `elem`.
    pub(super) fn formula(&self, e: &RExpr, elem: &str) -> String {
        formula(e, elem, &|m, x| self.path(m, x), self.names).0
    }

    /// `Gather(m, e)`: `e` printed with its set bound to the image under `m`.
    pub(super) fn gather(&mut self, m: MapId, e: Id) -> Piece {
        let maps = self.arena.maps();
        let (dom, cod) = (maps.domain(m), maps.codomain(m));
        let at = self.path(m, &self.bound(dom));
        let Some(c) = cod else { return self.pr(e) };
        let saved = std::mem::replace(&mut self.env[c.index()], at);
        let p = self.pr(e);
        self.env[c.index()] = saved;
        p
    }

    /// `Sum(m, b)`: `sum(k in K where m[k] == q) b`, or `sum(k in K) b`.
    pub(super) fn sum_over(&mut self, m: MapId, b: Id) -> Piece {
        let maps = self.arena.maps();
        let (k_set, q_set) = (maps.domain(m), maps.codomain(m));
        let Some(ks) = k_set else {
            return self.pr(b);
        };
        let k = self.fresh(ks);
        let saved = std::mem::replace(&mut self.env[ks.index()], k.clone());
        let body = wrap(self.pr(b), Kind::Prod);
        let set = self.names.set(k_set);
        let text = match q_set {
            None => format!("sum({k} in {set}) {body}"),
            Some(_) => format!(
                "sum({k} in {set} where {} == {}) {body}",
                self.path(m, &k),
                self.bound(q_set)
            ),
        };
        self.env[ks.index()] = saved;
        // As loose as a sum, so that an operation around it puts it in parentheses.
        (text, Kind::Sum)
    }

    /// A name for the element of a sum over `k`: the set's element name, primed until it
    /// differs from every name bound.
    fn fresh(&self, k: SetId) -> String {
        let mut name = self.names.elem(k);
        while self.env.contains(&name) {
            name.push('\'');
        }
        name
    }
}

impl Arena {
    /// Like [`Arena::display_all_abbreviated`], with element names bound to sets:
    /// `(set, name)` (e.g. the column element `k` of a `J_Omega` kernel); the other sets
    /// print with their element names.
    pub fn display_in(
        &self,
        ids: &[Id],
        names: &Names,
        abbrev: &[(Id, String)],
        bind: &[(SetId, String)],
    ) -> Vec<String> {
        let mut p = Printer::new(self, names);
        for (id, name) in abbrev {
            p.abbrev.add(self, *id, name);
        }
        for (s, n) in bind {
            if let Some(slot) = p.env.get_mut(s.index()) {
                *slot = n.clone();
            }
        }
        ids.iter().map(|&id| p.pr(id).0).collect()
    }

    /// A map applied to an element, as text (`a[l]`, `b[a[l]]`, `l + 1`).
    pub fn path_text(&self, m: MapId, elem: &str, names: &Names) -> String {
        Printer::new(self, names).path(m, elem)
    }

    /// An integer formula of the model (a set's size, a map's formula) as text, with its
    /// element written `elem`.
    pub fn formula_text(&self, e: &RExpr, elem: &str, names: &Names) -> String {
        Printer::new(self, names).formula(e, elem)
    }
}

/// An integer (construction-time) formula as text and its binding level (0 `if`,
/// comparisons and logic, 1 sums, 2 products, 3 unary minus, 4 atoms); `path(m, e)`
/// writes a map applied.
fn formula(
    e: &RExpr,
    elem: &str,
    path: &dyn Fn(MapId, &str) -> String,
    names: &Names,
) -> (String, u8) {
    let go = |e: &RExpr, elem: &str| formula(e, elem, path, names);
    let paren = |(s, l): (String, u8), min: u8| if l < min { format!("({s})") } else { s };
    match e {
        RExpr::Num(v) => {
            let t = number(*v).0;
            let level = if t.starts_with('-') { 3 } else { 4 };
            (t, level)
        }
        RExpr::Var(VarRef::Elem(_)) => (elem.to_string(), 4),
        RExpr::Var(v) => (names.var(*v), 4),
        RExpr::Let(l) => (format!("let{}", l.index()), 4),
        RExpr::Gather(m, inner) => match inner.as_ref() {
            RExpr::Var(VarRef::Elem(_)) => (path(*m, elem), 4),
            other => go(other, &path(*m, elem)),
        },
        RExpr::Sum(_, b) => (format!("sum(...) {}", paren(go(b, elem), 2)), 1),
        RExpr::Neg(a) => (format!("-{}", paren(go(a, elem), 3)), 3),
        RExpr::Binary(op, a, b) => {
            let (sym, level) = match op {
                BinOp::Add => (" + ", 1),
                BinOp::Sub => (" - ", 1),
                BinOp::Mul => ("*", 2),
                BinOp::Div => ("/", 2),
                BinOp::Pow => ("^", 4),
            };
            let right_min = if matches!(op, BinOp::Sub | BinOp::Div | BinOp::Pow) {
                level + 1
            } else {
                level
            };
            let (l, r) = (paren(go(a, elem), level), paren(go(b, elem), right_min));
            (format!("{l}{sym}{r}"), level)
        }
        RExpr::Call(f, args) => {
            let a: Vec<String> = args.iter().map(|a| go(a, elem).0).collect();
            (format!("{}({})", f.name(), a.join(", ")), 4)
        }
        RExpr::Int(op, a, b) => {
            let f = if *op == IntOp::Div { "div" } else { "mod" };
            (format!("{f}({}, {})", go(a, elem).0, go(b, elem).0), 4)
        }
        RExpr::Compare(op, a, b) => {
            let (a, b) = (paren(go(a, elem), 1), paren(go(b, elem), 1));
            (format!("{a} {} {b}", op.symbol()), 0)
        }
        RExpr::Logic(op, a, b) => {
            let w = if *op == LogicOp::And { "and" } else { "or" };
            let (a, b) = (paren(go(a, elem), 1), paren(go(b, elem), 1));
            (format!("{a} {w} {b}"), 0)
        }
        RExpr::Not(a) => (format!("not {}", paren(go(a, elem), 1)), 0),
        RExpr::If(c, a, b) => (
            format!(
                "if {} then {} else {}",
                go(c, elem).0,
                go(a, elem).0,
                go(b, elem).0
            ),
            0,
        ),
    }
}
