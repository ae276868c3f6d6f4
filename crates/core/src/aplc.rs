//! The APLC-TCP CPU (seed 002): programs loaded by the APLC dialect
//! (softplc-aplc) and a CPU configuration with its devices and system
//! devices. The engine is the same; the dialect is passed, not special-cased.

use std::path::Path;
use std::time::Duration;

use crate::engine::CpuConfig;
use crate::program::{Diagnostics, Program};

pub use softplc_aplc::comm::PortConfig;
pub use softplc_aplc::names::Name;

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

/// Loads `.apl` text already in memory; the program keeps its global
/// variable names ([`Program::globals`](crate::program::ops::Program)) for
/// device names from outside (contract §2).
pub fn load_bytes(name: &str, bytes: &[u8]) -> Result<Program, Diagnostics> {
    softplc_aplc::load_bytes(name, bytes)
}

/// The global variables of `.apl` files (see [`softplc_aplc::files::globals_of_files`]).
pub fn globals_of_files(paths: &[&Path]) -> Vec<(String, String)> {
    softplc_aplc::files::globals_of_files(paths)
}

/// Loads the `.apl` files of an APLC-TCP project as one user program (see
/// [`softplc_aplc::files::load_files`]).
pub fn load_files(paths: &[&Path]) -> Result<Program, Diagnostics> {
    softplc_aplc::files::load_files(paths)
}

/// A powered-on APLC-TCP CPU running one program file as MAIN's scan
/// program (`cfg` from [`cpu_config`]).
pub fn single_cpu(
    program: Program,
    cfg: CpuConfig,
    clock: Box<dyn crate::engine::Clock>,
) -> Result<crate::engine::Cpu, String> {
    crate::engine::Cpu::with_programs(
        vec![crate::engine::LoadedProgram {
            program,
            exec: Default::default(),
            interval: None,
            sim_time: None,
            local_devices: true,
        }],
        cfg,
        clock,
    )
}

/// An APLC-TCP CPU: its device layout, no latch ranges (no power-loss
/// retention, decision D5), watchdog 200 ms (D4), its system devices.
pub fn cpu_config() -> CpuConfig {
    cpu_config_with(Duration::from_millis(200), None)
}

/// [`cpu_config`] with a watchdog and constant scan (shown in SD34, SD33, SM8).
pub fn cpu_config_with(watchdog: Duration, constant_scan: Option<Duration>) -> CpuConfig {
    cpu_config_with_ports(watchdog, constant_scan, Vec::new())
}

/// [`cpu_config_with`] and the PORT1/PORT2 settings the SD registers show
/// (`[port1]`/`[port2]`, contract §3.3).
pub fn cpu_config_with_ports(
    watchdog: Duration,
    constant_scan: Option<Duration>,
    ports: Vec<softplc_aplc::comm::PortConfig>,
) -> CpuConfig {
    let ms = |d: Duration| d.as_millis().min(u16::MAX as u128) as u16;
    CpuConfig {
        devices: softplc_aplc::device_config(),
        watchdog,
        constant_scan,
        latch: Vec::new(),
        system: softplc_aplc::system_with_ports(ms(watchdog), constant_scan.map_or(0, ms), ports),
        // The APLC-TCP has no remote-RESET parameter: RESET in STOP is
        // always accepted, as before the MELSEC-Q parameter existed.
        remote_reset: true,
        ..CpuConfig::new(crate::profile::aplc())
    }
}
