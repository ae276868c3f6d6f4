//! One FMU instance as FMI 3.0 co-simulation sees it (§4.2, the state
//! machine of §4.3): the modes, which call each allows, value references,
//! and the communication step. Safe Rust; `ffi` only converts C arguments.

use std::path::{Path, PathBuf};

use softplc_core::access::Value;

use crate::plc::{self, Causality, Config, FmiType, Plc, SCAN_TIME};

/// The value reference of the independent variable `time`.
pub const TIME_VR: u32 = 0;
/// The value reference of the `scan_time` parameter; devices follow from
/// [`FIRST_DEVICE_VR`] in the order inputs, outputs.
pub const SCAN_TIME_VR: u32 = 1;
pub const FIRST_DEVICE_VR: u32 = 2;

/// FMI 3.0 co-simulation modes softplc goes through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Instantiated,
    Initialization,
    Step,
    Terminated,
}

/// One instance.
pub struct Slave {
    resources: PathBuf,
    config: Config,
    plc: Plc,
    mode: Mode,
    /// The master's start time: the PLC's power-on.
    start: f64,
    /// The end of the last communication step (the start time before).
    now: f64,
}

impl Slave {
    /// Loads the PLC of `resources/` (its token checked against `token`
    /// when given) and powers it on.
    pub fn instantiate(resources: &Path, token: Option<&str>) -> Result<Slave, String> {
        if let Some(token) = token {
            let ours = plc::token(resources)?;
            if ours != token {
                return Err(format!(
                    "instantiation token {token} does not match the resources in {} ({ours}): \
                     modelDescription.xml and resources/ come from different exports",
                    resources.display()
                ));
            }
        }
        let config = Config::read(resources)?;
        let plc = Plc::load(resources, &config, config.scan_time_us)?;
        Ok(Slave {
            resources: resources.to_path_buf(),
            config,
            plc,
            mode: Mode::Instantiated,
            start: 0.0,
            now: 0.0,
        })
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    pub fn plc(&self) -> &Plc {
        &self.plc
    }

    /// fmi3EnterInitializationMode.
    pub fn enter_initialization(&mut self, start_time: f64) -> Result<(), String> {
        self.expect(&[Mode::Instantiated], "fmi3EnterInitializationMode")?;
        if !start_time.is_finite() {
            return Err(format!("start time {start_time} is not a number"));
        }
        self.start = start_time;
        self.now = start_time;
        self.mode = Mode::Initialization;
        Ok(())
    }

    /// fmi3ExitInitializationMode: the schedule starts.
    pub fn exit_initialization(&mut self) -> Result<(), String> {
        self.expect(&[Mode::Initialization], "fmi3ExitInitializationMode")?;
        self.plc.start();
        self.mode = Mode::Step;
        Ok(())
    }

    /// fmi3DoStep from `t` to `t + h`: every scan that ends less than 1 µs
    /// after `t + h`, counted from the start time.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<u64, String> {
        self.expect(&[Mode::Step], "fmi3DoStep")?;
        if !(t.is_finite() && h.is_finite()) || h < 0.0 {
            return Err(format!(
                "fmi3DoStep: communication point {t} and step size {h} must be finite, the step not negative"
            ));
        }
        let end_us = (t + h - self.start) * 1e6;
        if end_us < -1.0 {
            return Err(format!(
                "fmi3DoStep: t + h = {} is before the start time {}",
                t + h,
                self.start
            ));
        }
        // Scans end on whole µs: the last one due is the last before end + 1 µs.
        let until = ((end_us + 1.0).ceil() - 1.0).max(0.0) as u64;
        let ran = self.plc.run_until(until)?;
        self.now = t + h;
        Ok(ran)
    }

    /// fmi3Terminate.
    pub fn terminate(&mut self) -> Result<(), String> {
        self.expect(&[Mode::Initialization, Mode::Step], "fmi3Terminate")?;
        self.mode = Mode::Terminated;
        Ok(())
    }

    /// fmi3Reset: powered on again from the resources, as instantiated.
    pub fn reset(&mut self) -> Result<(), String> {
        self.plc = Plc::load(&self.resources, &self.config, self.config.scan_time_us)?;
        self.mode = Mode::Instantiated;
        self.start = 0.0;
        self.now = 0.0;
        Ok(())
    }

    /// fmi3GetFMUState: the whole state, between steps.
    pub fn save_state(&mut self) -> Result<Vec<u8>, String> {
        self.expect(&[Mode::Step, Mode::Terminated], "fmi3GetFMUState")?;
        Ok(self.plc.save_state(self.start, self.now))
    }

    /// fmi3SetFMUState: back to a state of [`Slave::save_state`], in Step
    /// mode; a state of another FMU or damaged is refused and nothing
    /// changes.
    pub fn load_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        self.expect(&[Mode::Step, Mode::Terminated], "fmi3SetFMUState")?;
        let (start, now) = self.plc.load_state(bytes)?;
        self.start = start;
        self.now = now;
        self.mode = Mode::Step;
        Ok(())
    }

    fn expect(&self, modes: &[Mode], call: &str) -> Result<(), String> {
        if modes.contains(&self.mode) {
            return Ok(());
        }
        let allowed: Vec<String> = modes.iter().map(|m| format!("{m:?}")).collect();
        Err(format!(
            "{call} is not allowed in {:?} mode (only in {})",
            self.mode,
            allowed.join(" or ")
        ))
    }

    /// The device variable of `vr` with its expected type.
    fn var(&self, vr: u32, ty: FmiType) -> Result<usize, String> {
        let i = (vr as usize)
            .checked_sub(FIRST_DEVICE_VR as usize)
            .filter(|&i| i < self.plc.vars.len())
            .ok_or_else(|| format!("no variable has value reference {vr}"))?;
        let v = &self.plc.vars[i];
        if v.ty != ty {
            return Err(format!(
                "`{}` (value reference {vr}) is {}, not {}",
                v.name,
                v.ty.name(),
                ty.name()
            ));
        }
        Ok(i)
    }

    /// fmi3Get<Type> of `vrs` into `out` (the same length).
    pub fn get<T: FmiValue>(&self, vrs: &[u32], out: &mut [T]) -> Result<(), String> {
        check_len(vrs.len(), out.len())?;
        for (vr, slot) in vrs.iter().zip(out.iter_mut()) {
            let i = self.var(*vr, T::TYPE)?;
            *slot = T::from_value(&self.plc.get(i)?);
        }
        Ok(())
    }

    /// fmi3Set<Type>: inputs only, in any mode before termination. All or
    /// nothing: every value is checked before any is kept.
    pub fn set<T: FmiValue>(&mut self, vrs: &[u32], values: &[T]) -> Result<(), String> {
        check_len(vrs.len(), values.len())?;
        if self.mode == Mode::Terminated {
            return Err(format!(
                "fmi3Set{} is not allowed in Terminated mode",
                T::TYPE.name()
            ));
        }
        for (vr, x) in vrs.iter().zip(values) {
            let i = self.var(*vr, T::TYPE)?;
            self.plc.check(i, &x.to_value()).map_err(|e| {
                if self.plc.vars[i].causality == Causality::Output {
                    format!(
                        "`{}` (value reference {vr}) is an output and cannot be set",
                        self.plc.vars[i].name
                    )
                } else {
                    e
                }
            })?;
        }
        for (vr, x) in vrs.iter().zip(values) {
            let i = self.var(*vr, T::TYPE)?;
            self.plc.set(i, x.to_value())?;
        }
        Ok(())
    }

    /// fmi3GetFloat64: the time and the scan time, in seconds.
    pub fn get_f64(&self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        check_len(vrs.len(), out.len())?;
        for (vr, slot) in vrs.iter().zip(out.iter_mut()) {
            *slot = if *vr == TIME_VR {
                self.now
            } else {
                self.scan_time_vr(*vr)?;
                self.plc.scan_us() as f64 / 1e6
            };
        }
        Ok(())
    }

    /// fmi3SetFloat64: the scan time, before initialization ends.
    pub fn set_f64(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        check_len(vrs.len(), values.len())?;
        for (vr, x) in vrs.iter().zip(values) {
            self.scan_time_vr(*vr)?;
            self.expect(
                &[Mode::Instantiated, Mode::Initialization],
                "setting scan_time (a fixed parameter)",
            )?;
            let us = (x * 1e6).round();
            if !(1.0..=4e12).contains(&us) {
                return Err(format!(
                    "{SCAN_TIME} = {x} s: must be at least 1 µs (and less than 46 days)"
                ));
            }
            self.plc.set_scan_us(us as u64);
        }
        Ok(())
    }

    fn scan_time_vr(&self, vr: u32) -> Result<(), String> {
        if vr == SCAN_TIME_VR {
            return Ok(());
        }
        if vr == TIME_VR {
            return Err(
                "`time` (value reference 0) is the independent variable and cannot be set".into(),
            );
        }
        match self.var(vr, FmiType::Float64) {
            Err(e) => Err(e),
            Ok(_) => Err(format!("value reference {vr} is not Float64")),
        }
    }
}

fn check_len(nvr: usize, nvalues: usize) -> Result<(), String> {
    if nvr != nvalues {
        return Err(format!(
            "{nvr} value references but {nvalues} values (softplc's variables are scalars)"
        ));
    }
    Ok(())
}

/// A C type exchanged by fmi3Get/Set<Type> with its FMI type.
pub trait FmiValue: Copy {
    const TYPE: FmiType;
    fn from_value(v: &Value) -> Self;
    fn to_value(self) -> Value;
}

macro_rules! int_value {
    ($t:ty, $fmi:ident) => {
        impl FmiValue for $t {
            const TYPE: FmiType = FmiType::$fmi;
            fn from_value(v: &Value) -> Self {
                match v {
                    Value::Int(i) => *i as $t,
                    Value::Bool(b) => *b as $t,
                    Value::Float(f) => *f as $t,
                    Value::Str(_) => 0,
                }
            }
            fn to_value(self) -> Value {
                Value::Int(self as i64)
            }
        }
    };
}

int_value!(i16, Int16);
int_value!(u16, UInt16);
int_value!(i32, Int32);
int_value!(u32, UInt32);

impl FmiValue for f32 {
    const TYPE: FmiType = FmiType::Float32;
    fn from_value(v: &Value) -> Self {
        match v {
            Value::Float(f) => *f as f32,
            Value::Int(i) => *i as f32,
            _ => 0.0,
        }
    }
    fn to_value(self) -> Value {
        Value::Float(self as f64)
    }
}

impl FmiValue for bool {
    const TYPE: FmiType = FmiType::Boolean;
    fn from_value(v: &Value) -> Self {
        matches!(v, Value::Bool(true))
    }
    fn to_value(self) -> Value {
        Value::Bool(self)
    }
}
