//! `modelDescription.xml` of an FMU: what softplc needs to instantiate a
//! co-simulation FMU and exchange its scalar variables (FMI 3.0 §2.4).

/// The value types softplc exchanges with an FMU (FMI 3.0 §2.4.7.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarType {
    Float64,
    Float32,
    Int32,
    Boolean,
}

/// `causality` (FMI 3.0 §2.4.7.4): only these matter to softplc; others
/// (local, independent, calculatedParameter, structuralParameter) are kept
/// as `Other`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
    Other,
}

/// One scalar variable.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    pub value_reference: u32,
    pub causality: Causality,
    pub ty: VarType,
    /// `variability="constant"` or `"fixed"`: settable only before
    /// initialization.
    pub fixed: bool,
}

/// The parts of the model description softplc uses.
#[derive(Clone, Debug, PartialEq)]
pub struct Description {
    pub model_name: String,
    pub instantiation_token: String,
    /// `<CoSimulation modelIdentifier>`: the shared library's base name.
    pub model_identifier: String,
    pub can_handle_variable_step: bool,
    pub variables: Vec<Variable>,
}

/// The scalar types of FMI 3.0 that softplc does not exchange, for the
/// error message.
const OTHER_TYPES: &[&str] = &[
    "Int8",
    "UInt8",
    "Int16",
    "UInt16",
    "UInt32",
    "Int64",
    "UInt64",
    "String",
    "Binary",
    "Enumeration",
    "Clock",
];

/// Parses `text` (the content of `modelDescription.xml`). Errors say what is
/// wrong and where (line of the element).
pub fn parse(text: &str) -> Result<Description, String> {
    let doc = roxmltree::Document::parse(text).map_err(|e| format!("not valid XML: {e}"))?;
    let root = doc.root_element();
    let at = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row;
    if root.tag_name().name() != "fmiModelDescription" {
        return Err(format!(
            "the root element is <{}>, not <fmiModelDescription>",
            root.tag_name().name()
        ));
    }
    let version = root.attribute("fmiVersion").unwrap_or("");
    if !version.starts_with("3.") {
        return Err(if version.starts_with("2.") {
            format!(
                "fmiVersion {version}: FMI 2.0 FMUs are not supported, only FMI 3.0 co-simulation \
                 (export the model as FMI 3.0)"
            )
        } else {
            format!("fmiVersion `{version}`: only FMI 3.0 co-simulation FMUs are supported")
        });
    }
    let token = root
        .attribute("instantiationToken")
        .ok_or("<fmiModelDescription> has no instantiationToken")?;
    let model_name = root.attribute("modelName").unwrap_or("").to_string();
    let cs = root
        .children()
        .find(|n| n.has_tag_name("CoSimulation"))
        .ok_or_else(|| {
            let kinds: Vec<&str> = root
                .children()
                .filter(|n| n.has_tag_name("ModelExchange") || n.has_tag_name("ScheduledExecution"))
                .map(|n| n.tag_name().name())
                .collect();
            format!(
                "the FMU has no <CoSimulation> interface{} (softplc steps co-simulation FMUs only)",
                if kinds.is_empty() {
                    String::new()
                } else {
                    format!(" (it has {})", kinds.join(", "))
                }
            )
        })?;
    let model_identifier = cs
        .attribute("modelIdentifier")
        .filter(|m| !m.is_empty())
        .ok_or_else(|| format!("line {}: <CoSimulation> has no modelIdentifier", at(cs)))?;
    let flag = |n: roxmltree::Node, a: &str| n.attribute(a) == Some("true");
    let mut variables = Vec::new();
    if let Some(vars) = root.children().find(|n| n.has_tag_name("ModelVariables")) {
        for v in vars.children().filter(|n| n.is_element()) {
            let line = at(v);
            let tag = v.tag_name().name();
            let name = v
                .attribute("name")
                .ok_or_else(|| format!("line {line}: <{tag}> has no name"))?;
            let causality = match v.attribute("causality").unwrap_or("local") {
                "parameter" => Causality::Parameter,
                "input" => Causality::Input,
                "output" => Causality::Output,
                _ => Causality::Other,
            };
            let ty = match tag {
                "Float64" => VarType::Float64,
                "Float32" => VarType::Float32,
                "Int32" => VarType::Int32,
                "Boolean" => VarType::Boolean,
                t if OTHER_TYPES.contains(&t) => {
                    if causality == Causality::Other {
                        continue;
                    }
                    return Err(format!(
                        "line {line}: {} `{name}` has type {t}: softplc exchanges Float64, \
                         Float32, Int32 and Boolean variables only",
                        causality_name(causality)
                    ));
                }
                t => return Err(format!("line {line}: unknown variable element <{t}>")),
            };
            if v.children().any(|c| c.has_tag_name("Dimension")) {
                if causality == Causality::Other {
                    continue;
                }
                return Err(format!(
                    "line {line}: variable `{name}` is an array: softplc exchanges scalar variables only"
                ));
            }
            let value_reference = v
                .attribute("valueReference")
                .and_then(|r| r.parse::<u32>().ok())
                .ok_or_else(|| {
                    format!("line {line}: variable `{name}` has no valid valueReference")
                })?;
            let fixed = matches!(v.attribute("variability"), Some("fixed" | "constant"));
            variables.push(Variable {
                name: name.to_string(),
                value_reference,
                causality,
                ty,
                fixed,
            });
        }
    }
    Ok(Description {
        model_name,
        instantiation_token: token.to_string(),
        model_identifier: model_identifier.to_string(),
        can_handle_variable_step: flag(cs, "canHandleVariableCommunicationStepSize"),
        variables,
    })
}

pub fn causality_name(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Other => "local variable",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEATER: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="Heater" instantiationToken="tok-1">
  <CoSimulation modelIdentifier="Heater" canHandleVariableCommunicationStepSize="true"/>
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
    <Float64 name="capacity" valueReference="1" causality="parameter" variability="fixed" start="1000"/>
    <Float64 name="u" valueReference="5" causality="input" start="0"/>
    <Boolean name="on" valueReference="7" causality="input"/>
    <Int32 name="count" valueReference="8" causality="output"/>
    <Float64 name="temperature" valueReference="6" causality="output"/>
    <String name="note" valueReference="9" causality="local"/>
  </ModelVariables>
</fmiModelDescription>"#;

    #[test]
    fn reads_identifier_token_and_scalar_variables() {
        let d = parse(HEATER).unwrap();
        assert_eq!(d.model_identifier, "Heater");
        assert_eq!(d.instantiation_token, "tok-1");
        assert!(d.can_handle_variable_step);
        let names: Vec<&str> = d.variables.iter().map(|v| v.name.as_str()).collect();
        // The String local is not exchanged and is left out.
        assert_eq!(
            names,
            ["time", "capacity", "u", "on", "count", "temperature"]
        );
        assert_eq!(
            d.variables[1],
            Variable {
                name: "capacity".into(),
                value_reference: 1,
                causality: Causality::Parameter,
                ty: VarType::Float64,
                fixed: true,
            }
        );
        assert_eq!(d.variables[3].ty, VarType::Boolean);
        assert_eq!(d.variables[4].causality, Causality::Output);
        assert_eq!(d.variables[4].ty, VarType::Int32);
    }

    #[test]
    fn rejects_what_softplc_cannot_step_with_the_reason() {
        let err = |t: &str| parse(t).unwrap_err();
        assert!(err("<x").contains("not valid XML"));
        assert!(err("<fmiModelDescription fmiVersion=\"2.0\" guid=\"g\"/>")
            .contains("FMI 2.0 FMUs are not supported"));
        let me = "<fmiModelDescription fmiVersion=\"3.0\" instantiationToken=\"t\">\
                  <ModelExchange modelIdentifier=\"m\"/></fmiModelDescription>";
        assert!(err(me).contains("no <CoSimulation> interface (it has ModelExchange)"));
        let s = HEATER.replace(
            r#"<String name="note" valueReference="9" causality="local"/>"#,
            r#"<String name="note" valueReference="9" causality="output"/>"#,
        );
        assert_eq!(
            err(&s),
            "line 11: output `note` has type String: softplc exchanges Float64, Float32, \
             Int32 and Boolean variables only"
        );
        let no_vr = HEATER.replace(r#"valueReference="5" "#, "");
        assert!(err(&no_vr).contains("line 7: variable `u` has no valid valueReference"));
    }
}
