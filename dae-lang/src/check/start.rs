//! The initial point of a model that uses nothing of version 2, checked as it is
//! written: one constraint per algebraic unknown, every parameter default and initial
//! value finite, and every operation of the equations finite at the start
//! (`check::domain`). A model over sets is checked by its construction at the default
//! sizes instead (`crate::family::check_at_default_sizes`).

use super::{Checker, Component, Kind};
use crate::check::domain::{self, Named, Start};
use crate::check::eval::eval;
use crate::check::{count_mismatch, named_constraints, not_finite};
use crate::model::RExpr;

impl Checker<'_> {
    /// The checks of the start; `params`, `states` and `algs` are the resolved values
    /// (`None` where one is in error, already reported). The parameters' values.
    pub(super) fn check_start(
        &mut self,
        params: &[Option<RExpr>],
        states: &[Option<RExpr>],
        algs: &[Option<RExpr>],
    ) -> Vec<Option<f64>> {
        let m = self.m;
        let constraints = named_constraints(m).count();
        if self.algs.len() != constraints {
            self.diags
                .push(count_mismatch(m, self.algs.len(), constraints));
        }
        // Each default may use the ones before it.
        let mut values: Vec<Option<f64>> = Vec::with_capacity(params.len());
        for (c, e) in self.params.iter().zip(params) {
            let v = e.as_ref().and_then(|e| eval(e, &values));
            let v = v.filter(|v| {
                if !v.is_finite() {
                    let what = format!("the default of parameter `{}`", c.decl.name.name);
                    self.diags.push(not_finite(&what, *v, c.decl));
                }
                v.is_finite()
            });
            values.push(v);
        }
        let diags = &mut self.diags;
        let mut initial = |comps: &[Component<'_>], exprs: &[Option<RExpr>]| {
            comps
                .iter()
                .zip(exprs)
                .map(|(c, e)| {
                    let v = eval(e.as_ref()?, &values)?;
                    if !v.is_finite() {
                        let what = format!("the initial value of `{}`", c.decl.name.name);
                        diags.push(not_finite(&what, v, c.decl));
                    }
                    Some(v)
                })
                .collect::<Vec<Option<f64>>>()
        };
        let start = Start {
            params: &values,
            states: initial(&self.states, states),
            algs: initial(&self.algs, algs),
        };
        if !self.diags.is_empty() || !self.at_start {
            return values;
        }
        let table = &self.names;
        let names = |n: &str| {
            let e = table.get(n)?;
            Some(match e.kind {
                Kind::Param => Named::Param(e.first),
                Kind::State => Named::State(e.first),
                Kind::Alg => Named::Alg(e.first),
                Kind::Let => Named::Let(e.first),
                _ => return None,
            })
        };
        domain::check(m, &names, start, &self.lets, &mut self.diags);
        values
    }
}
