//! FMI 3.0 co-simulation FMUs as plant models (`type = "fmu"`, issue 16).

mod description;
// The FMI 3.0 C interface of an FMU library.
#[allow(unsafe_code)]
mod ffi;
mod unpack;

use std::path::Path;

use self::description::{causality_name, Causality, Description, VarType, Variable};
use self::ffi::Instance;
use super::params::Params;
use super::{analog, binary, bit, Model, Port};

/// Port values of one FMI type, exchanged with one fmi3Get/Set call.
#[derive(Default)]
struct Group<T> {
    vrs: Vec<u32>,
    /// The model port of each value reference.
    ports: Vec<usize>,
    buf: Vec<T>,
}

impl<T: Copy + Default> Group<T> {
    fn push(&mut self, vr: u32, port: usize) {
        self.vrs.push(vr);
        self.ports.push(port);
        self.buf.push(T::default());
    }
}

/// The ports of one direction, by type.
#[derive(Default)]
struct Groups {
    f64: Group<f64>,
    f32: Group<f32>,
    i32: Group<i32>,
    bool: Group<bool>,
}

impl Groups {
    fn push(&mut self, v: &Variable, port: usize) {
        match v.ty {
            VarType::Float64 => self.f64.push(v.value_reference, port),
            VarType::Float32 => self.f32.push(v.value_reference, port),
            VarType::Int32 => self.i32.push(v.value_reference, port),
            VarType::Boolean => self.bool.push(v.value_reference, port),
        }
    }
}

/// A co-simulation FMU (`fmu`) stepped in virtual time: before each step the
/// model inputs are set (fmi3Set<Type>), then fmi3DoStep advances the FMU
/// from the current communication point by `dt`, then the outputs are read
/// (fmi3Get<Type>); FMI 3.0 §4.2.
///
/// Ports: the FMU's variables with `causality="input"` (model inputs) and
/// `causality="output"` (model outputs), named as in `modelDescription.xml`,
/// in its order. Types: Float64, Float32, Int32 (inputs rounded and clamped)
/// and Boolean (true when `> 0.5`; outputs 0/1). An input or output of
/// another type, or an array, is rejected at load.
///
/// TOML parameters: `file` (required: the `.fmu` archive or an unpacked FMU
/// directory; relative to the scenario file), `start` (a table of start
/// values for parameters and inputs by variable name, set before
/// initialization).
///
/// Life cycle: unpack (into a temporary directory, removed when the model is
/// dropped), load the library, fmi3InstantiateCoSimulation (no event mode,
/// no early return), the `start` values, fmi3EnterInitializationMode (start
/// time 0) and fmi3ExitInitializationMode; the outputs after initialization
/// are the sensors' power-on values. FMI 2.0 FMUs, model-exchange-only
/// FMUs and scheduled execution are rejected at load with the reason.
///
/// A failing call (fmi3Error, fmi3Fatal, fmi3Discard, or the FMU ending the
/// simulation) makes the model hold its last outputs and report the error
/// through [`Model::fault`]: the scenario stops and fails with it. The cost
/// of a step is the FMU's: softplc allocates nothing, the FMU may.
pub struct Fmu {
    instance: Instance,
    /// Dropped after the instance: the unpacked files.
    _files: unpack::Unpacked,
    inputs: Vec<Port>,
    outputs: Vec<Port>,
    set: Groups,
    get: Groups,
    out_cache: Vec<f64>,
    /// The current communication point, s.
    now: f64,
    variable_step: bool,
    last_dt: f64,
    fault: Option<String>,
}

const KIND: &str = "fmu";

/// The `file` parameter (the other keys are checked too).
fn file_of(params: &toml::Table) -> Result<&str, String> {
    let p = Params::new(KIND, params, &["file", "start"])?;
    p.str("file")?
        .ok_or_else(|| "fmu: parameter `file`: required (the .fmu file)".into())
}

fn parse_description(text: &str) -> Result<Description, String> {
    description::parse(text).map_err(|e| format!("modelDescription.xml: {e}"))
}

/// The FMU at `params.file`, unpacked, and its model description.
fn open(params: &toml::Table) -> Result<(unpack::Unpacked, Description), String> {
    let file = file_of(params)?;
    let at = |e: String| format!("fmu {file}: {e}");
    let files = unpack::open(Path::new(file)).map_err(at)?;
    let desc = files
        .model_description()
        .and_then(|t| parse_description(&t))
        .map_err(at)?;
    Ok((files, desc))
}

fn ports_of(desc: &Description, causality: Causality) -> Vec<&Variable> {
    desc.variables
        .iter()
        .filter(|v| v.causality == causality)
        .collect()
}

/// The input and output ports of the FMU at `params.file`, from its model
/// description only (nothing is loaded): for checking a scenario's bindings.
pub fn ports(params: &toml::Table) -> Result<(Vec<Port>, Vec<Port>), String> {
    let file = file_of(params)?;
    let desc = unpack::model_description(Path::new(file))
        .and_then(|t| parse_description(&t))
        .map_err(|e| format!("fmu {file}: {e}"))?;
    let names = |c| {
        ports_of(&desc, c)
            .iter()
            .map(|v| Port::Owned(v.name.clone()))
            .collect()
    };
    Ok((names(Causality::Input), names(Causality::Output)))
}

impl Fmu {
    /// Builds from TOML parameters (see the type documentation).
    pub fn from_table(params: &toml::Table) -> Result<Self, String> {
        let (files, desc) = open(params)?;
        let file = params.get("file").and_then(|f| f.as_str()).unwrap_or("");
        let at = |e: String| format!("fmu {file}: {e}");
        let mut instance = Instance::new(files.dir(), &desc, &desc.model_name).map_err(at)?;
        if let Some(start) = params.get("start") {
            let start = start.as_table().ok_or_else(|| {
                at("parameter `start`: expected a table of variable = value".into())
            })?;
            for (name, value) in start {
                set_start(&mut instance, &desc, name, value).map_err(at)?;
            }
        }
        instance.enter_initialization_mode().map_err(at)?;
        instance.exit_initialization_mode().map_err(at)?;
        let ins = ports_of(&desc, Causality::Input);
        let outs = ports_of(&desc, Causality::Output);
        let mut set = Groups::default();
        for (i, v) in ins.iter().enumerate() {
            set.push(v, i);
        }
        let mut get = Groups::default();
        for (i, v) in outs.iter().enumerate() {
            get.push(v, i);
        }
        let mut fmu = Fmu {
            instance,
            _files: files,
            inputs: ins.iter().map(|v| Port::Owned(v.name.clone())).collect(),
            outputs: outs.iter().map(|v| Port::Owned(v.name.clone())).collect(),
            set,
            get,
            out_cache: vec![0.0; outs.len()],
            now: 0.0,
            variable_step: desc.can_handle_variable_step,
            last_dt: f64::NAN,
            fault: None,
        };
        fmu.read_outputs().map_err(at)?;
        Ok(fmu)
    }

    fn write_inputs(&mut self, inputs: &[f64]) -> Result<(), String> {
        let s = &mut self.set;
        for (b, &p) in s.f64.buf.iter_mut().zip(&s.f64.ports) {
            *b = analog(inputs[p]);
        }
        for (b, &p) in s.f32.buf.iter_mut().zip(&s.f32.ports) {
            *b = analog(inputs[p]) as f32;
        }
        for (b, &p) in s.i32.buf.iter_mut().zip(&s.i32.ports) {
            // `as` saturates at the i32 range.
            *b = analog(inputs[p]).round() as i32;
        }
        for (b, &p) in s.bool.buf.iter_mut().zip(&s.bool.ports) {
            *b = binary(inputs[p]);
        }
        let i = &mut self.instance;
        if !s.f64.vrs.is_empty() {
            i.set(&s.f64.vrs, &s.f64.buf)?;
        }
        if !s.f32.vrs.is_empty() {
            i.set(&s.f32.vrs, &s.f32.buf)?;
        }
        if !s.i32.vrs.is_empty() {
            i.set(&s.i32.vrs, &s.i32.buf)?;
        }
        if !s.bool.vrs.is_empty() {
            i.set(&s.bool.vrs, &s.bool.buf)?;
        }
        Ok(())
    }

    fn read_outputs(&mut self) -> Result<(), String> {
        let g = &mut self.get;
        let i = &mut self.instance;
        if !g.f64.vrs.is_empty() {
            i.get(&g.f64.vrs, &mut g.f64.buf)?;
        }
        if !g.f32.vrs.is_empty() {
            i.get(&g.f32.vrs, &mut g.f32.buf)?;
        }
        if !g.i32.vrs.is_empty() {
            i.get(&g.i32.vrs, &mut g.i32.buf)?;
        }
        if !g.bool.vrs.is_empty() {
            i.get(&g.bool.vrs, &mut g.bool.buf)?;
        }
        let out = &mut self.out_cache;
        for (&v, &p) in g.f64.buf.iter().zip(&g.f64.ports) {
            out[p] = v;
        }
        for (&v, &p) in g.f32.buf.iter().zip(&g.f32.ports) {
            out[p] = f64::from(v);
        }
        for (&v, &p) in g.i32.buf.iter().zip(&g.i32.ports) {
            out[p] = f64::from(v);
        }
        for (&v, &p) in g.bool.buf.iter().zip(&g.bool.ports) {
            out[p] = bit(v);
        }
        Ok(())
    }

    fn advance(&mut self, dt: f64, inputs: &[f64]) -> Result<(), String> {
        if !self.variable_step && !self.last_dt.is_nan() && dt != self.last_dt {
            return Err(format!(
                "the step changed from {} s to {dt} s and the FMU cannot handle a varying \
                 step size (canHandleVariableCommunicationStepSize is false)",
                self.last_dt
            ));
        }
        self.last_dt = dt;
        self.write_inputs(inputs)?;
        self.instance.do_step(self.now, dt)?;
        self.now += dt;
        self.read_outputs()
    }
}

/// Sets a `start` value before initialization.
fn set_start(
    instance: &mut Instance,
    desc: &Description,
    name: &str,
    value: &toml::Value,
) -> Result<(), String> {
    let settable = |v: &&Variable| matches!(v.causality, Causality::Parameter | Causality::Input);
    let Some(v) = desc
        .variables
        .iter()
        .filter(settable)
        .find(|v| v.name == name)
    else {
        let known: Vec<&str> = desc
            .variables
            .iter()
            .filter(settable)
            .map(|v| v.name.as_str())
            .collect();
        let what = match desc.variables.iter().find(|v| v.name == name) {
            Some(v) => match v.causality {
                Causality::Output => format!("`{name}` is an output"),
                c => format!("`{name}` is a {}", causality_name(c)),
            },
            None => format!("no variable `{name}`"),
        };
        return Err(format!(
            "start: {what}, not a parameter or input (parameters and inputs: {})",
            if known.is_empty() {
                "none".into()
            } else {
                known.join(", ")
            }
        ));
    };
    let num = || match value {
        toml::Value::Integer(i) => Ok(*i as f64),
        toml::Value::Float(f) if f.is_finite() => Ok(*f),
        _ => Err(format!("start: `{name}`: expected a number")),
    };
    let vr = [v.value_reference];
    let r = match v.ty {
        VarType::Float64 => instance.set(&vr, &[num()?]),
        VarType::Float32 => instance.set(&vr, &[num()? as f32]),
        VarType::Int32 => {
            let x = num()?;
            if x.fract() != 0.0 || x < f64::from(i32::MIN) || x > f64::from(i32::MAX) {
                return Err(format!("start: `{name}` is an Int32 (got {x})"));
            }
            instance.set(&vr, &[x as i32])
        }
        VarType::Boolean => match value {
            toml::Value::Boolean(b) => instance.set(&vr, &[*b]),
            _ => return Err(format!("start: `{name}`: expected true or false")),
        },
    };
    r.map_err(|e| format!("start: `{name}`: {e}"))
}

impl Model for Fmu {
    fn inputs(&self) -> &[Port] {
        &self.inputs
    }

    fn outputs(&self) -> &[Port] {
        &self.outputs
    }

    fn step(&mut self, dt: f64, inputs: &[f64], outputs: &mut [f64]) {
        if dt > 0.0 && self.fault.is_none() {
            if let Err(e) = self.advance(dt, inputs) {
                self.fault = Some(e);
            }
        }
        self.outputs_now(outputs);
    }

    fn outputs_now(&self, outputs: &mut [f64]) {
        outputs[..self.out_cache.len()].copy_from_slice(&self.out_cache);
    }

    fn fault(&self) -> Option<&str> {
        self.fault.as_deref()
    }
}
