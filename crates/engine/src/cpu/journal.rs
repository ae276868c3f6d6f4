//! The door's journal: every change made to the CPU from outside the scan —
//! writes through the [`door`](super::door), forcing and release, the
//! operating-state changes and remote operations, the battery-backed image
//! and the calendar set at start — told to one optional [`Journal`] (a
//! recording of a served session, `softplc serve --record`). Program writes
//! do not go through the door, and what the CPU does itself inside a scan
//! (the run input's RUN, an instruction's STOP) is not told: replaying the
//! journal between the same scans gives the same CPU.
//!
//! Without a journal a door write pays one `is_some` test; the scan pays one
//! too (the journal is set aside while it runs).

use super::*;
use softplc_ir::access::{DeviceSpec, RBlock, Value};

/// One change from outside, as the door made it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DoorEvent<'a> {
    /// [`Cpu::write_value`] (and [`Cpu::write_device`], its value parsed).
    Value {
        spec: &'a DeviceSpec,
        value: &'a Value,
    },
    /// [`Cpu::write_device`] with the value as text.
    Text {
        spec: &'a DeviceSpec,
        value: &'a str,
    },
    /// [`Cpu::write_span_words`]: `len` points of `kind` from `number`, R
    /// resolved in `block`.
    Words {
        kind: DeviceKind,
        number: u32,
        len: u32,
        block: RBlock,
        values: &'a [u16],
    },
    /// [`Cpu::write_span_bits`].
    Bits {
        kind: DeviceKind,
        number: u32,
        block: RBlock,
        values: &'a [bool],
    },
    /// [`Cpu::set_word`].
    Word {
        kind: DeviceKind,
        n: i64,
        value: u16,
    },
    /// [`Cpu::set_bit`].
    Bit {
        kind: DeviceKind,
        n: i64,
        value: bool,
    },
    /// [`Cpu::set_input`].
    Input {
        n: u32,
        on: bool,
    },
    /// [`Cpu::force`].
    Force {
        kind: DeviceKind,
        n: u32,
        on: bool,
    },
    /// [`Cpu::release`].
    Release {
        kind: DeviceKind,
        n: u32,
    },
    /// [`Cpu::release_all`].
    ReleaseAll,
    /// [`Cpu::set_run`], [`Cpu::set_stop`], [`Cpu::set_pause`],
    /// [`Cpu::reset`], [`Cpu::latch_clear`].
    Run,
    Stop,
    Pause,
    Reset,
    LatchClear {
        remote: bool,
    },
    /// [`Cpu::remote_run_clear`].
    RunClear(RunClear),
    /// [`Cpu::remote_run`], [`Cpu::remote_stop`], [`Cpu::remote_pause`]
    /// by `client`, [`Cpu::remote_reset`].
    RemoteRun {
        client: u32,
        force: bool,
    },
    RemoteStop {
        client: u32,
        force: bool,
    },
    RemotePause {
        client: u32,
        force: bool,
    },
    RemoteReset,
    /// [`Cpu::set_calendar_unix_us`].
    Calendar {
        unix_us: i64,
    },
    /// [`Cpu::restore_retained`].
    Retained {
        data: &'a [Option<Vec<u8>>],
    },
    /// [`Cpu::report_battery_error`].
    BatteryError {
        stop: bool,
    },
    /// [`Cpu::with_local_devices_of`] begins and ends: the writes between
    /// went to program file `slot`'s local devices.
    LocalsOf {
        slot: usize,
    },
    LocalsEnd,
    /// A change a journal of door writes cannot follow: a program file
    /// written during RUN, a state file loaded. A recording ends at the END
    /// before it.
    Unrecordable {
        why: &'static str,
    },
}

/// Where the door's changes go (`softplc-record`'s recorder).
pub trait Journal: Send {
    fn record(&mut self, event: DoorEvent<'_>);
}

impl Cpu {
    /// Tells every change from outside to `journal` from now on (`None`
    /// stops it).
    pub fn set_journal(&mut self, journal: Option<Box<dyn Journal>>) {
        self.journal = journal;
    }

    /// Whether a journal is kept.
    pub fn has_journal(&self) -> bool {
        self.journal.is_some()
    }

    /// Tells `event` to the journal, if there is one.
    /// Every door write of a device by name passes here, with or without a
    /// journal: a write to X the door does not mirror into the input image
    /// (an index-modified name) makes the next input refresh copy in full.
    #[inline]
    pub(super) fn note(&mut self, event: DoorEvent<'_>) {
        if let DoorEvent::Value { spec, .. } | DoorEvent::Text { spec, .. } = event {
            if spec.bit_span().is_none() && spec.device().is_some_and(|(k, _)| k == DeviceKind::X) {
                self.rt.x_touched();
            }
        }
        if let Some(j) = &mut self.journal {
            j.record(event);
        }
    }

    /// Runs `f` with the journal set aside: what it changes is the CPU's own
    /// doing (a scan) or part of one operation already told.
    #[inline]
    pub(super) fn untold<R>(&mut self, f: impl FnOnce(&mut Cpu) -> R) -> R {
        if self.journal.is_none() {
            return f(self);
        }
        let j = self.journal.take();
        let r = f(self);
        self.journal = j;
        r
    }
}
