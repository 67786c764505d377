//! The compiled form of family models (language version 2), and what runs it.
//!
//! A family model is compiled once, as templates, whatever its sizes: a
//! [`CompiledModel`](crate::CompiledModel) whose `programs` are a [`FamilyModel`] (a
//! model without sets has one too, whose programs are one group each, run once):
//!
//! * the [`Construction`]: sizes, sets, maps, parameters, initial values, inputs, the
//!   constraint families with their indices, the incidence checks and the
//!   [`Coupling`]s of `J_Omega`: everything construction needs to build an
//!   [`Instance`] at given sizes ([`construct`]: the reference, with every check that
//!   needs sizes);
//! * four [`Program`]s for the evaluation functions of the runtime's `Model` trait
//!   (`rhs`, `sliding`, `jacobian`, and `rate` for `omega_rate` and `beta`:
//!   `Omega' = beta + J_Omega z'` without `J_Omega`, `beta` at `z' = 0`): groups of
//!   straight-line code run once or once per element of a set, reading the model's vectors at element paths, with
//!   gathers, scatter-adds and the kernel loops of `J_Omega`. [`Program::eval`] is the
//!   vectorised interpreter (each instruction over chunks of elements).
//!
//! The layout of the runtime's vectors is [`Layout`]. A model without sets is the case
//! whose groups run once; its initial values, like every model's, are the
//! construction's ([`Construction`]).
//!
//! [`expand`] is the oracle of the tests: a family model at given sizes and maps
//! written out as the equivalent scalar (version-1) model.
//!
//! # What a back end does with it
//!
//! At construction (once per instance): [`construct`] (or the same steps in the
//! runtime, see its documentation for the order and the checks, each reported with the
//! span of the declaration concerned, which [`crate::line_col`] turns into a line and
//! column), giving set sizes, every map as an array, the [`Layout`], the parameter
//! vector, the initial states and algebraic guesses, the default input values and the
//! [`JacobianPattern`] (entries and, per coupling, the `[entry, l, k]` lists). Names of
//! the instance's slots are built from the component names: `x.y` over `P` at element
//! 3 is `x[3].y`, constraint `link` at element 7 is `link[7]`.
//!
//! At every evaluation: each [`Program`] as its documentation says, reading the vectors
//! at the layout's slots (inputs: the current values and derivatives of every input, in
//! the layout's input value vector; the runtime evaluates them, e.g. from the caller's
//! Taylor data `set_input(i, t0, [value, d1, ..])`, before calling). [`Program::eval`]
//! is the interpreter; a code generator emits one loop per group.
//!
//! # Construction-time expressions
//!
//! Set sizes, map formulas, parameter values, initial values and input defaults are
//! [`RExpr`]s evaluated per element `e` of the declaration's set (element 0 for a
//! scalar) with integer, real and condition values, typed as the checker typed them:
//!
//! * `Num(v)`: an integer when `v` is a whole number, else a real;
//! * `Var(Size(s))`: the size's value (integer); `Var(Elem(S))`: `e` (integer);
//!   `Var(Param(p))`: the parameter's value at `e` (its only value for a scalar
//!   parameter; parameters are evaluated in declaration order and read only earlier
//!   ones);
//! * `Gather(m, x)`: `x` evaluated at element `maps[m][e]`;
//! * `Neg`, `Binary(+ - *)`: exact on two integers (`i64`; an overflow is a construction
//!   error), real otherwise; `/` and `^` are real; `Call(f, ..)` real, except `min`,
//!   `max` and `abs` of integers, which stay integers;
//! * `Int(Div | Mod, a, b)`: floor division and modulo of integers (the result of `mod`
//!   has the sign of `b`); a zero divisor is a construction error;
//! * `Compare`: a condition (integers compare exactly, anything else as reals);
//!   `Logic(and | or)`, `Not`: conditions; `If(c, a, b)`: `a` where `c` holds, else `b`.
//!
//! A map's values must be integers in `0 .. |codomain|`; every other value must be a
//! finite number.

mod ceval;
mod construct;
mod eval;
mod expand;
mod layout;
mod program;
mod schedule;

pub(crate) use schedule::compile;

pub use construct::{AssignError, ConstructError, Instance, JacobianPattern, Spec, construct};
pub use eval::{Scratch, Values};
pub use expand::{Expanded, expand};
pub use layout::{Layout, Slot};
pub use program::{ArrayDef, Dest, EntryLoop, Factor, Group, Program, Sink};

use crate::ast::Span;
use crate::diag::Diagnostic;
use crate::model::{InputDef, MapDef, MapKind, Model, ParamDef, RExpr, SetDef, SizeDef, VarDef};
use crate::{AlgId, ConstraintId, MapId, SetId};

/// A constraint family (or a single constraint) of the compiled form.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintInfo {
    /// Name.
    pub name: String,
    /// Its set (`None`: one constraint).
    pub over: Option<SetId>,
    /// Its index `r` (the same for every element).
    pub index: usize,
    /// The declaration.
    pub span: Span,
}

/// A construction-time check: every element of `set` is the image of some element under
/// one of `maps` (the maps of the incidence sums over `set`: a particle in no link is an
/// error).
#[derive(Clone, Debug, PartialEq)]
pub struct Incidence {
    /// The set whose elements must be reached.
    pub set: SetId,
    /// The maps of the sums into it.
    pub maps: Vec<MapId>,
    /// The first declaration that sums into it.
    pub span: Span,
}

/// A coupling of `J_Omega`: the block of rows of a constraint family (over `L`, or one
/// row) and the columns of an algebraic unknown (over `K`, or one column) has an entry
/// `(l, k)` exactly where `row_map(l) == col_map(k)` (maps `L -> X`, `K -> X`, into the
/// same set or the unit). Its value is the sum of the kernel terms `R(l) * C(k)` of the
/// coupling (the jacobian program's [`EntryLoop`]). Two couplings may share entries
/// (their values add); e.g. the four couplings `a==a, a==b, b==a, b==b` of a particle
/// model's link family.
#[derive(Clone, Debug, PartialEq)]
pub struct Coupling {
    /// The constraint family of the rows.
    pub constraint: ConstraintId,
    /// The algebraic unknown of the columns.
    pub alg: AlgId,
    /// From the constraint's set (or the unit) to `X`.
    pub row_map: MapId,
    /// From the unknown's set (or the unit) to `X`.
    pub col_map: MapId,
}

/// What construction needs: the declarations of a family model (vectors expanded into
/// component families) with their construction-time expressions ([`RExpr`], evaluated as
/// [`construct`] documents).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Construction {
    /// Sizes with their defaults.
    pub sizes: Vec<SizeDef>,
    /// Sets with their size formulas (or given).
    pub sets: Vec<SetDef>,
    /// Every map the programs and couplings use (named, made by the checker, made by the
    /// analysis), by `MapId`.
    pub maps: Vec<MapDef>,
    /// Parameter components, by `ParamId`, with their value expressions.
    pub params: Vec<ParamDef>,
    /// State components with their initial values.
    pub states: Vec<VarDef>,
    /// Algebraic components with their initial guesses.
    pub algs: Vec<VarDef>,
    /// Input components with their defaults and derivative counts.
    pub inputs: Vec<InputDef>,
    /// Constraint families with their indices (0 before the analysis).
    pub constraints: Vec<ConstraintInfo>,
    /// The incidence checks.
    pub incidence: Vec<Incidence>,
    /// The couplings of `J_Omega` (empty before the analysis).
    pub couplings: Vec<Coupling>,
}

impl Construction {
    /// The construction of a checked model (no indices or couplings yet).
    pub fn from_model(m: &Model) -> Construction {
        let mut incidence: Vec<Incidence> = Vec::new();
        let mut note = |e: &RExpr, span: Span| {
            e.visit(&mut |x| {
                if let RExpr::Sum(map, _) = x {
                    let def = &m.maps[map.index()];
                    if let (Some(set), false) = (def.codomain, def.kind == MapKind::ToUnit) {
                        match incidence.iter_mut().find(|i| i.set == set) {
                            Some(i) if !i.maps.contains(map) => i.maps.push(*map),
                            Some(_) => {}
                            None => incidence.push(Incidence {
                                set,
                                maps: vec![*map],
                                span,
                            }),
                        }
                    }
                }
            })
        };
        for d in &m.ders {
            note(&d.expr, d.span);
        }
        for l in &m.lets {
            note(&l.expr, l.span);
        }
        for c in &m.constraints {
            note(&c.residual, c.span);
        }
        Construction {
            sizes: m.sizes.clone(),
            sets: m.sets.clone(),
            maps: m.maps.clone(),
            params: m.params.clone(),
            states: m.states.clone(),
            algs: m.algs.clone(),
            inputs: m.inputs.clone(),
            constraints: m
                .constraints
                .iter()
                .map(|c| ConstraintInfo {
                    name: c.name.clone(),
                    over: c.over,
                    index: 0,
                    span: c.span,
                })
                .collect(),
            incidence,
            couplings: Vec::new(),
        }
    }

    /// Whether every set's size has a formula and no map is given: then the construction
    /// at the default sizes needs nothing from the caller.
    pub fn self_contained(&self) -> bool {
        self.sets.iter().all(|s| s.size.is_some())
            && self.maps.iter().all(|m| m.kind != MapKind::Given)
    }
}

/// The compiled form of a family model; see the module documentation.
#[derive(Clone, Debug, PartialEq)]
pub struct FamilyModel {
    /// Everything construction needs.
    pub construction: Construction,
    /// `f(t, x, z)`: writes `dx` (output 0).
    pub rhs: Program,
    /// Writes `w` (output 0), `s` (output 1) and the cheap `alpha_hat` (output 2).
    pub sliding: Program,
    /// Writes the values of `J_Omega` at the instance's pattern (output 0).
    pub jacobian: Program,
    /// Writes `Omega' = beta + J_Omega z'` (output 0), the rate of `Omega` with the
    /// algebraic unknowns moving at `z' =` [`Values::alg_rates`]: the derivative of
    /// `Omega` along the motion (the walk of `beta` with `D[z] = z'`), so that
    /// `J_Omega z'` comes out in the form of `Omega`'s own terms (an incidence sum over
    /// links stays one sum) and costs about what `beta` costs, without `J_Omega`'s
    /// entry per pair of unknowns. With `z' = 0` it is `beta`: one program serves both
    /// (a separate `beta` program cost as much code again).
    pub rate: Program,
}

impl FamilyModel {
    /// The programs with their names, in the order of the `Model` trait.
    pub fn programs(&self) -> [(&'static str, &Program); 4] {
        [
            ("rhs", &self.rhs),
            ("sliding", &self.sliding),
            ("jacobian", &self.jacobian),
            ("rate", &self.rate),
        ]
    }
}

/// The checks of construction at the default sizes, run by the checker: when the model
/// needs nothing from the caller, the whole construction (a set without elements, a map
/// pointing outside its set, a non-finite value, a particle in no link, a count
/// mismatch); otherwise the sizes of the sets that have a formula. Fills in the default
/// of every scalar parameter that can be evaluated.
pub(crate) fn check_at_default_sizes(m: &mut Model, diags: &mut Vec<Diagnostic>) {
    let c = Construction::from_model(m);
    if c.self_contained() {
        match construct(&c, &Spec::default()) {
            Ok(inst) => {
                for (p, slot) in m.params.iter_mut().zip(&inst.layout.params) {
                    if p.family.over.is_none() {
                        p.default = inst.params[slot.offset];
                    }
                }
            }
            Err(e) => diags.push(e.diagnostic("with the default sizes")),
        }
        return;
    }
    // Sets given at construction: check what does not depend on them.
    let sizes: Vec<i64> = c.sizes.iter().map(|s| s.default).collect();
    let names: Vec<String> = c.sets.iter().map(|s| s.name.clone()).collect();
    let no_sets: Vec<Option<usize>> = vec![None; c.sets.len()];
    let mut maps = vec![None; c.maps.len()];
    let mut scalars: Vec<Vec<f64>> = Vec::new();
    for (i, p) in m.params.iter_mut().enumerate() {
        let mut env = ceval::Env {
            sizes: &sizes,
            set_sizes: &no_sets,
            map_defs: &c.maps,
            maps: &mut maps,
            params: &scalars,
            set_names: &names,
        };
        let v = if p.family.over.is_none() {
            env.eval(&c.params[i].value, 0)
                .map(|v| v.real())
                .unwrap_or(f64::NAN)
        } else {
            f64::NAN
        };
        p.default = v;
        scalars.push(vec![v]);
    }
    for s in &c.sets {
        let Some(f) = &s.size else { continue };
        let mut env = ceval::Env {
            sizes: &sizes,
            set_sizes: &no_sets,
            map_defs: &c.maps,
            maps: &mut maps,
            params: &[],
            set_names: &names,
        };
        match env.eval(f, 0) {
            Ok(ceval::Val::I(n)) if n >= 1 => {}
            Ok(v) => diags.push(
                Diagnostic::new(
                    format!(
                        "set `{}` has {} elements with the default sizes",
                        s.name,
                        v.real()
                    ),
                    s.span,
                    "no elements",
                )
                .hint("a set needs at least one element: change the formula or the default sizes"),
            ),
            Err(e) => {
                diags.push(Diagnostic::new(e.message, s.span, "at the default sizes").hint(e.hint))
            }
        }
    }
}
