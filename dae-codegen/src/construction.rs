//! A family model's [`Construction`] as a Rust expression: what the generated
//! `construction_data()` returns, built from literals (no parsing or analysis at run
//! time).
//!
//! The body declares a few short helper functions (`bin`, `num`,
//! `size`, `sp`, `param_def`, ...) and then the value, so that the code stays small:
//! one line for most declarations instead of a struct literal over several.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};

use dae_lang::VarRef;
use dae_lang::family::Construction;
use dae_lang::model::{Family, MapKind, RExpr};

use crate::family::lang;
use crate::rust::{number, usize_lit};

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
                quote!(K::Formula(#e))
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
        use dl::model::{Family, IntOp as I, MapKind as K, RExpr as E};
        use ::std::boxed::Box;
        use ::std::string::String;
        use ::std::vec::Vec;
        use ::core::option::Option::{self, None, Some};
        fn bx(e: E) -> Box<E> { Box::new(e) }
        fn num(v: f64) -> E { E::Num(v) }
        fn var(v: dl::VarRef) -> E { E::Var(v) }
        fn size(i: usize) -> E { E::Var(dl::VarRef::Size(dl::SizeId::new(i))) }
        fn elem(i: usize) -> E { E::Var(dl::VarRef::Elem(dl::SetId::new(i))) }
        fn param(i: usize) -> E { E::Var(dl::VarRef::Param(dl::ParamId::new(i))) }
        fn neg(a: E) -> E { E::Neg(bx(a)) }
        fn not(a: E) -> E { E::Not(bx(a)) }
        fn bin(op: B, a: E, b: E) -> E { E::Binary(op, bx(a), bx(b)) }
        fn cmp(op: C, a: E, b: E) -> E { E::Compare(op, bx(a), bx(b)) }
        fn logic(op: L, a: E, b: E) -> E { E::Logic(op, bx(a), bx(b)) }
        fn int(op: I, a: E, b: E) -> E { E::Int(op, bx(a), bx(b)) }
        fn ite(c: E, a: E, b: E) -> E { E::If(bx(c), bx(a), bx(b)) }
        fn gather(m: usize, a: E) -> E { E::Gather(dl::MapId::new(m), bx(a)) }
        fn sum(m: usize, a: E) -> E { E::Sum(dl::MapId::new(m), bx(a)) }
        fn sp(start: usize, end: usize) -> Span { Span { start, end } }
        fn set(s: Option<usize>) -> Option<dl::SetId> { s.map(dl::SetId::new) }
        fn fam(over: Option<usize>, dim: u8, component: u8) -> Family {
            Family { over: set(over), dim, component }
        }
        fn size_def(name: &str, default: i64, span: Span) -> dl::model::SizeDef {
            dl::model::SizeDef { name: String::from(name), default, span }
        }
        fn set_def(name: &str, size: Option<E>, elem: &str, span: Span) -> dl::model::SetDef {
            dl::model::SetDef { name: String::from(name), size, elem: String::from(elem), span }
        }
        fn map_def(
            name: &str, domain: Option<usize>, codomain: Option<usize>, kind: K, span: Span,
        ) -> dl::model::MapDef {
            dl::model::MapDef {
                name: String::from(name), domain: set(domain), codomain: set(codomain), kind, span,
            }
        }
        fn param_def(name: &str, default: f64, value: E, family: Family, span: Span)
            -> dl::model::ParamDef
        {
            dl::model::ParamDef { name: String::from(name), default, span, value, family }
        }
        fn var_def(name: &str, init: E, family: Family, span: Span) -> dl::model::VarDef {
            dl::model::VarDef { name: String::from(name), init, span, family }
        }
        fn input_def(name: &str, family: Family, derivatives: u8, default: E, span: Span)
            -> dl::model::InputDef
        {
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
    let two = |a: &RExpr, b: &RExpr| {
        let (a, b) = (rexpr(a), rexpr(b));
        quote!(#a, #b)
    };
    match e {
        RExpr::Num(v) => {
            let v = number(*v);
            quote!(num(#v))
        }
        RExpr::Var(v) => var_ref(*v),
        RExpr::Let(l) => {
            let l = id("LetId", l.index());
            quote!(E::Let(#l))
        }
        RExpr::Neg(a) => {
            let a = rexpr(a);
            quote!(neg(#a))
        }
        RExpr::Not(a) => {
            let a = rexpr(a);
            quote!(not(#a))
        }
        RExpr::Binary(op, a, b) => {
            let op = format_ident!("{op:?}");
            let ab = two(a, b);
            quote!(bin(B::#op, #ab))
        }
        RExpr::Compare(op, a, b) => {
            let op = format_ident!("{op:?}");
            let ab = two(a, b);
            quote!(cmp(C::#op, #ab))
        }
        RExpr::Logic(op, a, b) => {
            let op = format_ident!("{op:?}");
            let ab = two(a, b);
            quote!(logic(L::#op, #ab))
        }
        RExpr::Int(op, a, b) => {
            let op = format_ident!("{op:?}");
            let ab = two(a, b);
            quote!(int(I::#op, #ab))
        }
        RExpr::Call(f, args) => {
            let f = format_ident!("{f:?}");
            let args = args.iter().map(rexpr);
            quote!(E::Call(dl::Func::#f, Vec::from([#(#args),*])))
        }
        RExpr::Gather(m, a) => {
            let m = usize_lit(m.index());
            let a = rexpr(a);
            quote!(gather(#m, #a))
        }
        RExpr::Sum(m, a) => {
            let m = usize_lit(m.index());
            let a = rexpr(a);
            quote!(sum(#m, #a))
        }
        RExpr::If(k, a, b) => {
            let (k, a, b) = (rexpr(k), rexpr(a), rexpr(b));
            quote!(ite(#k, #a, #b))
        }
    }
}
