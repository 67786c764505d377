//! Rust code generation from a [`CompiledModel`].
//!
//! One type per model: a struct whose public fields are the model's parameters (with
//! the model's defaults in `Default`), implementing `::dae_runtime::Model`. Each trait
//! function is the straight-line code of one [`Tape`]: one `let` per instruction, so the
//! common sub-expressions shared by the outputs of a function are computed once. Inputs
//! are read from fixed-size array views (`&[f64; N]`), which removes bounds checks, and
//! nothing is allocated.
//!
//! The generated code names the runtime by absolute path (`::dae_runtime::Model`), so it
//! compiles in any crate that depends on `dae-runtime`.

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

use dae_lang::CompiledModel;
use dae_lang::tape::{BinaryOp, Instr, Operand, Tape, UnaryOp};
use dae_lang::{Func, VarRef};

/// Names a model or a parameter must not take as they are in the generated code: every
/// Rust keyword of every edition (strict, reserved and weak ones), the primitive types,
/// the names of the standard prelude (types, traits, variants, functions, derive macros),
/// and the crates and items the generated code names (`core`, `std`, `dae_runtime`,
/// `Model`). A struct named `f64` would shadow the type in every `f64` the code writes, one
/// named `Option` the prelude's in the user's module, one named `TryInto` the trait that
/// `try_into()` needs.
const RESERVED: &[&str] = &[
    // Strict keywords (2015 to 2024).
    "as",
    "async",
    "await",
    "break",
    "const",
    "continue",
    "crate",
    "dyn",
    "else",
    "enum",
    "extern",
    "false",
    "fn",
    "for",
    "if",
    "impl",
    "in",
    "let",
    "loop",
    "match",
    "mod",
    "move",
    "mut",
    "pub",
    "ref",
    "return",
    "self",
    "Self",
    "static",
    "struct",
    "super",
    "trait",
    "true",
    "type",
    "unsafe",
    "use",
    "where",
    "while",
    // Reserved keywords.
    "abstract",
    "become",
    "box",
    "do",
    "final",
    "gen",
    "macro",
    "override",
    "priv",
    "try",
    "typeof",
    "unsized",
    "virtual",
    "yield",
    // Weak keywords.
    "macro_rules",
    "raw",
    "safe",
    "union",
    // Primitive types.
    "bool",
    "char",
    "str",
    "f16",
    "f32",
    "f64",
    "f128",
    "i8",
    "i16",
    "i32",
    "i64",
    "i128",
    "isize",
    "u8",
    "u16",
    "u32",
    "u64",
    "u128",
    "usize",
    // The standard prelude (all editions).
    "Copy",
    "Send",
    "Sized",
    "Sync",
    "Unpin",
    "Drop",
    "Fn",
    "FnMut",
    "FnOnce",
    "AsyncFn",
    "AsyncFnMut",
    "AsyncFnOnce",
    "drop",
    "size_of",
    "size_of_val",
    "align_of",
    "align_of_val",
    "Box",
    "ToOwned",
    "Clone",
    "PartialEq",
    "PartialOrd",
    "Eq",
    "Ord",
    "AsRef",
    "AsMut",
    "Into",
    "From",
    "TryFrom",
    "TryInto",
    "FromIterator",
    "Default",
    "Iterator",
    "Extend",
    "IntoIterator",
    "DoubleEndedIterator",
    "ExactSizeIterator",
    "Option",
    "Some",
    "None",
    "Result",
    "Ok",
    "Err",
    "String",
    "ToString",
    "Vec",
    "Future",
    "IntoFuture",
    "Debug",
    "Hash",
    // Crates and items the generated code names.
    "core",
    "std",
    "alloc",
    "dae_runtime",
    "Model",
    "panic",
];

/// The Rust identifier of a model or parameter name (the type, or the field).
///
/// A name that is in the reserved list above, possibly followed by underscores, gets one
/// more underscore: `type` -> `type_`, `type_` -> `type__`, `f64` -> `f64_`, `Self_` ->
/// `Self__`; so does a name made of underscores only (`_` -> `__`). Other names are kept.
/// The mapping is injective (two names never give one identifier: only a name whose stem
/// is reserved changes, and it changes into a name with the same stem that was itself
/// changed), and its result is never a reserved name (none of them ends with `_`).
pub fn rust_ident(name: &str) -> String {
    let stem = name.trim_end_matches('_');
    if stem.is_empty() || RESERVED.contains(&stem) {
        format!("{name}_")
    } else {
        name.to_string()
    }
}

/// The tokens of the generated type and its `Model` implementation; for a family model
/// (`model.family` set), the kernels type implementing `dae_runtime::family::Kernels`
/// (see the crate documentation).
pub fn generate(model: &CompiledModel) -> TokenStream {
    if let Some(fam) = &model.family {
        return crate::family::generate_family(model, fam);
    }
    let ty = format_ident!("{}", rust_ident(&model.name));
    let name = &model.name;
    let fields: Vec<Ident> = model
        .params
        .iter()
        .map(|(p, _)| format_ident!("{}", rust_ident(p)))
        .collect();
    let defaults: Vec<Literal> = model
        .params
        .iter()
        .map(|(_, v)| Literal::f64_suffixed(*v))
        .collect();
    let param_docs: Vec<String> = model
        .params
        .iter()
        .map(|(p, v)| format!("Parameter `{p}` (default {v:?})."))
        .collect();
    let n = usize_lit(model.states.len());
    let m = usize_lit(model.algs.len());
    let np = usize_lit(model.params.len());
    let nw_len = model.w_len();
    let nw = usize_lit(nw_len);
    let nj = usize_lit(model.jacobian_pattern.len());
    let state_names = &model.states;
    let alg_names = &model.algs;
    let constraint_names = &model.constraints;
    let param_names: Vec<&String> = model.params.iter().map(|(p, _)| p).collect();
    let indices: Vec<Literal> = model.indices.iter().map(|r| usize_lit(*r)).collect();
    let rows: Vec<Literal> = model
        .jacobian_pattern
        .iter()
        .map(|e| usize_lit(e.0))
        .collect();
    let cols: Vec<Literal> = model
        .jacobian_pattern
        .iter()
        .map(|e| usize_lit(e.1))
        .collect();
    let param_idx: Vec<Literal> = (0..model.params.len()).map(usize_lit).collect();
    let doc = format!(
        "The DAE model `{name}`: {}, {} of {} {:?}.\n\nGenerated by dae-lang; \
         its fields are the model's parameters.",
        counted(model.states.len(), "state"),
        counted(model.algs.len(), "constraint"),
        if model.indices.len() == 1 {
            "index"
        } else {
            "indices"
        },
        model.indices
    );

    let init_state = body(&model.init_state, &fields, quote!(x));
    let init_alg = body(&model.init_alg, &fields, quote!(z));
    let rhs = body(&model.rhs, &fields, quote!(dx));
    let jac = body(&model.jacobian, &fields, quote!(values));
    let beta = body(&model.beta, &fields, quote!(beta));
    let sliding = sliding_body(&model.sliding, &fields, nw_len, model.algs.len());

    quote! {
        #[doc = #doc]
        #[derive(Clone, Debug, PartialEq)]
        #[allow(non_snake_case, non_camel_case_types)]
        pub struct #ty {
            #( #[doc = #param_docs] pub #fields: f64, )*
        }

        // A default may be any number the user wrote, e.g. 3.14159 for a parameter
        // `pi`, which clippy would deny (approx_constant) in the user's crate.
        #[allow(clippy::all)]
        impl ::core::default::Default for #ty {
            fn default() -> Self {
                Self { #( #fields: #defaults, )* }
            }
        }

        impl #ty {
            /// State names, in the order of the state vector.
            pub const STATE_NAMES: [&'static str; #n] = [#(#state_names),*];
            /// Algebraic names, in the order of the algebraic vector.
            pub const ALG_NAMES: [&'static str; #m] = [#(#alg_names),*];
            /// Constraint names.
            pub const CONSTRAINT_NAMES: [&'static str; #m] = [#(#constraint_names),*];
            /// Parameter names, in the order of `Model::param`.
            pub const PARAM_NAMES: [&'static str; #np] = [#(#param_names),*];
            /// Index of each constraint.
            pub const INDICES: [usize; #m] = [#(#indices),*];
            /// Entries of `J_Omega`, row-major.
            pub const JACOBIAN_PATTERN: [(usize, usize); #nj] = [#((#rows, #cols)),*];
        }

        #[allow(unused_variables, clippy::all)]
        impl ::dae_runtime::Model for #ty {
            fn info(&self) -> &::dae_runtime::ModelInfo {
                static INFO: ::std::sync::OnceLock<::dae_runtime::ModelInfo> =
                    ::std::sync::OnceLock::new();
                INFO.get_or_init(|| {
                    ::dae_runtime::ModelInfo::new(
                        #name,
                        &Self::STATE_NAMES,
                        &Self::ALG_NAMES,
                        &Self::CONSTRAINT_NAMES,
                        &Self::PARAM_NAMES,
                        &Self::INDICES,
                    )
                })
            }
            fn param(&self, i: usize) -> f64 {
                match i {
                    #( #param_idx => self.#fields, )*
                    _ => panic!("parameter index {} out of range: model {} has {} parameters", i, #name, #np),
                }
            }
            fn set_param(&mut self, i: usize, value: f64) {
                match i {
                    #( #param_idx => self.#fields = value, )*
                    _ => panic!("parameter index {} out of range: model {} has {} parameters", i, #name, #np),
                }
            }
            fn initial_state(&self, x: &mut [f64]) {
                let x: &mut [f64; #n] = x.try_into().expect("initial_state: x must have one entry per state");
                #init_state
            }
            fn initial_alg(&self, z: &mut [f64]) {
                let z: &mut [f64; #m] = z.try_into().expect("initial_alg: z must have one entry per algebraic");
                #init_alg
            }
            fn rhs(&self, t: f64, x: &[f64], z: &[f64], dx: &mut [f64]) {
                let x: &[f64; #n] = x.try_into().expect("rhs: x must have one entry per state");
                let z: &[f64; #m] = z.try_into().expect("rhs: z must have one entry per algebraic");
                let dx: &mut [f64; #n] = dx.try_into().expect("rhs: dx must have one entry per state");
                #rhs
            }
            fn sliding(&self, t: f64, x: &[f64], z: &[f64], mu: &[f64], w: &mut [f64], s: &mut [f64], alpha_hat: &mut [f64]) {
                let x: &[f64; #n] = x.try_into().expect("sliding: x must have one entry per state");
                let z: &[f64; #m] = z.try_into().expect("sliding: z must have one entry per algebraic");
                let mu: &[f64; #m] = mu.try_into().expect("sliding: mu must have one entry per constraint");
                let w: &mut [f64; #nw] = w.try_into().expect("sliding: w must have sum(r_i) entries");
                let s: &mut [f64; #m] = s.try_into().expect("sliding: s must have one entry per constraint");
                let alpha_hat: &mut [f64; #m] = alpha_hat.try_into().expect("sliding: alpha_hat must have one entry per constraint");
                #sliding
            }
            fn jacobian_pattern(&self) -> &[(usize, usize)] { &Self::JACOBIAN_PATTERN }
            fn jacobian(&self, t: f64, x: &[f64], z: &[f64], values: &mut [f64]) {
                let x: &[f64; #n] = x.try_into().expect("jacobian: x must have one entry per state");
                let z: &[f64; #m] = z.try_into().expect("jacobian: z must have one entry per algebraic");
                let values: &mut [f64; #nj] = values.try_into().expect("jacobian: values must match the pattern");
                #jac
            }
            fn beta(&self, t: f64, x: &[f64], z: &[f64], beta: &mut [f64]) {
                let x: &[f64; #n] = x.try_into().expect("beta: x must have one entry per state");
                let z: &[f64; #m] = z.try_into().expect("beta: z must have one entry per algebraic");
                let beta: &mut [f64; #m] = beta.try_into().expect("beta: beta must have one entry per constraint");
                #beta
            }
        }
    }
}

/// The generated code as Rust source: formatted with feature `pretty`, the tokens' text
/// (one line, the same code) without it.
pub fn emit_rust(model: &CompiledModel) -> String {
    let tokens = generate(model);
    #[cfg(feature = "pretty")]
    if let Ok(file) = syn::parse2::<syn::File>(tokens.clone()) {
        return prettyplease::unparse(&file);
    }
    // Without `pretty`, or if the generator ever produced something `syn` rejects (it
    // always produces valid Rust): the raw tokens rather than nothing.
    tokens.to_string()
}

/// `1 state`, `2 states`.
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

pub(crate) fn usize_lit(n: usize) -> Literal {
    Literal::usize_unsuffixed(n)
}

pub(crate) fn slot(k: u32) -> Ident {
    Ident::new(&format!("v{k}"), Span::call_site())
}

pub(crate) fn number(c: f64) -> TokenStream {
    if c.is_nan() {
        quote!(f64::NAN)
    } else if c == f64::INFINITY {
        quote!(f64::INFINITY)
    } else if c == f64::NEG_INFINITY {
        quote!(f64::NEG_INFINITY)
    } else if c < 0.0 {
        let l = Literal::f64_suffixed(-c);
        quote!((-#l))
    } else {
        let l = Literal::f64_suffixed(c);
        quote!(#l)
    }
}

fn operand(o: Operand, fields: &[Ident]) -> TokenStream {
    match o {
        Operand::Const(c) => number(c),
        Operand::Slot(k) => {
            let v = slot(k);
            quote!(#v)
        }
        Operand::Input(VarRef::Param(i)) => {
            let f = &fields[i.index()];
            quote!(self.#f)
        }
        Operand::Input(VarRef::State(i)) => {
            let i = usize_lit(i.index());
            quote!(x[#i])
        }
        Operand::Input(VarRef::Alg(i)) => {
            let i = usize_lit(i.index());
            quote!(z[#i])
        }
        Operand::Input(VarRef::Mu(i)) => {
            let i = usize_lit(i.index());
            quote!(mu[#i])
        }
        Operand::Input(VarRef::Time) => quote!(t),
        // Family programs only: never in a version-1 tape (`generate` rejects family
        // models first).
        Operand::Input(
            VarRef::Input(..) | VarRef::Elem(_) | VarRef::Size(_) | VarRef::AlgRate(_),
        )
        | Operand::Gather(..)
        | Operand::Array(_)
        | Operand::ArrayAt(..) => {
            quote!(::core::compile_error!(
                "an element path in a version-1 tape"
            ))
        }
    }
}

fn call_name(f: Func) -> Ident {
    Ident::new(f.name(), Span::call_site())
}

/// One instruction as an expression, its operands printed by `operand`.
pub(crate) fn instr(i: &Instr, operand: &impl Fn(Operand) -> TokenStream) -> TokenStream {
    match *i {
        Instr::Unary(op, a) => {
            let a = operand(a);
            match op {
                UnaryOp::Neg => quote!(-#a),
                UnaryOp::Powi(n) => quote!(f64::powi(#a, #n)),
                UnaryOp::Call(Func::Sign) => quote!({
                    let a: f64 = #a;
                    if a > 0.0 { 1.0 } else if a < 0.0 { -1.0 } else { a * 0.0 }
                }),
                UnaryOp::Call(f) => {
                    let name = call_name(f);
                    quote!(f64::#name(#a))
                }
            }
        }
        Instr::Binary(op, a, b) => {
            let a = operand(a);
            let b = operand(b);
            match op {
                BinaryOp::Add => quote!(#a + #b),
                BinaryOp::Sub => quote!(#a - #b),
                BinaryOp::Mul => quote!(#a * #b),
                BinaryOp::Div => quote!(#a / #b),
                BinaryOp::Call(f) => call2(f, a, b),
            }
        }
    }
}

/// A two-argument built-in, with the value [`Func::apply2`] defines.
fn call2(f: Func, a: TokenStream, b: TokenStream) -> TokenStream {
    match f {
        Func::Pow => quote!(f64::powf(#a, #b)),
        // NaN propagates, as in `Func::apply2` (f64::min would drop it).
        Func::Min | Func::Max => {
            let name = call_name(f);
            quote!({
                let (a, b): (f64, f64) = (#a, #b);
                if a.is_nan() || b.is_nan() { f64::NAN } else { f64::#name(a, b) }
            })
        }
        _ => {
            let name = call_name(f);
            quote!(f64::#name(#a, #b))
        }
    }
}

fn lets(tape: &Tape, fields: &[Ident]) -> TokenStream {
    let stmts = tape.instrs().iter().enumerate().map(|(k, i)| {
        let v = slot(k as u32);
        let e = instr(i, &|o| operand(o, fields));
        quote!(let #v: f64 = #e;)
    });
    quote!(#(#stmts)*)
}

/// Straight-line code writing all outputs of `tape` to `out[0..len]`.
fn body(tape: &Tape, fields: &[Ident], out: TokenStream) -> TokenStream {
    let lets = lets(tape, fields);
    let stores = tape.outputs().iter().enumerate().map(|(k, o)| {
        let e = operand(*o, fields);
        let k = usize_lit(k);
        quote!(#out[#k] = #e;)
    });
    quote!(#lets #(#stores)*)
}

/// The sliding tape writes three arrays: w, then s, then alpha_hat.
fn sliding_body(tape: &Tape, fields: &[Ident], nw: usize, m: usize) -> TokenStream {
    debug_assert_eq!(tape.outputs().len(), nw + 2 * m);
    let lets = lets(tape, fields);
    let stores = tape.outputs().iter().enumerate().map(|(k, o)| {
        let e = operand(*o, fields);
        if k < nw {
            let k = usize_lit(k);
            quote!(w[#k] = #e;)
        } else if k < nw + m {
            let k = usize_lit(k - nw);
            quote!(s[#k] = #e;)
        } else {
            let k = usize_lit(k - nw - m);
            quote!(alpha_hat[#k] = #e;)
        }
    });
    quote!(#lets #(#stores)*)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn rust_ident_keeps_plain_names_and_mangles_reserved_ones() {
        for plain in [
            "x", "Pendulum", "l1", "mu", "types", "_x", "x_", "v0", "selfish",
        ] {
            assert_eq!(rust_ident(plain), plain);
        }
        for (name, ident) in [
            ("type", "type_"),
            ("type_", "type__"),
            ("Self", "Self_"),
            ("Self_", "Self__"),
            ("f64", "f64_"),
            ("f64__", "f64___"),
            ("_", "__"),
            ("__", "___"),
            ("Default", "Default_"),
            ("Model", "Model_"),
            ("core", "core_"),
            ("gen", "gen_"),
            ("macro_rules", "macro_rules_"),
        ] {
            assert_eq!(rust_ident(name), ident, "{name}");
        }
    }

    #[test]
    fn rust_ident_is_injective_and_never_reserved() {
        // Every reserved name with zero to three trailing underscores, the all-underscore
        // names, and plain names: all distinct after mangling, none reserved, all
        // identifiers.
        let mut names: Vec<String> = Vec::new();
        for stem in RESERVED.iter().copied().chain(["", "x", "Pendulum"]) {
            for k in 0..4 {
                let name = format!("{stem}{}", "_".repeat(k));
                if !name.is_empty() {
                    names.push(name);
                }
            }
        }
        let mut seen = HashSet::new();
        for n in &names {
            let id = rust_ident(n);
            assert!(!RESERVED.contains(&id.as_str()), "{n} -> {id}");
            assert!(id != "_", "{n}");
            assert!(seen.insert(id.clone()), "{n} -> {id} collides");
            // A valid identifier (proc-macro2 panics on anything else).
            let _ = Ident::new(&id, Span::call_site());
        }
    }
}
