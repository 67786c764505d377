//! Element access (`x[i]`, `a[l]`), the maps it makes, and sums.
//!
//! An index names an element of the family's set, seen from the element at hand: the
//! element itself (`x[p]`), its image under a map (`x[a[l]]`, `x[a[b[k]]]`: a
//! composition), or an integer formula (`x[l + 1]`, `x[0]`, `x[N]`), which becomes an
//! anonymous map evaluated and range-checked at construction. A formula that does not
//! depend on the element is a map from the unit, reached through the map of the context
//! to the unit, so that every constant index goes through the unit (what the `J_Omega`
//! kernels rely on).

use super::expr::{Binding, Env, Ty, Val, Via, Where};
use super::{Checker, Kind};
use crate::ast::{CmpOp, Expr, ExprKind, Ident, Span};
use crate::diag::Diagnostic;
use crate::model::RExpr;
use crate::{MapId, SetId, VarRef};

/// The path from the element at hand to an indexed element: `None` is the element
/// itself.
type Path = Option<MapId>;

impl Checker<'_> {
    fn set_name(&self, s: SetId) -> &str {
        &self.sets[s.index()].name
    }

    /// `base[idx]`.
    pub(super) fn access(&mut self, base: &Expr, idx: &Expr, span: Span, env: &Env) -> Option<Val> {
        let ExprKind::Name(n) = &base.kind else {
            return self.err(
                Diagnostic::new(
                    "only a family or a map takes an index",
                    base.span,
                    "not a name",
                )
                .hint("index a declared family (`x[p]`) or map (`a[l]`)"),
            );
        };
        if env.binding(n).is_some() {
            return self.err(
                Diagnostic::new(
                    format!("`{n}` is an element: it takes no index"),
                    base.span,
                    "an element",
                )
                .hint("index a family or a map with it: `x[p]`, `a[p]`"),
            );
        }
        let Some(entry) = self.names.get(n.as_str()).copied() else {
            if crate::Func::from_name(n).is_some() {
                return self.unknown_name(n, base.span);
            }
            let indexed: Vec<&str> = self
                .ordered
                .iter()
                .copied()
                .filter(|x| self.names[x].kind == Kind::Map || self.names[x].over.is_some())
                .collect();
            let hint = match crate::check::names::suggest(n, indexed.iter().copied()) {
                Some(s) => format!("did you mean `{s}`?"),
                None => {
                    "declare it: `map NAME[l in L] -> P = ...;` or a family `NAME[p in P]`".into()
                }
            };
            return self.err(
                Diagnostic::new(
                    format!("unknown map or family `{n}`"),
                    base.span,
                    format!("not declared in model `{}`", self.m.name.name),
                )
                .hint(hint),
            );
        };
        match entry.kind {
            Kind::Set | Kind::Size => self.err(
                Diagnostic::new(
                    format!("`{n}` is {}: it takes no index", entry.kind.words()),
                    base.span,
                    entry.kind.words(),
                )
                .hint("index a family (`x[p]`) or a map (`a[l]`)"),
            ),
            Kind::Map => {
                let map = self.named_map(entry.first, base.span, env)?;
                let def = self.maps.get(map).clone();
                let domain = def.domain.expect("a named map has a set as domain");
                let path = self.index_path(idx, domain, &format!("map `{n}`"), env)?;
                let m = self.then(path, map);
                let elem = RExpr::Var(VarRef::Elem(def.codomain.expect("named map codomain")));
                Some(Val {
                    comps: vec![RExpr::Gather(m, Box::new(elem))],
                    ty: Ty::Int,
                })
            }
            _ => {
                let Some(set) = entry.over else {
                    return self.err(
                        Diagnostic::new(
                            format!("`{n}` is not a family: it takes no index"),
                            base.span,
                            format!("one value ({})", entry.kind.words()),
                        )
                        .related(entry.span, format!("`{n}` is declared here"))
                        .hint(format!(
                            "write `{n}` alone, or declare it over a set: `{n}[p in P]`"
                        )),
                    );
                };
                let path = self.index_path(idx, set, &format!("`{n}`"), env)?;
                let v = self.leaf(n, entry, span, env)?;
                let comps = match path {
                    None => v.comps,
                    Some(m) => v
                        .comps
                        .into_iter()
                        .map(|c| RExpr::Gather(m, Box::new(c)))
                        .collect(),
                };
                Some(Val { comps, ty: v.ty })
            }
        }
    }

    /// The id of named map number `k`, if the place may use it.
    fn named_map(&mut self, k: usize, span: Span, env: &Env) -> Option<MapId> {
        let nm = &self.named_maps[k];
        let (id, name) = (nm.id, nm.name);
        match env.place {
            Where::SetSize => {
                self.err(
                    Diagnostic::new(
                        format!("the size of set `{}` uses map `{name}`", env.owner),
                        span,
                        "a map",
                    )
                    .hint("a set's size is a formula over sizes and whole numbers"),
                )?;
                None
            }
            Where::MapFormula(i) if k >= i => {
                let d = if k == i {
                    Diagnostic::new(
                        format!("map `{name}` is defined in terms of itself"),
                        span,
                        "used in its own formula",
                    )
                    .hint("a map formula uses the element, sizes and maps declared before it")
                } else {
                    Diagnostic::new(
                        format!(
                            "the formula of map `{}` uses map `{name}`, which is declared after it",
                            env.owner
                        ),
                        span,
                        "declared later",
                    )
                    .hint(format!("declare `{name}` before `{}`", env.owner))
                };
                self.err(d)?;
                None
            }
            _ => Some(id),
        }
    }

    /// `path` then `map` (the map itself when `path` is the element at hand).
    fn then(&mut self, path: Path, map: MapId) -> MapId {
        match path {
            None => map,
            Some(p) => self.maps.compose(p, map),
        }
    }

    /// The path to the element `idx` of `target`, seen from the element at hand; `what`
    /// names what is indexed, for messages.
    pub(super) fn index_path(
        &mut self,
        idx: &Expr,
        target: SetId,
        what: &str,
        env: &Env,
    ) -> Option<Path> {
        match &idx.kind {
            ExprKind::Name(n) if env.binding(n).is_some() => {
                let b = env.binding(n).expect("checked").clone();
                if b.set != target {
                    let hint = self.through_a_map_hint(what, target, &b);
                    self.err(
                        Diagnostic::new(
                            format!(
                                "{what} takes an element of `{}`, but `{n}` is an element of `{}`",
                                self.set_name(target),
                                self.set_name(b.set)
                            ),
                            idx.span,
                            format!("an element of `{}`", self.set_name(b.set)),
                        )
                        .hint(hint),
                    )?;
                    return None;
                }
                match b.via {
                    Via::Here => Some(None),
                    Via::Map(m) => Some(Some(m)),
                    Via::Undetermined(sum) => {
                        self.err(
                            Diagnostic::new(format!("`{n}` is not determined inside this sum"), idx.span, "which element?")
                                .related(sum, "the sum")
                                .hint(format!(
                                    "inside `sum(k in K where m[k] == {n}) ...` the element `{n}` is `m[k]`; \
                                     a full sum, or a sum whose condition does not name `{n}`, cannot use it"
                                )),
                        )?;
                        None
                    }
                }
            }
            ExprKind::Index(base, inner) if self.is_named_map(base) => {
                let ExprKind::Name(mn) = &base.kind else {
                    return None;
                };
                let entry = self.names[mn.as_str()];
                let map = self.named_map(entry.first, base.span, env)?;
                let def = self.maps.get(map).clone();
                let (domain, codomain) = (def.domain.expect("set"), def.codomain.expect("set"));
                if codomain != target {
                    self.err(
                        Diagnostic::new(
                            format!(
                                "{what} takes an element of `{}`, but map `{mn}` gives elements of `{}`",
                                self.set_name(target),
                                self.set_name(codomain)
                            ),
                            base.span,
                            format!("goes to `{}`", self.set_name(codomain)),
                        )
                        .hint(format!("use a map to `{}`", self.set_name(target))),
                    )?;
                    return None;
                }
                let path = self.index_path(inner, domain, &format!("map `{mn}`"), env)?;
                Some(Some(self.then(path, map)))
            }
            _ => self.formula_path(idx, target, env),
        }
    }

    fn is_named_map(&self, base: &Expr) -> bool {
        matches!(&base.kind, ExprKind::Name(n) if self.names.get(n.as_str()).is_some_and(|e| e.kind == Kind::Map))
    }

    fn through_a_map_hint(&self, what: &str, target: SetId, b: &Binding) -> String {
        let maps: Vec<&str> = self
            .named_maps
            .iter()
            .filter(|m| {
                let d = self.maps.get(m.id);
                d.domain == Some(b.set) && d.codomain == Some(target)
            })
            .map(|m| m.name)
            .collect();
        match maps.first() {
            Some(m) => format!("go through a map: `{m}[{}]`", b.name),
            None => format!(
                "go through a map from `{}` to `{}` (declare one with `map a[{} in {}] -> {} = ...;`), \
                 or write a formula such as `{}[{} + 0]` if the numbers match on purpose",
                self.set_name(b.set),
                self.set_name(target),
                b.name,
                self.set_name(b.set),
                self.set_name(target),
                what.trim_matches('`'),
                b.name
            ),
        }
    }

    /// An integer formula used as an index: an anonymous map.
    fn formula_path(&mut self, idx: &Expr, target: SetId, env: &Env) -> Option<Path> {
        let mut inner = env.clone();
        if inner.place != Where::SetSize && !matches!(inner.place, Where::MapFormula(_)) {
            inner.place = Where::Index;
        }
        let v = self.expr(idx, &inner)?;
        if v.ty != Ty::Int {
            self.err(
                Diagnostic::new(format!("an index is an integer, not {}", v.ty.words()), idx.span, "not an integer")
                    .hint("index with an element (`x[p]`), a map (`x[a[l]]`) or an integer formula (`x[l + 1]`)"),
            )?;
            return None;
        }
        let f = v.comps.into_iter().next()?;
        let mut uses_elem = false;
        f.visit(&mut |e| uses_elem |= matches!(e, RExpr::Var(VarRef::Elem(_)) | RExpr::Gather(..)));
        let m = if uses_elem && env.ctx.is_some() {
            self.maps.formula(env.ctx, Some(target), f, idx.span)
        } else {
            let constant = self.maps.formula(None, Some(target), f, idx.span);
            let unit = self.maps.to_unit(env.ctx, idx.span);
            self.maps.compose(unit, constant)
        };
        Some(Some(m))
    }

    /// `sum(k in K where c) body` or `sum(k in K) body`.
    pub(super) fn sum(
        &mut self,
        elem: &Ident,
        set: &Ident,
        cond: Option<&Expr>,
        body: &Expr,
        span: Span,
        env: &Env,
    ) -> Option<Val> {
        let k_set = self.set_named(set).ok();
        if env.place != Where::Equation {
            self.err(
                Diagnostic::new(
                    format!("a sum in {}", where_words(env.place)),
                    span,
                    "not allowed here",
                )
                .hint("sums are for equations (`let`, `der`, constraints)"),
            )?;
        }
        let k_set = k_set?;
        if let Some(e) = self.names.get(elem.name.as_str()).copied() {
            self.err(
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
                .hint("choose another element name"),
            )?;
        }
        let k = Binding {
            name: elem.name.clone(),
            set: k_set,
            via: Via::Here,
        };
        let Some(cond) = cond else {
            // A full sum: a number, the same for every element at hand.
            let mut inner = env.clone();
            inner.ctx = Some(k_set);
            for b in &mut inner.binders {
                b.via = Via::Undetermined(span);
            }
            inner.binders.push(k);
            let v = self.expr(body, &inner)?;
            let m = self.maps.to_unit(Some(k_set), span);
            return self.summed(v, m, None, body.span);
        };
        let malformed = |c: &mut Self, why: &str| {
            c.err(
                Diagnostic::new(format!("malformed sum condition: {why}"), cond.span, "not `MAP[k] == ELEMENT`")
                    .hint(format!(
                        "a sum's condition says which elements to add: `sum({} in {} where a[{}] == p) ...`",
                        elem.name, set.name, elem.name
                    )),
            )
        };
        let ExprKind::Compare(CmpOp::Eq, lhs, rhs) = &cond.kind else {
            return malformed(self, "it is not an equality `==`");
        };
        let (l_uses, r_uses) = (mentions(lhs, &elem.name), mentions(rhs, &elem.name));
        let (map_side, target_side) = match (l_uses, r_uses) {
            (true, false) => (lhs.as_ref(), rhs.as_ref()),
            (false, true) => (rhs.as_ref(), lhs.as_ref()),
            (false, false) => {
                return malformed(
                    self,
                    &format!("it does not use the summation element `{}`", elem.name),
                );
            }
            (true, true) => return malformed(self, &format!("both sides use `{}`", elem.name)),
        };
        let mut k_env = env.clone();
        k_env.ctx = Some(k_set);
        k_env.binders = vec![k.clone()];
        let q = self
            .element_set(target_side, env)
            .or_else(|| self.element_set(map_side, &k_env));
        let Some(q) = q else {
            return malformed(self, "cannot tell which set the two sides are elements of");
        };
        let m = self.index_path(map_side, q, "the condition", &k_env)?;
        let m = m.unwrap_or_else(|| self.maps.identity(Some(k_set), cond.span));
        let target = self.index_path(target_side, q, "the condition", env)?;
        // Inside the body, the element at hand of the outside is m[k] when the condition
        // names it; otherwise the outside's elements are not determined.
        let mut inner = env.clone();
        inner.ctx = Some(k_set);
        for b in &mut inner.binders {
            b.via = match (target, b.via) {
                (None, Via::Here) => Via::Map(m),
                (None, Via::Map(v)) => Via::Map(self.maps.compose(m, v)),
                _ => Via::Undetermined(span),
            };
        }
        inner.binders.push(k);
        let v = self.expr(body, &inner)?;
        self.summed(v, m, target, body.span)
    }

    fn summed(&mut self, v: Val, m: MapId, target: Path, span: Span) -> Option<Val> {
        if v.ty == Ty::Bool {
            return self.err(
                Diagnostic::new("a sum of conditions", span, "a condition")
                    .hint("a sum adds numbers or vectors"),
            );
        }
        let ty = if v.ty == Ty::Int { Ty::Real } else { v.ty };
        let comps = v
            .comps
            .into_iter()
            .map(|c| {
                let s = RExpr::Sum(m, Box::new(c));
                match target {
                    None => s,
                    Some(t) => RExpr::Gather(t, Box::new(s)),
                }
            })
            .collect();
        Some(Val { comps, ty })
    }

    /// The set an element expression names: an element name's set, or a map's codomain.
    fn element_set(&self, e: &Expr, env: &Env) -> Option<SetId> {
        match &e.kind {
            ExprKind::Name(n) => env.binding(n).map(|b| b.set),
            ExprKind::Index(base, _) => match &base.kind {
                ExprKind::Name(n) => {
                    let entry = self.names.get(n.as_str())?;
                    (entry.kind == Kind::Map)
                        .then(|| self.maps.get(self.named_maps[entry.first].id).codomain)
                        .flatten()
                }
                _ => None,
            },
            _ => None,
        }
    }
}

fn where_words(w: Where) -> &'static str {
    match w {
        Where::SetSize => "the size of a set",
        Where::MapFormula(_) => "a map formula",
        Where::Index => "an index",
        Where::Param(_) => "a parameter's value",
        Where::Init => "an initial value",
        Where::Equation => "an equation",
    }
}

/// Whether `e` mentions the name `n`.
fn mentions(e: &Expr, n: &str) -> bool {
    match &e.kind {
        ExprKind::Name(m) => m == n,
        ExprKind::Num(_) | ExprKind::Time => false,
        ExprKind::Neg(a) | ExprKind::Not(a) | ExprKind::Field(a, _) => mentions(a, n),
        ExprKind::Binary(_, a, b)
        | ExprKind::Index(a, b)
        | ExprKind::Compare(_, a, b)
        | ExprKind::Logic(_, a, b) => mentions(a, n) || mentions(b, n),
        ExprKind::If(c, a, b) => mentions(c, n) || mentions(a, n) || mentions(b, n),
        ExprKind::Call(_, args) => args.iter().any(|a| mentions(a, n)),
        ExprKind::Sum { cond, body, .. } => {
            cond.as_ref().is_some_and(|c| mentions(c, n)) || mentions(body, n)
        }
    }
}
