//! `daec check --set NAME=VALUE --topology FILE`: the model checked at the given sizes
//! and parameters. Each `--set` replaces the value written in the model's declaration
//! (`size N = 10;`, `param m = 1.0;`) before the model is checked and analysed, so that
//! everything the check reports (the initial point, `J_Omega` and its condition number,
//! the model built at its sizes) is for the given values.

use crate::{Reported, source};
use dae_lang::Analysis;
use dae_lang::ast::{Expr, ExprKind, Item, ModelAst};
use dae_lang::model::Model;

/// The model of `file` to check (the one it holds, or `wanted`) with `sets` applied,
/// checked and analysed; a name the model cannot take is an error naming what it can.
pub(crate) fn analysed(
    name: &str,
    src: &str,
    wanted: Option<&str>,
    sets: &[(String, f64)],
) -> Result<Vec<(Model, Analysis)>, Reported> {
    let file = dae_lang::parse(src).map_err(|d| source::report(name, src, &d))?;
    let names: Vec<&str> = file.models.iter().map(|m| m.name.name.as_str()).collect();
    let pick = match (wanted, names.len()) {
        (Some(w), _) => names.iter().position(|n| *n == w),
        (None, 1) => Some(0),
        (None, _) => None,
    };
    let Some(i) = pick else {
        match wanted {
            Some(w) => error!("`{name}` has no model `{w}` (it has: {})", names.join(", ")),
            None if names.is_empty() => error!("`{name}` holds no model"),
            None => error!(
                "`{name}` holds {} models ({}); --set and --topology apply to one: choose it with --model",
                names.len(),
                names.join(", ")
            ),
        }
        return Err(Reported);
    };
    let mut ast = file.models[i].clone();
    // Checked as written first: the errors of the model itself come with its source,
    // and whether it is a family model says what --set can take.
    let family = dae_lang::check(&ast)
        .map_err(|d| source::report(name, src, &d))?
        .is_family();
    for (what, value) in sets {
        assign(&mut ast, family, what, *value)?;
    }
    let model = dae_lang::check(&ast).map_err(|d| source::report(name, src, &d))?;
    let analysis = dae_lang::analyze(&model, &dae_lang::AnalysisOptions::default())
        .map_err(|d| source::report(name, src, &d))?;
    Ok(vec![(model, analysis)])
}

/// Replaces the value of the size or scalar parameter `what` by `value`.
fn assign(ast: &mut ModelAst, family: bool, what: &str, value: f64) -> Result<(), Reported> {
    let number = |e: &mut Expr| {
        e.kind = ExprKind::Num(value);
    };
    for item in &mut ast.items {
        match item {
            Item::Size { name, value: e, .. } if name.name == what => {
                if value.fract() != 0.0 || value < 0.0 || value > i64::MAX as f64 / 2.0 {
                    error!(
                        "--set {what}={value}: `{what}` is a size, a whole number >= 0\n  hint: e.g. --set {what}=1000"
                    );
                    return Err(Reported);
                }
                number(e);
                return Ok(());
            }
            Item::Param(decls, _) => {
                if let Some(d) = decls.iter_mut().find(|d| d.name.name == what) {
                    if d.binder.is_some() || d.ty.is_some() {
                        error!(
                            "--set {what}={value}: `{what}` is a per-element or vector parameter, not a scalar\n  hint: change the formula of its declaration"
                        );
                        return Err(Reported);
                    }
                    number(&mut d.value);
                    return Ok(());
                }
            }
            _ => {}
        }
    }
    let sizes: Vec<&str> = ast
        .items
        .iter()
        .filter_map(|i| match i {
            Item::Size { name, .. } => Some(name.name.as_str()),
            _ => None,
        })
        .collect();
    let params: Vec<&str> = ast
        .items
        .iter()
        .filter_map(|i| match i {
            Item::Param(d, _) => Some(d),
            _ => None,
        })
        .flatten()
        .filter(|d| d.binder.is_none() && d.ty.is_none())
        .map(|d| d.name.name.as_str())
        .collect();
    let list = |v: &[&str]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    if family {
        error!(
            "--set {what}={value}: the model `{}` has no size or scalar parameter `{what}`\n  hint: --set takes the sizes ({}) and the scalar parameters ({})",
            ast.name.name,
            list(&sizes),
            list(&params)
        );
    } else {
        error!(
            "--set {what}={value}: `{}` has no parameter `{what}` (a version-1 model has no sizes)\n  hint: its parameters: {}",
            ast.name.name,
            list(&params)
        );
    }
    Err(Reported)
}
