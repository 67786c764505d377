//! Checks at the initial point: finite values, and a well-conditioned `J_Omega`.
//!
//! The values are those of the compiled programs, the code that will run (the
//! interpreter runs exactly these, the generated Rust is printed from them), not of a
//! separate evaluator; the initial values are the construction's, which the
//! interpreter starts from and the generated code prints.

use nalgebra::DMatrix;

use super::{ConstraintAnalysis, InitialPoint, text::wname};
use crate::analysis::AnalysisOptions;
use crate::ast::Span;
use crate::compiled::CompiledModel;
use crate::diag::Diagnostic;
use crate::family::{Program, Scratch, Spec, Values, construct};
use crate::model::Model;

/// What the initial point showed, for the [`super::Analysis`].
pub(super) struct AtInitial {
    pub point: InitialPoint,
    pub jacobian: Vec<f64>,
    pub condition_number: f64,
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
    model: &Model,
    constraints: &[ConstraintAnalysis],
    compiled: &CompiledModel,
    opts: &AnalysisOptions,
) -> Result<AtInitial, Vec<Diagnostic>> {
    let mut errors = Vec::new();
    let m = model.algs.len();
    let params: Vec<f64> = compiled.params.iter().map(|p| p.1).collect();
    // The construction evaluates the initial values (and refuses one that is not
    // finite, or that reads anything but parameters), as the interpreter and the
    // generated code do.
    let inst = construct(&compiled.programs.construction, &Spec::default())
        .map_err(|e| vec![e.to_diagnostic()])?;
    let (states, algs) = (inst.states.clone(), inst.algs.clone());
    let no_mu = vec![f64::NAN; m];
    let l = &inst.layout;
    // `mu` is not part of the initial point: it enters only `s` and `alpha_hat`, which
    // are not checked here.
    let zero_rates = vec![0.0; l.n_algs];
    let run = |p: &Program, alg_rates: &[f64], outs: &mut [&mut [f64]]| {
        let at = Values {
            params: &inst.params,
            states: &states,
            algs: &algs,
            alg_rates,
            mu: &no_mu,
            inputs: &[],
            t: 0.0,
        };
        p.eval(&inst, &at, &mut Scratch::new(p, &inst), outs);
    };
    let p = &compiled.programs;
    let mut f = vec![0.0; l.n_states];
    run(&p.rhs, &[], &mut [&mut f]);
    for (k, d) in model.ders.iter().enumerate() {
        let v = f[l.states[k].offset];
        if !v.is_finite() {
            let name = &compiled.states[k];
            errors.push(non_finite(d.span, format!("der({name})"), v));
        }
    }
    let (mut w, mut s, mut alpha_hat) = (vec![0.0; l.n_w], vec![0.0; m], vec![0.0; m]);
    run(&p.sliding, &[], &mut [&mut w, &mut s, &mut alpha_hat]);
    let pattern = &inst.jacobian.entries;
    let mut entries = vec![0.0; pattern.len()];
    run(&p.jacobian, &[], &mut [&mut entries]);
    let mut beta = vec![0.0; m];
    run(&p.rate, &zero_rates, &mut [&mut beta]);
    let mut jac = vec![0.0; m * m];
    for (&(row, col), &v) in pattern.iter().zip(&entries) {
        jac[row * m + col] = v;
    }
    for (i, c) in constraints.iter().enumerate() {
        // Report the first non-finite quantity of each constraint, in the order of the
        // derivation (w, J_Omega, beta): later ones derive from it.
        let (w_at, row) = (l.w[i].offset, l.rows[i].offset);
        let mut named: Vec<(String, f64)> = (0..c.index)
            .map(|j| (wname(&c.name, j, c.index), w[w_at + j]))
            .collect();
        for (&(_, col), &v) in pattern.iter().zip(&entries).filter(|((r, _), _)| *r == row) {
            let z = compiled.algs[col].as_str();
            named.push((format!("J({i}, {col}) = dOmega_{}/d{z}", c.name), v));
        }
        named.push((format!("beta_{}", c.name), beta[row]));
        if let Some((what, v)) = named.into_iter().find(|(_, v)| !v.is_finite()) {
            errors.push(non_finite(c.span, what, v));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let point = InitialPoint {
        params,
        states,
        algs,
    };
    let condition_number = condition(constraints, &jac, m, opts)?;
    Ok(AtInitial {
        point,
        jacobian: jac,
        condition_number,
    })
}

/// The 2-norm condition number of the `m x m` matrix `jac` (row-major), 1 for `m = 0`;
/// an error naming the dependent constraints if it is infinite or above the threshold.
fn condition(
    constraints: &[ConstraintAnalysis],
    jac: &[f64],
    m: usize,
    opts: &AnalysisOptions,
) -> Result<f64, Vec<Diagnostic>> {
    if m == 0 {
        return Ok(1.0);
    }
    let mat = DMatrix::from_row_slice(m, m, jac);
    let svd = mat.svd(true, false);
    let sv = &svd.singular_values;
    let (imin, smin) = sv.argmin();
    let smax = sv.max();
    let cond = if smin > 0.0 {
        smax / smin
    } else {
        f64::INFINITY
    };
    if cond.is_finite() && cond <= opts.condition_threshold {
        return Ok(cond);
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
        .map(|&i| format!("`{}`", constraints[i].name))
        .collect();
    let first = &constraints[involved[0]];
    let message = if smin == 0.0 || !cond.is_finite() {
        // The numerical rank at the usual tolerance of the SVD, `m eps sigma_max`.
        let rank = sv
            .iter()
            .filter(|&&v| v > m as f64 * f64::EPSILON * smax)
            .count();
        format!(
            "J_Omega is singular at the initial point: rank {rank} of {m} (constraints {})",
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
            let c = &constraints[i];
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
