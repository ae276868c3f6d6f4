//! PID test helpers shared by the `golden_pid_*` tests: the two instruction
//! families, loop data, the I/O word offsets and a CPU set up with them.

use super::{assert_running, Plc};
use softplc_core::engine::{CpuConfig, ErrorMode};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Fam {
    /// S.PIDINIT / S.PIDCONT (incomplete derivative, 001 ch. 8).
    S,
    /// PIDINIT / PIDCONT (complete derivative, 001 ch. 9).
    C,
}

impl Fam {
    pub fn params(self) -> u32 {
        match self {
            Fam::S => 14,
            Fam::C => 10,
        }
    }
    pub fn io(self) -> u32 {
        match self {
            Fam::S => 23,
            Fam::C => 18,
        }
    }
    pub fn prefix(self) -> &'static str {
        match self {
            Fam::S => "S.",
            Fam::C => "",
        }
    }
    /// SP.PIDINIT D500 once, S.PIDCONT D600 every scan (or the plain forms).
    pub fn program(self) -> String {
        match self {
            Fam::S => "LD SM400\nSP.PIDINIT D500\nS.PIDCONT D600\nEND\n".into(),
            Fam::C => "LD SM400\nPIDINITP D500\nPIDCONT D600\nEND\n".into(),
        }
    }
}

/// One loop's PID control data (001 §5.1(3)).
#[derive(Clone, Copy, Debug)]
pub struct Loop {
    pub select: i16,
    pub ts: i16,
    pub kp: i16,
    pub ti: i16,
    pub td: i16,
    pub alpha: i16,
    pub mvll: i16,
    pub mvhl: i16,
    pub dmvl: i16,
    pub dpvl: i16,
    pub kd: i16,
}

/// §5.8 common settings: reverse, Ts 1 s, Kp 1.00, TI ∞, TD 0, α 0, MV 0..2000,
/// rate limits 2000 (no alarm).
pub const BASE: Loop = Loop {
    select: 1,
    ts: 100,
    kp: 100,
    ti: 32767,
    td: 0,
    alpha: 0,
    mvll: 0,
    mvhl: 2000,
    dmvl: 2000,
    dpvl: 2000,
    kd: 0,
};

pub fn dev(n: u32) -> String {
    format!("D{n}")
}

/// Writes the control data at `base`: n = loops.len(), k, then each loop.
pub fn write_data(p: &mut Plc, fam: Fam, base: u32, k: i16, loops: &[Loop]) {
    p.set(&dev(base), &loops.len().to_string());
    p.set(&dev(base + 1), &k.to_string());
    for (i, l) in loops.iter().enumerate() {
        write_loop(p, fam, base + 2 + fam.params() * i as u32, l);
    }
}

/// Writes one loop's words at `at` (the PIDPRMW layout).
pub fn write_loop(p: &mut Plc, fam: Fam, at: u32, l: &Loop) {
    let mut w = vec![
        l.select, l.ts, l.kp, l.ti, l.td, l.alpha, l.mvll, l.mvhl, l.dmvl, l.dpvl,
    ];
    if fam == Fam::S {
        w.extend([0, l.kd, 0, 0]);
    }
    for (j, v) in w.iter().enumerate() {
        p.set(&dev(at + j as u32), &v.to_string());
    }
}

/// I/O word of loop `i` (0-based): 0 SV, 1 PV, 2 MV, 3 PVf, 4 MVMAN, 5 MAN/AUTO, 6 ALARM.
pub fn io(fam: Fam, i: u32, off: u32) -> String {
    dev(600 + 10 + fam.io() * i + off)
}

pub const SV: u32 = 0;
pub const PV: u32 = 1;
pub const MV: u32 = 2;
pub const PVF: u32 = 3;
pub const MVMAN: u32 = 4;
pub const MODE: u32 = 5;
pub const ALARM: u32 = 6;

/// A CPU with the family's program, `loops` registered at D500, every loop in
/// auto with SV `sv`, and `scan_ms` scans.
pub fn plc(fam: Fam, k: i16, loops: &[Loop], sv: i16, scan_ms: u64) -> Plc {
    plc_src(&fam.program(), fam, k, loops, sv, scan_ms)
}

pub fn plc_src(src: &str, fam: Fam, k: i16, loops: &[Loop], sv: i16, scan_ms: u64) -> Plc {
    let mut p = Plc::new(src);
    p.scan_time_us(scan_ms * 1000);
    write_data(&mut p, fam, 500, k, loops);
    for i in 0..loops.len() as u32 {
        p.set(&io(fam, i, SV), &sv.to_string());
        p.set(&io(fam, i, MODE), "1");
    }
    p
}

pub fn set(p: &mut Plc, fam: Fam, i: u32, off: u32, v: i64) {
    p.set(&io(fam, i, off), &v.to_string());
}

pub fn get(p: &Plc, fam: Fam, i: u32, off: u32) -> i64 {
    p.int(&io(fam, i, off))
}

/// Runs one scan per PV value and collects the MV word of loop 1 after each.
pub fn run_pv(p: &mut Plc, fam: Fam, pvs: &[i64]) -> Vec<i64> {
    pvs.iter()
        .map(|&pv| {
            set(p, fam, 0, PV, pv);
            p.scan();
            assert_running(p);
            get(p, fam, 0, MV)
        })
        .collect()
}

pub fn continue_on_error() -> CpuConfig {
    CpuConfig {
        operation_error: ErrorMode::Continue,
        ..softplc_core::profile::default_config()
    }
}
