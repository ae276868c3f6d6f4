//! `[[program]]`: the program files and their execution types (PLC parameter
//! "program setting", 004 §4.2, qcpu.md §2.2), in execution order.

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::ctx::Ctx;
use super::tree::{Entry, Item, Value};
use super::units::ranges;
use super::ProgramSpec;
use crate::engine::{CpuConfig, ExecType};

const TYPES: &[(&str, ExecType)] = &[
    ("initial", ExecType::Initial),
    ("scan", ExecType::Scan),
    ("low-speed", ExecType::LowSpeed),
    ("standby", ExecType::Standby),
    ("fixed-scan", ExecType::FixedScan),
];

/// Reads the `program` entry of the top-level table (absent: `None`).
pub(crate) fn programs(
    cx: &mut Ctx,
    entry: Option<&Entry>,
    dir: &Path,
    config: &CpuConfig,
) -> Vec<ProgramSpec> {
    let mut out = Vec::new();
    let Some(entry) = entry else {
        cx.error(
            &(0..0),
            "the project has no programs: add a [[program]] table with file and type for each program file",
        );
        return out;
    };
    let Some(tables) = cx.tables(
        entry,
        "program must be an array of tables: write a [[program]] table for each program file",
    ) else {
        return out;
    };
    let max = config.profile.capacity.programs;
    if let Some((item, _)) = tables.get(max) {
        cx.error(
            &item.span,
            format!(
                "too many programs ({}): a {} executes at most {max} program files",
                tables.len(),
                config.profile.model
            ),
        );
    }
    let mut types_ok = true;
    // Listed files by path (a map: 16,000 tables must not cost O(n²)).
    let mut files: std::collections::HashMap<PathBuf, &str> = std::collections::HashMap::new();
    let mut first_low_speed: Option<&Item> = None;
    for (item, t) in &tables {
        cx.unknown_keys(
            t,
            Some("[[program]]"),
            &["file", "type", "interval", "sim_time", "local_devices"],
        );
        let get = |k: &str| t.iter().find(|e| e.key == k);
        // file
        let mut file = None;
        match get("file") {
            None => cx.error(&item.span, "[[program]] needs a file = \"name.il\""),
            Some(e) => {
                if let Some(name) = cx.string(e, "a file name (a string)") {
                    let path = dir.join(name);
                    if name.trim().is_empty() {
                        cx.error(&e.item.span, "file must not be empty");
                    } else if let Some(prev) = files.get(&path) {
                        cx.error(
                            &e.item.span,
                            format!(
                                "program file \"{name}\" is listed twice (first as \"{prev}\")"
                            ),
                        );
                    } else if !path.is_file() {
                        cx.error(
                            &e.item.span,
                            format!("program file \"{name}\" not found ({})", path.display()),
                        );
                        files.insert(path, name);
                    } else {
                        files.insert(path.clone(), name);
                        file = Some(path);
                    }
                }
            }
        }
        // type
        let type_entry = get("type");
        let exec = match type_entry {
            None => Some(ExecType::Scan),
            Some(e) => cx.choice(e, TYPES),
        };
        if exec.is_none() {
            types_ok = false;
        }
        if exec == Some(ExecType::LowSpeed) && first_low_speed.is_none() {
            first_low_speed = Some(&type_entry.expect("low-speed is written").item);
        }
        // interval
        let mut interval = None;
        match (exec, get("interval")) {
            (Some(ExecType::FixedScan), None) => cx.error(
                &type_entry.expect("fixed-scan is written").item.span,
                format!(
                    "a fixed-scan program needs an interval ({}, or {})",
                    ranges::FIXED_SCAN_MS.describe(),
                    ranges::FIXED_SCAN_S.describe()
                ),
            ),
            (Some(ExecType::FixedScan), Some(e)) => {
                if let Some(text) = cx.string(e, "a duration string such as \"50ms\"") {
                    if let Some(d) = cx.parse_duration(e, text) {
                        if ranges::FIXED_SCAN_MS.contains(d) || ranges::FIXED_SCAN_S.contains(d) {
                            interval = Some(d);
                        } else {
                            cx.error(
                                &e.item.span,
                                format!(
                                    "interval \"{text}\" is out of range ({}, or {})",
                                    ranges::FIXED_SCAN_MS.describe(),
                                    ranges::FIXED_SCAN_S.describe()
                                ),
                            );
                        }
                    }
                }
            }
            (Some(other), Some(e)) => {
                let name = TYPES
                    .iter()
                    .find(|(_, t)| *t == other)
                    .map_or("", |(n, _)| n);
                cx.error(
                    &e.key_span,
                    format!("interval is only for fixed-scan programs (this one is {name})"),
                );
            }
            _ => {}
        }
        // sim_time: simulated execution time of one run (softplc extension for
        // virtual time, 0-2000 ms).
        let mut sim_time = None;
        if let Some(e) = get("sim_time") {
            if let Some(text) = cx.string(e, "a duration string such as \"1ms\"") {
                if let Some(d) = cx.parse_duration(e, text) {
                    if d <= Duration::from_secs(2) {
                        sim_time = Some(d);
                    } else {
                        cx.error(
                            &e.item.span,
                            format!("sim_time \"{text}\" is out of range (0-2000ms)"),
                        );
                    }
                }
            }
        }
        // local_devices: the program's "local device" file setting (004
        // L1370-1381): true "use the PLC file setting", false "not used".
        let mut local_devices = true;
        if let Some(e) = get("local_devices") {
            if crate::profile::is_aplc(config.profile) {
                cx.error(
                    &e.key_span,
                    format!("the {} has no local devices", config.profile.model),
                );
            } else if let Some(b) = cx.bool(
                e,
                "true (the project's local devices, default) or false (not used)",
            ) {
                local_devices = b;
            }
        }
        if let (Some(file), Some(exec)) = (file, exec) {
            out.push(ProgramSpec {
                file,
                exec,
                interval,
                sim_time,
                local_devices,
            });
        }
    }
    if types_ok {
        let runs = tables.iter().any(|(_, t)| {
            t.iter().find(|e| e.key == "type").is_none_or(
                |e| matches!(&e.item.value, Value::Str(s) if s == "scan" || s == "initial"),
            )
        });
        if !runs {
            cx.error(
                &tables[0].0.span,
                "no program of type scan or initial: a project needs at least one",
            );
        }
    }
    if let Some(at) = first_low_speed {
        if config.constant_scan.is_none() && config.low_speed_time.is_none() {
            cx.error(
                &at.span,
                "a low-speed program runs only in the spare time of a constant scan or for a \
                 low-speed execution time: set [ras] constant_scan or low_speed_time",
            );
        }
    }
    out
}
