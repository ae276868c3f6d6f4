//! Shared helpers: a real CPU, hex frames, and one-shot serving.
#![allow(dead_code)]

use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, CpuConfig, VirtualClock};
use softplc_modbus::{decode, serve, Map, Proto, Slave};

pub fn cpu_with(cfg: CpuConfig) -> Cpu {
    let prog =
        softplc_core::program::compile_il("t.il", "LD SM400\nOUT M8191\nEND\n", &cfg.devices)
            .unwrap();
    Cpu::new(prog, cfg, Box::new(VirtualClock::new()))
}

/// An APLC-TCP CPU (its device layout: C200-C255 as CN pairs, 128 X/Y).
pub fn aplc_cpu() -> Cpu {
    let prog = softplc_core::aplc::load_bytes("t.apl", b"LD SM0\nOUT M2047\n").unwrap();
    softplc_core::aplc::single_cpu(
        prog,
        softplc_core::aplc::cpu_config(),
        Box::new(VirtualClock::new()),
    )
    .unwrap()
}

pub fn cpu() -> Cpu {
    cpu_with(softplc_core::profile::default_config())
}

/// `"01 03 00 6B"` → bytes.
pub fn hex(s: &str) -> Vec<u8> {
    s.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect()
}

/// Decodes `request` (which must be exactly one frame) and serves it.
pub fn exchange(
    slave: &mut Slave,
    map: &Map,
    proto: Proto,
    request: &[u8],
    cpu: &mut Cpu,
) -> Option<Vec<u8>> {
    let (frame, used) = decode(proto, request)
        .unwrap_or_else(|e| panic!("{proto} request {request:02X?}: {e}"))
        .unwrap_or_else(|| panic!("{proto} request {request:02X?} incomplete"));
    assert_eq!(used, request.len(), "{proto} request {request:02X?} length");
    serve(slave, map, &frame, cpu)
}

/// Serves a hex RTU request on the Q map (station 1) and returns the hex response.
pub fn rtu(cpu: &mut Cpu, map: &Map, request: &str) -> Option<String> {
    let mut slave = Slave::new(1);
    exchange(&mut slave, map, Proto::Rtu, &hex(request), cpu).map(|r| to_hex(&r))
}

pub fn to_hex(b: &[u8]) -> String {
    b.iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

pub fn bit(cpu: &Cpu, kind: DeviceKind, n: i64) -> bool {
    cpu.memory().get_bit(kind, n).unwrap()
}

pub fn word(cpu: &Cpu, kind: DeviceKind, n: i64) -> u16 {
    cpu.memory().get_word(kind, n).unwrap()
}

pub fn set_bit(cpu: &mut Cpu, kind: DeviceKind, n: i64, v: bool) {
    cpu.set_bit(kind, n, v).unwrap()
}

pub fn set_word(cpu: &mut Cpu, kind: DeviceKind, n: i64, v: u16) {
    cpu.set_word(kind, n, v).unwrap()
}
