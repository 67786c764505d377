//! The identifiers and literals of generated code: the mangling of user names, number
//! and index literals, the slots of a tape, one instruction as an expression, and the
//! names under which the family kernels read their variables and maps. Both generators
//! (`rust` for version-1 models, `family` with `construction` and `vectors`) print
//! through these, so the same instruction is the same Rust in both.

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

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
                UnaryOp::Call(f) => call1(f, a),
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

/// A call of a built-in with the value [`Func::apply1`] or [`Func::apply2`] defines
/// (NaN for another number of arguments, which no checked model has).
pub(crate) fn call(f: Func, args: &[TokenStream]) -> TokenStream {
    match args {
        [a] => call1(f, a.clone()),
        [a, b] => call2(f, a.clone(), b.clone()),
        _ => quote!(f64::NAN),
    }
}

/// A one-argument built-in, with the value [`Func::apply1`] defines.
fn call1(f: Func, a: TokenStream) -> TokenStream {
    match f {
        Func::Sign => quote!({
            let a: f64 = #a;
            if a > 0.0 { 1.0 } else if a < 0.0 { -1.0 } else { a * 0.0 }
        }),
        _ => {
            let name = call_name(f);
            quote!(f64::#name(#a))
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

/// One `let` per instruction of `tape`, `let v<k>: f64 = ...;`, with its operands
/// written by `operand`.
pub(crate) fn lets(tape: &Tape, operand: &impl Fn(Operand) -> TokenStream) -> TokenStream {
    let stmts = tape.instrs().iter().enumerate().map(|(k, i)| {
        let v = slot(k as u32);
        let e = instr(i, operand);
        quote!(let #v: f64 = #e;)
    });
    quote!(#(#stmts)*)
}

/// The path of `dae-lang` as the runtime re-exports it (feature `families`).
pub(crate) fn lang() -> TokenStream {
    quote!(::dae_runtime::__dae_lang)
}

/// The local holding a variable: its value (scalar) or its slot (family).
pub(crate) fn var_ident(v: VarRef) -> Ident {
    match v {
        VarRef::Param(i) => format_ident!("p{}", i.index()),
        VarRef::State(i) => format_ident!("x{}", i.index()),
        VarRef::Alg(i) => format_ident!("z{}", i.index()),
        VarRef::AlgRate(i) => format_ident!("zr{}", i.index()),
        VarRef::Mu(k) => format_ident!("mu{}", k.index()),
        // Each derivative of an input has its own slot (a derivative block apart).
        VarRef::Input(i, j) => format_ident!("u{}_{}", i.index(), j),
        VarRef::Time => format_ident!("t"),
        VarRef::Elem(_) => format_ident!("e"),
        VarRef::Size(s) => format_ident!("size{}", s.index()),
    }
}

/// The vector a variable is read from and its [`Slot`](dae_lang::family::Slot) in
/// the instance's layout (an expression).
pub(crate) fn var_source(v: VarRef) -> Option<(TokenStream, TokenStream)> {
    let lit = |i: usize| usize_lit(i);
    Some(match v {
        VarRef::Param(i) => {
            let i = lit(i.index());
            (quote!(vals.params), quote!(inst.layout.params[#i]))
        }
        VarRef::State(i) => {
            let i = lit(i.index());
            (quote!(vals.states), quote!(inst.layout.states[#i]))
        }
        VarRef::Alg(i) => {
            let i = lit(i.index());
            (quote!(vals.algs), quote!(inst.layout.algs[#i]))
        }
        VarRef::AlgRate(i) => {
            let i = lit(i.index());
            (quote!(vals.alg_rates), quote!(inst.layout.algs[#i]))
        }
        VarRef::Mu(k) => {
            let k = lit(k.index());
            (quote!(vals.mu), quote!(inst.layout.rows[#k]))
        }
        // Derivative `j` sits `j` derivative blocks (a size-dependent length) further.
        VarRef::Input(i, j) => {
            let (i, j) = (lit(i.index()), lit(j as usize));
            (quote!(vals.inputs), quote!(inst.layout.input_value(#i, #j)))
        }
        VarRef::Time | VarRef::Elem(_) | VarRef::Size(_) => return None,
    })
}

pub(crate) fn map_ident(m: usize) -> Ident {
    format_ident!("m{m}")
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
