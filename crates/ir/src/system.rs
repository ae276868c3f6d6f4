//! The seam for a PLC family's system devices: what the engine writes into
//! special relays and registers around each scan and when an error is
//! recorded. MELSEC-Q's are the engine's own (`engine/special.rs`, used when a
//! CPU has no [`System`]); another dialect (the APLC) provides its own.

use crate::device::DeviceMemory;
use crate::fault::{ErrorCode, Fault};

/// Scan times measured at END, µs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanTimes {
    pub current_us: u64,
    pub min_us: u64,
    pub max_us: u64,
}

/// What an error does to the CPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// The CPU stops (until RESET).
    Stop,
    /// The CPU keeps running (a continuation error).
    Continue,
    /// An operation error: stops or continues as the CPU's "operation error"
    /// parameter says.
    Operation,
}

/// A family's system devices and error numbering.
pub trait System: Send + Sync + std::fmt::Debug {
    /// Power-on (and STOP→RUN) values of the system devices.
    fn power_on(&self, mem: &mut DeviceMemory);
    /// Relays set before the program runs (always-ON, first scan, clocks).
    fn scan_start(&self, mem: &mut DeviceMemory, since_run_us: u64, first_scan: bool);
    /// END (housekeeping) of a scan.
    fn scan_end(&self, mem: &mut DeviceMemory, times: ScanTimes);
    /// The family's number for `fault`; `None` when the condition is no
    /// error in this family (nothing is recorded).
    fn code(&self, fault: Fault) -> Option<ErrorCode>;
    /// The family's message for error `code`.
    fn message(&self, code: ErrorCode) -> &'static str;
    /// Records error `code` in the system devices.
    fn report_error(&self, mem: &mut DeviceMemory, code: ErrorCode);
    /// What error `code` does to the CPU.
    fn severity(&self, code: ErrorCode) -> Severity;
    /// Right after the device initial values were written (power-on, RESET,
    /// STOP→RUN, the restore of battery-backed memory from a state
    /// directory): data of the family that outranks them (the APLC's EEPROM
    /// image into D6000-D6999, 002 table 2-2 L971-979).
    fn initialised(&self, _mem: &mut DeviceMemory) {}
}
