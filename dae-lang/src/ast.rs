//! The abstract syntax tree of the `.dae` language, version 1.
//!
//! Both front ends (the pest parser for `.dae` files and the `dae!` macro, which parses
//! Rust tokens) produce these types. Every node carries the byte [`Span`] of its source
//! text; [`File::erase_spans`] sets them all to zero so that the two front ends can be
//! compared for structural equality.

/// A half-open byte range `start..end` into the source text.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    /// First byte.
    pub start: usize,
    /// One past the last byte.
    pub end: usize,
}

impl Span {
    /// A span from `start` to `end`.
    pub fn new(start: usize, end: usize) -> Self {
        Span { start, end }
    }

    /// The smallest span that covers both.
    pub fn join(self, other: Span) -> Span {
        Span {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }
}

/// A name with the place it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Ident {
    /// The name as written.
    pub name: String,
    /// Where.
    pub span: Span,
}

/// A source file: one or more models.
#[derive(Clone, Debug, PartialEq)]
pub struct File {
    /// The models in source order.
    pub models: Vec<ModelAst>,
}

/// `model NAME { items }`.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelAst {
    /// The model's name.
    pub name: Ident,
    /// Its items in source order.
    pub items: Vec<Item>,
    /// The whole `model ... { ... }` text.
    pub span: Span,
}

/// One `name = EXPR` in a `param`, `state`, `alg` or `let` item.
#[derive(Clone, Debug, PartialEq)]
pub struct Decl {
    /// The declared name.
    pub name: Ident,
    /// Its value (default, initial value or definition).
    pub value: Expr,
    /// `name = EXPR`.
    pub span: Span,
}

/// An item of a model.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// `param a = 1, b = a;`
    Param(Vec<Decl>, Span),
    /// `state x = 0, v = 1;`
    State(Vec<Decl>, Span),
    /// `alg z = 0;`
    Alg(Vec<Decl>, Span),
    /// `let n = EXPR;`
    Let(Decl, Span),
    /// `der(x) = EXPR;`
    Der {
        /// The state inside `der(...)`.
        target: Ident,
        /// The right-hand side.
        rhs: Expr,
        /// The whole item.
        span: Span,
    },
    /// `constraint NAME: lhs = rhs;` or `constraint lhs = rhs;`
    Constraint {
        /// The name, if one was written.
        name: Option<Ident>,
        /// Left-hand side.
        lhs: Expr,
        /// Right-hand side.
        rhs: Expr,
        /// The whole item.
        span: Span,
    },
}

/// An expression with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it was written.
    pub span: Span,
}

/// Binary operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `^` (right associative, binds tighter than unary minus)
    Pow,
}

/// The kinds of expression.
#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    /// A numeric literal.
    Num(f64),
    /// Time, the reserved name `t`.
    Time,
    /// A name (parameter, state, algebraic or let), resolved by the checker.
    Name(String),
    /// Unary minus.
    Neg(Box<Expr>),
    /// A binary operation.
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// A call of a built-in function; arity is checked by the checker.
    Call(Ident, Vec<Expr>),
}

impl File {
    /// Set every span in the tree to `0..0` (for comparing the two front ends).
    pub fn erase_spans(&mut self) {
        for m in &mut self.models {
            m.span = Span::default();
            m.name.span = Span::default();
            for item in &mut m.items {
                item.erase_spans();
            }
        }
    }
}

impl Decl {
    fn erase_spans(&mut self) {
        self.span = Span::default();
        self.name.span = Span::default();
        self.value.erase_spans();
    }
}

impl Item {
    fn erase_spans(&mut self) {
        match self {
            Item::Param(ds, s) | Item::State(ds, s) | Item::Alg(ds, s) => {
                *s = Span::default();
                ds.iter_mut().for_each(Decl::erase_spans);
            }
            Item::Let(d, s) => {
                *s = Span::default();
                d.erase_spans();
            }
            Item::Der { target, rhs, span } => {
                *span = Span::default();
                target.span = Span::default();
                rhs.erase_spans();
            }
            Item::Constraint {
                name,
                lhs,
                rhs,
                span,
            } => {
                *span = Span::default();
                if let Some(n) = name {
                    n.span = Span::default();
                }
                lhs.erase_spans();
                rhs.erase_spans();
            }
        }
    }
}

impl Expr {
    /// Set every span in this expression to `0..0`.
    pub fn erase_spans(&mut self) {
        self.span = Span::default();
        match &mut self.kind {
            ExprKind::Num(_) | ExprKind::Time | ExprKind::Name(_) => {}
            ExprKind::Neg(e) => e.erase_spans(),
            ExprKind::Binary(_, a, b) => {
                a.erase_spans();
                b.erase_spans();
            }
            ExprKind::Call(f, args) => {
                f.span = Span::default();
                args.iter_mut().for_each(Expr::erase_spans);
            }
        }
    }
}
