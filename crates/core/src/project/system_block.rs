//! `[system_block]` of an APLC-TCP project: the system block's run settings
//! (the APLC programming manual §2.2.1): the output table in STOP, "keep
//! device values" at STOP→RUN and the run input; the interrupt priority is
//! refused with its reason. Each error at its key.

use softplc_aplc::devices::{parse_device, Dev};

use super::ctx::Ctx;
use super::tree::{Entry, Item, Value};
use crate::engine::{CpuConfig, StopOutputs};

/// The settings read, for the system devices (SM9/SD9).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct SystemBlock {
    /// The run input's index 0-15 (X0-X17).
    pub run_input: Option<u8>,
}

/// Reads `[system_block]` into `config`.
pub(crate) fn system_block(cx: &mut Ctx, t: &[Entry], config: &mut CpuConfig) -> SystemBlock {
    const KEYS: &[&str] = &[
        "stop_outputs",
        "keep_device_values",
        "run_input",
        "interrupt_priority",
    ];
    cx.unknown_keys(t, Some("[system_block]"), KEYS);
    let mut out = SystemBlock::default();
    for e in t {
        match e.key.as_str() {
            "stop_outputs" => {
                if let Some(s) = stop_outputs(cx, e) {
                    config.stop_outputs = s;
                }
            }
            "keep_device_values" => {
                if let Some(b) = cx.bool(e, "true or false") {
                    config.keep_device_values = b;
                }
            }
            "run_input" => out.run_input = run_input(cx, e),
            "interrupt_priority" => cx.error(&e.key_span, INTERRUPT_PRIORITY),
            _ => {}
        }
    }
    out
}

/// The system block's interrupt priority page (two levels, low and high,
/// §2.2.1) has no setting in softplc: the interrupt routines run one after
/// another between scans and take no time, so no event can arrive while a
/// routine runs, and §9.2 fixes the order of those waiting (first in, first
/// out); a level has nothing to change.
const INTERRUPT_PRIORITY: &str = "[system_block] interrupt_priority is not a setting in softplc: interrupt routines run one after another at the start of a scan and take no time, so one can never interrupt another, the only thing a priority level could change; waiting events run first in, first out (APLC programming manual §2.2.1, §9.2)";

/// `"off"` (disable), `"hold"` (freeze) or the outputs ON in STOP as an
/// array of Y devices (configure; the others OFF).
fn stop_outputs(cx: &mut Ctx, e: &Entry) -> Option<StopOutputs> {
    const WHAT: &str = "stop_outputs must be \"off\", \"hold\" or an array of the Y outputs ON in STOP (such as [\"Y0\", \"Y5\"])";
    match &e.item.value {
        Value::Str(s) if s == "off" => Some(StopOutputs::Off),
        Value::Str(s) if s == "hold" => Some(StopOutputs::Hold),
        Value::Array(items) => {
            let mut on = Vec::new();
            for i in items {
                if let Some(n) = device(cx, i, Dev::Y, "stop_outputs") {
                    if !on.contains(&n) {
                        on.push(n);
                    }
                }
            }
            Some(StopOutputs::Table(on))
        }
        _ => {
            cx.error(&e.item.span, WHAT);
            None
        }
    }
}

/// `"off"` or an input X0-X17: its index counted from X0 (X10 is 8, SD9).
fn run_input(cx: &mut Ctx, e: &Entry) -> Option<u8> {
    if matches!(&e.item.value, Value::Str(s) if s == "off") {
        return None;
    }
    let n = device(cx, &e.item, Dev::X, "run_input")?;
    if n > 15 {
        cx.error(&e.item.span, "run_input must be one of X0-X17 or \"off\"");
        return None;
    }
    Some(n as u8)
}

/// A device name of kind `dev` (`"Y5"`, octal numbers), its number.
fn device(cx: &mut Ctx, item: &Item, dev: Dev, what: &str) -> Option<u32> {
    let text = cx.item_string(what, item, "a device name such as \"Y0\"")?;
    match parse_device(&text.to_ascii_uppercase()) {
        Ok(Some(r)) if r.dev == dev && r.group.is_none() && r.index.is_none() => Some(r.n),
        Ok(_) => {
            cx.error(
                &item.span,
                format!("{what}: \"{text}\" is not a {} device", dev.name()),
            );
            None
        }
        Err(m) => {
            cx.error(&item.span, format!("{what}: {m}"));
            None
        }
    }
}
