//! `modelDescription.xml` (FMI 2.0, co-simulation) from the variables of the model.

use std::fmt::Write;

use crate::config::Config;
use crate::variables::{Kind, Variable};

/// `&`, `<`, `>`, `"` escaped for an attribute.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The attributes and the description of a variable of each kind.
fn attributes(v: &Variable) -> (&'static str, &'static str, String) {
    match v.kind {
        Kind::Eps => (
            "parameter",
            "fixed",
            "layer half-width of every constraint: |s_i| <= eps after reaching".into(),
        ),
        Kind::Param => ("parameter", "fixed", "parameter of the model".into()),
        Kind::State => ("output", "continuous", "differential state".into()),
        Kind::Alg => ("output", "continuous", "algebraic unknown".into()),
        Kind::Error => (
            "output",
            "continuous",
            "constraint error g(t, x), the constraint's w".into(),
        ),
        Kind::Input => ("input", "continuous", "input of the model".into()),
    }
}

/// The whole `modelDescription.xml` of an FMU whose library is `identifier`.
pub(crate) fn model_description(
    config: &Config,
    identifier: &str,
    vars: &[Variable],
    generation: &str,
) -> String {
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="{}" guid="{}" description="DAE model simulated by DBSMC: every constraint error held in its layer eps" generationTool="{}" variableNamingConvention="flat" numberOfEventIndicators="0">"#,
        escape(&config.model),
        escape(&config.guid),
        escape(generation)
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{identifier}" needsExecutionTool="false" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="true" maxOutputDerivativeOrder="0" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="false" canSerializeFMUstate="false" providesDirectionalDerivative="false"/>"#
    );
    let _ = writeln!(
        x,
        r#"  <DefaultExperiment startTime="{:?}" stopTime="{:?}" stepSize="{:?}"/>"#,
        config.start_time, config.stop_time, config.step_size
    );
    let _ = writeln!(x, "  <ModelVariables>");
    for (vr, v) in vars.iter().enumerate() {
        let (causality, variability, description) = attributes(v);
        let initial = if causality == "parameter" {
            r#" initial="exact""#
        } else {
            ""
        };
        let _ = writeln!(
            x,
            r#"    <ScalarVariable name="{}" valueReference="{vr}" description="{}" causality="{causality}" variability="{variability}"{initial}>"#,
            escape(&v.name),
            escape(&description)
        );
        match v.start {
            Some(s) => {
                let _ = writeln!(x, r#"      <Real start="{s:?}"/>"#);
            }
            None => {
                let _ = writeln!(x, "      <Real/>");
            }
        }
        let _ = writeln!(x, "    </ScalarVariable>");
    }
    let _ = writeln!(x, "  </ModelVariables>");
    let _ = writeln!(x, "  <ModelStructure>");
    let outputs: Vec<usize> = vars
        .iter()
        .enumerate()
        .filter(|(_, v)| matches!(v.kind, Kind::State | Kind::Alg | Kind::Error))
        .map(|(i, _)| i + 1)
        .collect();
    for section in ["Outputs", "InitialUnknowns"] {
        if outputs.is_empty() {
            continue;
        }
        let _ = writeln!(x, "    <{section}>");
        for i in &outputs {
            let _ = writeln!(x, r#"      <Unknown index="{i}"/>"#);
        }
        let _ = writeln!(x, "    </{section}>");
    }
    let _ = writeln!(x, "  </ModelStructure>");
    let _ = writeln!(x, "</fmiModelDescription>");
    x
}

#[cfg(test)]
mod tests {
    use super::escape;

    #[test]
    fn names_are_escaped_for_attributes() {
        assert_eq!(escape(r#"a<b>&"c""#), "a&lt;b&gt;&amp;&quot;c&quot;");
    }
}
