//! The run settings of an APLC-style system block: the devices at STOP→RUN
//! and the external outputs in STOP (002 §2.1.6, §2.2.1). MELSEC-Q keeps the
//! devices and turns the outputs OFF, the defaults.

use super::*;
use crate::StopOutputs;

impl Cpu {
    /// STOP→RUN, before the device initial values: without "keep device
    /// values" every device but X (refreshed from the inputs), the file
    /// registers (the APLC's EEPROM image) and the system and module devices
    /// is cleared, so the initial values (the data block) and the family's
    /// data that outranks them start from zero (002 table 2-2); then the
    /// family re-initialises its system devices (`System::stop_to_run`).
    pub(super) fn stop_to_run_devices(&mut self) {
        if !self.cfg.keep_device_values {
            super::states::clear_user_devices(&mut self.rt.mem);
            self.rt.cpu.timer_rem.fill(0);
        }
        self.rt.system.stop_to_run(&mut self.rt.mem);
    }

    /// The external output Y`n` in STOP: OFF, held at its state of RUN→STOP,
    /// or as the output table lists it.
    pub(super) fn stop_output(&self, n: u32) -> bool {
        match &self.cfg.stop_outputs {
            StopOutputs::Off => false,
            StopOutputs::Hold => self.saved_y.get(n as usize).copied().unwrap_or(false),
            StopOutputs::Table(on) => on.contains(&n),
        }
    }
}
