//! Test harness: an APLC-TCP CPU running `.apl` text in virtual time, with
//! devices read and written by their APLC names.
#![allow(dead_code)]

use softplc_engine::{Cpu, CpuConfig, CpuState, LoadedProgram, VirtualClock};
use softplc_ir::access::Value;

pub struct Plc {
    pub cpu: Cpu,
    clock: VirtualClock,
    /// Virtual time of one scan, µs.
    pub scan_us: u64,
}

pub fn config() -> CpuConfig {
    CpuConfig {
        devices: softplc_aplc::device_config(),
        latch: Vec::new(),
        system: softplc_aplc::system(),
        ..CpuConfig::new(&softplc_aplc::profile::PROFILE)
    }
}

/// Loads `.apl` text (panics with the diagnostics if it does not load).
pub fn plc(src: &str) -> Plc {
    plc_with(src, config())
}

/// [`plc`] on a CPU configured by the caller.
pub fn plc_with(src: &str, config: CpuConfig) -> Plc {
    let program = softplc_aplc::load_bytes("t.apl", src.as_bytes())
        .unwrap_or_else(|d| panic!("load failed:\n{d}"));
    let clock = VirtualClock::new();
    let cpu = Cpu::with_programs(
        vec![LoadedProgram {
            program,
            exec: Default::default(),
            interval: None,
            sim_time: None,
            local_devices: true,
        }],
        config,
        Box::new(clock.clone()),
    )
    .unwrap();
    Plc {
        cpu,
        clock,
        scan_us: 10_000,
    }
}

/// The diagnostics of text that must not load, one per line.
pub fn errors(src: &str) -> String {
    match softplc_aplc::load_bytes("t.apl", src.as_bytes()) {
        Ok(_) => panic!("loaded:\n{src}"),
        Err(d) => d.to_string(),
    }
}

impl Plc {
    pub fn scan(&mut self) -> &mut Self {
        self.clock.advance_us(self.scan_us);
        self.cpu.scan();
        self
    }

    pub fn scans(&mut self, n: u32) -> &mut Self {
        for _ in 0..n {
            self.scan();
        }
        self
    }

    pub fn set(&mut self, name: &str, v: &str) -> &mut Self {
        let n = softplc_aplc::names::Name::parse(name).unwrap();
        let v = n.value(v).unwrap();
        self.cpu.write_value(&n.spec, &v).unwrap();
        self
    }

    pub fn get(&self, name: &str) -> Value {
        let n = softplc_aplc::names::Name::parse(name).unwrap();
        n.present(self.cpu.read_device(&n.spec).unwrap())
    }

    pub fn int(&self, name: &str) -> i64 {
        match self.get(name) {
            Value::Int(i) => i,
            Value::Bool(b) => b as i64,
            v => panic!("{name} = {v:?}"),
        }
    }

    pub fn real(&self, name: &str) -> f64 {
        match self.get(name) {
            Value::Float(f) => f,
            v => panic!("{name} = {v:?}"),
        }
    }

    pub fn bit(&self, name: &str) -> bool {
        matches!(self.get(name), Value::Bool(true))
    }

    pub fn running(&self) -> bool {
        self.cpu.state() == CpuState::Run
    }

    pub fn error_code(&self) -> Option<u16> {
        self.cpu.error().map(|e| e.code.0)
    }
}
