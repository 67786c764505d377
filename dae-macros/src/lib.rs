//! Procedural macros for DAE models, a thin shim over `dae-lang`.
//!
//! Use them through `dae-runtime` with its `macros` feature (`use dae_runtime::dae;`),
//! so that a crate needs one dependency. Each model becomes a type implementing
//! `dae_runtime::Model`; mistakes in a model are compile errors at the offending token.
//!
//! ```ignore
//! dae_runtime::dae! {
//!     model Decay {
//!         param k = 0.5;
//!         state x = 1.0;
//!         alg y = 0.0;
//!         der(x) = -k * x;
//!         constraint y = 2 * x;
//!     }
//! }
//! let model = Decay::default();
//! ```

use proc_macro::TokenStream;

/// Compile the `.dae` model(s) written inside the braces into Rust types.
#[proc_macro]
pub fn dae(input: TokenStream) -> TokenStream {
    dae_lang::expand::expand_dae(input.into()).into()
}

/// Compile the `.dae` file at a path relative to the crate's `Cargo.toml`
/// (`dae_file!("models/pendulum.dae")`); cargo rebuilds the crate when the file changes.
#[proc_macro]
pub fn dae_file(input: TokenStream) -> TokenStream {
    let dir = std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default();
    dae_lang::expand::expand_dae_file(input.into(), std::path::Path::new(&dir)).into()
}
