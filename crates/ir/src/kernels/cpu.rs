//! CPU-function instructions that every family has in the same form.

use crate::fault::Fault;
use crate::instr::{ExecCtx, Instr};

/// WDT (MELSEC PM §7.18, 004 §7.9; the APLC's WDT likewise): restarts the
/// watchdog timer, not the scan-time measurement.
#[derive(Debug)]
pub struct ResetWatchdog;

impl Instr for ResetWatchdog {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.cpu.reset_watchdog();
        Ok(())
    }
}
