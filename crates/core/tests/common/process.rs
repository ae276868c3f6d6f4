//! Shared by the process-control I/O and loop tests: a running loop tag and
//! the process-control error check.
#![allow(dead_code)]

use super::Plc;

/// Writes the documented loop-tag defaults at `D{d2}` (spec §3), but with
/// the loop running (ALM = 0), nothing inhibited (INH = 0) and MODE = AUT,
/// and ΔT = 1 s in SD1500.
pub fn loop_tag(p: &mut Plc, d2: u32) {
    p.set("SD1500:f32", "1");
    p.set(&format!("D{}", d2 + 1), "H10")
        .set(&format!("D{}", d2 + 3), "0")
        .set(&format!("D{}", d2 + 4), "0");
    for (off, v) in [
        (18, "100"),
        (22, "100"),
        (26, "100"),
        (30, "100"),
        (38, "0.2"),
        (44, "100"),
        (46, "1"),
        (48, "100"),
        (50, "100"),
        (52, "1"),
        (54, "10"),
        (60, "1"),
        (66, "1"),
        (68, "1"),
    ] {
        p.set(&format!("D{}:f32", d2 + off), v);
    }
}

pub fn f(v: f32) -> f64 {
    v as f64
}

/// 4100 with SD1502 = `detail`, SD1503 = `step` (000 §14, DEC-36).
pub fn assert_pc_error(p: &Plc, detail: i64, step: i64) {
    assert_eq!(p.error().map(|e| e.0), Some(4100));
    assert_eq!((p.int("SD1502"), p.int("SD1503")), (detail, step));
}
