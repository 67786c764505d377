//! The checker of version-2 models (families, vectors, construction-time forms).
//!
//! It runs in passes over one model: declare every name (with its set, vector type and
//! component ids), resolve the sizes of the sets and the formulas of the maps, the
//! parameter values and initial values (construction-time expressions), the `let`s
//! (lazily, so that a `let`'s vector type is known where it is used, whatever the
//! order), the `der` equations and the constraints; order the `let`s; and evaluate the
//! construction at the default sizes when nothing is given at construction, which
//! reports a set without elements, a map pointing outside its set, a particle in no link
//! or a count mismatch while the model is checked. Expressions are resolved by
//! `expr.rs` (types and vectors), `name.rs` (names, variables, `let`s) and `access.rs`
//! (element access, maps, sums).

mod access;
mod decl;
mod expr;
mod finish;
mod mass;
mod name;

use std::collections::{HashMap, HashSet};

use crate::ast::{Decl, Expr, ExprKind, Item, ModelAst, Span};
use crate::diag::Diagnostic;
use crate::maps::MapTable;
use crate::model::{Family, Model, RExpr, SetDef, SizeDef};
use crate::{MapId, SetId};

/// Whether a model uses anything of version 2; if not, the version-1 checker checks it.
pub(crate) fn uses_version_2(m: &ModelAst) -> bool {
    m.items.iter().any(|item| match item {
        Item::Size { .. } | Item::Set { .. } | Item::Map { .. } | Item::Input(..) => true,
        Item::Param(ds, _) | Item::State(ds, _) | Item::Alg(ds, _) => ds.iter().any(decl_v2),
        Item::Let(d, _) => decl_v2(d),
        Item::Mass { states, rows, .. } => {
            states.iter().any(|(_, elem)| elem.is_some()) || rows.iter().flatten().any(expr_v2)
        }
        Item::Der { elem, rhs, .. } => elem.is_some() || expr_v2(rhs),
        Item::Constraint {
            binder, lhs, rhs, ..
        } => binder.is_some() || expr_v2(lhs) || expr_v2(rhs),
    })
}

fn decl_v2(d: &Decl) -> bool {
    d.binder.is_some() || d.ty.is_some() || expr_v2(&d.value)
}

/// Functions of version 2 (vectors and integer formulas), resolved by the checker.
const FAMILY_FUNCTIONS: [&str; 7] = ["vec2", "vec3", "dot", "norm", "cross", "div", "mod"];

fn expr_v2(e: &Expr) -> bool {
    e.kind.is_version_2()
        || match &e.kind {
            ExprKind::Neg(a) => expr_v2(a),
            ExprKind::Binary(_, a, b) => expr_v2(a) || expr_v2(b),
            ExprKind::Call(f, args) => {
                FAMILY_FUNCTIONS.contains(&f.name.as_str()) || args.iter().any(expr_v2)
            }
            _ => false,
        }
}

/// What a declared name is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Size,
    Set,
    Map,
    Param,
    State,
    Alg,
    Let,
    Input,
}

impl Kind {
    pub(super) fn words(self) -> &'static str {
        match self {
            Kind::Size => "a size",
            Kind::Set => "a set",
            Kind::Map => "a map",
            Kind::Param => "a parameter",
            Kind::State => "a state",
            Kind::Alg => "an algebraic variable",
            Kind::Let => "a `let` definition",
            Kind::Input => "an input",
        }
    }
}

/// A declared name.
#[derive(Clone, Copy, Debug)]
pub(super) struct Entry {
    pub kind: Kind,
    /// Position among the declarations of its kind (source order).
    pub decl: usize,
    /// Id of its first component (params, states, algs, inputs), of the size, set or
    /// named map; for a `let`, its declaration number (components are numbered later).
    pub first: usize,
    /// The set of a family.
    pub over: Option<SetId>,
    /// Vector dimension (1 for a number).
    pub dim: u8,
    /// Where the name was declared.
    pub span: Span,
}

/// One component of a declaration (`x.y` of `state x[p in P]: vec3`).
pub(super) struct Component<'a> {
    pub decl: &'a Decl,
    pub name: String,
    pub family: Family,
    /// Time derivatives given (inputs only).
    pub derivatives: u8,
}

/// A `let` declaration, resolved on first use.
pub(super) enum LetState {
    Todo,
    InProgress,
    /// The components (provisional let ids inside), or `None` after an error.
    Done(Option<Vec<RExpr>>),
}

/// A named map: its declaration and id.
pub(super) struct NamedMap<'a> {
    pub name: &'a str,
    pub formula: Option<&'a Expr>,
    pub id: MapId,
}

/// The state of checking one model.
pub(super) struct Checker<'a> {
    pub m: &'a ModelAst,
    pub diags: Vec<Diagnostic>,
    pub names: HashMap<&'a str, Entry>,
    /// Declared names in source order (for suggestions).
    pub ordered: Vec<&'a str>,
    /// Names declared more than once (already reported).
    pub duplicated: HashSet<&'a str>,
    pub sizes: Vec<SizeDef>,
    pub sets: Vec<SetDef>,
    /// Set size formulas (resolved later).
    pub set_exprs: Vec<Option<&'a Expr>>,
    pub maps: MapTable,
    pub named_maps: Vec<NamedMap<'a>>,
    pub params: Vec<Component<'a>>,
    /// Declaration number of each parameter component (for "declared after it").
    pub param_decl: Vec<usize>,
    pub states: Vec<Component<'a>>,
    pub algs: Vec<Component<'a>>,
    pub inputs: Vec<Component<'a>>,
    /// `let` declarations in source order, their sets, and their resolution.
    pub lets: Vec<&'a Decl>,
    pub let_sets: Vec<Option<SetId>>,
    pub let_state: Vec<LetState>,
}

/// Provisional `let` ids: declaration `d`, component `c` is `3 d + c` until the `let`s
/// are ordered and numbered.
pub(super) const LET_STRIDE: usize = 3;

/// Checks one version-2 model.
pub(crate) fn check_model(m: &ModelAst) -> Result<Model, Vec<Diagnostic>> {
    let mut c = Checker {
        m,
        diags: Vec::new(),
        names: HashMap::new(),
        ordered: Vec::new(),
        duplicated: HashSet::new(),
        sizes: Vec::new(),
        sets: Vec::new(),
        set_exprs: Vec::new(),
        maps: MapTable::default(),
        named_maps: Vec::new(),
        params: Vec::new(),
        param_decl: Vec::new(),
        states: Vec::new(),
        algs: Vec::new(),
        inputs: Vec::new(),
        lets: Vec::new(),
        let_sets: Vec::new(),
        let_state: Vec::new(),
    };
    c.declare();
    c.finish()
}
