//! `[io]` and `[[slot]]`: the I/O assignment of the base units (004 ch. 5)
//! and the modules in the slots (ch. 8). The assignment rules the CPU checks
//! at power-on are load errors here, each naming the slot and quoting the
//! CPU's `SP.UNIT LAY ERR.` (004 §5: L2408, L2707, L2721-2727).

use std::ops::Range;

use super::ctx::Ctx;
use super::tree::{Entry, Item, Value};
use softplc_ir::device::{parse_operand, DeviceConfig, DeviceKind, Operand, Reach};
use softplc_ir::rack::{AutoRefresh, ModuleProfile, Rack, Slot, SlotType};

/// Slots of the main base and the extension bases together (004 L2402-2413).
pub const MAX_SLOTS: usize = 64;
/// The last I/O number of the bases (004 L2727).
pub const LAST_IO: u32 = 0xFFF;
/// Points an empty slot takes by default (004 L2531-2595).
pub const EMPTY_POINTS: u32 = 16;
/// Points a slot may take (004 L2619-2728).
const POINTS: &[u32] = &[0, 16, 32, 48, 64, 128, 256, 512, 1024];
/// First interrupt pointer of the intelligent function modules' setting.
const FIRST_MODULE_POINTER: u32 = 50;

const TYPES: &[(&str, SlotType)] = &[
    ("empty", SlotType::Empty),
    ("input", SlotType::Input),
    ("output", SlotType::Output),
    ("io", SlotType::Io),
    ("intelligent", SlotType::Intelligent),
    ("interrupt", SlotType::Interrupt),
];

const LAY: &str = "SP.UNIT LAY ERR.";

/// `[io]`: the points of an empty slot.
pub(crate) fn io(cx: &mut Ctx, t: &[Entry]) -> u32 {
    cx.unknown_keys(t, Some("[io]"), &["empty_points"]);
    let Some(e) = t.iter().find(|e| e.key == "empty_points") else {
        return EMPTY_POINTS;
    };
    match &e.item.value {
        Value::Int(n) if (16..=1024).contains(n) && n % 16 == 0 => *n as u32,
        _ => {
            cx.error(
                &e.item.span,
                "empty_points must be 16-1024 points in multiples of 16",
            );
            EMPTY_POINTS
        }
    }
}

/// The `slot` entry of the top-level table: the rack in slot order.
pub(crate) fn slots(
    cx: &mut Ctx,
    entry: Option<&Entry>,
    empty_points: u32,
    devices: &DeviceConfig,
) -> Rack {
    let mut rack = Rack::default();
    let Some(entry) = entry else {
        return rack;
    };
    let Some(tables) = cx.tables(
        entry,
        "slot must be an array of tables: write a [[slot]] table for each slot",
    ) else {
        return rack;
    };
    let mut next = 0u32;
    let mut taken: Vec<(Range<u32>, u32)> = Vec::new();
    let mut interrupt_module: Option<u32> = None;
    for (index, (item, t)) in tables.iter().enumerate() {
        let index = index as u32;
        let Some(slot) = slot(cx, index, item, t, empty_points, next, devices) else {
            continue;
        };
        let at = &item.span;
        let name = slot.describe();
        if slot.start % 16 != 0 {
            cx.error(
                at,
                format!(
                    "{name}: {LAY} the start I/O number {:X} is not a multiple of 16",
                    slot.start
                ),
            );
        }
        let io = slot.io();
        if slot.points > 0 && io.end - 1 > LAST_IO {
            cx.error(
                at,
                format!(
                    "{name}: {LAY} its I/O numbers {:X}-{:X} go beyond {LAST_IO:X}",
                    io.start,
                    io.end - 1
                ),
            );
        }
        if slot.kind != SlotType::Empty && index as usize >= MAX_SLOTS {
            cx.error(
                at,
                format!("{name}: {LAY} a module in slot {index} (the bases have {MAX_SLOTS} slots, 0-{})", MAX_SLOTS - 1),
            );
        }
        if slot.points > 0 {
            if let Some((r, other)) = taken
                .iter()
                .find(|(r, _)| r.start < io.end && io.start < r.end)
            {
                cx.error(
                    at,
                    format!(
                        "{name}: {LAY} its I/O numbers {:X}-{:X} overlap slot {other}'s ({:X}-{:X})",
                        io.start,
                        io.end - 1,
                        r.start,
                        r.end - 1
                    ),
                );
            }
            taken.push((io.clone(), index));
        }
        if slot.kind == SlotType::Interrupt {
            if let Some(first) = interrupt_module {
                cx.error(
                    at,
                    format!("{name}: one interrupt module per CPU (slot {first} has one)"),
                );
            }
            interrupt_module = Some(index);
        }
        for &(_, n) in &slot.interrupts {
            if let Some(other) = rack
                .slots
                .iter()
                .find(|s| s.interrupts.iter().any(|p| p.1 == n))
            {
                cx.error(
                    at,
                    format!(
                        "{name}: interrupt pointer I{n} is already raised by slot {}",
                        other.index
                    ),
                );
            }
        }
        next = io.end.max(next);
        rack.slots.push(slot);
    }
    rack
}

/// One `[[slot]]` table; `next` is the I/O number after the previous slot.
fn slot(
    cx: &mut Ctx,
    index: u32,
    item: &Item,
    t: &[Entry],
    empty_points: u32,
    next: u32,
    devices: &DeviceConfig,
) -> Option<Slot> {
    cx.unknown_keys(
        t,
        Some("[[slot]]"),
        &[
            "type",
            "points",
            "start",
            "module",
            "buffer_words",
            "interrupts",
            "refresh",
            "range",
            "switches",
            "control_cpu",
        ],
    );
    let get = |k: &str| t.iter().find(|e| e.key == k);
    let at = &item.span;
    let kind = match get("type") {
        None => {
            cx.error(
                at,
                format!("slot {index}: [[slot]] needs a type (empty, input, output, io, intelligent or interrupt)"),
            );
            return None;
        }
        Some(e) => cx.choice(e, TYPES)?,
    };
    let module = module(cx, index, kind, get("module"), at)?;
    let points = match get("points") {
        Some(e) => match &e.item.value {
            Value::Int(n) if POINTS.contains(&(*n as u32)) && *n >= 0 => *n as u32,
            _ => {
                cx.error(
                    &e.item.span,
                    format!("slot {index}: points must be one of 0, 16, 32, 48, 64, 128, 256, 512, 1024"),
                );
                return None;
            }
        },
        None => match (kind, module) {
            (SlotType::Empty, _) => empty_points,
            (_, Some(m)) => m.points,
            _ => {
                cx.error(
                    at,
                    format!(
                        "slot {index}: an {} slot needs points (16, 32, 64 …)",
                        kind.name()
                    ),
                );
                return None;
            }
        },
    };
    let start = match get("start") {
        None => next,
        Some(e) => {
            let text = cx.string(e, "a hex I/O number such as \"20\" (a string)")?;
            let digits = text.trim_start_matches("0x").trim_start_matches("0X");
            match u32::from_str_radix(digits, 16) {
                Ok(n) if !digits.is_empty() => n,
                _ => {
                    cx.error(
                        &e.item.span,
                        format!("slot {index}: start \"{text}\" is not a hex I/O number"),
                    );
                    return None;
                }
            }
        }
    };
    let buffer_words = match (module, get("buffer_words")) {
        (Some(m), None) if m.buffer_words > 0 => m.buffer_words,
        (Some(m), None) if m.kind == SlotType::Intelligent => {
            softplc_modules::generic::DEFAULT_WORDS
        }
        (Some(m), Some(e)) if m.buffer_words == 0 && m.kind == SlotType::Intelligent => {
            match &e.item.value {
                Value::Int(n) if (1..=65536).contains(n) => *n as u32,
                _ => {
                    cx.error(
                        &e.item.span,
                        format!("slot {index}: buffer_words must be 1-65536 words"),
                    );
                    return None;
                }
            }
        }
        (_, Some(e)) => {
            cx.error(
                &e.key_span,
                format!("slot {index}: buffer_words is for a generic module only (a profile has its own buffer memory)"),
            );
            return None;
        }
        _ => 0,
    };
    let switches = switches(cx, index, module, get("range"), get("switches"))?;
    let control_cpu = match get("control_cpu") {
        None => 1,
        Some(e) => match &e.item.value {
            Value::Int(n) if (1..=4).contains(n) => *n as u32,
            _ => {
                cx.error(
                    &e.item.span,
                    format!("slot {index}: control_cpu must be a CPU number 1-4"),
                );
                return None;
            }
        },
    };
    let mut slot = Slot {
        index,
        kind,
        points,
        start,
        module,
        buffer_words,
        interrupts: Vec::new(),
        refresh: Vec::new(),
        switches,
        control_cpu,
    };
    if let Some(e) = get("interrupts") {
        slot.interrupts = interrupts(cx, &slot, e)?;
    }
    if let Some(e) = get("refresh") {
        slot.refresh = refresh(cx, &slot, e, devices)?;
    }
    Some(slot)
}

/// The module of a slot: `module = "…"`, by default `generic` in an
/// intelligent slot and `QI60` in an interrupt slot. A profile in a slot of
/// another type is SP.UNIT LAY ERR. (004 L2721-2726).
fn module(
    cx: &mut Ctx,
    index: u32,
    kind: SlotType,
    entry: Option<&Entry>,
    at: &Range<usize>,
) -> Option<Option<&'static ModuleProfile>> {
    let Some(e) = entry else {
        return Some(match kind {
            SlotType::Intelligent => Some(&softplc_modules::GENERIC),
            SlotType::Interrupt => Some(&softplc_modules::QI60),
            _ => None,
        });
    };
    let name = cx.string(e, "a module profile name (a string)")?;
    let Some(m) = softplc_modules::find(name) else {
        let known: Vec<&str> = softplc_modules::PROFILES.iter().map(|p| p.name).collect();
        cx.error(
            &e.item.span,
            format!(
                "slot {index}: no module profile \"{name}\" (there are: {})",
                known.join(", ")
            ),
        );
        return None;
    };
    if m.kind != kind {
        cx.error(
            at,
            format!(
                "slot {index}: {LAY} the {} module {} is in a slot typed {} (write type = \"{}\")",
                m.kind.name(),
                m.name,
                kind.name(),
                m.kind.name()
            ),
        );
        return None;
    }
    Some(Some(m))
}

/// `range = ["4-20mA", …]` (CH1 first) and `switches = [0x0000, …]`: the
/// module's intelligent function module switch setting (switches 1-5 as its
/// manual assigns them), checked by the module's profile.
fn switches(
    cx: &mut Ctx,
    index: u32,
    module: Option<&'static ModuleProfile>,
    range: Option<&Entry>,
    raw: Option<&Entry>,
) -> Option<[u16; 5]> {
    let Some(first) = range.or(raw) else {
        return Some([0; 5]);
    };
    let Some(m) = module else {
        cx.error(
            &first.key_span,
            format!("slot {index}: {} is for a slot holding a module", first.key),
        );
        return None;
    };
    let names: Option<Vec<&str>> = match range {
        None => None,
        Some(e) => {
            let names = match &e.item.value {
                Value::Array(items) => items
                    .iter()
                    .map(|i| match &i.value {
                        Value::Str(s) => Some(s.as_str()),
                        _ => None,
                    })
                    .collect::<Option<Vec<&str>>>(),
                _ => None,
            };
            if names.is_none() {
                cx.error(
                    &e.item.span,
                    format!("slot {index}: range must be an array of range names, CH1 first, such as [\"4-20mA\", \"0-10V\"]"),
                );
                return None;
            }
            names
        }
    };
    let words: Option<[u16; 5]> = match raw {
        None => None,
        Some(e) => {
            let mut words = [0u16; 5];
            let ok = match &e.item.value {
                Value::Array(items) if items.len() <= 5 => {
                    items.iter().zip(&mut words).all(|(i, w)| match &i.value {
                        Value::Int(n) if (0..=0xFFFF).contains(n) => {
                            *w = *n as u16;
                            true
                        }
                        _ => false,
                    })
                }
                _ => false,
            };
            if !ok {
                cx.error(
                    &e.item.span,
                    format!(
                        "slot {index}: switches must be up to 5 numbers 0-0xFFFF (switches 1-5)"
                    ),
                );
                return None;
            }
            Some(words)
        }
    };
    match softplc_modules::switch_setting(m, names.as_deref(), words) {
        Ok(s) => Some(s),
        Err(msg) => {
            cx.error(
                &first.item.span,
                format!("slot {index} ({}): {msg}", m.name),
            );
            None
        }
    }
}

/// `interrupts = { 0 = "I50" }`: the interrupt pointer each of the module's
/// interrupt causes raises (the intelligent function module's interrupt
/// pointer setting, I50-I255; 004 L5600-5620).
fn interrupts(cx: &mut Ctx, slot: &Slot, e: &Entry) -> Option<Vec<(u32, u32)>> {
    let index = slot.index;
    let causes = slot.module.map_or(0, |m| m.causes);
    let Value::Table(t) = &e.item.value else {
        cx.error(
            &e.item.span,
            format!("slot {index}: interrupts must be a table of cause = \"I50\""),
        );
        return None;
    };
    if causes == 0 {
        cx.error(
            &e.key_span,
            format!(
                "{}: this module raises no interrupts of its own setting",
                slot.describe()
            ),
        );
        return None;
    }
    let mut out = Vec::new();
    for c in t {
        let cause = match c.key.parse::<u32>() {
            Ok(n) if n < causes => n,
            _ => {
                cx.error(
                    &c.key_span,
                    format!(
                        "slot {index}: interrupt cause `{}` is not 0-{}",
                        c.key,
                        causes - 1
                    ),
                );
                continue;
            }
        };
        let Some(text) = cx.string(c, "an interrupt pointer such as \"I50\"") else {
            continue;
        };
        let n = text
            .strip_prefix(['I', 'i'])
            .and_then(|d| d.parse::<u32>().ok())
            .filter(|n| (FIRST_MODULE_POINTER..=255).contains(n));
        match n {
            Some(n) => out.push((cause, n)),
            None => cx.error(
                &c.item.span,
                format!("slot {index}: \"{text}\" is not an intelligent module's interrupt pointer (I50-I255)"),
            ),
        }
    }
    Some(out)
}

/// Word devices an auto refresh may name.
const REFRESH_DEVICES: &[DeviceKind] =
    &[DeviceKind::D, DeviceKind::W, DeviceKind::R, DeviceKind::ZR];

/// `refresh = [{ buffer = 11, to = "D100", words = 4 }, { buffer = 1, from
/// = "D200", words = 2 }]`: the module's auto refresh at END (004 ch. 8,
/// L5440-5462): `to` copies buffer memory into the CPU's devices, `from`
/// the devices into buffer memory.
fn refresh(
    cx: &mut Ctx,
    slot: &Slot,
    e: &Entry,
    devices: &DeviceConfig,
) -> Option<Vec<AutoRefresh>> {
    let index = slot.index;
    let items: Vec<&Item> = match &e.item.value {
        Value::Array(a) => a.iter().collect(),
        _ => Vec::new(),
    };
    if items.is_empty() || slot.buffer_words == 0 {
        cx.error(
            &e.item.span,
            format!("slot {index}: refresh is an array of {{ buffer = 11, to = \"D100\", words = 4 }} tables on an intelligent module"),
        );
        return None;
    }
    let mut out = Vec::new();
    for item in items {
        let Value::Table(t) = &item.value else {
            cx.error(
                &item.span,
                format!("slot {index}: each refresh is a table {{ buffer, to or from, words }}"),
            );
            continue;
        };
        cx.unknown_keys(t, Some("refresh"), &["buffer", "to", "from", "words"]);
        let get = |k: &str| t.iter().find(|e| e.key == k);
        let int = |cx: &mut Ctx, k: &str| match get(k).map(|e| (&e.item.value, &e.item.span)) {
            Some((Value::Int(n), _)) if (0..=65535).contains(n) => Some(*n as u32),
            Some((_, span)) => {
                cx.error(span, format!("slot {index}: refresh {k} must be 0-65535"));
                None
            }
            None => {
                cx.error(&item.span, format!("slot {index}: a refresh needs {k}"));
                None
            }
        };
        let (Some(buffer), Some(words)) = (int(cx, "buffer"), int(cx, "words")) else {
            continue;
        };
        let (dev, to_cpu) = match (get("to"), get("from")) {
            (Some(d), None) => (d, true),
            (None, Some(d)) => (d, false),
            _ => {
                cx.error(&item.span, format!("slot {index}: a refresh has either to (module → CPU) or from (CPU → module)"));
                continue;
            }
        };
        let Some(text) = cx.string(dev, "a word device such as \"D100\"") else {
            continue;
        };
        let target = match parse_operand(text) {
            Ok(Operand::Device {
                dev: d,
                digits: None,
                bit: None,
                index: None,
            }) if d.reach == Reach::Memory && REFRESH_DEVICES.contains(&d.kind) => d,
            _ => {
                cx.error(
                    &dev.item.span,
                    format!("slot {index}: \"{text}\" is not a D, W, R or ZR device"),
                );
                continue;
            }
        };
        if words == 0 || buffer + words > slot.buffer_words {
            cx.error(
                &item.span,
                format!("slot {index}: refresh of {words} words from G{buffer} is outside the module's buffer memory (G0-G{})", slot.buffer_words - 1),
            );
            continue;
        }
        let kind = if target.kind == DeviceKind::R {
            DeviceKind::ZR
        } else {
            target.kind
        };
        let limit = if target.kind == DeviceKind::R {
            32768
        } else {
            devices.points(kind)
        };
        if target.number as u64 + words as u64 > limit as u64 {
            cx.error(
                &dev.item.span,
                format!("slot {index}: {words} words from {text} run past the last device"),
            );
            continue;
        }
        out.push(AutoRefresh {
            buffer,
            device: kind,
            number: target.number,
            words,
            to_cpu,
        });
    }
    Some(out)
}
