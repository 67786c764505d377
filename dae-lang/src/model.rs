//! The checked model: names resolved, items grouped and ordered.
//!
//! This is what the checker produces from a [`crate::ast::ModelAst`] and what the
//! symbolic lowering consumes. Every name is replaced by the [`VarRef`] it reads or by
//! the [`LetId`] of the definition it abbreviates; `let`s are kept as definitions (in an
//! order where each uses only earlier ones) so that the lowering can share them as DAG
//! nodes instead of copying their text.
//!
//! # Version 2: families
//!
//! A family model (one with `size`, `set`, `map` or `input` items) has declarations over
//! sets. After the checker, vectors are expanded into components: a `state x[p in P]:
//! vec3` is three state declarations `x.x`, `x.y`, `x.z`, each a family over `P`
//! ([`Family`] says over which set, and which component of how many). Every expression
//! is scalar and stands in a *context*: the set whose element is at hand (the set of the
//! declaration it belongs to), or the scalar context. A reference to a family
//! ([`RExpr::Var`], [`RExpr::Let`]) reads it at the element at hand;
//! [`RExpr::Gather`] reads an expression of another context through a map, and
//! [`RExpr::Sum`] sums an expression over the elements a map sends to the element at
//! hand. Sizes, maps and set sizes are known only at construction: the checked model
//! keeps them as formulas.

use crate::ast::{BinOp, CmpOp, LogicOp, Span};
use crate::{Func, LetId, MapId, SetId, VarRef};

/// A resolved expression.
#[derive(Clone, Debug, PartialEq)]
pub enum RExpr {
    /// A number.
    Num(f64),
    /// A parameter, state, algebraic unknown or `t`.
    Var(VarRef),
    /// A `let` definition, by its position in [`Model::lets`].
    Let(LetId),
    /// Unary minus.
    Neg(Box<RExpr>),
    /// Binary operation.
    Binary(BinOp, Box<RExpr>, Box<RExpr>),
    /// Built-in call with the right number of arguments.
    Call(Func, Vec<RExpr>),
    /// The expression (which stands in the context of the map's codomain) read at the
    /// image of the element at hand: `x[a[l]]` is `Gather(a, Var(x))` in the context of
    /// `l`. The map's domain is the context of this node (the scalar context for a map
    /// from the unit, e.g. the constant map of `x[0]` in a scalar expression).
    Gather(MapId, Box<RExpr>),
    /// The sum of the expression (in the context of the map's domain `K`) over the `k`
    /// whose image under the map is the element at hand (of the map's codomain): an
    /// incidence sum `sum(k in K where m[k] == q) body`. A map to the unit (scalar
    /// context) makes it a full sum `sum(k in K) body`.
    Sum(MapId, Box<RExpr>),
    /// A comparison: 1 if it holds, 0 if not. Construction-time expressions only.
    Compare(CmpOp, Box<RExpr>, Box<RExpr>),
    /// `and`, `or` of two conditions. Construction-time expressions only.
    Logic(LogicOp, Box<RExpr>, Box<RExpr>),
    /// `not` of a condition. Construction-time expressions only.
    Not(Box<RExpr>),
    /// `if c then a else b`. Construction-time expressions only.
    If(Box<RExpr>, Box<RExpr>, Box<RExpr>),
    /// `div(a, b)` (floor division) or `mod(a, b)` (floor modulo, the sign of `b`) of
    /// integers. Construction-time expressions only.
    Int(IntOp, Box<RExpr>, Box<RExpr>),
}

/// The integer operations of construction-time expressions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IntOp {
    /// `div(a, b)`: `floor(a / b)`.
    Div,
    /// `mod(a, b)`: `a - b * floor(a / b)`.
    Mod,
}

impl RExpr {
    /// Whether the expression uses a form allowed only at construction (`if`,
    /// comparisons, `and`, `or`, `not`, `div`, `mod`).
    pub fn is_construction_only(&self) -> bool {
        let mut found = false;
        self.visit(&mut |e| {
            found |= matches!(
                e,
                RExpr::Compare(..)
                    | RExpr::Logic(..)
                    | RExpr::Not(_)
                    | RExpr::If(..)
                    | RExpr::Int(..)
            )
        });
        found
    }

    /// Calls `f` on this expression and every sub-expression (parents first).
    pub fn visit(&self, f: &mut impl FnMut(&RExpr)) {
        f(self);
        match self {
            RExpr::Num(_) | RExpr::Var(_) | RExpr::Let(_) => {}
            RExpr::Neg(a) | RExpr::Not(a) | RExpr::Gather(_, a) | RExpr::Sum(_, a) => a.visit(f),
            RExpr::Binary(_, a, b)
            | RExpr::Compare(_, a, b)
            | RExpr::Logic(_, a, b)
            | RExpr::Int(_, a, b) => {
                a.visit(f);
                b.visit(f);
            }
            RExpr::If(c, a, b) => {
                c.visit(f);
                a.visit(f);
                b.visit(f);
            }
            RExpr::Call(_, args) => args.iter().for_each(|a| a.visit(f)),
        }
    }
}

/// Which set a declaration is a family over, and which component of a vector it is.
/// A version-1 declaration is [`Family::SCALAR`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Family {
    /// The set (`None`: one scalar value).
    pub over: Option<SetId>,
    /// The vector dimension of the declaration (1 for a scalar type, 2 or 3).
    pub dim: u8,
    /// Which component this is (`0 .. dim`).
    pub component: u8,
}

impl Family {
    /// A scalar declaration (version 1).
    pub const SCALAR: Family = Family {
        over: None,
        dim: 1,
        component: 0,
    };
}

/// `size N = 10;`
#[derive(Clone, Debug, PartialEq)]
pub struct SizeDef {
    /// Name.
    pub name: String,
    /// Default value (an integer >= 0); set at construction.
    pub default: i64,
    /// The whole item.
    pub span: Span,
}

/// `set P = N + 1;` or `set L;`
#[derive(Clone, Debug, PartialEq)]
pub struct SetDef {
    /// Name.
    pub name: String,
    /// Its size: an integer formula over the sizes, or `None` when given at construction.
    pub size: Option<RExpr>,
    /// The element name used to print templates over this set (the first binder written
    /// for it, else the set's name in lower case).
    pub elem: String,
    /// The whole item.
    pub span: Span,
}

/// A map between sets (named, or made by the checker or the analysis).
#[derive(Clone, Debug, PartialEq)]
pub struct MapDef {
    /// The written name; empty for a formula written inside an index (an anonymous
    /// map); `a then b` for a composition, `id` and `unit` for the other maps made by
    /// the checker and the analysis.
    pub name: String,
    /// The domain (`None`: the unit, one element 0, i.e. the scalar context).
    pub domain: Option<SetId>,
    /// The codomain (`None`: the unit).
    pub codomain: Option<SetId>,
    /// How its values are obtained.
    pub kind: MapKind,
    /// The declaration, or the expression that made the map.
    pub span: Span,
}

/// How a map's values are obtained (at construction).
#[derive(Clone, Debug, PartialEq)]
pub enum MapKind {
    /// Given by the caller (an edge list).
    Given,
    /// An integer formula in the context of the domain (the element as
    /// `Var(Elem(domain))`, sizes, other maps through `Gather`).
    Formula(RExpr),
    /// The maps applied one after the other, the first first (never empty; no identity,
    /// nothing after a map to the unit).
    Chain(Vec<MapId>),
    /// The map of the domain to the unit (every element to 0).
    ToUnit,
    /// The identity of the domain.
    Identity,
}

/// `input pin[p in P]: vec3 with 3 derivatives = ...;` (one component family).
#[derive(Clone, Debug, PartialEq)]
pub struct InputDef {
    /// Name (`pin.x` for a component).
    pub name: String,
    /// Set and component.
    pub family: Family,
    /// How many time derivatives the caller gives (beyond the value).
    pub derivatives: u8,
    /// The default value (derivatives 0): a construction-time expression.
    pub default: RExpr,
    /// The declaration.
    pub span: Span,
}

/// A parameter with its default value (already evaluated).
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDef {
    /// Name.
    pub name: String,
    /// Default value. In a family model, the value with the default sizes for a scalar
    /// parameter, NaN for a per-element one (whose value is `value` per element).
    pub default: f64,
    /// Where it was declared (the `name = EXPR` text).
    pub span: Span,
    /// The default as written: numbers and earlier parameters, and in a family model
    /// sizes and the element (a construction-time expression).
    pub value: RExpr,
    /// Set and component.
    pub family: Family,
}

/// A state or algebraic variable with its initial value (an expression over parameters).
#[derive(Clone, Debug, PartialEq)]
pub struct VarDef {
    /// Name.
    pub name: String,
    /// Initial value (state) or initial guess (algebraic); uses numbers and params only
    /// (and in a family model sizes and the element: a construction-time expression).
    pub init: RExpr,
    /// Where it was declared.
    pub span: Span,
    /// Set and component.
    pub family: Family,
}

/// `let name = expr;`
#[derive(Clone, Debug, PartialEq)]
pub struct LetDef {
    /// Name.
    pub name: String,
    /// Definition; refers only to lets with a smaller index.
    pub expr: RExpr,
    /// Where it was declared.
    pub span: Span,
    /// Set and component.
    pub family: Family,
}

/// `der(x) = expr;`
#[derive(Clone, Debug, PartialEq)]
pub struct DerDef {
    /// Right-hand side.
    pub expr: RExpr,
    /// The whole item.
    pub span: Span,
}

/// `mass [v1, ..., vn] = [...];`: the derivatives of `states` solve `M der(v) = rhs`,
/// `rhs[i]` being the right-hand side of `der(states[i])`.
#[derive(Clone, Debug, PartialEq)]
pub struct MassDef {
    /// The states, in the matrix's row and column order (distinct, each in one matrix).
    pub states: Vec<crate::StateId>,
    /// `M`, row-major, `n x n`: expressions over the parameters, the states, the lets
    /// and `t` (never an algebraic unknown).
    pub entries: Vec<RExpr>,
    /// Where each entry is written (same order).
    pub entry_spans: Vec<Span>,
    /// The whole item.
    pub span: Span,
}

/// `constraint name: lhs = rhs;` as the residual `0 = lhs - rhs`.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintDef {
    /// The written name, or `c1, c2, ...` in order for unnamed constraints.
    pub name: String,
    /// `lhs - rhs`.
    pub residual: RExpr,
    /// The whole item.
    pub span: Span,
    /// The set of a constraint family (`None` for one constraint).
    pub over: Option<SetId>,
}

/// A model whose names are resolved and whose structure is valid.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// Model name.
    pub name: String,
    /// The span of the model's name.
    pub span: Span,
    /// Parameters in declaration order.
    pub params: Vec<ParamDef>,
    /// Differential states in declaration order.
    pub states: Vec<VarDef>,
    /// Algebraic unknowns in declaration order.
    pub algs: Vec<VarDef>,
    /// Definitions, each using only earlier ones.
    pub lets: Vec<LetDef>,
    /// `ders[i]` is the right-hand side for `states[i]` (for a state in a mass matrix,
    /// its row of `M der(v) = rhs`).
    pub ders: Vec<DerDef>,
    /// The mass matrices (version 1; empty: every `der` is explicit).
    pub mass: Vec<MassDef>,
    /// Constraints in declaration order; as many as `algs` (in a family model, as many
    /// constraints as algebraic unknowns once the sets have their sizes).
    pub constraints: Vec<ConstraintDef>,
    /// Sizes (version 2; empty otherwise).
    pub sizes: Vec<SizeDef>,
    /// Sets (version 2).
    pub sets: Vec<SetDef>,
    /// Maps: the named ones in declaration order, then those the checker made.
    pub maps: Vec<MapDef>,
    /// Input component families (version 2).
    pub inputs: Vec<InputDef>,
}

impl Model {
    /// Whether this is a family model (sizes, sets or inputs, or an initial value that
    /// only construction can evaluate), analysed as templates; otherwise it is analysed
    /// exactly as a version-1 model.
    pub fn is_family(&self) -> bool {
        !self.sizes.is_empty()
            || !self.sets.is_empty()
            || !self.inputs.is_empty()
            || self
                .states
                .iter()
                .chain(&self.algs)
                .any(|v| v.init.is_construction_only())
    }
}
