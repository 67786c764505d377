//! `mass [v[p], ...] = [...]` in a family model: one matrix per element of the set the
//! listed states are families over (a vector state lists its components in order), its
//! entries resolved in that element's context. The version-1 checker's rules apply
//! (`crate::check::mass`): distinct states, a square matrix, no algebraic unknown.

use super::Checker;
use super::expr::{Binding, Env, Ty, Via, Where};
use crate::StateId;
use crate::ast::{Ident, Item};
use crate::check::mass::{Listed, check_shape};
use crate::diag::Diagnostic;
use crate::model::MassDef;

impl Checker<'_> {
    /// The mass matrices, in the order written (the ones in error reported and left out).
    pub(super) fn mass_matrices(&mut self) -> Vec<MassDef> {
        let mut listed = Listed::default();
        let mut out = Vec::new();
        for item in &self.m.items {
            let Item::Mass { states, rows, span } = item else {
                continue;
            };
            let before = self.diags.len();
            let mut env = Env {
                ctx: None,
                binders: Vec::new(),
                place: Where::Equation,
                owner: "the mass matrix".to_string(),
            };
            let mut ids = Vec::new();
            for (k, (name, elem)) in states.iter().enumerate() {
                let Some((first, dim, over)) = self.mass_state(name, elem.as_ref()) else {
                    continue;
                };
                if k == 0 {
                    env.ctx = over;
                } else if over != env.ctx {
                    self.diags.push(
                        Diagnostic::new(
                            format!("`{}` is not over the set of the first state listed", name.name),
                            name.span,
                            "another set",
                        )
                        .hint("the states of one mass matrix are families over one set (one matrix per element), or all scalars"),
                    );
                    continue;
                }
                if let (Some(set), Some(e)) = (over, elem) {
                    env.binders.push(Binding {
                        name: e.name.clone(),
                        set,
                        via: Via::Here,
                    });
                }
                for c in 0..dim {
                    if listed.first_time(first + c, name, &mut self.diags) {
                        ids.push(StateId::new(first + c));
                    }
                }
            }
            if self.diags.len() > before {
                continue;
            }
            if !check_shape(ids.len(), rows, *span, &mut self.diags) {
                continue;
            }
            let mut entries = Vec::new();
            let mut entry_spans = Vec::new();
            for e in rows.iter().flatten() {
                let Some(v) = self.expr(e, &env) else {
                    continue;
                };
                if v.dim() != 1 || v.ty == Ty::Bool {
                    self.diags.push(
                        Diagnostic::new(
                            format!("a mass matrix entry is {}", v.ty.words()),
                            e.span,
                            "not a number",
                        )
                        .hint("each entry is one number: a vector state lists its components as rows and columns of their own"),
                    );
                    continue;
                }
                entries.extend(v.comps);
                entry_spans.push(e.span);
            }
            if self.diags.len() == before {
                out.push(MassDef {
                    states: ids,
                    entries,
                    entry_spans,
                    span: *span,
                });
            }
        }
        out
    }

    /// The first component, dimension and set of the state `name` listed in a mass
    /// matrix at the element `elem` (which a family must name and a scalar must not).
    fn mass_state(
        &mut self,
        name: &Ident,
        elem: Option<&Ident>,
    ) -> Option<(usize, usize, Option<crate::SetId>)> {
        let text = name.name.as_str();
        let entry = self.state_named(name)?;
        match (entry.over, elem) {
            (Some(set), None) => {
                let s = &self.sets[set.index()];
                self.diags.push(
                    Diagnostic::new(
                        format!("`{text}` is a family over `{}`", s.name),
                        name.span,
                        "which element?",
                    )
                    .hint(format!(
                        "name the element: `mass [{text}[{}]] = ...;`",
                        s.elem
                    )),
                );
                None
            }
            (None, Some(e)) => {
                self.diags.push(
                    Diagnostic::new(
                        format!("`{text}[{}]`: `{text}` is not a family", e.name),
                        e.span,
                        "no element",
                    )
                    .hint(format!("write `{text}` alone")),
                );
                None
            }
            _ => Some((entry.first, entry.dim as usize, entry.over)),
        }
    }
}
