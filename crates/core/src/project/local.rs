//! `[devices] local`: the local-device ranges (PLC parameter "device
//! setting", 004 L5854, §10.13.1 (b), (d)): one range per device among M,
//! V, T, ST, C and D, the same for every program. A timer, retentive-timer
//! or counter range (`T0-T9`, also written `TN0-TN9`) covers contact, coil
//! and current value. Whether a program uses them is its `[[program]]
//! local_devices` (`programs.rs`).

use super::ctx::Ctx;
use super::devices::LOCAL;
use super::latch::{family_name, parse_range, Spec};
use super::tree::{Entry, Value};
use crate::device::{DeviceConfig, DeviceKind};
use crate::engine::LocalRange;

/// The devices that can be local (004 §10.13.1 (b)).
const ALLOWED: &[DeviceKind] = {
    use DeviceKind::*;
    &[M, V, TS, STS, CS, D]
};

/// Reads `local` of the `[devices]` table `t` (absent: none) against the
/// device points.
pub(crate) fn local(cx: &mut Ctx, t: &[Entry], devices: &DeviceConfig) -> Vec<LocalRange> {
    let Some(e) = t.iter().find(|e| e.key == LOCAL) else {
        return Vec::new();
    };
    let Value::Array(items) = &e.item.value else {
        cx.error(
            &e.item.span,
            format!(
                "{LOCAL} must be an array of ranges such as [\"D0-D99\", \"M0-M99\"], not {}",
                e.item.value.type_name()
            ),
        );
        return Vec::new();
    };
    let not_allowed = |fam: DeviceKind| {
        (!ALLOWED.contains(&fam)).then(|| {
            format!(
                "{} cannot be a local device; local devices are M, V, T, ST, C and D",
                family_name(fam)
            )
        })
    };
    let mut specs: Vec<Spec> = Vec::new();
    for item in items {
        let Some(text) = cx.item_string(LOCAL, item, "device ranges such as \"D0-D99\"") else {
            continue;
        };
        let Some(spec) = parse_range(cx, item, text, devices, not_allowed) else {
            continue;
        };
        if let Some(prev) = specs.iter().find(|s| s.family == spec.family) {
            cx.error(
                &item.span,
                format!(
                    "{LOCAL} already has a range for {} (\"{}\"); the parameter allows one range per device, the same for every program",
                    family_name(spec.family),
                    prev.text
                ),
            );
            continue;
        }
        specs.push(spec);
    }
    specs
        .iter()
        .map(|s| LocalRange {
            kind: s.family,
            start: s.start,
            end: s.end,
        })
        .collect()
}
