//! Models built in code rather than parsed: a small builder, and the reference models
//! used by tests and benchmarks (the 3-D double pendulum of the thesis, planar chains).
//!
//! ```
//! use dae_lang::fixtures::{ModelBuilder, E};
//! use dae_lang::{analyze, AnalysisOptions};
//! let mut b = ModelBuilder::new("Index2");
//! let x = b.state("x", 0.0);
//! let z = b.alg("z", 0.0);
//! b.der(&x, z);
//! b.constraint("c", x, E::t().sin());
//! let a = analyze(&b.build(), &AnalysisOptions::default()).unwrap();
//! assert_eq!(a.indices(), vec![2]);
//! ```

use std::ops;

use crate::ast::{BinOp, Span};
use crate::model::{ConstraintDef, DerDef, Family, LetDef, Model, ParamDef, RExpr, VarDef};
use crate::{AlgId, Func, LetId, ParamId, StateId, VarRef};

/// A resolved expression with arithmetic operators, for building models in code.
#[derive(Clone, Debug, PartialEq)]
pub struct E(pub RExpr);

impl E {
    /// A number.
    pub fn num(v: f64) -> E {
        E(RExpr::Num(v))
    }

    /// Time `t`.
    pub fn t() -> E {
        E(RExpr::Var(VarRef::Time))
    }

    /// `self ^ e`.
    pub fn pow(self, e: impl Into<E>) -> E {
        E(RExpr::Binary(
            BinOp::Pow,
            Box::new(self.0),
            Box::new(e.into().0),
        ))
    }

    /// A one-argument built-in.
    pub fn call1(f: Func, a: E) -> E {
        E(RExpr::Call(f, vec![a.0]))
    }

    /// A two-argument built-in.
    pub fn call2(f: Func, a: E, b: E) -> E {
        E(RExpr::Call(f, vec![a.0, b.0]))
    }

    /// `sqrt(self)`
    pub fn sqrt(self) -> E {
        E::call1(Func::Sqrt, self)
    }

    /// `sin(self)`
    pub fn sin(self) -> E {
        E::call1(Func::Sin, self)
    }

    /// `cos(self)`
    pub fn cos(self) -> E {
        E::call1(Func::Cos, self)
    }
}

impl From<f64> for E {
    fn from(v: f64) -> E {
        E::num(v)
    }
}

macro_rules! binop {
    ($tr:ident, $m:ident, $op:expr) => {
        impl<R: Into<E>> ops::$tr<R> for E {
            type Output = E;
            fn $m(self, r: R) -> E {
                E(RExpr::Binary($op, Box::new(self.0), Box::new(r.into().0)))
            }
        }
        impl ops::$tr<E> for f64 {
            type Output = E;
            fn $m(self, r: E) -> E {
                E(RExpr::Binary(
                    $op,
                    Box::new(RExpr::Num(self)),
                    Box::new(r.0),
                ))
            }
        }
    };
}
binop!(Add, add, BinOp::Add);
binop!(Sub, sub, BinOp::Sub);
binop!(Mul, mul, BinOp::Mul);
binop!(Div, div, BinOp::Div);

impl ops::Neg for E {
    type Output = E;
    fn neg(self) -> E {
        E(RExpr::Neg(Box::new(self.0)))
    }
}

/// Builds a [`Model`] item by item. Every item gets its own one-byte span (in creation
/// order) so that diagnostics can be told apart.
#[derive(Clone, Debug)]
pub struct ModelBuilder {
    m: Model,
    ders: Vec<Option<DerDef>>,
    next: usize,
}

impl ModelBuilder {
    /// An empty model.
    pub fn new(name: &str) -> ModelBuilder {
        ModelBuilder {
            m: Model {
                name: name.into(),
                span: Span::new(0, 0),
                params: vec![],
                states: vec![],
                algs: vec![],
                lets: vec![],
                ders: vec![],
                mass: vec![],
                constraints: vec![],
                sizes: vec![],
                sets: vec![],
                maps: vec![],
                inputs: vec![],
            },
            ders: vec![],
            next: 1,
        }
    }

    fn span(&mut self) -> Span {
        self.next += 1;
        Span::new(self.next - 1, self.next)
    }

    /// `param name = default;`
    pub fn param(&mut self, name: &str, default: f64) -> E {
        let span = self.span();
        self.m.params.push(ParamDef {
            name: name.into(),
            default,
            span,
            value: RExpr::Num(default),
            family: Family::SCALAR,
        });
        E(RExpr::Var(VarRef::Param(ParamId::new(
            self.m.params.len() - 1,
        ))))
    }

    /// `state name = init;`
    pub fn state(&mut self, name: &str, init: impl Into<E>) -> E {
        let span = self.span();
        self.m.states.push(VarDef {
            name: name.into(),
            init: init.into().0,
            span,
            family: Family::SCALAR,
        });
        self.ders.push(None);
        E(RExpr::Var(VarRef::State(StateId::new(
            self.m.states.len() - 1,
        ))))
    }

    /// `alg name = init;`
    pub fn alg(&mut self, name: &str, init: impl Into<E>) -> E {
        let span = self.span();
        self.m.algs.push(VarDef {
            name: name.into(),
            init: init.into().0,
            span,
            family: Family::SCALAR,
        });
        E(RExpr::Var(VarRef::Alg(AlgId::new(self.m.algs.len() - 1))))
    }

    /// `let name = expr;`
    pub fn let_(&mut self, name: &str, expr: E) -> E {
        let span = self.span();
        self.m.lets.push(LetDef {
            name: name.into(),
            expr: expr.0,
            span,
            family: Family::SCALAR,
        });
        E(RExpr::Let(LetId::new(self.m.lets.len() - 1)))
    }

    /// `der(state) = rhs;` (`state` must be an expression returned by [`ModelBuilder::state`];
    /// anything else is ignored).
    pub fn der(&mut self, state: &E, rhs: impl Into<E>) {
        let span = self.span();
        if let E(RExpr::Var(VarRef::State(i))) = state {
            self.ders[i.index()] = Some(DerDef {
                expr: rhs.into().0,
                span,
            });
        }
    }

    /// `constraint name: lhs = rhs;`
    pub fn constraint(&mut self, name: &str, lhs: impl Into<E>, rhs: impl Into<E>) {
        let span = self.span();
        let residual = (lhs.into() - rhs.into()).0;
        self.m.constraints.push(ConstraintDef {
            name: name.into(),
            residual,
            span,
            over: None,
        });
    }

    /// The model. A state without a `der` gets `der(x) = 0`.
    pub fn build(mut self) -> Model {
        let span = self.span();
        self.m.ders = self
            .ders
            .into_iter()
            .map(|d| {
                d.unwrap_or(DerDef {
                    expr: RExpr::Num(0.0),
                    span,
                })
            })
            .collect();
        self.m
    }
}

/// The 3-D double pendulum of the thesis (docs/method.md section 8): masses 0.1, links 2.0,
/// g = 9.8, `R1 = (-1, 0, 0)`, `R2 = (-5, 0, 0)`, at rest, tensions `z1, z2` (initial 0).
/// States in order `rx1 ry1 rz1 vx1 vy1 vz1 rx2 ry2 rz2 vx2 vy2 vz2`.
pub fn double_pendulum_3d() -> Model {
    double_pendulum_3d_at([-1.0, 0.0, 0.0], [-5.0, 0.0, 0.0])
}

/// The 3-D double pendulum with the given initial positions (velocities zero).
pub fn double_pendulum_3d_at(r1: [f64; 3], r2: [f64; 3]) -> Model {
    let mut b = ModelBuilder::new("DoublePendulum3D");
    let m1 = b.param("m1", 0.1);
    let m2 = b.param("m2", 0.1);
    let l1p = b.param("L1", 2.0);
    let l2p = b.param("L2", 2.0);
    let g = b.param("g", 9.8);
    let axes = ["x", "y", "z"];
    let mut p1 = Vec::new();
    let mut v1 = Vec::new();
    let mut p2 = Vec::new();
    let mut v2 = Vec::new();
    for (k, a) in axes.iter().enumerate() {
        p1.push(b.state(&format!("r{a}1"), r1[k]));
        v1.push(b.state(&format!("v{a}1"), 0.0));
    }
    for (k, a) in axes.iter().enumerate() {
        p2.push(b.state(&format!("r{a}2"), r2[k]));
        v2.push(b.state(&format!("v{a}2"), 0.0));
    }
    let z1 = b.alg("z1", 0.0);
    let z2 = b.alg("z2", 0.0);
    let l1 = b.let_(
        "l1",
        (p1[0].clone().pow(2.0) + p1[1].clone().pow(2.0) + p1[2].clone().pow(2.0)).sqrt(),
    );
    let d: Vec<E> = (0..3)
        .map(|k| b.let_(&format!("d{}", axes[k]), p2[k].clone() - p1[k].clone()))
        .collect();
    let l2 = b.let_(
        "l2",
        (d[0].clone().pow(2.0) + d[1].clone().pow(2.0) + d[2].clone().pow(2.0)).sqrt(),
    );
    for k in 0..3 {
        let grav1 = if k == 2 { g.clone() } else { E::num(0.0) };
        let grav2 = if k == 2 { g.clone() } else { E::num(0.0) };
        b.der(&p1[k], v1[k].clone());
        b.der(&p2[k], v2[k].clone());
        let f1 = (-(z1.clone() * p1[k].clone() / l1.clone())
            + z2.clone() * d[k].clone() / l2.clone())
            / m1.clone()
            - grav1;
        let f2 = -(z2.clone() * d[k].clone() / l2.clone()) / m2.clone() - grav2;
        b.der(&v1[k], f1);
        b.der(&v2[k], f2);
    }
    b.constraint("link1", l1, l1p);
    b.constraint("link2", l2, l2p);
    b.build()
}

/// A planar chain of `n` point masses (mass `m = 0.1`) joined by links of length `L = 1`,
/// link 1 from the origin (pinned) to particle 1, link `i` from particle `i-1` to `i`,
/// gravity `g = 9.8` along `-y`, lets `l<i>` for the link lengths. Starts straight along
/// `+x` at rest with zero tensions. `n` index-3 constraints, `4 n` states.
pub fn planar_chain(n: usize) -> Model {
    let mut b = ModelBuilder::new("PlanarChain");
    let m = b.param("m", 0.1);
    let len = b.param("L", 1.0);
    let g = b.param("g", 9.8);
    let mut px = Vec::new();
    let mut py = Vec::new();
    let mut vx = Vec::new();
    let mut vy = Vec::new();
    for k in 1..=n {
        px.push(b.state(&format!("x{k}"), k as f64));
        py.push(b.state(&format!("y{k}"), 0.0));
        vx.push(b.state(&format!("vx{k}"), 0.0));
        vy.push(b.state(&format!("vy{k}"), 0.0));
    }
    let z: Vec<E> = (1..=n).map(|k| b.alg(&format!("z{k}"), 0.0)).collect();
    // Link i (0-based) joins particle i-1 (or the origin) to particle i.
    let mut dx = Vec::new();
    let mut dy = Vec::new();
    let mut l = Vec::new();
    for i in 0..n {
        let (x0, y0) = if i == 0 {
            (E::num(0.0), E::num(0.0))
        } else {
            (px[i - 1].clone(), py[i - 1].clone())
        };
        let ddx = b.let_(&format!("dx{}", i + 1), px[i].clone() - x0);
        let ddy = b.let_(&format!("dy{}", i + 1), py[i].clone() - y0);
        let li = b.let_(
            &format!("l{}", i + 1),
            (ddx.clone().pow(2.0) + ddy.clone().pow(2.0)).sqrt(),
        );
        dx.push(ddx);
        dy.push(ddy);
        l.push(li);
    }
    for k in 0..n {
        // Particle k: link k pulls it back toward particle k-1, link k+1 toward particle k+1.
        let mut fx = -(z[k].clone() * dx[k].clone() / l[k].clone());
        let mut fy = -(z[k].clone() * dy[k].clone() / l[k].clone());
        if k + 1 < n {
            fx = fx + z[k + 1].clone() * dx[k + 1].clone() / l[k + 1].clone();
            fy = fy + z[k + 1].clone() * dy[k + 1].clone() / l[k + 1].clone();
        }
        b.der(&px[k], vx[k].clone());
        b.der(&py[k], vy[k].clone());
        b.der(&vx[k], fx / m.clone());
        b.der(&vy[k], fy / m.clone() - g.clone());
    }
    for (i, li) in l.into_iter().enumerate() {
        b.constraint(&format!("link{}", i + 1), li, len.clone());
    }
    b.build()
}
