//! Communication (002 §6.10 L8063-8546, chapter 10 L10312-10694; spec
//! aplc.md §4.15, §6, decision D26): the `Modbus` master instruction
//! ([`modbus`]), `EVWRT`/`EVRD` on it ([`inverter`]), the free port's
//! `XMT`/`RCV` ([`freeport`]), the port
//! settings ([`config`]) and the numbering of each port's SM/SD registers
//! ([`Regs`]).
//!
//! The instructions never touch a line: they check their operands, set the
//! port's flags and leave the request in the port's [`mailbox`]; the
//! communication phase after END (crate `softplc-ports`, L914-941: program,
//! then communication, then housekeeping) sends it and writes the answer,
//! the flags and the error codes, so the scan does no I/O.

pub mod config;
pub mod freeport;
pub mod inverter;
pub mod mailbox;
pub mod modbus;

pub use config::{Mode, Parity, PortConfig, Protocol, Val};

/// Where a port's flags and registers are (Appendix 1-2; decision D26 and
/// spec §10 item 5: channel n is PORTn).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Regs {
    /// SM120/SM130: TX enable; +1 RX enable, +2 TX done, +3 RX done, +4 idle.
    pub sm_free: u32,
    /// SM135/SM137: Modbus master done; SM136/SM138 error.
    pub sm_done: u32,
    pub sm_error: u32,
    /// SD120/SD150: the free-port block (mode word, start and end
    /// characters, timeouts, +5 completion code, +6 last character, +7 count,
    /// +8 current TX character).
    pub sd_free: u32,
    /// SD135/SD140 own station, SD136/SD141 timeout, SD137/SD142 retries,
    /// SD139/SD144 master error code.
    pub sd_station: u32,
    pub sd_timeout: u32,
    pub sd_retries: u32,
    pub sd_error: u32,
    /// First serial interrupt event (char TX, char RX, frame TX, frame RX):
    /// 34-37 for PORT1 with enables SM52-SM55 (§3.5); PORT2 has none.
    pub events: Option<(u8, u32)>,
}

/// SM offsets from [`Regs::sm_free`].
pub const TX_ENABLE: u32 = 0;
pub const RX_ENABLE: u32 = 1;
pub const TX_DONE: u32 = 2;
pub const RX_DONE: u32 = 3;
pub const IDLE: u32 = 4;

/// SD offsets from [`Regs::sd_free`].
pub const SD_START: u32 = 1;
pub const SD_END: u32 = 2;
pub const SD_CHAR_TIMEOUT: u32 = 3;
pub const SD_FRAME_TIMEOUT: u32 = 4;
pub const SD_CODE: u32 = 5;
pub const SD_LAST: u32 = 6;
pub const SD_COUNT: u32 = 7;
pub const SD_TX_CHAR: u32 = 8;

/// SD125 completion bits (§6.9).
pub const DONE_USER_ABORT: u16 = 1;
pub const DONE_END_CHAR: u16 = 1 << 1;
pub const DONE_MAX_COUNT: u16 = 1 << 2;
pub const DONE_CHAR_TIMEOUT: u16 = 1 << 3;
pub const DONE_FRAME_TIMEOUT: u16 = 1 << 4;

impl Regs {
    /// PORT1 or PORT2 (`port` 1 or 2; anything else is PORT2).
    pub const fn of(port: u8) -> Regs {
        if port == 1 {
            Regs {
                sm_free: 120,
                sm_done: 135,
                sm_error: 136,
                sd_free: 120,
                sd_station: 135,
                sd_timeout: 136,
                sd_retries: 137,
                sd_error: 139,
                events: Some((34, 52)),
            }
        } else {
            Regs {
                sm_free: 130,
                sm_done: 137,
                sm_error: 138,
                sd_free: 150,
                sd_station: 140,
                sd_timeout: 141,
                sd_retries: 142,
                sd_error: 144,
                events: None,
            }
        }
    }
}

/// The channel operand S1: the constant 1 (PORT1) or 2 (PORT2). PORT0 is
/// the USB programming port (L10341), which softplc does not have.
pub(crate) fn channel(a: &mut softplc_lang::compile::Args<'_, '_>, k: usize) -> Option<u8> {
    match a.text(k).trim() {
        "1" => Some(1),
        "2" => Some(2),
        "0" => {
            a.error(
                k,
                "channel 0 is PORT0, the USB programming port (programming protocol only, APLC programming manual §10.1); use 1 (PORT1) or 2 (PORT2)",
            );
            None
        }
        t => {
            let t = t.to_string();
            a.error(
                k,
                format!("`{t}`: the channel is the constant 1 (PORT1) or 2 (PORT2) (APLC programming manual §6.12.1)"),
            );
            None
        }
    }
}

/// A D operand without index or bit group (a buffer the communication phase
/// writes after END, when a V frame of the calling POU no longer exists).
pub(crate) fn d_buffer(
    a: &mut softplc_lang::compile::Args<'_, '_>,
    k: usize,
    cite: &str,
) -> Option<u32> {
    use crate::devices::{parse_device, Dev};
    match parse_device(&a.text(k).to_ascii_uppercase()) {
        Ok(Some(d)) if d.dev == Dev::D && d.group.is_none() && d.index.is_none() => Some(d.n),
        Ok(Some(d)) if d.dev == Dev::V => {
            let t = a.text(k).to_string();
            a.error(k, format!("`{t}`: softplc takes this buffer in D only: the reply is written after END, when the POU's V frame is gone ({cite})"));
            None
        }
        _ => {
            let t = a.text(k).to_string();
            a.error(
                k,
                format!("`{t}`: a D register without index is needed here ({cite})"),
            );
            None
        }
    }
}
