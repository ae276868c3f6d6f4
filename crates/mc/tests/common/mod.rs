//! Shared helpers: a small CPU and hand-built frame headers.
#![allow(dead_code)]

use softplc_core::engine::{Cpu, CpuConfig, VirtualClock};

/// X0 drives Y0; X1 divides by zero (a stop error).
pub const PROGRAM: &str = "LD X0\nOUT Y0\nLD X1\n/ D0 K0 D1\nEND\n";

pub fn cpu_with(cfg: CpuConfig) -> (Cpu, VirtualClock) {
    let prog = softplc_core::program::compile_il("t.il", PROGRAM, &cfg.devices).unwrap();
    let clock = VirtualClock::new();
    let cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    (cpu, clock)
}

pub fn cpu() -> Cpu {
    cpu_with(softplc_core::profile::default_config()).0
}

/// 3E binary request: subheader 50 00, network 00, PC FF, I/O 03FF (FF 03),
/// station 00, data length (LE, monitoring timer + `body`), monitoring timer
/// 0010 (10 00), then `body` (command, subcommand, request data).
pub fn bin3e(body: &[u8]) -> Vec<u8> {
    let len = (2 + body.len()) as u16;
    let mut f = vec![0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00];
    f.extend_from_slice(&len.to_le_bytes());
    f.extend_from_slice(&[0x10, 0x00]);
    f.extend_from_slice(body);
    f
}

/// 4E binary request: subheader 54 00, serial 1234 (34 12), fixed 00 00, then as 3E.
pub fn bin4e(body: &[u8]) -> Vec<u8> {
    let mut f = vec![0x54, 0x00, 0x34, 0x12, 0x00, 0x00];
    f.extend_from_slice(&bin3e(body)[2..]);
    f
}

/// 3E ASCII request: "5000", "00", "FF", "03FF", "00", data length (4 hex
/// characters, monitoring timer + `body`), timer "0010", then `body`.
pub fn ascii3e(body: &str) -> Vec<u8> {
    format!("500000FF03FF00{:04X}0010{body}", 4 + body.len()).into_bytes()
}

/// 4E ASCII request: "5400", serial "1234", "0000", then as 3E.
pub fn ascii4e(body: &str) -> Vec<u8> {
    let mut f = b"540012340000".to_vec();
    f.extend_from_slice(&ascii3e(body)[4..]);
    f
}

/// 3E binary response: D0 00, echoed 00 FF FF 03 00, data length (end code +
/// `data`), end code 00 00, `data`.
pub fn bin3e_ok(data: &[u8]) -> Vec<u8> {
    let len = (2 + data.len()) as u16;
    let mut f = vec![0xD0, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00];
    f.extend_from_slice(&len.to_le_bytes());
    f.extend_from_slice(&[0x00, 0x00]);
    f.extend_from_slice(data);
    f
}

/// 4E binary response: D4 00, serial 34 12, 00 00, then as 3E.
pub fn bin4e_ok(data: &[u8]) -> Vec<u8> {
    let mut f = vec![0xD4, 0x00, 0x34, 0x12, 0x00, 0x00];
    f.extend_from_slice(&bin3e_ok(data)[2..]);
    f
}

/// 3E ASCII response: "D000", "00FF03FF00", length, "0000", `data`.
pub fn ascii3e_ok(data: &str) -> Vec<u8> {
    format!("D00000FF03FF00{:04X}0000{data}", 4 + data.len()).into_bytes()
}

/// 3E binary error response: end code, then the error information (network 00,
/// PC FF, I/O FF 03, station 00, command, subcommand).
pub fn bin3e_err(end: u16, command: u16, sub: u16) -> Vec<u8> {
    let mut f = vec![0xD0, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0B, 0x00];
    f.extend_from_slice(&end.to_le_bytes());
    f.extend_from_slice(&[0x00, 0xFF, 0xFF, 0x03, 0x00]);
    f.extend_from_slice(&command.to_le_bytes());
    f.extend_from_slice(&sub.to_le_bytes());
    f
}

/// 3E ASCII error response: length 0016 (end code 4 + error information 18).
pub fn ascii3e_err(end: u16, command: u16, sub: u16) -> Vec<u8> {
    format!("D00000FF03FF000016{end:04X}00FF03FF00{command:04X}{sub:04X}").into_bytes()
}
