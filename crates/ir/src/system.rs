//! The seam for a PLC family's system devices: what the engine writes into
//! special relays and registers around each scan and when an error is
//! recorded. MELSEC-Q's are the engine's own (`engine/special.rs`, used when a
//! CPU has no [`System`]); another dialect (the APLC) provides its own.

use crate::device::DeviceMemory;
use crate::fault::ErrorCode;

/// Scan times measured at END, µs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanTimes {
    pub current_us: u64,
    pub min_us: u64,
    pub max_us: u64,
}

/// A family's system devices and error numbering.
pub trait System: Send + Sync + std::fmt::Debug {
    /// Power-on (and STOP→RUN) values of the system devices.
    fn power_on(&self, mem: &mut DeviceMemory);
    /// Relays set before the program runs (always-ON, first scan, clocks).
    fn scan_start(&self, mem: &mut DeviceMemory, since_run_us: u64, first_scan: bool);
    /// END (housekeeping) of a scan.
    fn scan_end(&self, mem: &mut DeviceMemory, times: ScanTimes);
    /// The family's code for a fault the shared kernels or the engine raise
    /// (range, operation, watchdog errors are MELSEC-numbered there); `None`
    /// when the condition is no error in this family (nothing is recorded).
    fn code(&self, code: ErrorCode) -> Option<ErrorCode>;
    /// Records error `code` (already translated) in the system devices.
    fn report_error(&self, mem: &mut DeviceMemory, code: ErrorCode);
    /// True when error `code` stops the CPU.
    fn stops(&self, code: ErrorCode) -> bool;
    /// Right after the device initial values were written (power-on, RESET,
    /// STOP→RUN, the restore of battery-backed memory from a state
    /// directory): data of the family that outranks them (the APLC's EEPROM
    /// image into D6000-D6999, 002 table 2-2 L971-979).
    fn initialised(&self, _mem: &mut DeviceMemory) {}
}
