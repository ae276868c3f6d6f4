//! `[cpu]`, `[timers]`, `[ras]`, `[interrupts]`, `[clock]` and `[state]`.

use std::time::Duration;

use super::ctx::Ctx;
use super::tree::{Entry, Value};
use super::units::{ranges, show};
use crate::engine::calendar::DateTime;
use crate::engine::{CpuConfig, ErrorMode, StopToRunOutput};
use crate::profile::Profile;

/// `[process]`: the process CPU's decisions (spec/process-control.md
/// DEC-1 … DEC-36), each `key = true|false`; only on a process CPU model.
pub(crate) fn process(
    cx: &mut Ctx,
    e: &Entry,
    t: &[Entry],
    profile: &Profile,
    out: &mut crate::program::ProcessSettings,
) {
    use softplc_melsec::process::settings::KEYS;
    let model = profile.model;
    if !softplc_melsec::is_process_model(model) {
        cx.error(
            &e.item.span,
            format!(
                "[process] sets the process CPU's decisions, but the model is {model} \
                 (a process CPU is Q02PHCPU, Q06PHCPU, Q12PHCPU, Q25PHCPU, Q12PRHCPU or Q25PRHCPU)"
            ),
        );
        return;
    }
    let names: Vec<&str> = KEYS.iter().map(|k| k.name).collect();
    cx.unknown_keys(t, Some("[process]"), &names);
    for e in t {
        if !names.contains(&e.key.as_str()) {
            continue;
        }
        if let Some(v) = cx.bool(e, "true or false") {
            if e.key == "detail_codes" && !v {
                // The error codes apply to every instruction and the manual
                // offers no other assignment to switch to.
                cx.error(
                    &e.item.span,
                    "detail_codes = false: the manual describes no other assignment of the \
                     SD1502 detail codes (Process Control Instructions manual §2.2.5, \
                     chapter 14), so only true is accepted",
                );
                continue;
            }
            out.set(&e.key, v);
        }
    }
}

/// The model named `text` (case-insensitive), as softplc spells it, or an
/// error listing the models.
pub fn known_model(text: &str) -> Result<&'static Profile, String> {
    crate::profile::find(text)
}

/// Steps of program memory a model has (1k = 1024 steps; decision).
pub fn program_capacity(profile: &Profile) -> u32 {
    profile.capacity.program_steps
}

/// The file header every program file takes in program memory (004 L1018:
/// "文件标题容量（缺省值：34 步）").
pub const FILE_HEADER_STEPS: u32 = 34;

/// Checks that programs of `steps` (one entry per file, as `(file, steps)`)
/// fit the model's program memory with their file headers; the error names the
/// first file that does not fit.
pub fn check_capacity(
    profile: &Profile,
    files: &[(&str, u32)],
) -> Result<(), crate::program::Diagnostic> {
    let capacity = program_capacity(profile);
    let model = profile.model;
    let mut used = 0u64;
    for (file, steps) in files {
        used += (*steps + FILE_HEADER_STEPS) as u64;
        if used > capacity as u64 {
            let total: u64 = files
                .iter()
                .map(|(_, s)| (*s + FILE_HEADER_STEPS) as u64)
                .sum();
            return Err(crate::program::Diagnostic {
                file: file.to_string(),
                line: 1,
                col: 1,
                message: format!(
                    "the programs take {total} steps ({FILE_HEADER_STEPS} file-header steps a file \
                     included), more than the {model}'s program memory of {capacity} steps"
                ),
            });
        }
    }
    Ok(())
}

/// `[cpu] model`, `a_compatibility` and `common_pointer`; returns the first
/// common pointer.
pub(crate) fn cpu(
    cx: &mut Ctx,
    t: &[Entry],
    config: &mut CpuConfig,
    melsec: &mut softplc_melsec::system::Params,
) -> Option<u32> {
    cx.unknown_keys(
        t,
        Some("[cpu]"),
        &[
            "model",
            "common_pointer",
            "exec",
            "a_compatibility",
            "online_write_steps",
            "online_reserve_steps",
        ],
    );
    if let Some(e) = t.iter().find(|e| e.key == "model") {
        model(cx, e, config);
    }
    if let Some(e) = t.iter().find(|e| e.key == "a_compatibility") {
        a_compatibility(cx, e, config, melsec);
    }
    online_limits(cx, t, config);
    let e = t.iter().find(|e| e.key == "common_pointer")?;
    let text = cx.string(e, "a pointer such as \"P2048\"")?;
    let n = text
        .strip_prefix(['P', 'p'])
        .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
        .and_then(|d| d.parse::<u32>().ok())
        .filter(|n| *n <= 4095);
    if n.is_none() {
        cx.error(
            &e.item.span,
            format!("common_pointer \"{text}\" is not a pointer P0-P4095"),
        );
    }
    n
}

/// `[cpu] online_write_steps` (1-512, default 512) and
/// `online_reserve_steps` (0-65535, default 500): the limits of writing a
/// program during RUN (004 §4.8 (b), (e)).
fn online_limits(cx: &mut Ctx, t: &[Entry], config: &mut CpuConfig) {
    let keys: [(&str, u32, &mut u32); 2] = [
        ("online_write_steps", 512, &mut config.online.max_steps),
        (
            "online_reserve_steps",
            65535,
            &mut config.online.reserve_steps,
        ),
    ];
    let least = |key: &str| u32::from(key == "online_write_steps");
    for (key, most, field) in keys {
        let Some(e) = t.iter().find(|e| e.key == key) else {
            continue;
        };
        match e.item.value {
            Value::Int(n) if (i64::from(least(key))..=i64::from(most)).contains(&n) => {
                *field = n as u32
            }
            _ => cx.error(
                &e.item.span,
                format!(
                    "{key} must be a number of steps from {} to {most}",
                    least(key)
                ),
            ),
        }
    }
}

/// `[cpu] a_compatibility`: the MELSEC-Q parameter "A-series CPU
/// compatibility" (SM1000/SD1000 maintained; ON by default, 004 L5831).
fn a_compatibility(
    cx: &mut Ctx,
    e: &Entry,
    config: &CpuConfig,
    melsec: &mut softplc_melsec::system::Params,
) {
    let Some(on) = cx.bool(e, "true or false") else {
        return;
    };
    if crate::profile::is_aplc(config.profile) {
        cx.error(
            &e.item.span,
            format!(
                "a_compatibility is a MELSEC-Q parameter (SM1000/SD1000); the {} has none",
                config.profile.model
            ),
        );
        return;
    }
    melsec.a_compatibility = on;
}

/// `[cpu] exec`: "auto", "jit" or "interp" (`crate::tier`).
pub(crate) fn exec(cx: &mut Ctx, t: &[Entry]) -> Option<crate::tier::Exec> {
    let e = t.iter().find(|e| e.key == "exec")?;
    cx.choice(e, &crate::tier::Exec::CHOICES)
}

fn model(cx: &mut Ctx, e: &Entry, config: &mut CpuConfig) {
    let Some(text) = cx.string(e, "a CPU model name such as \"Q06HCPU\"") else {
        return;
    };
    match crate::profile::find(text) {
        Ok(p) if p != config.profile => {
            *config = CpuConfig {
                profile: p,
                devices: (p.default_devices)(),
                system: (p.default_system)(),
                ..config.clone()
            }
        }
        Ok(_) => {}
        Err(e2) => cx.error(&e.item.span, e2),
    }
}

/// `[timers] low`, `high`: the timer time bases (004 Table 3.1, ch. 9).
pub(crate) fn timers(cx: &mut Ctx, t: &[Entry], config: &mut CpuConfig) {
    cx.unknown_keys(t, Some("[timers]"), &["low", "high"]);
    for e in t {
        match e.key.as_str() {
            "low" => {
                if let Some(d) = cx.duration(e, ranges::TIMER_LOW) {
                    config.timer_low = d;
                }
            }
            "high" => {
                if let Some(d) = cx.duration(e, ranges::TIMER_HIGH) {
                    config.timer_high = d;
                }
            }
            _ => {}
        }
    }
}

/// The PLC RAS error classes (004 §7.15 (3), L4911-4922) whose errors need
/// hardware softplc does not have: their keys are refused with the reason.
fn ras_class_without_hardware(key: &str) -> Option<&'static str> {
    Some(match key {
        "extension_instruction_error" => {
            "no instruction softplc runs raises an extension instruction error"
        }
        "fuse_blown_error" => "softplc has no output modules with fuses (FUSE BREAK OFF)",
        "io_verify_error" => "softplc's I/O modules never change while it runs (UNIT VERIFY ERR.)",
        "memory_card_access_error" | "memory_card_operation_error" => {
            "softplc has no memory card (ICM.OPE.ERROR)"
        }
        "external_power_error" => {
            "the manual reserves it for future use and softplc has no external power supply"
        }
        _ => return None,
    })
}

/// An optional time setting: a duration or `"off"`.
fn optional(cx: &mut Ctx, e: &Entry, range: super::units::Range) -> Option<Option<Duration>> {
    if matches!(&e.item.value, Value::Str(s) if s == "off") {
        return Some(None);
    }
    cx.duration(e, range).map(Some)
}

/// `[ras]`: the PLC RAS parameters.
pub(crate) fn ras(cx: &mut Ctx, t: &[Entry], config: &mut CpuConfig) {
    const KEYS: &[&str] = &[
        "watchdog",
        "constant_scan",
        "operation_error",
        "stop_to_run_output",
        "low_speed_time",
        "low_speed_monitor",
        "initial_monitor",
        "run_contact",
        "pause_contact",
        "remote_reset",
        "module_error",
        "file_access_error",
    ];
    for e in t {
        if let Some(why) = ras_class_without_hardware(&e.key) {
            cx.error(
                &e.key_span,
                format!(
                    "[ras] {}: {why}, so the error class never occurs (QCPU manual §7.15 (3))",
                    e.key
                ),
            );
        } else if !KEYS.contains(&e.key.as_str()) {
            cx.unknown_key(e, Some("[ras]"), KEYS);
        }
    }
    let mut watchdog_ok = true;
    let mut constant_scan_at = None;
    for e in t {
        match e.key.as_str() {
            "watchdog" => match cx.duration(e, ranges::WATCHDOG) {
                Some(d) => config.watchdog = d,
                None => watchdog_ok = false,
            },
            "constant_scan" => {
                if let Some(d) = optional(cx, e, ranges::CONSTANT_SCAN) {
                    config.constant_scan = d;
                    constant_scan_at = Some(e);
                }
            }
            "operation_error" | "module_error" | "file_access_error" => {
                let choices = [("stop", ErrorMode::Stop), ("continue", ErrorMode::Continue)];
                if let Some(m) = cx.choice(e, &choices) {
                    match e.key.as_str() {
                        "operation_error" => config.operation_error = m,
                        "module_error" => config.module_error = m,
                        _ => config.file_error = m,
                    }
                }
            }
            "stop_to_run_output" => {
                let choices = [
                    ("previous", StopToRunOutput::Previous),
                    ("recalculate", StopToRunOutput::Recalculate),
                ];
                if let Some(m) = cx.choice(e, &choices) {
                    config.stop_to_run_output = m;
                }
            }
            "low_speed_time" => {
                if let Some(d) = optional(cx, e, ranges::LOW_SPEED_TIME) {
                    config.low_speed_time = d;
                }
            }
            "low_speed_monitor" => {
                if let Some(d) = optional(cx, e, ranges::LOW_SPEED_MONITOR) {
                    config.low_speed_monitor = d;
                }
            }
            "initial_monitor" => {
                if let Some(d) = optional(cx, e, ranges::INITIAL_MONITOR) {
                    config.initial_monitor = d;
                }
            }
            "run_contact" => {
                if let Some(n) = contact(cx, e) {
                    config.run_contact = Some(n);
                }
            }
            "pause_contact" => {
                if let Some(n) = contact(cx, e) {
                    config.pause_contact = Some(n);
                }
            }
            "remote_reset" => {
                if let Some(b) = cx.bool(e, "true or false") {
                    config.remote_reset = b;
                }
            }
            _ => {}
        }
    }
    // The PAUSE contact works only with a RUN contact: the manual sets them
    // as one parameter, "RUN-PAUSE contacts" (004 §7.6.5 *2).
    if let (Some(e), None) = (
        t.iter().find(|e| e.key == "pause_contact"),
        config.run_contact,
    ) {
        if config.pause_contact.is_some() {
            cx.error(
                &e.key_span,
                "pause_contact needs run_contact: the CPU sets them as one parameter, the RUN-PAUSE contacts",
            );
        }
    }
    // WDT > constant scan (004 L3462-3475).
    if let (Some(e), Some(cs), true) = (constant_scan_at, config.constant_scan, watchdog_ok) {
        if cs >= config.watchdog {
            let given = t.iter().any(|e| e.key == "watchdog");
            cx.error(
                &e.item.span,
                format!(
                    "constant_scan \"{}\" must be shorter than the watchdog ({}{}); the CPU requires watchdog > constant scan",
                    show(cs),
                    show(config.watchdog),
                    if given { "" } else { ", the default" }
                ),
            );
        }
    }
}

/// `[ras] run_contact`, `pause_contact`: an input X0-X1FFF (004 L1061).
fn contact(cx: &mut Ctx, e: &Entry) -> Option<u32> {
    use softplc_ir::device::{parse_operand, DeviceKind, Operand, Reach};
    let text = cx.string(e, "an input such as \"X10\"")?;
    match parse_operand(text) {
        Ok(Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) if dev.reach == Reach::Memory && dev.kind == DeviceKind::X && dev.number <= 0x1FFF => {
            Some(dev.number)
        }
        _ => {
            cx.error(
                &e.item.span,
                format!("{} \"{text}\" must be an input X0-X1FFF", e.key),
            );
            None
        }
    }
}

/// `[interrupts] I28` … `I31`: fixed-cycle interrupt periods (004 App. 3);
/// `counter_start`: the interrupt counters.
pub(crate) fn interrupts(cx: &mut Ctx, t: &[Entry], config: &mut CpuConfig) {
    const KEYS: &[&str] = &["I28", "I29", "I30", "I31", "counter_start"];
    for e in t {
        if e.key == "counter_start" {
            config.interrupt_counters = counter_start(cx, e, config);
            continue;
        }
        let up = e.key.to_ascii_uppercase();
        let Some(i) = KEYS.iter().position(|k| *k == up) else {
            let is_pointer =
                up.len() > 1 && up.starts_with('I') && up[1..].bytes().all(|b| b.is_ascii_digit());
            if is_pointer {
                cx.error(
                    &e.key_span,
                    format!(
                        "{} has no settable period: only I28-I31 are fixed-cycle interrupts",
                        e.key
                    ),
                );
            } else {
                cx.unknown_key(e, Some("[interrupts]"), KEYS);
            }
            continue;
        };
        if t.iter()
            .take_while(|o| !std::ptr::eq(*o, e))
            .any(|o| o.key.eq_ignore_ascii_case(&e.key))
        {
            cx.error(&e.key_span, format!("{up} is given twice"));
            continue;
        }
        if let Some(d) = cx.duration(e, ranges::INTERRUPT) {
            config.interrupt_periods[i] = d;
        }
    }
}

/// Interrupt counters (004 L6600-6645, the counters C): 256 counters from the
/// first one, `C<n>` counting I0, `C<n+1>` I1 … `C<n+255>` I255.
const INTERRUPT_COUNTERS: u32 = 256;

/// `counter_start = "C300"`: the first interrupt counter; the 256 counters
/// must be within the CPU's C points.
fn counter_start(cx: &mut Ctx, e: &Entry, config: &CpuConfig) -> Option<u32> {
    let text = cx.string(e, "a counter such as \"C300\"")?;
    let points = config.devices.points(crate::device::DeviceKind::CN);
    let n = text
        .strip_prefix(['C', 'c'])
        .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
        .and_then(|d| d.parse::<u32>().ok());
    match n {
        Some(n)
            if n.checked_add(INTERRUPT_COUNTERS)
                .is_some_and(|end| end <= points) =>
        {
            Some(n)
        }
        Some(n) => {
            cx.error(
                &e.item.span,
                format!(
                    "counter_start \"{text}\": the {INTERRUPT_COUNTERS} interrupt counters C{n}-C{} \
                     (one per interrupt pointer I0-I255) end past the last counter C{}",
                    n.saturating_add(INTERRUPT_COUNTERS - 1),
                    points.saturating_sub(1)
                ),
            );
            None
        }
        None => {
            cx.error(
                &e.item.span,
                format!("counter_start \"{text}\" is not a counter such as \"C300\""),
            );
            None
        }
    }
}

/// `[clock] start`: the calendar clock at power-on.
pub(crate) fn clock(cx: &mut Ctx, t: &[Entry], config: &mut CpuConfig) {
    cx.unknown_keys(t, Some("[clock]"), &["start"]);
    let Some(e) = t.iter().find(|e| e.key == "start") else {
        return;
    };
    let text = match &e.item.value {
        Value::Str(s) | Value::Datetime(s) => s.as_str(),
        v => {
            cx.error(
                &e.item.span,
                format!(
                    "start must be a date and time such as \"2000-01-01T00:00:00\", not {}",
                    v.type_name()
                ),
            );
            return;
        }
    };
    match parse_datetime(text) {
        Some(dt) if dt.is_valid() => config.clock_start = dt,
        Some(dt) if !(1980..=2079).contains(&dt.year) => {
            cx.error(
                &e.item.span,
                format!("start \"{text}\" is outside the clock's years 1980-2079"),
            );
        }
        _ => cx.error(
            &e.item.span,
            format!(
                "start \"{text}\" is not a valid local date and time (write \"YYYY-MM-DDTHH:MM:SS\", e.g. \"2000-01-01T00:00:00\")"
            ),
        ),
    }
}

/// `YYYY-MM-DDTHH:MM:SS` (or a space instead of `T`).
fn parse_datetime(s: &str) -> Option<DateTime> {
    DateTime::parse(s)
}

/// `[state]`: `dir`, the persistence directory relative to the project, and
/// `on_damage`, what a damaged state directory does at power-on.
pub(crate) fn state<'t>(
    cx: &mut Ctx,
    t: &'t [Entry],
    on_damage: &mut crate::persist::OnDamage,
) -> Option<&'t str> {
    use crate::persist::OnDamage;
    cx.unknown_keys(t, Some("[state]"), &["dir", "on_damage"]);
    if let Some(e) = t.iter().find(|e| e.key == "on_damage") {
        let choices = [("continue", OnDamage::Continue), ("stop", OnDamage::Stop)];
        if let Some(m) = cx.choice(e, &choices) {
            *on_damage = m;
        }
    }
    let e = t.iter().find(|e| e.key == "dir")?;
    let d = cx.string(e, "a directory path (a string)")?;
    if d.trim().is_empty() {
        cx.error(&e.item.span, "dir must not be empty");
        return None;
    }
    Some(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn datetimes() {
        let dt = parse_datetime("2024-02-29T23:59:58").unwrap();
        assert!(dt.is_valid());
        assert_eq!((dt.year, dt.month, dt.day, dt.second), (2024, 2, 29, 58));
        assert!(parse_datetime("2024-02-29 23:59:58").is_some());
        assert!(!parse_datetime("2023-02-29T00:00:00").unwrap().is_valid());
        assert!(parse_datetime("2023-02-28").is_none());
        assert!(parse_datetime("2023-02-28T00:00:00Z").is_none());
        assert!(parse_datetime("2023-+2-28T00:00:00").is_none());
    }
}
