//! A process-control loop on a Q06PHCPU for the control-instruction tests
//! (`golden_process_pid`, `golden_process_at1`, `process_pid_differential`),
//! included with `#[path]`: operands `S1 = D0` (E1), `D1 = D100` (BW, BB at
//! D102), `S2 = D200`, `D2 = D1000` (the loop tag), `S3 = D300` (E2; the
//! upper loop's INH is D292 = S3 − 8); ΔT = 1 s; the loop running in AUT with
//! nothing inhibited and the loop-tag defaults of the manual (spec §3).
#![allow(dead_code)]

use super::common::Plc;
use softplc_core::program::ProcessSettings;

/// The five-operand program of one control instruction.
pub fn program(mnemonic: &str) -> String {
    format!("LD SM400\n{mnemonic} D0 D100 D200 D1000 D300\nEND\n")
}

pub fn setf(p: &mut Plc, dev: &str, v: f32) {
    p.set(&format!("{dev}:f32"), &format!("{v:e}"));
}

pub fn getf(p: &Plc, dev: &str) -> f32 {
    p.real(dev) as f32
}

/// A loop-tag float, D1000 + `off`.
pub fn tf(p: &mut Plc, off: u32, v: f32) {
    setf(p, &format!("D{}", 1000 + off), v);
}

pub fn tag(p: &Plc, off: u32) -> f32 {
    getf(p, &format!("D{}", 1000 + off))
}

/// A loop-tag word.
pub fn tw(p: &mut Plc, off: u32, v: u16) {
    p.set(&format!("D{}:u16", 1000 + off), &v.to_string());
}

pub fn word(p: &Plc, dev: &str) -> u16 {
    p.int(&format!("{dev}:u16")) as u16
}

pub fn tagw(p: &Plc, off: u32) -> u16 {
    word(p, &format!("D{}", 1000 + off))
}

pub fn bw(p: &Plc) -> f32 {
    getf(p, "D100")
}

pub fn bb(p: &Plc) -> u16 {
    word(p, "D102")
}

pub const MAN: u16 = 0x8;
pub const AUT: u16 = 0x10;
pub const CAS: u16 = 0x20;
pub const CMB: u16 = 0x40;
pub const CMV: u16 = 0x200;
pub const SPA: u16 = 1 << 14;
pub const DVLA: u16 = 1 << 2;
pub const MHA: u16 = 1 << 1;
pub const MLA: u16 = 1 << 0;
pub const DMLA: u16 = 1 << 11;
pub const ERRI: u16 = 1 << 15;
pub const TRKF: u16 = 1 << 14;

/// Writes the S2 constants of `mnemonic` with the manual's defaults (MTD 8,
/// DVLS 2, PN 0, TRK 0, SVPTN 3, NMAX 100, NMIN 0).
pub fn constants(p: &mut Plc, mnemonic: &str) {
    let w = |p: &mut Plc, n: u32, v: u16| {
        p.set(&format!("D{}:u16", 200 + n), &v.to_string());
    };
    match mnemonic {
        "S.PID" | "S.2PID" | "S.IPD" | "S.PIDP" => {
            setf(p, "D200", 8.0);
            setf(p, "D202", 2.0);
            w(p, 4, 0);
            w(p, 5, 0);
            w(p, 6, 3);
            if mnemonic == "S.PIDP" {
                setf(p, "D207", 100.0);
                setf(p, "D209", 0.0);
            }
        }
        "S.SPI" | "S.BPI" => {
            setf(p, "D200", 2.0);
            w(p, 2, 0);
            w(p, 3, 0);
            w(p, 4, 3);
        }
        "S.R" => {
            w(p, 0, 0);
            w(p, 1, 3);
        }
        _ => {
            w(p, 0, 0);
            w(p, 1, 0);
            w(p, 2, 3);
        }
    }
}

/// PN, TRK and SVPTN offsets in S2 of `mnemonic` (S.R has no PN: `None`).
pub fn pattern_at(mnemonic: &str) -> (Option<u32>, u32, u32) {
    match mnemonic {
        "S.PID" | "S.2PID" | "S.IPD" | "S.PIDP" => (Some(204), 205, 206),
        "S.SPI" | "S.BPI" => (Some(202), 203, 204),
        "S.R" => (None, 200, 201),
        _ => (Some(200), 201, 202),
    }
}

/// The loop-tag defaults, then RUN (ALM 0), INH 0, MODE AUT, ΔT = 1 s.
pub fn defaults(p: &mut Plc) {
    setf(p, "SD1500", 1.0);
    tw(p, 1, AUT);
    tw(p, 3, 0);
    tw(p, 4, 0);
    for (off, v) in [
        (18, 100.0),
        (22, 100.0),
        (26, 100.0),
        (30, 100.0),
        (38, 0.2),
        (44, 100.0),
        (46, 1.0),
        (48, 100.0),
        (50, 100.0),
        (52, 1.0),
        (54, 10.0),
        (60, 1.0),
        (66, 1.0),
        (68, 1.0),
        (72, 1.0),
        (74, 100.0),
        (76, 10.0),
    ] {
        tf(p, off, v);
    }
}

/// A CPU running `mnemonic` on the loop, set up as the module says.
pub fn start_with(mnemonic: &str, s: ProcessSettings) -> Plc {
    let mut p = Plc::process_with(&program(mnemonic), s);
    defaults(&mut p);
    constants(&mut p, mnemonic);
    p
}

pub fn start(mnemonic: &str) -> Plc {
    start_with(mnemonic, ProcessSettings::default())
}

/// (SD1502, SD1503) after the 4100 the scans up to `scans` raise; panics
/// when none is raised.
pub fn error_after(p: &mut Plc, scans: u32) -> (i64, i64) {
    for _ in 0..scans {
        p.scan();
        if p.error().is_some() {
            break;
        }
    }
    assert_eq!(
        p.error().map(|e| e.0),
        Some(4100),
        "no 4100 within {scans} scans"
    );
    (p.int("SD1502"), p.int("SD1503"))
}

/// An error case: what, the setup, (SD1502, SD1503).
pub type Case = (&'static str, Box<dyn Fn(&mut Plc)>, (i64, i64));
