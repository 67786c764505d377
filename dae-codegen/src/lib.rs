//! `dae-codegen`: Rust code generation for DAE models, on top of `dae-lang`.
//!
//! `dae-lang` compiles a `.dae` model into a [`CompiledModel`]: its programs (the
//! straight-line groups the interpreter runs, for `rhs`, `sliding`, `jacobian` and the
//! rate `Omega'`). This crate prints them as Rust ([`generate`], [`emit_rust`]). For a
//! model without sets: one type per model, a struct whose public fields are the model's
//! parameters, implementing `::dae_runtime::Model` with straight-line code on
//! fixed-size arrays (the layout and the entries of `J_Omega` fixed at generation; no
//! allocation, shared sub-expressions computed once; `beta` and `omega_rate` from the
//! rate program, the initial values the construction's formulas over the fields).
//!
//! It also holds everything that turns Rust tokens or files into that code, so that the
//! proc-macro crate `dae-macros` stays a thin shim (as `pest_derive` over
//! `pest_generator`):
//!
//! * [`TokenSource`]: the second front door, model text given as Rust tokens (`dae!`);
//! * [`expand_dae`], [`expand_dae_file`]: the expansions of `dae!` and `dae_file!`,
//!   errors as `compile_error!` at the offending tokens;
//! * [`compile_file_to_out_dir`]: the build-script entry point.
//!
//! ```
//! let src = "
//!     model Tracking {
//!         param a = 1.0;
//!         state x = 0.0;
//!         alg z = 1.0;
//!         der(x) = z - x;
//!         constraint follow: x = a * sin(t);
//!     }";
//! let models = dae_lang::compile_source(src).expect("a valid model");
//! let rust = dae_codegen::emit_rust(&models[0]);
//! assert!(rust.contains("pub struct Tracking"));
//! assert!(rust.contains("Model for Tracking")); // `impl ::dae_runtime::Model for ...`
//! ```
//!
//! # Family models (language version 2)
//!
//! A model with sets, maps and per-element declarations (`examples/models/chain.dae`)
//! is compiled once, whatever its sizes. For it the generator emits, instead of a
//! `Model` type:
//!
//! * a kernels type named after the model (`Chain`) implementing
//!   `dae_runtime::family::Kernels`: one function per program (`rhs`, `sliding`,
//!   `jacobian`, `omega_rate`), each a sequence of loops `for e in 0..inst.set_sizes[S]`, one
//!   per group of the compiled program, around the group's straight-line code (one `let`
//!   per instruction, as for version 1). Inside a loop a family variable is read at
//!   `offset + stride * e` (offsets read from the instance's layout before the loops,
//!   strides literals of the declarations, checked against the layout once per
//!   instance; the components of a `vec3` element read or written together as one
//!   `[f64; 3]`, under one bounds check), a gather at `inst.maps[m][e]`, a sum is a scatter-add
//!   `a[m[e]] += ...` into an accumulator set to zero first, and the values of `J_Omega`
//!   are entry loops over the instance's `[entry, l, k]` lists, one per coupling. The
//!   intermediate arrays live in a scratch type (`ChainScratch`: one `[Vec<f64>; n]` per
//!   program) that `Kernels::scratch` sizes once per instance: an evaluation allocates
//!   nothing;
//! * `Kernels::construction` returns the model's `Construction` (sizes, sets, maps,
//!   declarations with their construction-time formulas, couplings), built by the
//!   generated `construction_data()` from literals: nothing is parsed or analysed at run
//!   time;
//! * `Chain::new(&spec)`: the model at the sizes of a `dae_runtime::family::Spec`
//!   (sizes, given sets and maps, scalar parameter overrides by name; defaults for the
//!   rest), the runtime's `FamilyInstance<Chain>`, which implements
//!   `dae_runtime::Model` and so runs in the `Simulator`. A size of 0, a map outside its
//!   set or an unknown name is a `ConstructError` naming the declaration.
//!
//! Nothing in the generated code depends on the sizes: one compiled binary runs a chain
//! of 10 links or of 10^5, and the code's length does not grow with them (the cloth of
//! `examples/models/cloth.dae` is 1,782 formatted lines at any size, `daec emit
//! examples/models/cloth.dae | wc -l`). The loops
//! compute what the interpreter of the same programs (`dae_lang::family::Program::eval`)
//! computes, which is the oracle of the tests. The generated code needs the runtime's
//! `families` feature:
//!
//! ```toml
//! dae-runtime = { version = "0.1", features = ["macros", "families"] }
//! ```
//!
//! ```ignore
//! dae_runtime::dae_file!("models/chain.dae");
//! let spec = dae_runtime::family::Spec { sizes: vec![("N".into(), 10_000)], ..Default::default() };
//! let chain = Chain::new(&spec)?; // a dae_runtime::Model with 60,006 states
//! ```
//!
//! # Features
//!
//! * `pretty`: [`emit_rust`] (and so [`compile_file_to_out_dir`]) formats the code with
//!   `prettyplease`, for code that people read (`daec emit`). Without it the code is the
//!   tokens' text, which compiles the same; the macros leave it off, so that a crate
//!   using `dae!` does not compile `syn` and `prettyplease`.
#![warn(missing_docs)]

mod construction;
mod expand;
mod family;
mod literals;
mod rust;
mod tokens;
mod vectors;

use dae_lang::CompiledModel;
use proc_macro2::TokenStream;

pub use expand::{compile_file_to_out_dir, expand_dae, expand_dae_file};
pub use literals::rust_ident;
pub use tokens::TokenSource;

/// The tokens of the generated type and its `Model` implementation (a model without
/// sets); for a family model, the kernels type implementing
/// `dae_runtime::family::Kernels` (see the crate documentation).
pub fn generate(model: &CompiledModel) -> TokenStream {
    if model.is_family() {
        family::generate_family(model, &model.programs)
    } else {
        rust::generate_scalar(model)
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
