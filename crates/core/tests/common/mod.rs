//! Test harness: a CPU on virtual time with device access by name.
#![allow(dead_code)]

use softplc_core::access::{DeviceSpec, Value};
use std::time::Duration;

use softplc_core::engine::{
    Cpu, CpuConfig, CpuState, ErrorCode, ExecType, LoadedProgram, VirtualClock,
};
use softplc_core::program::{compile_il, compile_il_in, dialect_for, ProcessSettings};

pub mod pid;
pub mod process;
pub mod project;

/// A CPU on the tier `SOFTPLC_EXEC` names (the interpreter when unset), so
/// every golden test runs on both tiers (`.ci/run` runs them with `jit`).
pub struct Plc {
    pub cpu: Cpu,
    clock: VirtualClock,
    scan_us: u64,
}

impl Plc {
    /// Compiles `.il` text with the default Q06HCPU configuration; panics with the
    /// diagnostics if it does not load. Scans take 10 ms of virtual time.
    pub fn new(src: &str) -> Plc {
        Plc::with_config(src, softplc_core::profile::default_config())
    }

    /// Compiles `.il` text for a process CPU (Q06PHCPU) with the given
    /// process-control decisions.
    pub fn process_with(src: &str, settings: ProcessSettings) -> Plc {
        Plc::compiled_for(src, process_cpu(), settings)
    }

    /// Compiles `.il` text for `model` (any MELSEC model: its dialect and
    /// default devices).
    pub fn on_model(src: &str, model: &str) -> Plc {
        let profile = softplc_core::profile::find(model).expect("a known model");
        Plc::compiled_for(src, profile, ProcessSettings::default())
    }

    fn compiled_for(
        src: &str,
        profile: &'static softplc_core::profile::Profile,
        settings: ProcessSettings,
    ) -> Plc {
        let cfg = softplc_core::profile::config(profile);
        let dialect = dialect_for(profile, settings);
        let prog = compile_il_in("test.il", src, &cfg.devices, &dialect)
            .unwrap_or_else(|d| panic!("load failed:\n{d}"));
        let clock = VirtualClock::new();
        let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
        softplc_core::tier::apply_env(&mut cpu);
        Plc {
            cpu,
            clock,
            scan_us: 10_000,
        }
    }

    /// [`Plc::process_with`] the spec's decisions.
    pub fn process(src: &str) -> Plc {
        Plc::process_with(src, ProcessSettings::default())
    }

    pub fn with_config(src: &str, cfg: CpuConfig) -> Plc {
        let prog = compile_il("test.il", src, &cfg.devices)
            .unwrap_or_else(|d| panic!("load failed:\n{d}"));
        let clock = VirtualClock::new();
        let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
        softplc_core::tier::apply_env(&mut cpu);
        Plc {
            cpu,
            clock,
            scan_us: 10_000,
        }
    }

    /// A CPU with several programs in parameter order: (source, type, interval).
    pub fn with_programs(progs: &[(&str, ExecType, Option<Duration>)], cfg: CpuConfig) -> Plc {
        let loaded = progs
            .iter()
            .enumerate()
            .map(|(i, (src, exec, interval))| LoadedProgram {
                program: compile_il(&format!("p{i}.il"), src, &cfg.devices)
                    .unwrap_or_else(|d| panic!("load failed:\n{d}")),
                exec: *exec,
                interval: *interval,
                sim_time: None,
                local_devices: true,
            })
            .collect();
        let clock = VirtualClock::new();
        let mut cpu = Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
        softplc_core::tier::apply_env(&mut cpu);
        Plc {
            cpu,
            clock,
            scan_us: 10_000,
        }
    }

    /// A project: `plc.toml` text and its program files (name, text), built
    /// as `run` builds it; panics with the diagnostics if it does not load.
    pub fn project(toml: &str, files: &[(&str, &str)]) -> Plc {
        Plc::try_project(toml, files).unwrap_or_else(|d| panic!("load failed:\n{d}"))
    }

    /// [`Plc::project`], or the diagnostics as `line:col: message` lines.
    pub fn try_project(toml: &str, files: &[(&str, &str)]) -> Result<Plc, String> {
        let dir = project::scratch(toml);
        for (name, text) in files {
            std::fs::write(dir.join(name), text).unwrap();
        }
        let clock = VirtualClock::new();
        let built = softplc_core::project::load_project(&dir)
            .and_then(|p| p.build_cpu(Box::new(clock.clone())));
        let _ = std::fs::remove_dir_all(&dir);
        let mut cpu = built.map_err(|d| {
            d.0.iter()
                .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                .collect::<Vec<_>>()
                .join("\n")
        })?;
        softplc_core::tier::apply_env(&mut cpu);
        Ok(Plc {
            cpu,
            clock,
            scan_us: 10_000,
        })
    }

    /// Sets the virtual duration of each following scan.
    pub fn scan_time_us(&mut self, us: u64) -> &mut Self {
        self.scan_us = us;
        self
    }

    pub fn scan(&mut self) -> &mut Self {
        self.clock.advance_us(self.scan_us);
        self.cpu.scan();
        self
    }

    pub fn scans(&mut self, n: u64) -> &mut Self {
        for _ in 0..n {
            self.scan();
        }
        self
    }

    /// Writes a device by name (`X0`, `D10:f32`, `K4M0`); values as on the CLI.
    pub fn set(&mut self, dev: &str, value: &str) -> &mut Self {
        let spec = DeviceSpec::parse(dev).unwrap();
        self.cpu.write_device(&spec, value).unwrap();
        self
    }

    pub fn get(&self, dev: &str) -> Value {
        self.cpu
            .read_device(&DeviceSpec::parse(dev).unwrap())
            .unwrap()
    }

    pub fn bit(&self, dev: &str) -> bool {
        match self.get(dev) {
            Value::Bool(b) => b,
            v => panic!("{dev} is not a bit: {v:?}"),
        }
    }

    /// A word (default i16) or typed word (`D0:u32`) as an integer.
    pub fn int(&self, dev: &str) -> i64 {
        match self.get(dev) {
            Value::Int(i) => i,
            v => panic!("{dev} is not an integer: {v:?}"),
        }
    }

    pub fn real(&self, dev: &str) -> f64 {
        match self.get(&format!("{dev}:f32")) {
            Value::Float(f) => f,
            v => panic!("{dev} is not a float: {v:?}"),
        }
    }

    pub fn state(&self) -> CpuState {
        self.cpu.state()
    }

    /// The error code in SD0 / the engine's latest error.
    pub fn error(&self) -> Option<ErrorCode> {
        self.cpu.error().map(|e| e.code)
    }
}

/// Diagnostics of a process-CPU program that must fail to load, as
/// `line:col: message`.
pub fn process_diagnostics(src: &str) -> Vec<String> {
    process_diagnostics_with(src, ProcessSettings::default())
}

/// [`process_diagnostics`] under the decisions `s`.
pub fn process_diagnostics_with(src: &str, s: ProcessSettings) -> Vec<String> {
    let dialect = dialect_for(process_cpu(), s);
    match compile_il_in(
        "t.il",
        src,
        &softplc_core::profile::default_config().devices,
        &dialect,
    ) {
        Ok(_) => panic!("expected diagnostics"),
        Err(d) => {
            d.0.iter()
                .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                .collect()
        }
    }
}

/// Diagnostics of a program that must fail to load on `model`, as
/// `line:col: message`.
pub fn model_diagnostics(model: &str, src: &str) -> Vec<String> {
    let profile = softplc_core::profile::find(model).expect("a known model");
    let dialect = dialect_for(profile, ProcessSettings::default());
    let devices = softplc_core::profile::config(profile).devices;
    match compile_il_in("t.il", src, &devices, &dialect) {
        Ok(_) => panic!("program loaded on {model} but errors were expected:\n{src}"),
        Err(d) => {
            d.0.iter()
                .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                .collect()
        }
    }
}

/// Diagnostics of a program that must fail to load, as `line:col: message`.
pub fn diagnostics(src: &str) -> Vec<String> {
    match compile_il(
        "test.il",
        src,
        &softplc_core::profile::default_config().devices,
    ) {
        Ok(_) => panic!("program loaded but errors were expected:\n{src}"),
        Err(d) => {
            d.0.iter()
                .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                .collect()
        }
    }
}

/// Asserts that the CPU stopped with error `code`: STOP, the engine's error,
/// SD0 and SM0.
pub fn assert_stopped(p: &Plc, code: u16) {
    assert_eq!(p.state(), CpuState::Stop);
    assert_eq!(p.error(), Some(ErrorCode(code)));
    assert_eq!(p.int("SD0"), code as i64);
    assert!(p.bit("SM0"));
}

/// Asserts that the CPU runs without error.
pub fn assert_running(p: &Plc) {
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.error(), None);
}

/// Sets X0, X1, … from a string of '0'/'1', X0 first.
pub fn inputs(p: &mut Plc, bits: &str) {
    for (i, c) in bits.chars().enumerate() {
        p.set(&format!("X{i}"), if c == '1' { "1" } else { "0" });
    }
}

/// Reads Y0, Y1, … Y(n-1) as a '0'/'1' string, Y0 first.
pub fn outputs(p: &Plc, n: usize) -> String {
    (0..n)
        .map(|i| if p.bit(&format!("Y{i}")) { '1' } else { '0' })
        .collect()
}

/// The process CPU the process-control tests run on.
pub fn process_cpu() -> &'static softplc_core::profile::Profile {
    softplc_core::profile::find("Q06PHCPU").expect("a known model")
}
