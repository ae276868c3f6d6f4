//! The APLC-TCP CPU (seed 002): programs loaded by the APLC dialect
//! (softplc-aplc) and a CPU configuration with its devices and system
//! devices. The engine is the same; the dialect is passed, not special-cased.

use std::path::Path;
use std::time::Duration;

use crate::engine::CpuConfig;
use crate::program::{Diagnostics, Program};

pub use softplc_aplc::names::Name;

/// The model name that selects the APLC dialect (contract §4).
pub const MODEL: &str = "APLC-TCP";

/// True for a program file read as `.apl` by default (contract §2
/// `--dialect`: by name).
pub fn is_apl(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("apl"))
}

/// Loads an `.apl` program (any file name).
pub fn load_file(path: &Path) -> Result<Program, Diagnostics> {
    softplc_aplc::load_file(path)
}

/// Loads `.apl` text already in memory.
pub fn load_bytes(name: &str, bytes: &[u8]) -> Result<Program, Diagnostics> {
    softplc_aplc::load_bytes(name, bytes)
}

/// An APLC-TCP CPU: its device layout, no latch ranges (no power-loss
/// retention, decision D5), watchdog 200 ms (D4), its system devices.
pub fn cpu_config() -> CpuConfig {
    CpuConfig {
        model: MODEL.to_string(),
        devices: softplc_aplc::device_config(),
        watchdog: Duration::from_millis(200),
        latch: Vec::new(),
        system: Some(softplc_aplc::system()),
        ..CpuConfig::default()
    }
}
