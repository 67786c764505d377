//! The abstract syntax tree of the `.dae` language (versions 1 and 2).
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

/// One `name = EXPR` in a `param`, `state`, `alg`, `let` or `input` item; in version 2
/// also `name[e in S]: TYPE = EXPR` (one value per element of `S`, of a vector type).
#[derive(Clone, Debug, PartialEq)]
pub struct Decl {
    /// The declared name.
    pub name: Ident,
    /// `[e in S]` (or `[S]`): a family over the set `S`; `None` for a scalar declaration.
    pub binder: Option<Binder>,
    /// `: vec3` after the name (and binder); `None` for a scalar.
    pub ty: Option<Ident>,
    /// Its value (default, initial value or definition).
    pub value: Expr,
    /// `name = EXPR`.
    pub span: Span,
}

/// `[e in S]` after a declared name: the element name `e` (optional: `[S]`) and the set.
#[derive(Clone, Debug, PartialEq)]
pub struct Binder {
    /// The element's name, if written.
    pub elem: Option<Ident>,
    /// The set.
    pub set: Ident,
    /// `[e in S]`.
    pub span: Span,
}

/// One declaration of an `input` item: a [`Decl`] with the number of time derivatives
/// the caller gives (`with 3 derivatives`; 0 when not written).
#[derive(Clone, Debug, PartialEq)]
pub struct InputDecl {
    /// Name, binder, type and default value.
    pub decl: Decl,
    /// `with K derivatives`: `K` and the span of the clause.
    pub derivatives: Option<(u32, Span)>,
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
    /// `der(x) = EXPR;` or `der(x[p]) = EXPR;`
    Der {
        /// The state inside `der(...)`.
        target: Ident,
        /// `p` in `der(x[p])`: names the element of a state family.
        elem: Option<Ident>,
        /// The right-hand side.
        rhs: Expr,
        /// The whole item.
        span: Span,
    },
    /// `mass [v1, v2] = [m11, m12; m21, m22];`: the derivatives of the listed states
    /// solve `M der(v) = rhs`, where `rhs` are the right-hand sides of their `der` items.
    Mass {
        /// The states whose derivatives the matrix multiplies, in its column order, each
        /// with the element it is named at in a family model (`v[p]`).
        states: Vec<(Ident, Option<Ident>)>,
        /// The rows of the matrix, as written.
        rows: Vec<Vec<Expr>>,
        /// The whole item.
        span: Span,
    },
    /// `constraint NAME: lhs = rhs;`, `constraint lhs = rhs;` or a constraint family
    /// `constraint NAME[e in S]: lhs = rhs;`
    Constraint {
        /// The name, if one was written.
        name: Option<Ident>,
        /// `[e in S]` of a constraint family.
        binder: Option<Binder>,
        /// Left-hand side.
        lhs: Expr,
        /// Right-hand side.
        rhs: Expr,
        /// The whole item.
        span: Span,
    },
    /// `size N = 10;`
    Size {
        /// The size's name.
        name: Ident,
        /// Its default value.
        value: Expr,
        /// The whole item.
        span: Span,
    },
    /// `set P = N + 1;` or `set L;` (size given at construction).
    Set {
        /// The set's name.
        name: Ident,
        /// Its size, a formula over sizes; `None` when given at construction.
        size: Option<Expr>,
        /// The whole item.
        span: Span,
    },
    /// `map a[l in L] -> P = l;` or `map a[l in L] -> P;` (given at construction).
    Map {
        /// The map's name.
        name: Ident,
        /// The domain: `[l in L]`.
        binder: Binder,
        /// The codomain.
        codomain: Ident,
        /// The formula giving the image of the element; `None` when given at construction.
        formula: Option<Expr>,
        /// The whole item.
        span: Span,
    },
    /// `input pin[p in P]: vec3 with 3 derivatives = vec3(0, 0, 0);`
    Input(Vec<InputDecl>, Span),
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

/// Comparison operators (construction-time expressions only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CmpOp {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

impl CmpOp {
    /// The operator as written.
    pub fn symbol(self) -> &'static str {
        match self {
            CmpOp::Eq => "==",
            CmpOp::Ne => "!=",
            CmpOp::Lt => "<",
            CmpOp::Le => "<=",
            CmpOp::Gt => ">",
            CmpOp::Ge => ">=",
        }
    }

    /// Whether `a op b` holds.
    pub fn holds<T: PartialOrd>(self, a: T, b: T) -> bool {
        match self {
            CmpOp::Eq => a == b,
            CmpOp::Ne => a != b,
            CmpOp::Lt => a < b,
            CmpOp::Le => a <= b,
            CmpOp::Gt => a > b,
            CmpOp::Ge => a >= b,
        }
    }
}

/// `and`, `or` (construction-time expressions only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LogicOp {
    /// `and`
    And,
    /// `or`
    Or,
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
    /// `x[i]`: element `i` of a family or a map (version 2).
    Index(Box<Expr>, Box<Expr>),
    /// `e.x`: a component of a vector (version 2).
    Field(Box<Expr>, Ident),
    /// `sum(k in K where c) body` or `sum(k in K) body` (version 2).
    Sum {
        /// The summation element.
        elem: Ident,
        /// Its set.
        set: Ident,
        /// The condition after `where`.
        cond: Option<Box<Expr>>,
        /// The summed expression.
        body: Box<Expr>,
    },
    /// `a == b` and the other comparisons (construction-time, version 2).
    Compare(CmpOp, Box<Expr>, Box<Expr>),
    /// `a and b`, `a or b` (construction-time, version 2).
    Logic(LogicOp, Box<Expr>, Box<Expr>),
    /// `not a` (construction-time, version 2).
    Not(Box<Expr>),
    /// `if c then a else b` (construction-time, version 2).
    If(Box<Expr>, Box<Expr>, Box<Expr>),
}

impl ExprKind {
    /// Whether this form is version 2's alone (element access, components, sums and the
    /// construction-time forms): a model with one is checked as a version-2 model.
    pub(crate) fn is_version_2(&self) -> bool {
        match self {
            ExprKind::Num(_)
            | ExprKind::Time
            | ExprKind::Name(_)
            | ExprKind::Neg(_)
            | ExprKind::Binary(..)
            | ExprKind::Call(..) => false,
            ExprKind::Index(..)
            | ExprKind::Field(..)
            | ExprKind::Sum { .. }
            | ExprKind::Compare(..)
            | ExprKind::Logic(..)
            | ExprKind::Not(_)
            | ExprKind::If(..) => true,
        }
    }
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
        if let Some(b) = &mut self.binder {
            b.erase_spans();
        }
        if let Some(t) = &mut self.ty {
            t.span = Span::default();
        }
        self.value.erase_spans();
    }
}

impl Binder {
    fn erase_spans(&mut self) {
        self.span = Span::default();
        self.set.span = Span::default();
        if let Some(e) = &mut self.elem {
            e.span = Span::default();
        }
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
            Item::Der {
                target,
                elem,
                rhs,
                span,
            } => {
                *span = Span::default();
                target.span = Span::default();
                if let Some(e) = elem {
                    e.span = Span::default();
                }
                rhs.erase_spans();
            }
            Item::Constraint {
                name,
                binder,
                lhs,
                rhs,
                span,
            } => {
                *span = Span::default();
                if let Some(n) = name {
                    n.span = Span::default();
                }
                if let Some(b) = binder {
                    b.erase_spans();
                }
                lhs.erase_spans();
                rhs.erase_spans();
            }
            Item::Mass { states, rows, span } => {
                *span = Span::default();
                for (name, elem) in states {
                    name.span = Span::default();
                    if let Some(e) = elem {
                        e.span = Span::default();
                    }
                }
                rows.iter_mut().flatten().for_each(Expr::erase_spans);
            }
            Item::Size { name, value, span } => {
                *span = Span::default();
                name.span = Span::default();
                value.erase_spans();
            }
            Item::Set { name, size, span } => {
                *span = Span::default();
                name.span = Span::default();
                if let Some(e) = size {
                    e.erase_spans();
                }
            }
            Item::Map {
                name,
                binder,
                codomain,
                formula,
                span,
            } => {
                *span = Span::default();
                name.span = Span::default();
                binder.erase_spans();
                codomain.span = Span::default();
                if let Some(e) = formula {
                    e.erase_spans();
                }
            }
            Item::Input(ds, s) => {
                *s = Span::default();
                for d in ds {
                    d.decl.erase_spans();
                    if let Some((_, sp)) = &mut d.derivatives {
                        *sp = Span::default();
                    }
                }
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
            ExprKind::Index(a, b) | ExprKind::Compare(_, a, b) | ExprKind::Logic(_, a, b) => {
                a.erase_spans();
                b.erase_spans();
            }
            ExprKind::Field(a, f) => {
                a.erase_spans();
                f.span = Span::default();
            }
            ExprKind::Not(a) => a.erase_spans(),
            ExprKind::If(c, a, b) => {
                c.erase_spans();
                a.erase_spans();
                b.erase_spans();
            }
            ExprKind::Sum {
                elem,
                set,
                cond,
                body,
            } => {
                elem.span = Span::default();
                set.span = Span::default();
                if let Some(c) = cond {
                    c.erase_spans();
                }
                body.erase_spans();
            }
        }
    }
}
