//! The model an FMU runs: compiled from its source at instantiation and evaluated by the
//! runtime's interpreter, as `daec run` evaluates it.

use dae_lang::family::AssignError;
use dae_runtime::Model;
use dae_runtime::family::{FamilyInstance, Interpreted, Interpreter, Kernels};

use crate::config::Config;

/// A model with the inputs an importer may drive (a family model's input families; a
/// version-1 model has none).
pub(crate) trait Driven: Model {
    /// Number of inputs.
    fn n_inputs(&self) -> usize {
        0
    }
    /// Name of input `i`.
    fn input_name(&self, _i: usize) -> &str {
        unreachable!("a model without inputs")
    }
    /// How many time derivatives input `i` carries.
    fn input_order(&self, _i: usize) -> usize {
        0
    }
    /// Value and derivatives of input `i` at the time its data was given.
    fn input_taylor(&self, _i: usize) -> &[f64] {
        &[]
    }
    /// Input `i` as the polynomial with `taylor = [value, d1, ..]` at `t0`.
    fn set_input(&mut self, _i: usize, _t0: f64, _taylor: &[f64]) -> Result<(), String> {
        Err("the model has no inputs".into())
    }
}

impl Driven for FamilyInstance<Interpreter> {
    fn n_inputs(&self) -> usize {
        FamilyInstance::n_inputs(self)
    }
    fn input_name(&self, i: usize) -> &str {
        FamilyInstance::input_name(self, i)
    }
    fn input_order(&self, i: usize) -> usize {
        FamilyInstance::input_order(self, i)
    }
    fn input_taylor(&self, i: usize) -> &[f64] {
        self.input(i).1
    }
    fn set_input(&mut self, i: usize, t0: f64, taylor: &[f64]) -> Result<(), String> {
        FamilyInstance::set_input(self, i, t0, taylor).map_err(|e| e.to_string())
    }
}

/// The model of an FMU: the interpreted model at the sizes and parameters of the
/// configuration.
pub(crate) type Loaded = Box<Interpreted>;

/// Compiles `config.model` of `src` and applies `config.sets`. Every failure is one
/// message naming what is wrong (a diagnostic is rendered with its line).
pub(crate) fn load(src: &str, config: &Config) -> Result<Loaded, String> {
    let compiled = dae_lang::compile_source(src).map_err(|errors| {
        errors
            .iter()
            .map(|d| d.render(crate::config::SOURCE_FILE, src, false))
            .collect::<Vec<_>>()
            .join("\n")
    })?;
    let names: Vec<&str> = compiled.iter().map(|m| m.name.as_str()).collect();
    let Some(compiled) = compiled.iter().find(|m| m.name == config.model).cloned() else {
        return Err(format!(
            "the source has no model `{}` (it has: {})",
            config.model,
            names.join(", ")
        ));
    };
    let version_1 = !compiled.is_family();
    let kernels = Interpreter::new(compiled);
    let c = kernels.construction();
    let mut spec = dae_lang::family::Spec::default();
    for (name, value) in &config.sets {
        spec.assign(c, name, *value).map_err(|e| match e {
            AssignError::NotWhole => format!("{name} = {value}: a size is a whole number >= 0"),
            AssignError::PerElement(family) => {
                format!("`{family}` is a per-element parameter: it is set through its formula")
            }
            AssignError::Unknown if version_1 => format!(
                "`{}` has no parameter `{name}` (a version-1 model has no sizes)",
                config.model
            ),
            AssignError::Unknown => format!("the model has no size or scalar parameter `{name}`"),
        })?;
    }
    if let Some(m) = c
        .maps
        .iter()
        .find(|m| m.kind == dae_lang::model::MapKind::Given)
    {
        return Err(format!(
            "the map `{}` is given at construction (a topology file), which an FMU does not take: give it a formula in the model",
            m.name
        ));
    }
    if let Some(s) = c.sets.iter().find(|s| s.size.is_none()) {
        return Err(format!(
            "the set `{}` is given at construction (a topology file), which an FMU does not take: give it a size in the model",
            s.name
        ));
    }
    FamilyInstance::interpreted(kernels, &spec)
        .map(Box::new)
        .map_err(|e| {
            e.to_diagnostic()
                .render(crate::config::SOURCE_FILE, src, false)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use dae_runtime::Model;

    const SRC: &str = "model Decay {
        param a = 2;
        param b = 3 * a;
        state x = b;
        alg z = 0;
        der(x) = z - x;
        constraint hold: x = b;
    }";

    #[test]
    fn a_version_1_parameter_set_in_the_configuration_reaches_those_that_read_it() {
        let mut config = Config::new("Decay", 1e-3, 1.0);
        config.sets = vec![("a".into(), 5.0)];
        let m = load(SRC, &config).unwrap();
        let b = m.param_index("b").unwrap();
        assert_eq!(m.param(b), 15.0);
        let mut x = [0.0];
        m.initial_state(&mut x);
        assert_eq!(x, [15.0]);
    }

    #[test]
    fn an_unknown_parameter_of_a_version_1_model_is_named() {
        let mut config = Config::new("Decay", 1e-3, 1.0);
        config.sets = vec![("N".into(), 5.0)];
        let err = load(SRC, &config).err().unwrap();
        assert!(
            err.contains("`Decay` has no parameter `N` (a version-1 model has no sizes)"),
            "{err}"
        );
    }
}
