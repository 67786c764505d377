//! The checked model: names resolved, items grouped and ordered.
//!
//! This is what the checker produces from a [`crate::ast::ModelAst`] and what the
//! symbolic lowering consumes. Every name is replaced by the [`VarRef`] it reads or by
//! the [`LetId`] of the definition it abbreviates; `let`s are kept as definitions (in an
//! order where each uses only earlier ones) so that the lowering can share them as DAG
//! nodes instead of copying their text.

use crate::ast::{BinOp, Span};
use crate::{Func, LetId, VarRef};

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
}

/// A parameter with its default value (already evaluated).
#[derive(Clone, Debug, PartialEq)]
pub struct ParamDef {
    /// Name.
    pub name: String,
    /// Default value.
    pub default: f64,
    /// Where it was declared (the `name = EXPR` text).
    pub span: Span,
}

/// A state or algebraic variable with its initial value (an expression over parameters).
#[derive(Clone, Debug, PartialEq)]
pub struct VarDef {
    /// Name.
    pub name: String,
    /// Initial value (state) or initial guess (algebraic); uses numbers and params only.
    pub init: RExpr,
    /// Where it was declared.
    pub span: Span,
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
}

/// `der(x) = expr;`
#[derive(Clone, Debug, PartialEq)]
pub struct DerDef {
    /// Right-hand side.
    pub expr: RExpr,
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
    /// `ders[i]` is the right-hand side for `states[i]`.
    pub ders: Vec<DerDef>,
    /// Constraints in declaration order; as many as `algs`.
    pub constraints: Vec<ConstraintDef>,
}
