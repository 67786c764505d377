//! Procedural macros for DAE models, a thin shim over `dae-codegen` (which holds the
//! logic: the token front end, the expansion and the code generator).
//!
//! Use them through `dae-runtime` with its `macros` feature, so that a crate needs one
//! dependency:
//!
//! ```toml
//! [dependencies]
//! dae-runtime = { version = "0.1", features = ["macros"] }
//! ```
//!
//! Each model becomes a public struct named after the model, whose public `f64` fields
//! are the model's parameters (`Default` gives the declared values), implementing
//! `dae_runtime::Model`; a name that Rust reserves gets a trailing underscore (see
//! `dae_codegen::rust_ident`). The whole compiler (parsing, checking, index analysis,
//! symbolic differentiation) runs at compile time: the generated functions are
//! straight-line arithmetic. Mistakes in a model are compile errors pointing at the
//! offending tokens, with the compiler's hint.
//!
//! ```
//! use dae_runtime::{Model, dae};
//!
//! dae! {
//!     // x' = z - x with x held on a sin(t): an index-2 tracking problem.
//!     model Tracking {
//!         param a = 1.0;
//!         state x = 0.0;
//!         alg z = 1.0;
//!         der(x) = z - x;
//!         constraint follow: x = a * sin(t);
//!     }
//! }
//!
//! let mut model = Tracking::default();
//! assert_eq!(model.indices(), &[2]);
//! model.a = 2.0; // parameters are fields (also `Model::set_param`)
//! let mut dx = [0.0];
//! model.rhs(0.0, &[0.5], &[1.5], &mut dx);
//! assert_eq!(dx[0], 1.0);
//! ```
//!
//! A mistake does not compile:
//!
//! ```compile_fail
//! dae_runtime::dae! {
//!     model Decay {
//!         state x = 1.0;
//!         der(x) = -k * x; // error: unknown name `k`, at `k`
//!     }
//! }
//! # fn main() {}
//! ```
//!
//! `dae_file!("models/name.dae")` does the same for a file (path relative to the crate's
//! `Cargo.toml`); build scripts can instead call `dae_codegen::compile_file_to_out_dir`
//! and `include!` the result.

use proc_macro::TokenStream;

/// Compile the `.dae` model(s) written inside the braces into Rust types.
#[proc_macro]
pub fn dae(input: TokenStream) -> TokenStream {
    dae_codegen::expand_dae(input.into()).into()
}

/// Compile the `.dae` file at a path relative to the crate's `Cargo.toml`
/// (`dae_file!("models/pendulum.dae")`); cargo rebuilds the crate when the file changes.
#[proc_macro]
pub fn dae_file(input: TokenStream) -> TokenStream {
    let dir = std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default();
    dae_codegen::expand_dae_file(input.into(), std::path::Path::new(&dir)).into()
}
