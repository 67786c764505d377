//! A family model's [`Construction`] as a Rust expression: what the generated
//! `construction_data()` returns, built from literals (no parsing or analysis at run
//! time).
//!
//! The body declares a few short helper functions (`num`, `size`, `sp`, `param_def`,
//! ...) and then the value, so that the code stays small: one line for most
//! declarations instead of a struct literal over several. Formulas are written infix,
//! as in the source: a local wrapper `X` of the expression type overloads `+ - * /` and
//! unary `-`, each building the node it spells, and the emitter keeps the tree's shape
//! with the parentheses Rust's precedence needs (both operands of a left-associative
//! operator of the same level keep theirs on the right, so `a - (b - c)` stays so).

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use dae_lang::VarRef;
use dae_lang::ast::BinOp;
use dae_lang::family::Construction;
use dae_lang::model::{Family, MapKind, RExpr};

use crate::literals::{lang, number, usize_lit};

/// The [`Construction`] as the body of a function returning it (with `dae_lang` at
/// [`lang`]).
pub(crate) fn construction_expr(c: &Construction) -> TokenStream {
    let sizes = c.sizes.iter().map(|s| {
        let (name, default, span) = (&s.name, s.default, span(s.span));
        quote!(size_def(#name, #default, #span))
    });
    let sets = c.sets.iter().map(|s| {
        let name = &s.name;
        let size = opt(s.size.as_ref().map(rexpr));
        let elem = &s.elem;
        let span = span(s.span);
        quote!(set_def(#name, #size, #elem, #span))
    });
    let maps = c.maps.iter().map(|m| {
        let name = &m.name;
        let domain = opt(m.domain.map(|s| usize_lit(s.index())));
        let codomain = opt(m.codomain.map(|s| usize_lit(s.index())));
        let kind = match &m.kind {
            MapKind::Given => quote!(K::Given),
            MapKind::Formula(e) => {
                let e = rexpr(e);
                quote!(formula(#e))
            }
            MapKind::Chain(ms) => {
                let ms = ms.iter().map(|m| usize_lit(m.index()));
                quote!(K::Chain(Vec::from([#(dl::MapId::new(#ms)),*])))
            }
            MapKind::ToUnit => quote!(K::ToUnit),
            MapKind::Identity => quote!(K::Identity),
        };
        let span = span(m.span);
        quote!(map_def(#name, #domain, #codomain, #kind, #span))
    });
    let params = c.params.iter().map(|p| {
        let name = &p.name;
        let default = number(p.default);
        let value = rexpr(&p.value);
        let (family, span) = (family(p.family), span(p.span));
        quote!(param_def(#name, #default, #value, #family, #span))
    });
    let var = |v: &dae_lang::model::VarDef| {
        let name = &v.name;
        let init = rexpr(&v.init);
        let (family, span) = (family(v.family), span(v.span));
        quote!(var_def(#name, #init, #family, #span))
    };
    let states = c.states.iter().map(var);
    let algs = c.algs.iter().map(var);
    let inputs = c.inputs.iter().map(|i| {
        let name = &i.name;
        let derivatives = i.derivatives;
        let default = rexpr(&i.default);
        let (family, span) = (family(i.family), span(i.span));
        quote!(input_def(#name, #family, #derivatives, #default, #span))
    });
    let constraints = c.constraints.iter().map(|k| {
        let name = &k.name;
        let over = opt(k.over.map(|s| usize_lit(s.index())));
        let index = usize_lit(k.index);
        let span = span(k.span);
        quote!(constraint(#name, #over, #index, #span))
    });
    let incidence = c.incidence.iter().map(|i| {
        let set = usize_lit(i.set.index());
        let maps = i.maps.iter().map(|m| usize_lit(m.index()));
        let span = span(i.span);
        quote!(incidence(#set, &[#(#maps),*], #span))
    });
    let couplings = c.couplings.iter().map(|k| {
        let ids = [
            k.constraint.index(),
            k.alg.index(),
            k.row_map.index(),
            k.col_map.index(),
        ]
        .map(usize_lit);
        quote!(coupling(#(#ids),*))
    });
    let dl = lang();
    quote! {
        use #dl as dl;
        use dl::ast::{BinOp as B, CmpOp as C, LogicOp as L, Span};
        use dl::Func as F;
        use dl::model::{Family, IntOp as I, MapKind as K, RExpr as E};
        use ::std::boxed::Box;
        use ::std::string::String;
        use ::std::vec::Vec;
        use ::core::option::Option::{self, None, Some};
        /// An expression being built; `+ - * /` and unary `-` make the node they spell.
        struct X(E);
        fn bx(e: X) -> Box<E> { Box::new(e.0) }
        impl ::core::ops::Add for X { type Output = X; fn add(self, b: X) -> X { bin(B::Add, self, b) } }
        impl ::core::ops::Sub for X { type Output = X; fn sub(self, b: X) -> X { bin(B::Sub, self, b) } }
        impl ::core::ops::Mul for X { type Output = X; fn mul(self, b: X) -> X { bin(B::Mul, self, b) } }
        impl ::core::ops::Div for X { type Output = X; fn div(self, b: X) -> X { bin(B::Div, self, b) } }
        impl ::core::ops::Neg for X { type Output = X; fn neg(self) -> X { X(E::Neg(bx(self))) } }
        fn num(v: f64) -> X { X(E::Num(v)) }
        fn var(v: dl::VarRef) -> X { X(E::Var(v)) }
        fn size(i: usize) -> X { var(dl::VarRef::Size(dl::SizeId::new(i))) }
        fn elem(i: usize) -> X { var(dl::VarRef::Elem(dl::SetId::new(i))) }
        fn param(i: usize) -> X { var(dl::VarRef::Param(dl::ParamId::new(i))) }
        fn not(a: X) -> X { X(E::Not(bx(a))) }
        fn bin(op: B, a: X, b: X) -> X { X(E::Binary(op, bx(a), bx(b))) }
        fn pow(a: X, b: X) -> X { bin(B::Pow, a, b) }
        fn call<const N: usize>(f: F, args: [X; N]) -> X {
            X(E::Call(f, Vec::from(args.map(|a| a.0))))
        }
        fn cmp(op: C, a: X, b: X) -> X { X(E::Compare(op, bx(a), bx(b))) }
        fn logic(op: L, a: X, b: X) -> X { X(E::Logic(op, bx(a), bx(b))) }
        fn int(op: I, a: X, b: X) -> X { X(E::Int(op, bx(a), bx(b))) }
        fn ite(c: X, a: X, b: X) -> X { X(E::If(bx(c), bx(a), bx(b))) }
        fn gather(m: usize, a: X) -> X { X(E::Gather(dl::MapId::new(m), bx(a))) }
        fn sum(m: usize, a: X) -> X { X(E::Sum(dl::MapId::new(m), bx(a))) }
        fn formula(e: X) -> K { K::Formula(e.0) }
        fn sp(start: usize, end: usize) -> Span { Span { start, end } }
        fn set(s: Option<usize>) -> Option<dl::SetId> { s.map(dl::SetId::new) }
        fn fam(over: Option<usize>, dim: u8, component: u8) -> Family {
            Family { over: set(over), dim, component }
        }
        fn size_def(name: &str, default: i64, span: Span) -> dl::model::SizeDef {
            dl::model::SizeDef { name: String::from(name), default, span }
        }
        fn set_def(name: &str, size: Option<X>, elem: &str, span: Span) -> dl::model::SetDef {
            let size = size.map(|e| e.0);
            dl::model::SetDef { name: String::from(name), size, elem: String::from(elem), span }
        }
        fn map_def(
            name: &str, domain: Option<usize>, codomain: Option<usize>, kind: K, span: Span,
        ) -> dl::model::MapDef {
            dl::model::MapDef {
                name: String::from(name), domain: set(domain), codomain: set(codomain), kind, span,
            }
        }
        fn param_def(name: &str, default: f64, value: X, family: Family, span: Span)
            -> dl::model::ParamDef
        {
            dl::model::ParamDef { name: String::from(name), default, span, value: value.0, family }
        }
        fn var_def(name: &str, init: X, family: Family, span: Span) -> dl::model::VarDef {
            dl::model::VarDef { name: String::from(name), init: init.0, span, family }
        }
        fn input_def(name: &str, family: Family, derivatives: u8, default: X, span: Span)
            -> dl::model::InputDef
        {
            let default = default.0;
            dl::model::InputDef { name: String::from(name), family, derivatives, default, span }
        }
        fn constraint(name: &str, over: Option<usize>, index: usize, span: Span)
            -> dl::family::ConstraintInfo
        {
            dl::family::ConstraintInfo { name: String::from(name), over: set(over), index, span }
        }
        fn incidence(set: usize, maps: &[usize], span: Span) -> dl::family::Incidence {
            dl::family::Incidence {
                set: dl::SetId::new(set),
                maps: maps.iter().map(|&m| dl::MapId::new(m)).collect(),
                span,
            }
        }
        fn coupling(constraint: usize, alg: usize, row_map: usize, col_map: usize)
            -> dl::family::Coupling
        {
            dl::family::Coupling {
                constraint: dl::ConstraintId::new(constraint),
                alg: dl::AlgId::new(alg),
                row_map: dl::MapId::new(row_map),
                col_map: dl::MapId::new(col_map),
            }
        }
        dl::family::Construction {
            sizes: Vec::from([#(#sizes),*]),
            sets: Vec::from([#(#sets),*]),
            maps: Vec::from([#(#maps),*]),
            params: Vec::from([#(#params),*]),
            states: Vec::from([#(#states),*]),
            algs: Vec::from([#(#algs),*]),
            inputs: Vec::from([#(#inputs),*]),
            constraints: Vec::from([#(#constraints),*]),
            incidence: Vec::from([#(#incidence),*]),
            couplings: Vec::from([#(#couplings),*]),
        }
    }
}

fn opt(x: Option<impl quote::ToTokens>) -> TokenStream {
    match x {
        Some(t) => quote!(Some(#t)),
        None => quote!(None),
    }
}

fn span(s: dae_lang::ast::Span) -> TokenStream {
    let (a, b) = (usize_lit(s.start), usize_lit(s.end));
    quote!(sp(#a, #b))
}

fn family(f: Family) -> TokenStream {
    let over = opt(f.over.map(|s| usize_lit(s.index())));
    let (dim, component) = (usize_lit(f.dim.into()), usize_lit(f.component.into()));
    quote!(fam(#over, #dim, #component))
}

/// `dl::Kind::new(i)`.
fn id(kind: &str, i: usize) -> TokenStream {
    let kind = format_ident!("{kind}");
    let i = usize_lit(i);
    quote!(dl::#kind::new(#i))
}

fn var_ref(v: VarRef) -> TokenStream {
    match v {
        VarRef::Param(i) => {
            let i = usize_lit(i.index());
            return quote!(param(#i));
        }
        VarRef::Size(s) => {
            let s = usize_lit(s.index());
            return quote!(size(#s));
        }
        VarRef::Elem(s) => {
            let s = usize_lit(s.index());
            return quote!(elem(#s));
        }
        _ => {}
    }
    let v = match v {
        VarRef::State(i) => {
            let i = id("StateId", i.index());
            quote!(dl::VarRef::State(#i))
        }
        VarRef::Alg(i) => {
            let i = id("AlgId", i.index());
            quote!(dl::VarRef::Alg(#i))
        }
        VarRef::AlgRate(i) => {
            let i = id("AlgId", i.index());
            quote!(dl::VarRef::AlgRate(#i))
        }
        VarRef::Mu(k) => {
            let k = id("ConstraintId", k.index());
            quote!(dl::VarRef::Mu(#k))
        }
        VarRef::Input(i, j) => {
            let i = id("InputId", i.index());
            quote!(dl::VarRef::Input(#i, #j))
        }
        VarRef::Time => quote!(dl::VarRef::Time),
        VarRef::Param(_) | VarRef::Size(_) | VarRef::Elem(_) => unreachable!("handled above"),
    };
    quote!(var(#v))
}

/// A construction-time expression, with the helpers of [`construction_expr`].
fn rexpr(e: &RExpr) -> TokenStream {
    infix(e).0
}

/// How tightly an emitted expression binds: a sum, a product, a negation, or a call or
/// leaf (which never needs parentheses).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Level {
    Sum,
    Product,
    Negation,
    Atom,
}

/// `e` as Rust over the wrapper `X`, and how tightly it binds.
fn infix(e: &RExpr) -> (TokenStream, Level) {
    let atom = |t: TokenStream| (t, Level::Atom);
    let two = |a: &RExpr, b: &RExpr| {
        let (a, b) = (rexpr(a), rexpr(b));
        quote!(#a, #b)
    };
    match e {
        RExpr::Num(v) => {
            let v = number(*v);
            atom(quote!(num(#v)))
        }
        RExpr::Var(v) => atom(var_ref(*v)),
        RExpr::Let(l) => {
            let l = id("LetId", l.index());
            atom(quote!(X(E::Let(#l))))
        }
        RExpr::Neg(a) => {
            let a = operand(a, Level::Atom);
            (quote!(-#a), Level::Negation)
        }
        RExpr::Not(a) => {
            let a = rexpr(a);
            atom(quote!(not(#a)))
        }
        RExpr::Binary(BinOp::Pow, a, b) => {
            let ab = two(a, b);
            atom(quote!(pow(#ab)))
        }
        RExpr::Binary(op, a, b) => {
            let (level, op) = match op {
                BinOp::Add => (Level::Sum, quote!(+)),
                BinOp::Sub => (Level::Sum, quote!(-)),
                BinOp::Mul => (Level::Product, quote!(*)),
                BinOp::Div => (Level::Product, quote!(/)),
                BinOp::Pow => unreachable!("a call, above"),
            };
            // Left-associative: the left operand may be of the same level, the right
            // one must bind tighter to keep the tree.
            let a = operand(a, level);
            let b = operand(b, next(level));
            (quote!(#a #op #b), level)
        }
        RExpr::Compare(op, a, b) => {
            let op = format_ident!("{op:?}");
            let ab = two(a, b);
            atom(quote!(cmp(C::#op, #ab)))
        }
        RExpr::Logic(op, a, b) => {
            let op = format_ident!("{op:?}");
            let ab = two(a, b);
            atom(quote!(logic(L::#op, #ab)))
        }
        RExpr::Int(op, a, b) => {
            let op = format_ident!("{op:?}");
            let ab = two(a, b);
            atom(quote!(int(I::#op, #ab)))
        }
        RExpr::Call(f, args) => {
            let f = format_ident!("{f:?}");
            let args = args.iter().map(rexpr);
            atom(quote!(call(F::#f, [#(#args),*])))
        }
        RExpr::Gather(m, a) => {
            let m = usize_lit(m.index());
            let a = rexpr(a);
            atom(quote!(gather(#m, #a)))
        }
        RExpr::Sum(m, a) => {
            let m = usize_lit(m.index());
            let a = rexpr(a);
            atom(quote!(sum(#m, #a)))
        }
        RExpr::If(k, a, b) => {
            let (k, a, b) = (rexpr(k), rexpr(a), rexpr(b));
            atom(quote!(ite(#k, #a, #b)))
        }
    }
}

/// `e` as an operand that must bind at least at `level`: in parentheses if it binds
/// less tightly.
fn operand(e: &RExpr, level: Level) -> TokenStream {
    let (t, own) = infix(e);
    if own >= level { t } else { quote!((#t)) }
}

/// The level just above `level`.
fn next(level: Level) -> Level {
    match level {
        Level::Sum => Level::Product,
        Level::Product => Level::Negation,
        Level::Negation | Level::Atom => Level::Atom,
    }
}
