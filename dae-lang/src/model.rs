//! The checked model: names resolved, items grouped and ordered.
//!
//! This is what the checker produces from a [`crate::ast::ModelAst`] and what the
//! symbolic lowering consumes. Every name is replaced by its [`Var`]; `let`s are kept
//! as definitions (in an order where each uses only earlier ones) so that the lowering
//! can share them as DAG nodes instead of copying their text.

use crate::ast::{BinOp, Span};

/// A resolved reference to something declared in the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Var {
    /// Index into [`Model::params`].
    Param(usize),
    /// Index into [`Model::states`].
    State(usize),
    /// Index into [`Model::algs`].
    Alg(usize),
    /// Index into [`Model::lets`].
    Let(usize),
    /// Time `t`.
    Time,
}

/// Built-in functions of the language.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Func {
    /// `sin`
    Sin,
    /// `cos`
    Cos,
    /// `tan`
    Tan,
    /// `asin`
    Asin,
    /// `acos`
    Acos,
    /// `atan`
    Atan,
    /// `sinh`
    Sinh,
    /// `cosh`
    Cosh,
    /// `tanh`
    Tanh,
    /// `exp`
    Exp,
    /// `ln` (natural logarithm)
    Ln,
    /// `sqrt`
    Sqrt,
    /// `abs`
    Abs,
    /// `sign` (-1, 0 or 1)
    Sign,
    /// `atan2(y, x)`
    Atan2,
    /// `pow(a, b)` = `a^b`
    Pow,
    /// `min(a, b)`
    Min,
    /// `max(a, b)`
    Max,
}

impl Func {
    /// Every function, in the order of the language reference.
    pub const ALL: [Func; 18] = [
        Func::Sin,
        Func::Cos,
        Func::Tan,
        Func::Asin,
        Func::Acos,
        Func::Atan,
        Func::Sinh,
        Func::Cosh,
        Func::Tanh,
        Func::Exp,
        Func::Ln,
        Func::Sqrt,
        Func::Abs,
        Func::Sign,
        Func::Atan2,
        Func::Pow,
        Func::Min,
        Func::Max,
    ];

    /// The name as written in the language.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Sinh => "sinh",
            Func::Cosh => "cosh",
            Func::Tanh => "tanh",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Sqrt => "sqrt",
            Func::Abs => "abs",
            Func::Sign => "sign",
            Func::Atan2 => "atan2",
            Func::Pow => "pow",
            Func::Min => "min",
            Func::Max => "max",
        }
    }

    /// Look a function up by its name.
    pub fn from_name(name: &str) -> Option<Func> {
        Func::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Number of arguments.
    pub fn arity(self) -> usize {
        match self {
            Func::Atan2 | Func::Pow | Func::Min | Func::Max => 2,
            _ => 1,
        }
    }

    /// The value of a one-argument function: the one definition of the language's
    /// semantics, shared by the checker, the symbolic evaluator and the interpreter (the
    /// code generator emits the same operations). `sign` is -1, 0 or 1 (`f64::signum`
    /// gives 1 at 0) and NaN for NaN. A two-argument function gives NaN.
    pub fn apply1(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Atan => x.atan(),
            Func::Sinh => x.sinh(),
            Func::Cosh => x.cosh(),
            Func::Tanh => x.tanh(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Sqrt => x.sqrt(),
            Func::Abs => x.abs(),
            Func::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    x * 0.0
                }
            }
            Func::Atan2 | Func::Pow | Func::Min | Func::Max => f64::NAN,
        }
    }

    /// The value of a two-argument function (see [`Func::apply1`]). `min` and `max`
    /// propagate a NaN operand (`f64::min` would drop it and hide the error). A
    /// one-argument function gives NaN.
    pub fn apply2(self, a: f64, b: f64) -> f64 {
        match self {
            Func::Atan2 => a.atan2(b),
            Func::Pow => a.powf(b),
            Func::Min | Func::Max if a.is_nan() || b.is_nan() => f64::NAN,
            Func::Min => a.min(b),
            Func::Max => a.max(b),
            _ => f64::NAN,
        }
    }
}

/// A resolved expression.
#[derive(Clone, Debug, PartialEq)]
pub enum RExpr {
    /// A number.
    Num(f64),
    /// A declared name or `t`.
    Var(Var),
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
