//! The run settings of an APLC-style system block: the devices at STOP→RUN,
//! the external outputs in STOP and the run input (002 §2.1.6, §2.2.1,
//! §2.3.2). MELSEC-Q keeps the devices, turns the outputs OFF and has no
//! run input, the defaults.

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
        self.rt.x_touched();
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

    /// 002 §2.3.2 "复位方式": power-on and RESET enter RUN only when the run
    /// input is ON; otherwise the CPU waits in STOP for it.
    pub(super) fn run_input_power_on(&mut self) {
        if let Some(n) = self.cfg.run_input {
            if !self.input(n) {
                // The run input stands in for the RUN switch.
                self.enter_stop(softplc_ir::system::Cause::Switch);
            }
        }
    }

    /// 002 §2.2.1 "输入点", §2.3.2 "输入点开机模式": at each END in STOP, an
    /// OFF→ON change of the run input since the last one (however brief)
    /// starts RUN, unless a stop error holds or the mode switch is at STOP
    /// (the STOP instruction leaves the switch at RUN). The input going OFF
    /// in RUN changes nothing: §2.3.2 lists the STOP instruction, a stop
    /// error and the programming tool as the ways to STOP.
    pub(super) fn run_input_end(&mut self) {
        let rises = std::mem::take(&mut self.input_rises);
        self.input_falls = 0;
        let Some(n) = self.cfg.run_input else {
            return;
        };
        let rose = rises.checked_shr(n).is_some_and(|r| r & 1 != 0);
        if !rose || self.state != CpuState::Stop || self.stop_error {
            return;
        }
        let _ = if self.stopped_by_instruction {
            self.set_run()
        } else {
            self.run_unless_stopped()
        };
    }
}
