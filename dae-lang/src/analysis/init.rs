//! Checks at the initial point: finite values, and a well-conditioned `J_Omega`.

use nalgebra::DMatrix;

use super::{Analysis, AnalysisOptions, InitialPoint, lower::lower_expr, text::wname};
use crate::ast::Span;
use crate::diag::Diagnostic;
use crate::model::{Model, VarDef};
use crate::sym::{Id, Point};

/// Evaluate the initial values of states or algebraic unknowns (expressions over params).
fn initial_values(
    a: &mut Analysis,
    defs: &[VarDef],
    params: &[f64],
    what: &str,
    errors: &mut Vec<Diagnostic>,
) -> Vec<f64> {
    let ids: Vec<Id> = defs
        .iter()
        .map(|d| lower_expr(&mut a.arena, &[], &d.init))
        .collect();
    let p = Point {
        params,
        ..Point::default()
    };
    let mut buf = Vec::new();
    a.arena.eval_all(&p, &mut buf);
    ids.iter()
        .zip(defs)
        .map(|(id, d)| {
            let v = buf[id.index()];
            if !v.is_finite() {
                errors.push(Diagnostic {
                    message: format!("the {what} of `{}` is {v}", d.name),
                    span: d.span,
                    label: "not a finite number".into(),
                    hint: Some("initial values must be finite; check the parameters used".into()),
                    related: vec![],
                });
            }
            v
        })
        .collect()
}

fn non_finite(span: Span, what: String, v: f64) -> Diagnostic {
    Diagnostic {
        message: format!("{what} is {v} at the initial point"),
        span,
        label: "not finite at t = 0 with the initial states and guesses".into(),
        hint: Some(
            "check for a division by zero or a function outside its domain (sqrt, ln, asin) at the initial values"
                .into(),
        ),
        related: vec![],
    }
}

pub(super) fn check_initial_point(
    a: &mut Analysis,
    model: &Model,
    opts: &AnalysisOptions,
) -> Result<(), Vec<Diagnostic>> {
    let mut errors = Vec::new();
    let params: Vec<f64> = model.params.iter().map(|p| p.default).collect();
    let states = initial_values(a, &model.states, &params, "initial value", &mut errors);
    let algs = initial_values(a, &model.algs, &params, "initial guess", &mut errors);
    if !errors.is_empty() {
        return Err(errors);
    }
    let p = Point {
        params: &params,
        states: &states,
        algs: &algs,
        t: 0.0,
        mu: &[],
    };
    let mut v = Vec::new();
    a.arena.eval_all(&p, &mut v);
    let val = |id: Id| v[id.index()];
    for (k, (&fk, d)) in a.f.iter().zip(&model.ders).enumerate() {
        if !val(fk).is_finite() {
            let name = a.names.states.get(k).cloned().unwrap_or_default();
            errors.push(non_finite(d.span, format!("der({name})"), val(fk)));
        }
    }
    let m = a.constraints.len();
    let n = model.algs.len();
    let mut jac = vec![0.0; m * n];
    for (i, c) in a.constraints.iter().enumerate() {
        // Report the first non-finite quantity of each constraint: later ones derive from it.
        let mut named: Vec<(String, Id)> =
            c.w.iter()
                .enumerate()
                .map(|(j, &w)| (wname(&c.name, j, c.index), w))
                .collect();
        for &(k, id) in c.jacobian_row.iter().filter(|(k, _)| k.index() < n) {
            let z = super::alg_name(&a.names, k);
            let col = k.index();
            named.push((format!("J({i}, {col}) = dOmega_{}/d{z}", c.name), id));
            jac[i * n + col] = val(id);
        }
        named.push((format!("beta_{}", c.name), c.beta));
        if let Some((what, id)) = named.into_iter().find(|(_, id)| !val(*id).is_finite()) {
            errors.push(non_finite(c.span, what, val(id)));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    a.initial = InitialPoint {
        params,
        states,
        algs,
    };
    a.jacobian_at_initial = jac;
    if m == 0 {
        return Ok(());
    }
    let mat = DMatrix::from_row_slice(m, n, &a.jacobian_at_initial);
    let svd = mat.svd(true, false);
    let sv = &svd.singular_values;
    let (imin, smin) = sv.argmin();
    let smax = sv.max();
    let cond = if smin > 0.0 {
        smax / smin
    } else {
        f64::INFINITY
    };
    a.condition_number = cond;
    if cond.is_finite() && cond <= opts.condition_threshold {
        return Ok(());
    }
    // Rows with large components in the left singular vector of the smallest singular value
    // are the constraints whose rows are (nearly) dependent.
    let u = svd
        .u
        .as_ref()
        .expect("svd computed with u")
        .column(imin)
        .into_owned();
    let umax = u.amax();
    let involved: Vec<usize> = (0..m).filter(|&i| u[i].abs() >= 0.1 * umax).collect();
    let names: Vec<String> = involved
        .iter()
        .map(|&i| format!("`{}`", a.constraints[i].name))
        .collect();
    let first = &a.constraints[involved[0]];
    let message = if smin == 0.0 || !cond.is_finite() {
        format!(
            "J_Omega is singular at the initial point (constraints {})",
            names.join(", ")
        )
    } else {
        format!(
            "J_Omega is ill-conditioned at the initial point: condition number {cond:.3e} > {:.1e} (constraints {})",
            opts.condition_threshold,
            names.join(", ")
        )
    };
    let related = involved[1..]
        .iter()
        .map(|&i| {
            let c = &a.constraints[i];
            (
                c.span,
                format!("`{}` is part of the same dependent combination", c.name),
            )
        })
        .collect();
    Err(vec![Diagnostic {
        message,
        span: first.span,
        label: format!(
            "the rows of J_Omega = dOmega/dz of these constraints are (nearly) dependent (condition number {cond:.3e})"
        ),
        hint: Some(
            "remove duplicated or redundant constraints, or start from a configuration where they are independent"
                .into(),
        ),
        related,
    }])
}
