//! An APLC-TCP project (`[cpu] model = "APLC-TCP"`, contract §1.1 item 10,
//! §4): the APLC device layout and system devices; the MELSEC-only tables are
//! load errors; program files are `.apl`.

use super::ctx::Ctx;
use super::tree::Entry;
use super::ProgramSpec;
use crate::engine::{CpuConfig, ExecType};
use crate::program::{Diagnostic, Program};

/// Applies the APLC-TCP CPU to `config` (after `[ras]` was read) and reports
/// the tables and keys the APLC does not have. The watchdog is at most
/// 1000 ms and below 100 ms acts as 100 ms; the constant scan is at most the
/// watchdog (L953, L1103, SD33-SD34, decision D4).
pub(crate) fn configure(
    cx: &mut Ctx,
    top: &[Entry],
    config: &mut CpuConfig,
    ports: &[softplc_aplc::comm::PortConfig],
) {
    let ras = top.iter().find(|e| e.key == "ras");
    let key = |k: &str| match ras.map(|r| &r.item.value) {
        Some(super::tree::Value::Table(t)) => {
            t.iter().find(|e| e.key == k).map(|e| e.item.span.clone())
        }
        _ => None,
    };
    let limit = std::time::Duration::from_millis(1000);
    if config.watchdog > limit {
        let at = key("watchdog").unwrap_or(0..0);
        cx.error(
            &at,
            "watchdog: APLC-TCP allows 0-1000 ms (APLC programming manual §2.2.1)",
        );
    }
    config.watchdog = config.watchdog.max(std::time::Duration::from_millis(100));
    if let Some(cs) = config.constant_scan {
        if cs > limit || cs > config.watchdog {
            let at = key("constant_scan").unwrap_or(0..0);
            cx.error(
                &at,
                "constant_scan: APLC-TCP allows 0-1000 ms, not above the watchdog (APLC programming manual §2.1.4)",
            );
        }
    }
    let base =
        crate::aplc::cpu_config_with_ports(config.watchdog, config.constant_scan, ports.to_vec());
    config.devices = base.devices;
    config.system = base.system;
    config.latch = Vec::new();
    // Without "keep device values" the devices are re-initialised at
    // STOP→RUN (§2.1.6, §2.2.1): the option is off unless chosen.
    config.keep_device_values = false;
    if let Some(e) = top.iter().find(|e| e.key == "system_block") {
        if let Some(t) = cx.table(e, "[system_block]") {
            let block = super::system_block::system_block(cx, t, config);
            config.run_input = block.run_input.map(u32::from);
            let ms = |d: std::time::Duration| d.as_millis().min(u16::MAX as u128) as u16;
            config.system = softplc_aplc::system_with_run_input(
                ms(config.watchdog),
                config.constant_scan.map_or(0, ms),
                ports.to_vec(),
                block.run_input,
            );
        }
    }
    for e in top {
        let why = match e.key.as_str() {
            "latch" => "APLC-TCP has no power-loss retention (APLC programming manual §2.1.7)",
            "interrupts" | "devices" | "timers" => "it is MELSEC-only",
            _ => continue,
        };
        cx.error(
            &e.key_span,
            format!("[{}] in an APLC-TCP project: {why}", e.key),
        );
    }
    if let Some(ras) = top.iter().find(|e| e.key == "ras") {
        if let super::tree::Value::Table(t) = &ras.item.value {
            for e in t {
                if matches!(
                    e.key.as_str(),
                    "operation_error"
                        | "module_error"
                        | "file_access_error"
                        | "stop_to_run_output"
                        | "run_contact"
                        | "pause_contact"
                        | "remote_reset"
                ) {
                    cx.error(
                        &e.key_span,
                        format!("[ras] {} is MELSEC-only: not in an APLC-TCP project", e.key),
                    );
                }
            }
        }
    }
}

/// Loads the programs of an APLC-TCP project: every `[[program]]` file is
/// read as `.apl` and all of them form one user program (contract §1.1
/// item 10, [`crate::aplc::load_files`]); scan programs only.
pub(crate) fn load(specs: &[ProgramSpec], manifest: &str) -> Result<Vec<Program>, Vec<Diagnostic>> {
    let mut diags = Vec::new();
    for s in specs {
        if s.exec != ExecType::Scan {
            diags.push(Diagnostic {
                file: manifest.to_string(),
                line: 1,
                col: 1,
                message: format!(
                    "{}: APLC-TCP programs are scan programs (type \"scan\")",
                    s.file.display()
                ),
            });
        }
    }
    if !diags.is_empty() {
        return Err(diags);
    }
    let files: Vec<&std::path::Path> = specs.iter().map(|s| s.file.as_path()).collect();
    crate::aplc::load_files(&files)
        .map(|p| vec![p])
        .map_err(|d| d.0)
}
