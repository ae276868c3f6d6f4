//! Scenario files: TOML parsing and validation. Everything that does not need
//! the CPU is checked here (syntax of device names, times inside the run,
//! model types and parameters); device ranges are checked when the scenario is
//! built against the loaded program.

use softplc_core::names::Names;
use softplc_core::profile::Profile;
use std::path::PathBuf;

mod expect;
mod fleet;
mod parse;
mod peer;
mod values;

pub use fleet::{BlockSpec, ClientProtocol, ClientSpec, LinkSpec, PlcSpec, PortRef, Remote};
pub(crate) use values::channel;
pub use values::Layout;

/// What the scenario runs: a program file or a project.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A program file (`.il` or GX Works2 `.csv`).
    Program(PathBuf),
    /// A project directory or its `plc.toml`.
    Project(PathBuf),
    /// A multi-CPU system: a directory with `system.toml`, or that file.
    /// Device names take `CPUn/` prefixes (`CPU2/D0`; none is CPU 1).
    System(PathBuf),
}

/// Scaling of a model port bound to a device.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// Values pass unchanged (bits are 0/1; word values are rounded and clamped
    /// to the device type; `:f32` devices hold the value as is).
    None,
    /// A/D (model output → device) or D/A (device → model input) conversion
    /// between the engineering range and the raw digital range.
    Analog { raw: (i32, i32), eng: (f64, f64) },
    /// A bit device read as a model input: `off` when OFF, `on` when ON.
    Bit { off: f64, on: f64 },
    /// A module channel (`U<n>\CH<k>`) and an engineering value: the linear
    /// map of `eng` onto the channel's physical `signal` (mA or V), as a
    /// transmitter (model output → analog input) or an actuator (analog
    /// output → model input) scales it. Not clamped: the module fixes what
    /// is beyond its range.
    Signal { signal: (f64, f64), eng: (f64, f64) },
}

/// Where a model input comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum InputBinding {
    /// A constant value.
    Const(f64),
    /// A device read before every step.
    Device { device: String, scale: Scale },
}

/// Where a model output goes.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputBinding {
    pub device: String,
    pub scale: Scale,
}

/// A plant model bound to devices.
#[derive(Clone, Debug)]
pub struct ModelSpec {
    pub name: String,
    pub kind: String,
    pub params: toml::Table,
    /// (port index, binding), in port order.
    pub inputs: Vec<(usize, InputBinding)>,
    pub outputs: Vec<(usize, OutputBinding)>,
}

/// A write before a scan (timeline entries with `every` are expanded).
#[derive(Clone, Debug, PartialEq)]
pub struct EventSpec {
    /// 1-based scan before which the writes happen.
    pub scan: u64,
    /// (device, value as text for `Cpu::write_device`).
    pub set: Vec<(String, String)>,
}

/// A condition on one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cond {
    /// `|v − value| ≤ tol` (for `:f32` devices with `tol = 0`, `value` is
    /// compared after rounding to f32).
    Eq {
        value: f64,
        tol: f64,
    },
    Gt(f64),
    Lt(f64),
    Ge(f64),
    Le(f64),
}

/// The setpoint of a settle/overshoot check.
#[derive(Clone, Debug, PartialEq)]
pub enum Setpoint {
    Value(f64),
    Device(String),
}

/// The settling band.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Band {
    /// Percent of the setpoint step (SV − PV at the start of the window); of
    /// |SV| when there is no step.
    Percent(f64),
    /// Absolute, in device units.
    Abs(f64),
}

/// When an expectation is checked, resolved to scans.
#[derive(Clone, Debug, PartialEq)]
pub enum ExpectKind {
    /// The condition holds at this scan.
    At { scan: u64, cond: Cond },
    /// The condition holds at some scan in `first..=last`.
    Within { first: u64, last: u64, cond: Cond },
    /// The condition holds at every scan in `first..=last`.
    Always { first: u64, last: u64, cond: Cond },
    /// The condition holds at no scan in `first..=last`.
    Never { first: u64, last: u64, cond: Cond },
    /// Loop performance over `first..=last`: settled (inside the band from
    /// `deadline` on) and overshoot at most `max_overshoot` % of the step.
    Settle {
        first: u64,
        last: u64,
        setpoint: Setpoint,
        band: Band,
        deadline: Option<u64>,
        max_overshoot: Option<f64>,
    },
}

/// One `[[expect]]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct ExpectSpec {
    /// The pass/fail line's text.
    pub text: String,
    pub device: String,
    /// More devices shown in the history of a failure.
    pub show: Vec<String>,
    pub kind: ExpectKind,
}

/// `[trace]`: devices recorded for CSV and plots.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TraceSpec {
    pub devices: Vec<String>,
    /// CSV file to write (relative paths are relative to the scenario file).
    pub file: Option<PathBuf>,
    /// Sample period; default: every scan, or fewer so that a run keeps at
    /// most [`DEFAULT_MAX_SAMPLES`] samples.
    pub interval_us: Option<u64>,
}

/// `[plot]`: an SVG of traced devices over time.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotSpec {
    pub file: PathBuf,
    /// Devices to draw (default: the trace devices, else the expectation
    /// devices).
    pub devices: Vec<String>,
    pub title: Option<String>,
}

/// A simulated device on an APLC port's line (`[[peer]]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PeerSpec {
    /// The PLC (0-based) of a fleet whose port it is on (0 for one PLC).
    pub plc: usize,
    /// 1 = PORT1, 2 = PORT2.
    pub port: u8,
    /// Answer delay after a frame's last byte (default: the RTU silence
    /// plus 1 ms for a slave).
    pub delay_us: Option<u64>,
    pub kind: PeerKind,
}

#[derive(Clone, Debug, PartialEq)]
pub enum PeerKind {
    /// A Modbus slave device: station, framing (`None`: the port's), the
    /// size of its tables, silent (absent), initial values (address, value)
    /// and registers following a plant model output (register, model,
    /// output, gain).
    Slave {
        station: u8,
        ascii: Option<bool>,
        size: u16,
        silent: bool,
        holding: Vec<(u16, i64)>,
        input_registers: Vec<(u16, i64)>,
        coils: Vec<(u16, i64)>,
        inputs: Vec<(u16, i64)>,
        follow: Vec<(u16, String, String, f64)>,
    },
    /// A free-port device: expect bytes → answer bytes, or send at a time.
    Script(Vec<ScriptStep>),
}

#[derive(Clone, Debug, PartialEq)]
pub enum ScriptStep {
    Expect {
        expect: Vec<u8>,
        answer: Vec<u8>,
        delay_us: u64,
    },
    Send {
        at_us: u64,
        bytes: Vec<u8>,
    },
}

/// Samples a trace keeps by default (the sample period grows for long runs).
pub const DEFAULT_MAX_SAMPLES: u64 = 10_000;

/// A parsed scenario.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// The scenario file (for reports).
    pub file: PathBuf,
    pub name: String,
    pub source: Source,
    /// `cpu`: the CPU model a program file runs on (default Q06HCPU; e.g.
    /// "Q06PHCPU" for the process-control instructions). A project sets its
    /// own with `[cpu] model`.
    pub cpu: Option<&'static Profile>,
    /// The CPU the scenario runs: `cpu`, the project's `[cpu] model`, or by
    /// the program file (`.apl`: the APLC-TCP; else the Q06HCPU); CPU 1's
    /// of a multi-CPU system.
    pub profile: &'static Profile,
    /// What the file's device names mean, one entry per CPU (CPU 1 first;
    /// a single CPU has one): APLC names (and the programs' global names)
    /// for an `.apl` program, `cpu = "APLC-TCP"` or an APLC-TCP project
    /// (contract §2), else MELSEC names.
    pub names: Vec<Names>,
    /// Virtual time per scan, µs: the step of a multi-CPU system, whose
    /// CPUs scan at their own constant scan (this time without one).
    pub scan_us: u64,
    /// Scans (steps) to run (the duration rounded up to whole scans).
    pub scans: u64,
    pub models: Vec<ModelSpec>,
    /// Sorted by scan (file order within a scan).
    pub timeline: Vec<EventSpec>,
    pub expects: Vec<ExpectSpec>,
    pub trace: TraceSpec,
    pub plot: Option<PlotSpec>,
    /// `[port1]`/`[port2]` of an APLC program file (a project has them in
    /// plc.toml).
    pub ports: Vec<softplc_ports::PortConfig>,
    /// `[[peer]]`: the devices on the ports' lines.
    pub peers: Vec<PeerSpec>,
    /// How device names choose their CPU (`names` is flat in its order).
    pub layout: Layout,
    /// `[[plc]]`: the PLCs of a fleet (empty: one PLC, `source`; else
    /// `source`, `cpu` and `profile` are the first PLC's).
    pub plcs: Vec<PlcSpec>,
    /// `[[link]]`: serial ports of two PLCs wired together.
    pub links: Vec<LinkSpec>,
    /// `[[client]]`: HMIs or SCADA polling a PLC.
    pub clients: Vec<ClientSpec>,
}
