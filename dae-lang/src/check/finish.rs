//! The passes after the declarations: values, equations, the order of the `let`s, the
//! model, and the construction at the default sizes.

use std::collections::HashMap;

use super::expr::{Env, Ty, Val, Where};
use super::{Checker, Component, Entry, Kind, LET_STRIDE, LetState};
use crate::ast::{BinOp, Ident, Item, Span};
use crate::check::{NamedConstraint, der_of_non_state, der_of_time, lets, named_constraints};
use crate::diag::Diagnostic;
use crate::model::{
    ConstraintDef, DerDef, Family, InputDef, LetDef, MapKind, MassDef, Model, ParamDef, RExpr,
    VarDef,
};

impl Checker<'_> {
    /// Resolves everything after the declarations and builds the model.
    pub(super) fn finish(mut self) -> Result<Model, Vec<Diagnostic>> {
        self.set_sizes();
        self.map_formulas();
        let params = self.params_values();
        let states = self.inits(Kind::State);
        let algs = self.inits(Kind::Alg);
        let inputs = self.inits(Kind::Input);
        for d in 0..self.lets.len() {
            self.resolve_let(d);
        }
        let ders = self.ders();
        let mass = self.mass_matrices();
        let constraints = self.constraints();
        let let_order = self.order_lets();
        let start = self
            .version1
            .then(|| self.check_start(&params, &states, &algs));
        if !self.diags.is_empty() {
            self.diags.sort_by_key(|d| d.span.start);
            return Err(self.diags);
        }
        let mut model = self.build(
            params,
            states,
            algs,
            inputs,
            ders,
            mass,
            constraints,
            &let_order,
        );
        let mut diags = Vec::new();
        crate::check::mass::algebraic_entries(&model, &mut diags);
        match start {
            // Every value is known: an unknown one came with an error.
            Some(values) => {
                for (p, v) in model.params.iter_mut().zip(values) {
                    p.default = v.unwrap_or(f64::NAN);
                }
            }
            None => crate::family::check_at_default_sizes(&mut model, &mut diags),
        }
        if diags.is_empty() {
            Ok(model)
        } else {
            diags.sort_by_key(|d| d.span.start);
            Err(diags)
        }
    }

    fn set_sizes(&mut self) {
        for i in 0..self.sets.len() {
            let Some(e) = self.set_exprs[i] else { continue };
            let env = Env {
                ctx: None,
                binders: Vec::new(),
                place: Where::SetSize,
                owner: self.sets[i].name.clone(),
            };
            if let Some(v) = self.expr(e, &env) {
                if v.ty != Ty::Int {
                    self.diags.push(
                        Diagnostic::new(
                            format!("the size of set `{}` is not an integer", self.sets[i].name),
                            e.span,
                            v.ty.words(),
                        )
                        .hint("a set's size is an integer formula over sizes"),
                    );
                } else {
                    self.sets[i].size = v.comps.into_iter().next();
                }
            }
        }
    }

    fn map_formulas(&mut self) {
        for k in 0..self.named_maps.len() {
            let (id, formula, name) = {
                let nm = &self.named_maps[k];
                (nm.id, nm.formula, nm.name.to_string())
            };
            let Some(formula) = formula else { continue };
            let def = self.maps.get(id).clone();
            let domain = def.domain;
            let binder = self.m.items.iter().find_map(|item| match item {
                Item::Map {
                    name: n, binder, ..
                } if n.name == name => binder.elem.as_ref(),
                _ => None,
            });
            let mut env = Env {
                ctx: domain,
                binders: Vec::new(),
                place: Where::MapFormula(k),
                owner: name.clone(),
            };
            if let (Some(set), Some(b)) = (domain, binder) {
                env.binders.push(super::expr::Binding {
                    name: b.name.clone(),
                    set,
                    via: super::expr::Via::Here,
                });
            }
            let Some(v) = self.expr(formula, &env) else {
                continue;
            };
            if v.ty != Ty::Int {
                self.diags.push(
                    Diagnostic::new(format!("the formula of map `{name}` is not an integer"), formula.span, v.ty.words())
                        .hint("a map formula gives an element: an integer formula in the element, sizes and maps"),
                );
                continue;
            }
            if let Some(f) = v.comps.into_iter().next() {
                self.maps.set_kind(id, MapKind::Formula(f));
            }
        }
    }

    /// Resolves one component family's value (all components of a declaration at once)
    /// and checks its type.
    fn value(&mut self, c: &Component<'_>, place: Where) -> Option<Val> {
        let env = self.decl_env(c.decl, c.family.over, place);
        let v = self.expr(&c.decl.value, &env)?;
        if v.ty == Ty::Bool {
            return self.err(
                Diagnostic::new(
                    format!(
                        "the value of `{}` is a condition, not a number",
                        c.decl.name.name
                    ),
                    c.decl.value.span,
                    "a condition",
                )
                .hint("write `if c then 1 else 0` for a number"),
            );
        }
        self.check_declared_type(c.decl, &v)
    }

    /// The values of the parameters, in order (each may use the ones declared before).
    fn params_values(&mut self) -> Vec<Option<RExpr>> {
        let comps = std::mem::take(&mut self.params);
        let mut out = vec![None; comps.len()];
        let mut i = 0;
        while i < comps.len() {
            let c = &comps[i];
            let dim = c.family.dim as usize;
            let place = Where::Param(self.param_decl[i]);
            if let Some(v) = self.value(c, place) {
                for (k, e) in v.comps.into_iter().enumerate() {
                    out[i + k] = Some(e);
                }
            }
            i += dim;
        }
        self.params = comps;
        out
    }

    /// The initial values of states or algebraic unknowns, or the defaults of inputs.
    fn inits(&mut self, kind: Kind) -> Vec<Option<RExpr>> {
        let comps = std::mem::take(match kind {
            Kind::State => &mut self.states,
            Kind::Alg => &mut self.algs,
            _ => &mut self.inputs,
        });
        let mut out = vec![None; comps.len()];
        let mut i = 0;
        while i < comps.len() {
            let dim = comps[i].family.dim as usize;
            if let Some(v) = self.value(&comps[i], Where::Init) {
                for (k, e) in v.comps.into_iter().enumerate() {
                    out[i + k] = Some(e);
                }
            }
            i += dim;
        }
        *match kind {
            Kind::State => &mut self.states,
            Kind::Alg => &mut self.algs,
            _ => &mut self.inputs,
        } = comps;
        out
    }

    /// The `der` equations, per state component.
    /// The state `name` names (in `der(name)` or a `mass` item), or `None` with the
    /// error reported (nothing more for a name declared twice, already reported).
    pub(super) fn state_named(&mut self, name: &Ident) -> Option<Entry> {
        let text = name.name.as_str();
        match self.names.get(text) {
            Some(e) if e.kind == Kind::State => Some(*e),
            Some(_) if self.duplicated.contains(text) => None,
            Some(e) => {
                let d = der_of_non_state(text, name.span, e.kind.words(), e.span);
                self.diags.push(d);
                None
            }
            None => {
                if text == "t" {
                    self.diags.push(der_of_time(name.span));
                } else {
                    self.unknown_name(text, name.span);
                }
                None
            }
        }
    }

    fn ders(&mut self) -> Vec<Option<DerDef>> {
        let m = self.m;
        let mut out: Vec<Option<DerDef>> = vec![None; self.states.len()];
        let mut first: HashMap<usize, Span> = HashMap::new();
        for item in &m.items {
            let Item::Der {
                target,
                elem,
                rhs,
                span,
            } = item
            else {
                continue;
            };
            let name = target.name.as_str();
            let Some(entry) = self.state_named(target) else {
                if elem.is_none() {
                    // The right-hand side's own errors are reported all the same.
                    let env = Env {
                        ctx: None,
                        binders: Vec::new(),
                        place: Where::Equation,
                        owner: format!("der({name})"),
                    };
                    self.expr(rhs, &env);
                }
                continue;
            };
            let mut env = Env {
                ctx: entry.over,
                binders: Vec::new(),
                place: Where::Equation,
                owner: format!("der({name})"),
            };
            match (entry.over, elem) {
                (Some(set), Some(e)) => {
                    if let Some(other) = self.names.get(e.name.as_str()) {
                        self.diags.push(
                            Diagnostic::new(
                                format!(
                                    "the element name `{}` is also declared as {}",
                                    e.name,
                                    other.kind.words()
                                ),
                                e.span,
                                "element name",
                            )
                            .hint("choose another element name"),
                        );
                        continue;
                    }
                    env.binders.push(super::expr::Binding {
                        name: e.name.clone(),
                        set,
                        via: super::expr::Via::Here,
                    });
                }
                (Some(set), None) => {
                    let s = &self.sets[set.index()];
                    self.diags.push(
                        Diagnostic::new(
                            format!("`der({name})`: `{name}` is a family over `{}`", s.name),
                            target.span,
                            "which element?",
                        )
                        .hint(format!(
                            "name the element: `der({name}[{}]) = ...;`",
                            s.elem
                        )),
                    );
                    continue;
                }
                (None, Some(e)) => {
                    self.diags.push(
                        Diagnostic::new(
                            format!("`der({name}[{}])`: `{name}` is not a family", e.name),
                            e.span,
                            "no element",
                        )
                        .hint(format!("write `der({name}) = ...;`")),
                    );
                    continue;
                }
                (None, None) => {}
            }
            let v = self.expr(rhs, &env);
            if let Some(prev) = first.get(&entry.first) {
                self.diags.push(
                    Diagnostic::new(
                        format!("state `{name}` has two equations `der({name}) = ...`"),
                        *span,
                        "second equation",
                    )
                    .related(*prev, "first equation")
                    .hint("keep one of them: each state has exactly one `der` equation"),
                );
                continue;
            }
            first.insert(entry.first, *span);
            let Some(v) = v else { continue };
            if v.dim() != entry.dim || v.ty == Ty::Bool {
                let want = if entry.dim == 1 {
                    "a number".to_string()
                } else {
                    format!("a vec{}", entry.dim)
                };
                self.diags.push(
                    Diagnostic::new(
                        format!(
                            "`der({name})` is {want}, but the right-hand side is {}",
                            v.ty.words()
                        ),
                        rhs.span,
                        "vector/scalar mismatch",
                    )
                    .hint("the derivative of a state has the state's type"),
                );
                continue;
            }
            for (c, e) in v.comps.into_iter().enumerate() {
                out[entry.first + c] = Some(DerDef {
                    expr: e,
                    span: *span,
                });
            }
        }
        let mut reported = std::collections::HashSet::new();
        for (i, c) in self.states.iter().enumerate() {
            if out[i].is_none()
                && !first.contains_key(&(i - c.family.component as usize))
                && reported.insert(c.decl.name.span)
            {
                let name = &c.decl.name.name;
                self.diags.push(
                    Diagnostic::new(format!("state `{name}` has no equation `der({name}) = ...`"), c.decl.name.span, "declared here")
                        .hint(format!("add `der({name}) = ...;`, or declare `{name}` with `alg` if it has no derivative")),
                );
            }
        }
        out
    }

    /// The constraints in order (families and single constraints), named.
    fn constraints(&mut self) -> Vec<Option<ConstraintDef>> {
        let m = self.m;
        let mut out = Vec::new();
        let mut seen: HashMap<String, Span> = HashMap::new();
        for constraint in named_constraints(m) {
            let NamedConstraint {
                name: cname,
                name_span: cspan,
                written,
                binder,
                lhs,
                rhs,
                span,
            } = constraint;
            if written && super::decl::is_reserved(&cname, self.version1) {
                let (message, hint) = super::decl::reserved_message(&cname);
                self.diags
                    .push(Diagnostic::new(message, cspan, "reserved word").hint(hint));
            }
            if let Some(first) = seen.get(&cname) {
                self.diags.push(
                    Diagnostic::new(
                        format!("two constraints named `{cname}`"),
                        cspan,
                        "second use of the name",
                    )
                    .related(*first, "first use of the name")
                    .hint("rename one of them: constraint names are unique in a model"),
                );
            } else {
                seen.insert(cname.clone(), cspan);
            }
            let Ok(over) = self.binder_set(binder) else {
                out.push(None);
                continue;
            };
            let mut env = Env {
                ctx: over,
                binders: Vec::new(),
                place: Where::Equation,
                owner: cname.clone(),
            };
            if let (Some(set), Some(e)) = (over, binder.and_then(|b| b.elem.as_ref())) {
                env.binders.push(super::expr::Binding {
                    name: e.name.clone(),
                    set,
                    via: super::expr::Via::Here,
                });
            }
            let (l, r) = (self.expr(lhs, &env), self.expr(rhs, &env));
            let residual = match (l, r) {
                (Some(l), Some(r)) if l.ty.is_scalar_number() && r.ty.is_scalar_number() => {
                    Some(RExpr::Binary(
                        BinOp::Sub,
                        Box::new(l.comps[0].clone()),
                        Box::new(r.comps[0].clone()),
                    ))
                }
                (Some(l), Some(r)) => {
                    let bad = if l.ty.is_scalar_number() { r.ty } else { l.ty };
                    self.diags.push(
                        Diagnostic::new(
                            format!("constraint `{cname}` is {}, not one equation", bad.words()),
                            span,
                            "vector constraint",
                        )
                        .hint("a constraint is one scalar equation: constrain a number such as `norm(d[l])`, `dot(a, b)` or `v.x`"),
                    );
                    None
                }
                _ => None,
            };
            out.push(residual.map(|residual| ConstraintDef {
                name: cname,
                residual,
                span,
                over,
            }));
        }
        out
    }

    /// Orders the `let` declarations so that each follows those it uses; reports cycles.
    /// Returns the declaration order.
    fn order_lets(&mut self) -> Vec<usize> {
        let uses: Vec<Vec<usize>> = self
            .let_state
            .iter()
            .map(|s| {
                let mut out = Vec::new();
                if let LetState::Done(Some(comps)) = s {
                    let mut comp_uses = Vec::new();
                    for c in comps {
                        lets::let_uses(c, &mut comp_uses);
                    }
                    for u in comp_uses {
                        let d = u / LET_STRIDE;
                        if !out.contains(&d) {
                            out.push(d);
                        }
                    }
                }
                out
            })
            .collect();
        let order = lets::order(&uses);
        for cycle in &order.cycles {
            self.diags.push(lets::cycle_error(cycle, &self.lets));
        }
        order.order
    }

    #[allow(clippy::too_many_arguments)]
    fn build(
        mut self,
        params: Vec<Option<RExpr>>,
        states: Vec<Option<RExpr>>,
        algs: Vec<Option<RExpr>>,
        inputs: Vec<Option<RExpr>>,
        ders: Vec<Option<DerDef>>,
        mut mass: Vec<MassDef>,
        constraints: Vec<Option<ConstraintDef>>,
        let_order: &[usize],
    ) -> Model {
        // Final let ids: declarations in order, components in order.
        let mut new_index = vec![0; self.lets.len() * LET_STRIDE];
        let mut lets_out: Vec<LetDef> = Vec::new();
        for &d in let_order {
            let LetState::Done(Some(comps)) =
                std::mem::replace(&mut self.let_state[d], LetState::Todo)
            else {
                continue;
            };
            let decl = self.lets[d];
            let dim = comps.len() as u8;
            for (c, expr) in comps.into_iter().enumerate() {
                new_index[d * LET_STRIDE + c] = lets_out.len();
                lets_out.push(LetDef {
                    name: super::decl::component_name(&decl.name.name, dim, c as u8),
                    expr,
                    span: decl.span,
                    family: Family {
                        over: self.let_sets[d],
                        dim,
                        component: c as u8,
                    },
                });
            }
        }
        let renumber = |e: &mut RExpr| lets::renumber(e, &new_index);
        for l in &mut lets_out {
            renumber(&mut l.expr);
        }
        let mut ders_out: Vec<DerDef> = ders.into_iter().flatten().collect();
        ders_out.iter_mut().for_each(|d| renumber(&mut d.expr));
        mass.iter_mut()
            .flat_map(|m| &mut m.entries)
            .for_each(&renumber);
        let mut constraints_out: Vec<ConstraintDef> = constraints.into_iter().flatten().collect();
        constraints_out
            .iter_mut()
            .for_each(|c| renumber(&mut c.residual));
        let var = |c: &Component<'_>, init: Option<RExpr>| VarDef {
            name: c.name.clone(),
            init: init.unwrap_or(RExpr::Num(f64::NAN)),
            span: c.decl.span,
            family: c.family,
        };
        let states_out = self
            .states
            .iter()
            .zip(states)
            .map(|(c, e)| var(c, e))
            .collect();
        let algs_out = self.algs.iter().zip(algs).map(|(c, e)| var(c, e)).collect();
        let inputs_out = self
            .inputs
            .iter()
            .zip(inputs)
            .map(|(c, e)| InputDef {
                name: c.name.clone(),
                family: c.family,
                derivatives: c.derivatives,
                default: e.unwrap_or(RExpr::Num(f64::NAN)),
                span: c.decl.span,
            })
            .collect();
        let params_out = self
            .params
            .iter()
            .zip(params)
            .map(|(c, e)| ParamDef {
                name: c.name.clone(),
                // Filled in by the evaluation at the default sizes.
                default: f64::NAN,
                span: c.decl.span,
                value: e.unwrap_or(RExpr::Num(f64::NAN)),
                family: c.family,
            })
            .collect();
        Model {
            name: self.m.name.name.clone(),
            span: self.m.name.span,
            params: params_out,
            states: states_out,
            algs: algs_out,
            lets: lets_out,
            ders: ders_out,
            mass,
            constraints: constraints_out,
            sizes: self.sizes,
            sets: self.sets,
            maps: self.maps.into_defs(),
            inputs: inputs_out,
        }
    }
}

impl Ty {
    fn is_scalar_number(self) -> bool {
        matches!(self, Ty::Int | Ty::Real)
    }
}
