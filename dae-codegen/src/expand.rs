//! Support for the `dae!` and `dae_file!` macros and for build scripts.
//!
//! The proc-macro crate `dae-macros` is a thin shim over these functions, so that all
//! the logic lives here. Errors become `compile_error!`s: for `dae!`
//! at the span of the offending token, for `dae_file!` at the path literal, with the
//! rendered diagnostic (file:line:col, source line, hint) as the message.

use std::path::{Path, PathBuf};

use proc_macro2::{Delimiter, Group, Literal, Span, TokenStream, TokenTree};
use quote::{quote, quote_spanned};

use dae_lang::Diagnostic;

use crate::tokens::TokenSource;
use crate::{emit_rust, generate};

/// Expand `dae! { model ... }`: the generated types, or compile errors at the tokens.
pub fn expand_dae(input: TokenStream) -> TokenStream {
    let src = TokenSource::new(input);
    match dae_lang::compile_source(src.text()) {
        Ok(models) => models.iter().map(generate).collect(),
        Err(diags) => diags
            .iter()
            .map(|d| {
                let (first, last) = src.span_range(d.span);
                compile_error_between(first, last, &one_line(d))
            })
            .collect(),
    }
}

/// Expand `dae_file!("path/relative/to/the/crate.dae")`.
///
/// `manifest_dir` is the user crate's `CARGO_MANIFEST_DIR`. The expansion includes the
/// file with `include_str!` so that cargo rebuilds the crate when the file changes.
pub fn expand_dae_file(input: TokenStream, manifest_dir: &Path) -> TokenStream {
    let (rel, span) = match path_literal(input) {
        Ok(x) => x,
        Err((span, msg)) => return quote_spanned!(span=> ::core::compile_error!(#msg);),
    };
    let path = manifest_dir.join(&rel);
    let source = match std::fs::read_to_string(&path) {
        Ok(s) => s,
        Err(e) => {
            let msg = format!("cannot read `{}`: {e}", path.display());
            return quote_spanned!(span=> ::core::compile_error!(#msg););
        }
    };
    let abs = path.to_string_lossy().into_owned();
    match dae_lang::compile_source(&source) {
        Ok(models) => {
            let types: TokenStream = models.iter().map(generate).collect();
            quote! {
                const _: &str = ::core::include_str!(#abs);
                #types
            }
        }
        Err(diags) => {
            let renderer = dae_lang::Renderer::new(&rel, &source, false);
            let msg: String = diags.iter().map(|d| renderer.render(d)).collect();
            quote_spanned!(span=> ::core::compile_error!(#msg);)
        }
    }
}

/// For build scripts: compile the `.dae` file at `path` into `OUT_DIR/<stem>.rs` and
/// tell cargo to rerun when it changes. Include the result with
/// `include!(concat!(env!("OUT_DIR"), "/<stem>.rs"));`.
///
/// Returns the written path, or the rendered diagnostics.
pub fn compile_file_to_out_dir(path: impl AsRef<Path>) -> Result<PathBuf, String> {
    let path = path.as_ref();
    println!("cargo:rerun-if-changed={}", path.display());
    let out_dir = std::env::var_os("OUT_DIR")
        .ok_or_else(|| "OUT_DIR is not set: call this from a build script".to_string())?;
    let source = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    let name = path.display().to_string();
    let models = dae_lang::compile_source(&source).map_err(|ds| {
        let renderer = dae_lang::Renderer::new(&name, &source, false);
        ds.iter().map(|d| renderer.render(d)).collect::<String>()
    })?;
    let code: String = models.iter().map(emit_rust).collect::<Vec<_>>().join("\n");
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let out = Path::new(&out_dir).join(format!("{stem}.rs"));
    std::fs::write(&out, code).map_err(|e| format!("cannot write `{}`: {e}", out.display()))?;
    Ok(out)
}

/// `::core::compile_error! { "msg" }` with the path at `first` and the braces at
/// `last`: rustc reports the error over the whole range from `first` to `last`.
fn compile_error_between(first: Span, last: Span, msg: &str) -> TokenStream {
    let path = quote_spanned!(first=> ::core::compile_error!);
    let mut lit = Literal::string(msg);
    lit.set_span(last);
    let mut body = Group::new(Delimiter::Brace, TokenTree::Literal(lit).into());
    body.set_span(last);
    let mut out = path;
    out.extend([TokenTree::Group(body)]);
    out
}

/// A diagnostic as one message for `compile_error!`: what, then the hint.
fn one_line(d: &Diagnostic) -> String {
    match &d.hint {
        Some(h) => format!("{}\n  = help: {h}", d.message),
        None => d.message.clone(),
    }
}

fn path_literal(input: TokenStream) -> Result<(String, Span), (Span, String)> {
    let mut it = input.into_iter();
    let usage = "expected one string literal: dae_file!(\"models/name.dae\")";
    let lit = match (it.next(), it.next()) {
        (Some(TokenTree::Literal(l)), None) => l,
        (Some(t), _) => return Err((t.span(), usage.to_string())),
        (None, _) => return Err((Span::call_site(), usage.to_string())),
    };
    let text = lit.to_string();
    match text.strip_prefix('"').and_then(|s| s.strip_suffix('"')) {
        Some(s) if !s.contains('\\') => Ok((s.to_string(), lit.span())),
        _ => Err((lit.span(), usage.to_string())),
    }
}
