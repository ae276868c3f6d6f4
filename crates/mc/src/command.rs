//! Commands and subcommands, and the request data each one carries.
//!
//! | command | subcommand | request | [`Command`] |
//! |---|---|---|---|
//! | `0401` batch read | `0000` word units, `0001` bit units | head device, points | [`Command::BatchRead`] |
//! | `1401` batch write | `0000` word units | head device, points, one word a point | [`Command::BatchWriteWords`] |
//! | `1401` batch write | `0001` bit units | head device, points, one bit a point | [`Command::BatchWriteBits`] |
//! | `0403` random read | `0000` | word points, dword points, devices | [`Command::RandomRead`] |
//! | `1402` random write | `0000` word units | word points, dword points, (device, value)… | [`Command::RandomWriteWords`] |
//! | `1402` random write | `0001` bit units | points, (device, 00/01)… | [`Command::RandomWriteBits`] |
//! | `1001` remote RUN | `0000` | mode (0001 normal, 0003 forced), clear mode (00/01/02), fixed 00 | [`Command::RemoteRun`] |
//! | `1002` remote STOP | `0000` | fixed 0001 | [`Command::RemoteStop`] |
//! | `1003` remote PAUSE | `0000` | mode (0001/0003) | [`Command::RemotePause`] |
//! | `1005` remote latch clear | `0000` | fixed 0001 | [`Command::RemoteLatchClear`] |
//! | `1006` remote RESET | `0000` | fixed 0001 | [`Command::RemoteReset`] |
//! | `0101` read CPU model | `0000` | — | [`Command::ReadCpuModel`] |
//! | `1630` remote password unlock | `0000` | password | [`Command::Unlock`] |
//! | `1631` remote password lock | `0000` | password | [`Command::Lock`] |
//! | `0619` loopback test | `0000` | length, data | [`Command::Loopback`] |
//! | `0601` intelligent function module buffer memory batch read | `0000` | start address (4), number of bytes (2), module number (2) | [`Command::BufferRead`] |
//! | `1601` intelligent function module buffer memory batch write | `0000` | start address, number of bytes, module number, data | [`Command::BufferWrite`] |
//! | `0401`, `1401`, `0403`, `1402` with the device extension | `0080` word units, `0081` bit units | the same, every device in the extension specification (`U<n>\G<addr>`) | [`Command::Extended`] |
//!
//! Buffer memory (SLMP Reference Manual SH-080956ENG §10.2 "Intelligent
//! Function Module", commands 0601/1601; MELSEC-Q/L MC Protocol Reference
//! Manual SH-080008): the start address is a byte address, the buffer-memory
//! word address × 2 (softplc's simulated Q modules add no module-specific
//! value to it); the number of bytes is 2–1920 (words × 2); the module number
//! is the module's start I/O number / 16, the `<n>` of `U<n>\G`. Both must
//! be even (`C05C` otherwise): buffer memory is words. The data is one word
//! a buffer-memory address, as word devices carry it (binary 2 bytes, low
//! byte first; ASCII 4 hexadecimal digits, upper digit first — softplc's
//! reading of the manual's word layout).
//!
//! The device extension specification (SH-080956ENG Appendix 1; layout in
//! `codec`) reaches buffer memory as the module access device G:
//! `U3\G1` in a batch or random read or write. Subcommands 0082/0083 (the
//! iQ-R format) answer `C059` like 0002/0003.
//!
//! Per-request limits (Q/L CPU, QnA-compatible 3E and 4E frames):
//!
//! | request | limit | end code past it |
//! |---|---|---|
//! | batch read/write, word units | 1–960 words ([`MAX_BATCH_WORDS`]) | `C052` |
//! | batch read/write, bit units | 1–7168 points ([`MAX_BATCH_BITS`]) | `C051` |
//! | random read | 1–192 word + double-word points ([`MAX_RANDOM_READ`]) | `C054` |
//! | random write, word units | word points × 12 + dword points × 14 ≤ 1920 ([`MAX_RANDOM_WRITE_WEIGHT`]), at least one point | `C054` |
//! | random write, bit units | 1–188 points ([`MAX_RANDOM_WRITE_BITS`]) | `C053` |
//! | loopback | 1–960 bytes ([`MAX_LOOPBACK`]) | `C05C` |
//!
//! Format notes:
//! - Fixed values (`0001` of STOP/latch clear/RESET, the `00` after the RUN clear
//!   mode) are read but not checked; their length is.
//! - The remote password is accepted in both published layouts: the SLMP one
//!   (2-byte length, then the characters) and the bare 4 characters of the older
//!   MC protocol manuals. [`encode_request`](crate::encode_request) writes the SLMP layout, as
//!   pymcprotocol does. Passwords and loopback data are characters in ASCII
//!   frames too (not hex-encoded).
//! - Loopback data is echoed whatever it holds; the manuals ask for `0`–`9`,
//!   `A`–`F` but softplc does not insist.

use crate::codec::{BodyError, BodyResult, Reader, Writer};
use crate::device::DeviceRef;
use crate::end_code::EndCode;
use crate::frame::DataCode;

pub const MAX_BATCH_WORDS: usize = 960;
pub const MAX_BATCH_BITS: usize = 7168;
pub const MAX_RANDOM_READ: usize = 192;
pub const MAX_RANDOM_WRITE_WEIGHT: usize = 1920;
pub const MAX_RANDOM_WRITE_BITS: usize = 188;
pub const MAX_LOOPBACK: usize = 960;
/// Longest remote password accepted (SLMP allows 6–32 characters on iQ-R; Q uses 4).
pub const MAX_PASSWORD: usize = 32;

pub const BATCH_READ: u16 = 0x0401;
pub const BATCH_WRITE: u16 = 0x1401;
pub const RANDOM_READ: u16 = 0x0403;
pub const RANDOM_WRITE: u16 = 0x1402;
pub const REMOTE_RUN: u16 = 0x1001;
pub const REMOTE_STOP: u16 = 0x1002;
pub const REMOTE_PAUSE: u16 = 0x1003;
pub const REMOTE_LATCH_CLEAR: u16 = 0x1005;
pub const REMOTE_RESET: u16 = 0x1006;
pub const READ_CPU_MODEL: u16 = 0x0101;
pub const UNLOCK: u16 = 0x1630;
pub const LOCK: u16 = 0x1631;
pub const LOOPBACK: u16 = 0x0619;
pub const BUFFER_READ: u16 = 0x0601;
pub const BUFFER_WRITE: u16 = 0x1601;
/// Subcommand bit of the device extension specification (0080/0081).
pub const EXTENSION: u16 = 0x0080;
/// Most bytes one buffer-memory request reads or writes (960 words).
pub const MAX_BUFFER_BYTES: usize = 1920;

/// Access unit of batch read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// Subcommand 0000: 16-bit words (16 points of a bit device a word).
    Word,
    /// Subcommand 0001: one point a bit (bit devices only).
    Bit,
}

/// Device memory clear at remote RUN.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClearMode {
    /// 00: do not clear.
    None,
    /// 01: clear every device outside the latch ranges.
    OutsideLatch,
    /// 02: clear every device, latch ranges included.
    All,
}

impl ClearMode {
    fn code(self) -> u8 {
        match self {
            ClearMode::None => 0,
            ClearMode::OutsideLatch => 1,
            ClearMode::All => 2,
        }
    }
}

/// A decoded request body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    BatchRead {
        unit: Unit,
        head: DeviceRef,
        points: u16,
    },
    BatchWriteWords {
        head: DeviceRef,
        values: Vec<u16>,
    },
    BatchWriteBits {
        head: DeviceRef,
        values: Vec<bool>,
    },
    RandomRead {
        words: Vec<DeviceRef>,
        dwords: Vec<DeviceRef>,
    },
    RandomWriteWords {
        words: Vec<(DeviceRef, u16)>,
        dwords: Vec<(DeviceRef, u32)>,
    },
    RandomWriteBits {
        points: Vec<(DeviceRef, bool)>,
    },
    RemoteRun {
        /// Mode 0003: execute even while another client holds the CPU in
        /// remote STOP/PAUSE (`Cpu::remote_run`).
        force: bool,
        clear: ClearMode,
    },
    RemoteStop,
    RemotePause {
        force: bool,
    },
    RemoteLatchClear,
    RemoteReset,
    ReadCpuModel,
    Unlock {
        password: Vec<u8>,
    },
    Lock {
        password: Vec<u8>,
    },
    Loopback {
        data: Vec<u8>,
    },
    /// 0601: `bytes` bytes of buffer memory from byte address `start` of the
    /// module whose start I/O number is `module` × 16.
    BufferRead {
        start: u32,
        bytes: u16,
        module: u16,
    },
    /// 1601: one word a buffer-memory address from byte address `start`.
    BufferWrite {
        start: u32,
        module: u16,
        values: Vec<u16>,
    },
    /// A batch or random read or write (0401, 1401, 0403, 1402) whose devices
    /// are in the device extension specification (subcommand 0080/0081): the
    /// way to buffer memory `U<n>\G<addr>` ([`DeviceRef::module`]).
    Extended(Box<Command>),
}

impl Command {
    /// Whether executing the command may change device memory or the CPU's
    /// state (writes and remote operations): a server commits the END at which
    /// it ran before acknowledging it.
    pub fn changes_memory(&self) -> bool {
        use Command::*;
        match self {
            Extended(c) => c.changes_memory(),
            _ => !matches!(
                self,
                BatchRead { .. }
                    | RandomRead { .. }
                    | BufferRead { .. }
                    | ReadCpuModel
                    | Unlock { .. }
                    | Lock { .. }
                    | Loopback { .. }
            ),
        }
    }

    /// Whether its devices are in the device extension specification.
    pub fn is_extended(&self) -> bool {
        matches!(self, Command::Extended(_))
    }

    /// The command and subcommand codes.
    pub fn codes(&self) -> (u16, u16) {
        use Command::*;
        match self {
            BatchRead { unit, .. } => (BATCH_READ, (*unit == Unit::Bit) as u16),
            BatchWriteWords { .. } => (BATCH_WRITE, 0),
            BatchWriteBits { .. } => (BATCH_WRITE, 1),
            RandomRead { .. } => (RANDOM_READ, 0),
            RandomWriteWords { .. } => (RANDOM_WRITE, 0),
            RandomWriteBits { .. } => (RANDOM_WRITE, 1),
            RemoteRun { .. } => (REMOTE_RUN, 0),
            RemoteStop => (REMOTE_STOP, 0),
            RemotePause { .. } => (REMOTE_PAUSE, 0),
            RemoteLatchClear => (REMOTE_LATCH_CLEAR, 0),
            RemoteReset => (REMOTE_RESET, 0),
            ReadCpuModel => (READ_CPU_MODEL, 0),
            Unlock { .. } => (UNLOCK, 0),
            Lock { .. } => (LOCK, 0),
            Loopback { .. } => (LOOPBACK, 0),
            BufferRead { .. } => (BUFFER_READ, 0),
            BufferWrite { .. } => (BUFFER_WRITE, 0),
            Extended(c) => {
                let (command, sub) = c.codes();
                (command, sub | EXTENSION)
            }
        }
    }

    /// Decodes the request data after the command and subcommand. `subcommand_at`
    /// is the subcommand's offset, for errors about it.
    pub(crate) fn decode(
        command: u16,
        subcommand: u16,
        subcommand_at: usize,
        r: &mut Reader<'_>,
    ) -> BodyResult<Command> {
        let bad_sub = BodyError {
            end_code: EndCode::COMMAND,
            offset: subcommand_at,
            what: "subcommand not supported by this command",
        };
        let extended = matches!(
            command,
            BATCH_READ | BATCH_WRITE | RANDOM_READ | RANDOM_WRITE
        ) && (subcommand & !1) == EXTENSION;
        r.set_extended(extended);
        let subcommand = if extended {
            subcommand & !EXTENSION
        } else {
            subcommand
        };
        let sub = |allowed: &[u16]| {
            if allowed.contains(&subcommand) {
                Ok(())
            } else {
                Err(bad_sub)
            }
        };
        let cmd = match command {
            BATCH_READ => {
                sub(&[0, 1])?;
                let unit = if subcommand == 1 {
                    Unit::Bit
                } else {
                    Unit::Word
                };
                let head_at = r.offset();
                let head = r.device()?;
                let points_at = r.offset();
                let points = r.u16("points")?;
                check_batch(unit, head, head_at, points as usize, points_at)?;
                Command::BatchRead { unit, head, points }
            }
            BATCH_WRITE => {
                sub(&[0, 1])?;
                let unit = if subcommand == 1 {
                    Unit::Bit
                } else {
                    Unit::Word
                };
                let head_at = r.offset();
                let head = r.device()?;
                let points_at = r.offset();
                let points = r.u16("points")? as usize;
                check_batch(unit, head, head_at, points, points_at)?;
                match unit {
                    Unit::Word => {
                        let values = (0..points)
                            .map(|_| r.u16("word data"))
                            .collect::<BodyResult<_>>()?;
                        Command::BatchWriteWords { head, values }
                    }
                    Unit::Bit => Command::BatchWriteBits {
                        head,
                        values: r.bits(points)?,
                    },
                }
            }
            RANDOM_READ => {
                sub(&[0])?;
                let at = r.offset();
                let nw = r.u8("word points")? as usize;
                let nd = r.u8("double-word points")? as usize;
                if nw + nd == 0 || nw + nd > MAX_RANDOM_READ {
                    return Err(BodyError {
                        end_code: EndCode::RANDOM_WORD_POINTS,
                        offset: at,
                        what: "random read needs 1-192 word and double-word points",
                    });
                }
                let words = (0..nw).map(|_| r.device()).collect::<BodyResult<_>>()?;
                let dwords = (0..nd).map(|_| r.device()).collect::<BodyResult<_>>()?;
                Command::RandomRead { words, dwords }
            }
            RANDOM_WRITE if subcommand == 0 => {
                let at = r.offset();
                let nw = r.u8("word points")? as usize;
                let nd = r.u8("double-word points")? as usize;
                if nw + nd == 0 || nw * 12 + nd * 14 > MAX_RANDOM_WRITE_WEIGHT {
                    return Err(BodyError {
                        end_code: EndCode::RANDOM_WORD_POINTS,
                        offset: at,
                        what:
                            "random write needs 1 or more points and words*12 + dwords*14 <= 1920",
                    });
                }
                let words = (0..nw)
                    .map(|_| Ok((r.device()?, r.u16("word data")?)))
                    .collect::<BodyResult<_>>()?;
                let dwords = (0..nd)
                    .map(|_| Ok((r.device()?, r.u32("double-word data")?)))
                    .collect::<BodyResult<_>>()?;
                Command::RandomWriteWords { words, dwords }
            }
            RANDOM_WRITE => {
                sub(&[1])?;
                let at = r.offset();
                let n = r.u8("bit points")? as usize;
                if n == 0 || n > MAX_RANDOM_WRITE_BITS {
                    return Err(BodyError {
                        end_code: EndCode::RANDOM_BIT_POINTS,
                        offset: at,
                        what: "random write in bit units needs 1-188 points",
                    });
                }
                let mut points = Vec::with_capacity(n);
                for _ in 0..n {
                    let dev_at = r.offset();
                    let d = r.device()?;
                    if !d.device.is_bit() {
                        return Err(BodyError {
                            end_code: EndCode::REQUEST_CONTENTS,
                            offset: dev_at,
                            what: "bit-unit access to a word device",
                        });
                    }
                    points.push((d, r.bit_value()?));
                }
                Command::RandomWriteBits { points }
            }
            REMOTE_RUN => {
                sub(&[0])?;
                let force = mode(r)?;
                let at = r.offset();
                let clear = match r.u8("clear mode")? {
                    0 => ClearMode::None,
                    1 => ClearMode::OutsideLatch,
                    2 => ClearMode::All,
                    _ => {
                        return Err(BodyError {
                            end_code: EndCode::REQUEST_CONTENTS,
                            offset: at,
                            what: "clear mode must be 00, 01 or 02",
                        })
                    }
                };
                r.u8("fixed value")?;
                Command::RemoteRun { force, clear }
            }
            REMOTE_STOP | REMOTE_LATCH_CLEAR | REMOTE_RESET => {
                sub(&[0])?;
                r.u16("fixed value")?;
                match command {
                    REMOTE_STOP => Command::RemoteStop,
                    REMOTE_LATCH_CLEAR => Command::RemoteLatchClear,
                    _ => Command::RemoteReset,
                }
            }
            REMOTE_PAUSE => {
                sub(&[0])?;
                Command::RemotePause { force: mode(r)? }
            }
            READ_CPU_MODEL => {
                sub(&[0])?;
                Command::ReadCpuModel
            }
            UNLOCK | LOCK => {
                sub(&[0])?;
                let password = password(r)?;
                if command == UNLOCK {
                    Command::Unlock { password }
                } else {
                    Command::Lock { password }
                }
            }
            LOOPBACK => {
                sub(&[0])?;
                let at = r.offset();
                let n = r.u16("loopback length")? as usize;
                if n == 0 || n > MAX_LOOPBACK {
                    return Err(BodyError {
                        end_code: EndCode::REQUEST_CONTENTS,
                        offset: at,
                        what: "loopback data must be 1-960 bytes",
                    });
                }
                Command::Loopback {
                    data: r.take(n, "loopback data")?.to_vec(),
                }
            }
            BUFFER_READ => {
                sub(&[0])?;
                let (start, bytes) = buffer_range(r)?;
                Command::BufferRead {
                    start,
                    bytes: bytes as u16,
                    module: r.u16("module number")?,
                }
            }
            BUFFER_WRITE => {
                sub(&[0])?;
                let (start, bytes) = buffer_range(r)?;
                let module = r.u16("module number")?;
                let values = (0..bytes / 2)
                    .map(|_| r.u16("write data"))
                    .collect::<BodyResult<_>>()?;
                Command::BufferWrite {
                    start,
                    module,
                    values,
                }
            }
            _ => {
                return Err(BodyError {
                    end_code: EndCode::COMMAND,
                    offset: subcommand_at - r.code().width(2),
                    what: "unknown command",
                })
            }
        };
        r.finish()?;
        Ok(if extended {
            Command::Extended(Box::new(cmd))
        } else {
            cmd
        })
    }

    /// Appends the request data after the command and subcommand.
    pub(crate) fn encode_body(&self, w: &mut Writer<'_>) {
        use Command::*;
        match self {
            BatchRead { head, points, .. } => {
                w.device(head);
                w.u16(*points);
            }
            BatchWriteWords { head, values } => {
                w.device(head);
                w.u16(values.len() as u16);
                for v in values {
                    w.u16(*v);
                }
            }
            BatchWriteBits { head, values } => {
                w.device(head);
                w.u16(values.len() as u16);
                w.bits(values);
            }
            RandomRead { words, dwords } => {
                w.u8(words.len() as u8);
                w.u8(dwords.len() as u8);
                for d in words.iter().chain(dwords) {
                    w.device(d);
                }
            }
            RandomWriteWords { words, dwords } => {
                w.u8(words.len() as u8);
                w.u8(dwords.len() as u8);
                for (d, v) in words {
                    w.device(d);
                    w.u16(*v);
                }
                for (d, v) in dwords {
                    w.device(d);
                    w.u32(*v);
                }
            }
            RandomWriteBits { points } => {
                w.u8(points.len() as u8);
                for (d, v) in points {
                    w.device(d);
                    w.bit_value(*v);
                }
            }
            RemoteRun { force, clear } => {
                w.u16(if *force { 3 } else { 1 });
                w.u8(clear.code());
                w.u8(0);
            }
            RemoteStop | RemoteLatchClear | RemoteReset => w.u16(1),
            RemotePause { force } => w.u16(if *force { 3 } else { 1 }),
            ReadCpuModel => {}
            Unlock { password } | Lock { password } => {
                w.u16(password.len() as u16);
                w.raw(password);
            }
            Loopback { data } => {
                w.u16(data.len() as u16);
                w.raw(data);
            }
            BufferRead {
                start,
                bytes,
                module,
            } => {
                w.u32(*start);
                w.u16(*bytes);
                w.u16(*module);
            }
            BufferWrite {
                start,
                module,
                values,
            } => {
                w.u32(*start);
                w.u16((values.len() * 2) as u16);
                w.u16(*module);
                for v in values {
                    w.u16(*v);
                }
            }
            Extended(c) => {
                let plain = w.extended;
                w.extended = true;
                c.encode_body(w);
                w.extended = plain;
            }
        }
    }
}

/// The start address and number of bytes of 0601/1601: 2–1920 bytes
/// (`C052` otherwise), both even (`C05C`: buffer memory is words).
fn buffer_range(r: &mut Reader<'_>) -> BodyResult<(u32, usize)> {
    let start_at = r.offset();
    let start = r.u32("start address")?;
    let bytes_at = r.offset();
    let bytes = r.u16("number of bytes")? as usize;
    if !(2..=MAX_BUFFER_BYTES).contains(&bytes) {
        return Err(BodyError {
            end_code: EndCode::WORD_POINTS,
            offset: bytes_at,
            what: "buffer memory access needs 2-1920 bytes",
        });
    }
    if !bytes.is_multiple_of(2) {
        return Err(BodyError {
            end_code: EndCode::REQUEST_CONTENTS,
            offset: bytes_at,
            what: "buffer memory is words: the number of bytes must be even",
        });
    }
    if !start.is_multiple_of(2) {
        return Err(BodyError {
            end_code: EndCode::REQUEST_CONTENTS,
            offset: start_at,
            what: "buffer memory is words: the start address (word address x 2) must be even",
        });
    }
    Ok((start, bytes))
}

impl DataCode {
    /// Width in the frame of a field of `bytes` binary bytes.
    pub(crate) fn width(self, bytes: usize) -> usize {
        match self {
            DataCode::Binary => bytes,
            DataCode::Ascii => 2 * bytes,
        }
    }
}

fn check_batch(
    unit: Unit,
    head: DeviceRef,
    head_at: usize,
    points: usize,
    points_at: usize,
) -> BodyResult<()> {
    match unit {
        Unit::Bit if !head.device.is_bit() => Err(BodyError {
            end_code: EndCode::REQUEST_CONTENTS,
            offset: head_at,
            what: "bit-unit access to a word device",
        }),
        Unit::Bit if points == 0 || points > MAX_BATCH_BITS => Err(BodyError {
            end_code: EndCode::BIT_POINTS,
            offset: points_at,
            what: "batch access in bit units needs 1-7168 points",
        }),
        Unit::Word if points == 0 || points > MAX_BATCH_WORDS => Err(BodyError {
            end_code: EndCode::WORD_POINTS,
            offset: points_at,
            what: "batch access in word units needs 1-960 words",
        }),
        _ => Ok(()),
    }
}

/// Remote RUN/PAUSE mode: 0001 normal, 0003 forced.
fn mode(r: &mut Reader<'_>) -> BodyResult<bool> {
    let at = r.offset();
    match r.u16("mode")? {
        1 => Ok(false),
        3 => Ok(true),
        _ => Err(BodyError {
            end_code: EndCode::REQUEST_CONTENTS,
            offset: at,
            what: "mode must be 0001 or 0003",
        }),
    }
}

/// The remote password: SLMP layout (length, characters) or bare 4 characters.
///
/// The SLMP layout is recognised by its length field matching the characters
/// that follow; otherwise a body of exactly 4 bytes (characters) is the bare
/// layout of the QnA/Q MC protocol manuals. (The two overlap only for a binary
/// body `02 00 x y`, which no printable 4-character password can be.)
fn password(r: &mut Reader<'_>) -> BodyResult<Vec<u8>> {
    let width = r.code().width(2);
    let rest = r.peek();
    let declared = match r.code() {
        DataCode::Binary if rest.len() >= 2 => {
            Some(u16::from_le_bytes([rest[0], rest[1]]) as usize)
        }
        DataCode::Ascii if rest.len() >= 4 => {
            crate::codec::parse_hex(&rest[..4]).map(|v| v as usize)
        }
        _ => None,
    };
    let prefixed = declared.is_some_and(|n| n >= 1 && n + width == rest.len());
    if !prefixed && rest.len() == 4 {
        return Ok(r.take(4, "password")?.to_vec());
    }
    let at = r.offset();
    let n = r.u16("password length")? as usize;
    if n == 0 || n > MAX_PASSWORD {
        return Err(BodyError {
            end_code: EndCode::REQUEST_CONTENTS,
            offset: at,
            what: "password length must be 1-32",
        });
    }
    Ok(r.take(n, "password")?.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_distinct_per_variant() {
        assert_eq!(Command::RemoteStop.codes(), (0x1002, 0));
        assert_eq!(
            Command::RandomWriteBits { points: vec![] }.codes(),
            (0x1402, 1)
        );
    }
}
