//! Index analysis and realization (docs/method.md sections 1-2).
//!
//! For each constraint `g_i`: differentiate `w_i = g_i` along the flow (z held constant)
//! until an algebraic unknown appears; that derivative is `Omega_i = w_i^(r_i - 1)` and
//! `r_i` is the index. Then `J_Omega` row `i` = `dOmega_i/dz`, `beta_i = D[Omega_i]`
//! (which may contain z), and with a symbolic realization parameter `mu_i`:
//! `s_i = sum_{j<r} C(r-1, j) mu^j w^(j)`,
//! `alpha_i = mu^(r-1) beta_i + sum_{j=1}^{r-1} C(r-1, j-1) mu^(j-1) w^(j)` (corrected
//! coefficients) and the cheap `alpha_hat_i = alpha_i - mu^(r-1) beta_i`.
//! The initial values are lowered into the same arena ([`derive`]). Every function is
//! then compiled into its tape (`crate::compile`, [`CompiledModel`]), and those tapes,
//! the ones that will run, are evaluated at the initial point ([`Analysis::checked`]),
//! where non-finite values and a singular or ill-conditioned `J_Omega` are errors.

mod family;
#[cfg(any(test, feature = "fixtures"))]
pub mod fixtures;
mod init;
mod lower;
#[cfg(test)]
mod tests;
mod text;

use crate::ast::Span;
use crate::compiled::CompiledModel;
use crate::diag::Diagnostic;
use crate::model::{ConstraintDef, Model};
use crate::sym::{Arena, DiffContext, Id, Names, dep};
use crate::{AlgId, ConstraintId, MapId};

pub use lower::{Lowered, lower};

/// Options of [`analyze`](crate::analyze).
#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisOptions {
    /// Most time derivatives taken of a constraint looking for an algebraic unknown
    /// (so the largest index found is this plus one). Default 8.
    pub max_differentiations: usize,
    /// Largest accepted 2-norm condition number of `J_Omega` at the initial point.
    /// Default 1e12.
    pub condition_threshold: f64,
    /// Simplify while building (default true; false only to measure what it buys).
    pub simplify: bool,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions {
            max_differentiations: 8,
            condition_threshold: 1e12,
            simplify: true,
        }
    }
}

/// The analysis of one constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintAnalysis {
    /// The constraint's name.
    pub name: String,
    /// Where it was written.
    pub span: Span,
    /// Its index `r` (1 = an algebraic unknown appears in the constraint itself).
    pub index: usize,
    /// Names of the algebraic unknowns in `Omega` (the sparsity pattern of the row).
    pub depends_on: Vec<String>,
}

/// The expressions of one constraint's realization, in the analysis' arena.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintExprs {
    /// `w[j] = w^(j)` for `j = 0 .. r-1` (so `w[r-1]` is `Omega`).
    pub w: Vec<Id>,
    /// `Omega = w^(r-1)`, the first derivative that contains an algebraic unknown.
    pub omega: Id,
    /// The non-zero entries `(column = algebraic unknown, dOmega/dz_column)` of this row
    /// of `J_Omega`, by column (version 1; empty for a family model).
    pub jacobian_row: Vec<(AlgId, Id)>,
    /// The kernels of this constraint's rows of `J_Omega`, one per coupling (a
    /// version-1 model: one per entry of `jacobian_row`, that entry times 1).
    pub kernels: Vec<Kernel>,
    /// `beta = dOmega/dt + (dOmega/dx) f` (may contain z).
    pub beta: Id,
    /// `Omega' = beta + J_Omega z'`, the rate of `Omega` with the algebraic unknowns
    /// moving at `z'` (the leaves [`VarRef::AlgRate`](crate::VarRef::AlgRate)): the rate
    /// program's output.
    pub rate: Id,
    /// The realization parameter `mu` of this constraint (a leaf, printed `mu<i+1>`).
    pub mu: Id,
    /// Sliding surface `s`.
    pub s: Id,
    /// `alpha` in `s' = J_s v + alpha`.
    pub alpha: Id,
    /// The cheap `alpha_hat = alpha - mu^(r-1) beta`.
    pub alpha_hat: Id,
}

/// The kernel of one coupling of `J_Omega`: the rows of a constraint (over `L`) and the
/// columns of an algebraic unknown (over `K`) meet where `row_map(l) == col_map(k)`,
/// and there `dOmega(l)/dz(k) = sum of row(l) * col(k)` over the terms.
#[derive(Clone, Debug, PartialEq)]
pub struct Kernel {
    /// The algebraic unknown of the columns.
    pub alg: AlgId,
    /// From the constraint's set to the meeting set.
    pub row_map: MapId,
    /// From the unknown's set to the meeting set.
    pub col_map: MapId,
    /// `(row factor, column factor)` of each term.
    pub terms: Vec<(Id, Id)>,
}

/// A model and its realization as expressions in one arena: what `daec derive` prints
/// and what the tapes are emitted from.
#[derive(Clone, Debug)]
pub struct SymbolicModel {
    /// The arena holding every expression below.
    pub arena: Arena,
    /// Names for printing.
    pub names: Names,
    /// `f[k]`: right-hand side of `der(x_k)`.
    pub f: Vec<Id>,
    /// Nodes of the lets.
    pub lets: Vec<Id>,
    /// Names of the lets (same order).
    pub let_names: Vec<String>,
    /// One entry per constraint, in declaration order.
    pub constraints: Vec<ConstraintExprs>,
}

/// The values at the initial point (default parameters, initial states and algebraic
/// guesses, `t = 0`).
#[derive(Clone, Debug, PartialEq)]
pub struct InitialPoint {
    /// Parameter defaults.
    pub params: Vec<f64>,
    /// Initial states.
    pub states: Vec<f64>,
    /// Initial algebraic guesses.
    pub algs: Vec<f64>,
}

/// The result of [`analyze`](crate::analyze).
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The model's name.
    pub model_name: String,
    /// One entry per constraint, in declaration order.
    pub constraints: Vec<ConstraintAnalysis>,
    /// The initial point everything was checked at.
    pub initial: InitialPoint,
    /// `J_Omega` at the initial point, row-major, constraints x algebraic unknowns.
    pub jacobian_at_initial: Vec<f64>,
    /// Its 2-norm condition number (1 for a model without constraints).
    pub condition_number: f64,
    pub(crate) symbolic: SymbolicModel,
    pub(crate) compiled: CompiledModel,
}

impl Analysis {
    /// The indices `r_i`, in constraint order.
    pub fn indices(&self) -> Vec<usize> {
        self.constraints.iter().map(|c| c.index).collect()
    }

    /// The expressions the analysis built (the arena, the realization of every
    /// constraint). Internal representation: feature `internals`.
    #[cfg(any(test, feature = "internals"))]
    pub fn symbolic(&self) -> &SymbolicModel {
        &self.symbolic
    }
}

/// Binomial coefficient `C(n, k)` as a float (exact for the small n used here).
fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64)
}

/// The derivation of a checked model: index, `J_Omega` (a row per constraint, or the
/// kernels of a family model), `beta`, `s`, `alpha`, `alpha_hat`, in one arena. Every
/// problem found is returned, each as a diagnostic with the span of the item concerned.
/// The compiled form and the checks at the initial point follow ([`Analysis::checked`]).
pub(crate) fn derive(
    model: &Model,
    opts: &AnalysisOptions,
) -> Result<(Vec<ConstraintAnalysis>, SymbolicModel), Vec<Diagnostic>> {
    let is_family = model.is_family();
    let Lowered {
        mut arena,
        f,
        g,
        lets,
    } = lower(model, opts.simplify);
    let mut derivatives = DiffContext::new(f.clone());
    let names = Names::from_model(model);
    let mut errors = Vec::new();
    let mut summaries = Vec::with_capacity(g.len());
    let mut exprs = Vec::with_capacity(g.len());
    for (i, (&gi, def)) in g.iter().zip(&model.constraints).enumerate() {
        match index_of(&mut arena, &mut derivatives, gi, opts.max_differentiations) {
            Ok(w) => match realize(&mut arena, &mut derivatives, &names, i, def, w, is_family) {
                Ok((summary, e)) => {
                    summaries.push(summary);
                    exprs.push(e);
                }
                Err(d) => errors.push(d),
            },
            Err(kind) => errors.push(no_index(&arena, &names, model, i, gi, kind, opts)),
        }
    }
    // A family model's counts are checked per set, at the default sizes, by the checker.
    if !is_family && model.algs.len() != model.constraints.len() {
        let (n, m) = (model.algs.len(), model.constraints.len());
        let message = format!("{n} algebraic unknowns but {m} constraints");
        errors.push(
            Diagnostic::new(message, model.span, "J_Omega must be square")
                .hint("declare exactly one constraint per `alg` variable"),
        );
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    // Initial values are the construction's (evaluated by `crate::family::construct`,
    // at the default sizes here), not lowered.
    if !is_family {
        scalar_programs_exprs(&mut arena, &mut derivatives, model, &mut exprs);
    }
    let symbolic = SymbolicModel {
        arena,
        names,
        f,
        lets,
        let_names: model.lets.iter().map(|l| l.name.clone()).collect(),
        constraints: exprs,
    };
    if is_family {
        family::check_inputs(model, &summaries, &symbolic)?;
    }
    Ok((summaries, symbolic))
}

impl Analysis {
    /// The analysis of `model` from its derivation and its compiled form: for a
    /// version-1 model the programs that will run are evaluated at the initial point, where
    /// non-finite values and a singular or ill-conditioned `J_Omega` are errors. A
    /// family model's initial point needs an instance and is checked at construction
    /// (the runtime), so `initial` and `jacobian_at_initial` are empty and
    /// `condition_number` NaN.
    pub(crate) fn checked(
        model: &Model,
        constraints: Vec<ConstraintAnalysis>,
        symbolic: SymbolicModel,
        compiled: CompiledModel,
        opts: &AnalysisOptions,
    ) -> Result<Analysis, Vec<Diagnostic>> {
        let (initial, jacobian_at_initial, condition_number) = if compiled.is_family() {
            let empty = InitialPoint {
                params: Vec::new(),
                states: Vec::new(),
                algs: Vec::new(),
            };
            (empty, Vec::new(), f64::NAN)
        } else {
            let at = init::check_initial_point(model, &constraints, &compiled, opts)?;
            (at.point, at.jacobian, at.condition_number)
        };
        Ok(Analysis {
            model_name: model.name.clone(),
            constraints,
            initial,
            jacobian_at_initial,
            condition_number,
            symbolic,
            compiled,
        })
    }
}

/// Why a constraint has no index.
enum NoIndex {
    /// `w^(j)` does not depend on any state, `t` or algebraic unknown.
    Constant(usize),
    /// No algebraic unknown after the maximum number of derivatives.
    TooMany,
}

/// `w^(0..r)` up to the first that contains an algebraic unknown.
fn index_of(
    arena: &mut Arena,
    derivatives: &mut DiffContext,
    g: Id,
    max: usize,
) -> Result<Vec<Id>, NoIndex> {
    let mut w = vec![g];
    loop {
        let last = *w.last().expect("w starts with g");
        if arena.has_alg(last) {
            return Ok(w);
        }
        if !arena.has_state_or_time(last) {
            return Err(NoIndex::Constant(w.len() - 1));
        }
        if w.len() > max {
            return Err(NoIndex::TooMany);
        }
        w.push(derivatives.dt(arena, last));
    }
}

/// The realization of constraint `i` (`def`) from its derivatives `w`: for a family
/// model `J_Omega` as kernels and `Omega'` too (the rate program), for a version-1
/// model `J_Omega` as the entries of its row.
fn realize(
    arena: &mut Arena,
    derivatives: &mut DiffContext,
    names: &Names,
    i: usize,
    def: &ConstraintDef,
    w: Vec<Id>,
    is_family: bool,
) -> Result<(ConstraintAnalysis, ConstraintExprs), Diagnostic> {
    let r = w.len();
    let omega = w[r - 1];
    let cols = arena.algs_in(omega);
    let (jacobian_row, kernels) = if is_family {
        (
            Vec::new(),
            family::kernels(arena, names, def, omega, &cols)?,
        )
    } else {
        (jacobian_row(arena, derivatives, omega, &cols), Vec::new())
    };
    let beta = derivatives.dt(arena, omega);
    // A version-1 model's `Omega'` is derived last (`scalar_programs_exprs`).
    let rate = if is_family {
        derivatives.dt_moving(arena, omega)
    } else {
        omega
    };
    let mu = arena.mu(ConstraintId::new(i));
    let (s, alpha, alpha_hat) = sliding_exprs(arena, &w, beta, mu);
    let summary = ConstraintAnalysis {
        name: def.name.clone(),
        span: def.span,
        index: r,
        depends_on: cols.iter().map(|&k| alg_name(names, k)).collect(),
    };
    let exprs = ConstraintExprs {
        w,
        omega,
        jacobian_row,
        kernels,
        beta,
        rate,
        mu,
        s,
        alpha,
        alpha_hat,
    };
    Ok((summary, exprs))
}

/// What the programs of a version-1 model need beyond the derivation: `Omega'` of every
/// constraint and its row of `J_Omega` as kernels of one term each (the entry times 1,
/// rows and columns meeting in the unit). Built after everything the derivation text
/// reads, so that its nodes keep their ids.
fn scalar_programs_exprs(
    arena: &mut Arena,
    derivatives: &mut DiffContext,
    model: &Model,
    exprs: &mut [ConstraintExprs],
) {
    let one = arena.num(1.0);
    let unit = arena.maps_mut().identity(None, model.span);
    for e in exprs {
        e.rate = derivatives.dt_moving(arena, e.omega);
        e.kernels = e
            .jacobian_row
            .iter()
            .map(|&(alg, entry)| Kernel {
                alg,
                row_map: unit,
                col_map: unit,
                terms: vec![(entry, one)],
            })
            .collect();
    }
}

/// The non-zero entries `(k, dOmega/dz_k)` of a row of `J_Omega`.
fn jacobian_row(
    arena: &mut Arena,
    derivatives: &mut DiffContext,
    omega: Id,
    cols: &[AlgId],
) -> Vec<(AlgId, Id)> {
    let mut row = Vec::with_capacity(cols.len());
    for &k in cols {
        let z = arena.alg(k);
        let d = derivatives.diff(arena, omega, z);
        if arena.as_const(d) != Some(0.0) {
            row.push((k, d));
        }
    }
    row
}

/// `s`, `alpha` and `alpha_hat` of a constraint from its derivatives `w`, `beta` and its
/// realization parameter `mu`.
fn sliding_exprs(arena: &mut Arena, w: &[Id], beta: Id, mu: Id) -> (Id, Id, Id) {
    let r = w.len();
    let mu_pow = |arena: &mut Arena, j: usize| arena.powf(mu, j as f64);
    // s = sum_{j=0}^{r-1} C(r-1, j) mu^j w^(j)
    let mut s_terms = Vec::with_capacity(r);
    for (j, &wj) in w.iter().enumerate() {
        let m = mu_pow(arena, j);
        s_terms.push((arena.mul(m, wj), binomial(r - 1, j)));
    }
    let s = arena.lin(0.0, &s_terms);
    // alpha_hat = sum_{j=1}^{r-1} C(r-1, j-1) mu^(j-1) w^(j); alpha = mu^(r-1) beta + alpha_hat
    let mut a_terms = Vec::with_capacity(r);
    for (j, &wj) in w.iter().enumerate().skip(1) {
        let m = mu_pow(arena, j - 1);
        a_terms.push((arena.mul(m, wj), binomial(r - 1, j - 1)));
    }
    let alpha_hat = arena.lin(0.0, &a_terms);
    let m = mu_pow(arena, r - 1);
    let mb = arena.mul(m, beta);
    let alpha = arena.add(mb, alpha_hat);
    (s, alpha, alpha_hat)
}

/// The name of a declaration's family: `pin` for the component `pin.x` (a version-1
/// name has no component).
fn family_name(name: &str) -> String {
    name.split('.').next().unwrap_or(name).to_string()
}

/// The name of an algebraic unknown's family.
fn alg_name(names: &Names, k: AlgId) -> String {
    family_name(&names.var(crate::VarRef::Alg(k)))
}

fn no_index(
    arena: &Arena,
    names: &Names,
    model: &Model,
    i: usize,
    g: Id,
    kind: NoIndex,
    opts: &AnalysisOptions,
) -> Diagnostic {
    let def = &model.constraints[i];
    let vars: Vec<String> = arena
        .leaves_in(g, dep::STATE | dep::TIME | dep::PARAM)
        .into_iter()
        .map(|l| arena.display(l, names))
        .collect();
    let vars = if vars.is_empty() {
        "no variables".to_string()
    } else {
        vars.join(", ")
    };
    let (message, hint) = match kind {
        NoIndex::Constant(0) => (
            format!("constraint `{}` does not depend on any state, algebraic unknown or t", def.name),
            "a constraint must restrict the motion: make it depend on the states".to_string(),
        ),
        NoIndex::Constant(j) => (
            format!(
                "constraint `{}` has no index: its time derivative {j} is constant, so no algebraic unknown ever appears",
                def.name
            ),
            "the algebraic unknowns must drive the states this constraint depends on (through some `der`)".to_string(),
        ),
        NoIndex::TooMany => (
            format!(
                "constraint `{}` has no index: no algebraic unknown appears after {} time derivatives",
                def.name, opts.max_differentiations
            ),
            "the algebraic unknowns must drive the states this constraint depends on (through some `der`)".to_string(),
        ),
    };
    Diagnostic::new(message, def.span, format!("depends on {vars}")).hint(hint)
}
