//! `[latch]`: latch (1) and latch (2) ranges (PLC parameter "device setting",
//! 004 §7.3, L5852-5853, L5862-5863).
//!
//! - Latch (1), cleared by latch clear: B, F, V, T, ST, C, D, W.
//! - Latch (2), not cleared by the RESET/L.CLR switch: L, F, V, T, ST, C, D, W.
//! - One range per device and kind.
//!
//! The latch relay L is latched over its whole range whatever `[latch]` says
//! (004 L3522, L6181-6185): it is latch (1), except a part given in `latch2`.
//! A timer, retentive-timer or counter range (`T0-T9`, also written `TN0-TN9`)
//! becomes one [`LatchRange`] of the contact kind (TS, STS, CS), which stands for
//! contact, coil and current value, as the engine reads it.

use super::ctx::Ctx;
use super::tree::{Entry, Item, Value};
use crate::device::{parse_operand, DeviceConfig, DeviceKind, Operand};
use crate::engine::LatchRange;

pub(super) fn family_name(kind: DeviceKind) -> &'static str {
    match kind {
        DeviceKind::TS => "T",
        DeviceKind::STS => "ST",
        DeviceKind::CS => "C",
        k => k.name(),
    }
}

const LATCH1: &[DeviceKind] = {
    use DeviceKind::*;
    &[B, F, V, TS, STS, CS, D, W]
};
const LATCH2: &[DeviceKind] = {
    use DeviceKind::*;
    &[L, F, V, TS, STS, CS, D, W]
};

fn allowed_list(allowed: &[DeviceKind]) -> String {
    allowed
        .iter()
        .map(|k| family_name(*k))
        .collect::<Vec<_>>()
        .join(", ")
}

/// One range as read: device family, first and last number, and its text.
pub(super) struct Spec<'t> {
    pub family: DeviceKind,
    pub start: u32,
    pub end: u32,
    pub text: &'t str,
}

/// Reads `[latch]` (absent: `None`) into the latch ranges of the CPU.
pub(crate) fn latch(cx: &mut Ctx, t: Option<&[Entry]>, devices: &DeviceConfig) -> Vec<LatchRange> {
    let l_points = devices.points(DeviceKind::L);
    let mut out = Vec::new();
    let Some(t) = t else {
        if l_points > 0 {
            out.push(range(DeviceKind::L, 0, l_points - 1, true));
        }
        return out;
    };
    cx.unknown_keys(t, Some("[latch]"), &["latch1", "latch2"]);
    let mut specs: [Vec<Spec>; 2] = [Vec::new(), Vec::new()];
    for (n, (key, allowed)) in [("latch1", LATCH1), ("latch2", LATCH2)].iter().enumerate() {
        let Some(e) = t.iter().find(|e| e.key == *key) else {
            continue;
        };
        let Value::Array(items) = &e.item.value else {
            cx.error(
                &e.item.span,
                format!(
                    "{key} must be an array of ranges such as [\"D1000-D1999\"], not {}",
                    e.item.value.type_name()
                ),
            );
            continue;
        };
        for item in items {
            let Some(text) = cx.item_string(key, item, "device ranges such as \"D1000-D1999\"")
            else {
                continue;
            };
            let not_allowed = |fam: DeviceKind| {
                if allowed.contains(&fam) {
                    None
                } else if fam == DeviceKind::L {
                    Some("L is always latched (latch (1)) over its whole range; put a part of it in latch2 to keep it through latch clear".to_string())
                } else {
                    Some(format!(
                        "{} cannot be in {key}; {key} allows {}",
                        family_name(fam),
                        allowed_list(allowed)
                    ))
                }
            };
            let Some(spec) = parse_range(cx, item, text, devices, not_allowed) else {
                continue;
            };
            if let Some(prev) = specs[n].iter().find(|s| s.family == spec.family) {
                cx.error(
                    &item.span,
                    format!(
                        "{key} already has a range for {} (\"{}\"); the parameter allows one range per device",
                        family_name(spec.family),
                        prev.text
                    ),
                );
                continue;
            }
            if n == 1 {
                if let Some(prev) = specs[0]
                    .iter()
                    .find(|s| s.family == spec.family && s.start <= spec.end && spec.start <= s.end)
                {
                    cx.error(
                        &item.span,
                        format!(
                            "latch2 range \"{text}\" overlaps the latch1 range \"{}\"",
                            prev.text
                        ),
                    );
                    continue;
                }
            }
            specs[n].push(spec);
        }
    }
    // L: latch (1) over all of it except the latch (2) part.
    let l2 = specs[1].iter().find(|s| s.family == DeviceKind::L);
    match l2 {
        Some(s) => {
            if s.start > 0 {
                out.push(range(DeviceKind::L, 0, s.start - 1, true));
            }
            if s.end + 1 < l_points {
                out.push(range(DeviceKind::L, s.end + 1, l_points - 1, true));
            }
        }
        None if l_points > 0 => out.push(range(DeviceKind::L, 0, l_points - 1, true)),
        None => {}
    }
    for (n, list) in specs.iter().enumerate() {
        for s in list {
            out.push(range(s.family, s.start, s.end, n == 0));
        }
    }
    out
}

fn range(kind: DeviceKind, start: u32, end: u32, clearable: bool) -> LatchRange {
    LatchRange {
        kind,
        start,
        end,
        clearable,
    }
}

/// `D1000-D1999` or a single device `D5`, of a device family that
/// `not_allowed` has no objection to (its message otherwise).
pub(super) fn parse_range<'t>(
    cx: &mut Ctx,
    item: &'t Item,
    text: &'t str,
    devices: &DeviceConfig,
    not_allowed: impl Fn(DeviceKind) -> Option<String>,
) -> Option<Spec<'t>> {
    let (a, b) = match text.split_once('-') {
        Some((a, b)) => (a.trim(), b.trim()),
        None => (text.trim(), text.trim()),
    };
    let dev = |s: &str| match parse_operand(s) {
        Ok(Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) => Some(dev),
        _ => None,
    };
    let (Some(first), Some(last)) = (dev(a), dev(b)) else {
        cx.error(
            &item.span,
            format!("\"{text}\" is not a device range (write e.g. \"D1000-D1999\" or \"B0-B1F\")"),
        );
        return None;
    };
    let fam = first.kind.range_kind();
    if last.kind.range_kind() != fam {
        cx.error(
            &item.span,
            format!("\"{text}\": a range must start and end in the same device"),
        );
        return None;
    }
    if let Some(msg) = not_allowed(fam) {
        cx.error(&item.span, msg);
        return None;
    }
    let (start, end) = (first.number, last.number);
    if start > end {
        cx.error(
            &item.span,
            format!("range \"{text}\" ends before it starts"),
        );
        return None;
    }
    let points = devices.points(fam);
    if end >= points {
        cx.error(
            &item.span,
            format!(
                "\"{text}\": {} is outside the configured points ({} has {points})",
                fam.format(end).replacen(fam.name(), family_name(fam), 1),
                family_name(fam)
            ),
        );
        return None;
    }
    Some(Spec {
        family: fam,
        start,
        end,
        text,
    })
}
