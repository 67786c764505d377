//! The table of a family model's maps, with compositions kept canonical.
//!
//! Both the checker (element access `x[a[b[k]]]`, formulas written in an index, constant
//! indices) and the analysis (gathers of gathers, the conditions of `J_Omega`'s kernels)
//! make maps; both go through [`MapTable`], so that one map has one [`MapId`] and two
//! conditions on the same pair of maps compare equal.
//!
//! Canonical form of a composition (a [`MapKind::Chain`], first map first): chains are
//! flattened, identities dropped, and everything before a map to the unit is absorbed
//! into the map of the chain's domain to the unit (`m` then "to the unit" is "to the
//! unit"). A chain of one map is that map.

use crate::MapId;
use crate::SetId;
use crate::ast::Span;
use crate::model::{MapDef, MapKind, RExpr};

/// The maps of a model; see the module documentation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MapTable {
    defs: Vec<MapDef>,
}

impl MapTable {
    /// A table holding `defs` (the named maps of a model and those made so far).
    pub fn new(defs: Vec<MapDef>) -> MapTable {
        MapTable { defs }
    }

    /// The maps, by id.
    pub fn defs(&self) -> &[MapDef] {
        &self.defs
    }

    /// The table's maps, taking it apart.
    pub fn into_defs(self) -> Vec<MapDef> {
        self.defs
    }

    /// One map.
    pub fn get(&self, m: MapId) -> &MapDef {
        &self.defs[m.index()]
    }

    /// Domain of a map (`None`: the unit).
    pub fn domain(&self, m: MapId) -> Option<SetId> {
        self.get(m).domain
    }

    /// Codomain of a map (`None`: the unit).
    pub fn codomain(&self, m: MapId) -> Option<SetId> {
        self.get(m).codomain
    }

    /// Adds a map as it is (a named map: never merged with another).
    pub fn push(&mut self, def: MapDef) -> MapId {
        self.defs.push(def);
        MapId::new(self.defs.len() - 1)
    }

    /// Replaces the kind of map `m` (the formula of a named map, once resolved).
    pub fn set_kind(&mut self, m: MapId, kind: MapKind) {
        self.defs[m.index()].kind = kind;
    }

    /// The id of a map equal to `def` (same domain, codomain and kind), adding it if new.
    pub fn intern(&mut self, def: MapDef) -> MapId {
        // Named maps (given, or with a formula) keep their identity: only maps made by
        // the checker and the analysis are merged.
        if let Some(i) = self.defs.iter().position(|d| {
            d.domain == def.domain
                && d.codomain == def.codomain
                && d.kind == def.kind
                && !is_named(d)
        }) {
            return MapId::new(i);
        }
        self.defs.push(def);
        MapId::new(self.defs.len() - 1)
    }

    /// The identity of `set`.
    pub fn identity(&mut self, set: Option<SetId>, span: Span) -> MapId {
        self.intern(MapDef {
            name: "id".into(),
            domain: set,
            codomain: set,
            kind: MapKind::Identity,
            span,
        })
    }

    /// The map of `set` to the unit (the scalar context).
    pub fn to_unit(&mut self, set: Option<SetId>, span: Span) -> MapId {
        if set.is_none() {
            return self.identity(None, span);
        }
        self.intern(MapDef {
            name: "unit".into(),
            domain: set,
            codomain: None,
            kind: MapKind::ToUnit,
            span,
        })
    }

    /// `first` then `then`: the map `e -> then(first(e))` (the codomain of `first` must
    /// be the domain of `then`).
    pub fn compose(&mut self, first: MapId, then: MapId) -> MapId {
        debug_assert_eq!(
            self.codomain(first),
            self.domain(then),
            "maps do not compose"
        );
        let mut chain = Vec::new();
        self.flatten(first, &mut chain);
        self.flatten(then, &mut chain);
        self.chain(chain, self.get(first).span)
    }

    /// The canonical map of a list of maps applied in order (see the module docs).
    fn chain(&mut self, maps: Vec<MapId>, span: Span) -> MapId {
        let domain = self.domain(maps[0]);
        let codomain = self.codomain(maps[maps.len() - 1]);
        let mut out: Vec<MapId> = Vec::with_capacity(maps.len());
        for m in maps {
            match self.get(m).kind {
                MapKind::Identity => {}
                MapKind::ToUnit => {
                    out.clear();
                    let u = self.to_unit(domain, span);
                    if self.get(u).kind == MapKind::ToUnit {
                        out.push(u);
                    }
                }
                _ => out.push(m),
            }
        }
        match out.len() {
            0 => self.identity(domain, span),
            1 => out[0],
            _ => {
                let name = out
                    .iter()
                    .map(|m| self.get(*m).name.clone())
                    .collect::<Vec<_>>()
                    .join(" then ");
                self.intern(MapDef {
                    name,
                    domain,
                    codomain,
                    kind: MapKind::Chain(out),
                    span,
                })
            }
        }
    }

    fn flatten(&self, m: MapId, out: &mut Vec<MapId>) {
        match &self.get(m).kind {
            MapKind::Chain(ms) => out.extend(ms.iter().copied()),
            _ => out.push(m),
        }
    }

    /// Whether the map sends every element to one element (it goes through the unit):
    /// then `Some(r0)`, the map from the unit it applies after the unit (the identity of
    /// the unit for a map to the unit itself).
    pub fn through_unit(&mut self, m: MapId) -> Option<MapId> {
        let span = self.get(m).span;
        match &self.get(m).kind {
            MapKind::ToUnit => Some(self.identity(None, span)),
            _ if self.domain(m).is_none() => Some(m),
            MapKind::Chain(ms) if self.get(ms[0]).kind == MapKind::ToUnit => {
                let rest: Vec<MapId> = ms[1..].to_vec();
                Some(self.chain(rest, span))
            }
            _ => None,
        }
    }

    /// An anonymous map given by an integer formula (in the context of `domain`); equal
    /// formulas between the same sets are one map.
    pub fn formula(
        &mut self,
        domain: Option<SetId>,
        codomain: Option<SetId>,
        formula: RExpr,
        span: Span,
    ) -> MapId {
        self.intern(MapDef {
            name: String::new(),
            domain,
            codomain,
            kind: MapKind::Formula(formula),
            span,
        })
    }
}

/// A named map (declared with `map`, given or with a formula) is never merged with an
/// equal one; the maps the checker and the analysis make are. An anonymous formula map
/// has an empty name.
pub fn is_named(d: &MapDef) -> bool {
    match d.kind {
        MapKind::Given => true,
        MapKind::Formula(_) => !d.name.is_empty(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> (MapTable, MapId, MapId) {
        let s = Span::default();
        let (l, p) = (Some(SetId::new(0)), Some(SetId::new(1)));
        let mut t = MapTable::default();
        let a = t.intern(MapDef {
            name: "a".into(),
            domain: l,
            codomain: p,
            kind: MapKind::Given,
            span: s,
        });
        let c = t.intern(MapDef {
            name: "c".into(),
            domain: p,
            codomain: l,
            kind: MapKind::Given,
            span: s,
        });
        (t, a, c)
    }

    #[test]
    fn compositions_are_canonical() {
        let (mut t, a, c) = table();
        let s = Span::default();
        let ac = t.compose(a, c);
        let ca = t.compose(c, a);
        assert_ne!(ac, ca);
        // (a then c) then a == a then (c then a)
        let left = t.compose(ac, a);
        let right = t.compose(a, ca);
        assert_eq!(left, right);
        assert_eq!(t.get(left).kind, MapKind::Chain(vec![a, c, a]));
        // identities vanish
        let id = t.identity(t.domain(a), s);
        assert_eq!(t.compose(id, a), a);
        // anything then the unit is the unit of the domain
        let u = t.to_unit(t.codomain(a), s);
        let au = t.compose(a, u);
        assert_eq!(au, t.to_unit(t.domain(a), s));
        assert_eq!(t.through_unit(au), Some(t.identity(None, s)));
        assert_eq!(t.through_unit(a), None);
    }

    #[test]
    fn constant_maps_go_through_the_unit() {
        let (mut t, a, _) = table();
        let s = Span::default();
        let zero = t.formula(None, t.codomain(a), RExpr::Num(0.0), s);
        let u = t.to_unit(t.domain(a), s);
        let k = t.compose(u, zero);
        assert_eq!(t.through_unit(k), Some(zero));
        assert_eq!(t.through_unit(zero), Some(zero));
    }
}
