//! `[devices]`: device points (PLC parameter "device setting", 004 §10.2,
//! L5952-6012) and the file register size; its local-device ranges are
//! `local.rs`'s.

use std::ops::Range;

use super::ctx::Ctx;
use super::tree::{Entry, Value};
use crate::device::{DeviceConfig, DeviceKind};

/// Devices whose points may be changed, by their key.
pub(crate) const CHANGEABLE: &[(&str, DeviceKind)] = {
    use DeviceKind::*;
    &[
        ("M", M),
        ("L", L),
        ("F", F),
        ("V", V),
        ("B", B),
        ("T", TS),
        ("ST", STS),
        ("C", CS),
        ("D", D),
        ("W", W),
    ]
};

/// Devices with a fixed size (004 L5954-5956 and Table 10.1).
const FIXED: &[(&str, DeviceKind)] = {
    use DeviceKind::*;
    &[
        ("X", X),
        ("Y", Y),
        ("S", S),
        ("SB", SB),
        ("SW", SW),
        ("SM", SM),
        ("SD", SD),
        ("Z", Z),
        ("FX", FX),
        ("FY", FY),
        ("FD", FD),
    ]
};

/// The file-register key: points of ZR (R is the first 32K of it).
pub(crate) const FILE_REGISTER: &str = "file_register";
/// The file-register file's name (SD641-SD646).
pub(crate) const FILE_REGISTER_NAME: &str = "file_register_name";
/// The local-device ranges (read by `local.rs` once the points are known).
pub(crate) const LOCAL: &str = "local";

/// Points of one device: 16-point units, at most 32K (004 L5968-5970).
const MAX_POINTS: i64 = 32 * 1024;
/// File registers: 0-1018K in 1K-point units (004 Table 10.1; a 4 MB flash card
/// holds ZR0-1042431, L1041).
const MAX_FILE_REGISTER: i64 = 1018 * 1024;
/// User device memory: 29K words, of which the fixed devices take 3.7K (L5960).
const MEMORY_TENTHS: u64 = 29 * 1024 * 10;
const FIXED_TENTHS: u64 = 37 * 1024;
/// Bit devices in total, T/ST/C counted twice (L5977-5980).
const MAX_BITS: u64 = 64 * 1024;

fn key_list() -> Vec<&'static str> {
    CHANGEABLE
        .iter()
        .map(|(k, _)| *k)
        .chain([FILE_REGISTER, FILE_REGISTER_NAME, LOCAL])
        .collect()
}

/// Reads `[devices]` into `cfg` and the file-register file's name into
/// `file_register_name`; `table_at` is the span of the table, where errors
/// about the totals are reported.
pub(crate) fn devices(
    cx: &mut Ctx,
    t: &[Entry],
    table_at: Range<usize>,
    cfg: &mut DeviceConfig,
    file_register_name: &mut [u8; 8],
) {
    let mut bad = false;
    let mut seen: Vec<String> = Vec::new();
    for e in t {
        let up = e.key.to_ascii_uppercase();
        if e.key == LOCAL {
            continue;
        }
        if e.key == FILE_REGISTER_NAME {
            if let Some(text) = cx.string(e, "a file name such as \"MAIN\"") {
                match softplc_melsec::system::file_register::file_name(text) {
                    Ok(name) => *file_register_name = name,
                    Err(msg) => cx.error(&e.item.span, msg),
                }
            }
            continue;
        }
        if e.key == FILE_REGISTER {
            if let Some(n) = points(cx, e, MAX_FILE_REGISTER, 1024, "1K-point (1024) units") {
                cfg.set_points(DeviceKind::ZR, n);
            }
            continue;
        }
        if seen.contains(&up) {
            cx.error(&e.key_span, format!("{up} is given twice"));
            continue;
        }
        seen.push(up.clone());
        if let Some((_, kind)) = CHANGEABLE.iter().find(|(k, _)| *k == up) {
            match points(cx, e, MAX_POINTS, 16, "16-point units") {
                Some(n) => cfg.set_points(*kind, n),
                None => bad = true,
            }
        } else if let Some((name, kind)) = FIXED.iter().find(|(k, _)| *k == up) {
            cx.error(
                &e.key_span,
                format!(
                    "{name} has a fixed size ({} points) and cannot be changed",
                    cfg.points(*kind)
                ),
            );
        } else if up == "R" || up == "ZR" {
            cx.error(
                &e.key_span,
                format!("set the file register size with {FILE_REGISTER} (ZR points; R is the first 32768 of them)"),
            );
        } else {
            cx.unknown_key(e, Some("[devices]"), &key_list());
        }
    }
    if bad {
        return;
    }
    let p = |k: DeviceKind| cfg.points(k) as u64;
    use DeviceKind::*;
    let bits = p(M) + p(L) + p(F) + p(V) + p(B);
    let timers = p(TS) + p(STS) + p(CS);
    let tenths = FIXED_TENTHS + 10 * (bits / 16 + p(D) + p(W) + timers / 16 * 18);
    if tenths > MEMORY_TENTHS {
        cx.error(
            &table_at,
            format!(
                "the device points need {}.{} words of device memory, more than 29K (29696): \
                 3.7K + (M+L+F+V+B)/16 + (D+W) + (T+ST+C)/16×18 = 3788.8 + {} + {} + {}",
                tenths / 10,
                tenths % 10,
                bits / 16,
                p(D) + p(W),
                timers / 16 * 18
            ),
        );
    }
    let total_bits = bits + p(SB) + p(S) + 2 * timers;
    if total_bits > MAX_BITS {
        cx.error(
            &table_at,
            format!(
                "the bit devices total {total_bits} points, more than 64K (65536): \
                 M+L+F+V+B+SB+S + 2×(T+ST+C)"
            ),
        );
    }
}

/// A point count: an integer `0..=max` in multiples of `unit`.
fn points(cx: &mut Ctx, e: &Entry, max: i64, unit: i64, units: &str) -> Option<u32> {
    let n = match &e.item.value {
        Value::Int(n) => *n,
        v => {
            cx.error(
                &e.item.span,
                format!(
                    "{} must be a number of points (an integer), not {}",
                    e.key,
                    v.type_name()
                ),
            );
            return None;
        }
    };
    if (0..=max).contains(&n) && n % unit == 0 {
        Some(n as u32)
    } else {
        cx.error(
            &e.item.span,
            format!(
                "{} = {n} is out of range (0-{max} points in {units})",
                e.key
            ),
        );
        None
    }
}
