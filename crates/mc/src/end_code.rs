//! End codes: the completion status a response carries.
//!
//! `0x0000` is normal completion. The `Cxxx` codes are the ones the QnA-compatible
//! 3E/4E frame specification lists for errors detected while processing the MC
//! protocol message (Q03UDE CPU built-in Ethernet manual §5.1.4, L-series built-in
//! Ethernet manual §5.4, SLMP reference manual error table); `4xxx` codes are errors
//! detected by the CPU module itself (QCPU User's Manual (Hardware Design,
//! Maintenance and Inspection) Appendix 1, "error codes returned to the request
//! source").
//!
//! | code | constant | when softplc returns it |
//! |---|---|---|
//! | `0000` | [`EndCode::OK`] | normal completion |
//! | `C050` | [`EndCode::ASCII_DATA`] | ASCII frame: a field that must be hexadecimal (or decimal for a decimal device number) holds another character |
//! | `C051` | [`EndCode::BIT_POINTS`] | batch read/write in bit units: 0 or more than 7168 points |
//! | `C052` | [`EndCode::WORD_POINTS`] | batch read/write in word units: 0 or more than 960 words; buffer memory read/write (0601/1601): fewer than 2 or more than 1920 bytes |
//! | `C053` | [`EndCode::RANDOM_BIT_POINTS`] | random write in bit units: 0 or more than 188 points |
//! | `C054` | [`EndCode::RANDOM_WORD_POINTS`] | random read: 0 or more than 192 word + double-word points; random write in word units: 0 points or word points × 12 + double-word points × 14 > 1920 |
//! | `C056` | [`EndCode::ADDRESS_RANGE`] | the head device plus the points runs past the last point of the device (as configured), or the device has 0 points |
//! | `C058` | [`EndCode::ASCII_LENGTH`] | ASCII frame: the request data length does not match what the command needs |
//! | `C059` | [`EndCode::COMMAND`] | unknown command, or a subcommand the command does not have for a Q CPU (iQ-R subcommands 0002/0003 and 0082/0083) |
//! | `C05B` | [`EndCode::DEVICE`] | unknown device code, or one a Q CPU has not (iQ-R long timers, LZ, RD, ...); G outside the device extension specification; link direct devices (`J\`) |
//! | `C05C` | [`EndCode::REQUEST_CONTENTS`] | bit-unit access to a word device; a mode or clear-mode value outside the specification; loopback length outside 1–960; password length outside 1–32; an odd buffer-memory start address or number of bytes; index modification or indirect specification in the device extension |
//! | `C05F` | [`EndCode::NOT_EXECUTABLE`] | remote RUN while a stop error is held (RESET first); remote PAUSE while in STOP |
//! | `C060` | [`EndCode::BIT_DATA`] | bit data other than 0/1 (binary nibble or byte, ASCII character) |
//! | `C061` | [`EndCode::DATA_LENGTH`] | binary frame: the request data length does not match what the command needs |
//! | `C200` | [`EndCode::PASSWORD_MISMATCH`] | remote password unlock or lock with the wrong password |
//! | `C201` | [`EndCode::PASSWORD_LOCKED`] | any request but unlock (1630) and loopback (0619) while the connection is locked by the remote password |
//! | `4010` | [`EndCode::CPU_RUNNING`] | remote latch clear or remote RESET while the CPU is in RUN or PAUSE (both are accepted in STOP only) |
//! | `4041` | [`EndCode::BUFFER_RANGE`] | buffer memory (0601/1601, `U<n>\G<addr>`): the range runs past the module's buffer memory |
//! | `4043` | [`EndCode::NO_MODULE`] | buffer memory of a unit (start I/O number / 16) with no intelligent function module |
//! | `4B00` | [`EndCode::NO_DESTINATION`] | a multi-CPU system: the request destination module I/O number is `03E0`-`03E3` of a CPU the system does not have |
//!
//! Decisions: the real E71 distinguishes `C058` (ASCII) from `C061` (binary) for a
//! length mismatch, and softplc does the same. `C05F` and `4010` for refused
//! remote operations are softplc's choices: the SLMP manuals only say such a
//! request "is terminated abnormally". `4B00` for a destination CPU that is
//! not there is softplc's choice too: it is the CPU's code for an error at the
//! access destination (a wrong request destination module I/O number among its
//! causes); the manuals at hand name no code for an absent CPU.

use std::fmt;

/// A completion code as carried in a response.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct EndCode(pub u16);

impl EndCode {
    /// Normal completion.
    pub const OK: EndCode = EndCode(0x0000);
    /// ASCII data that cannot be converted to binary.
    pub const ASCII_DATA: EndCode = EndCode(0xC050);
    /// Number of bit points for batch read/write out of range.
    pub const BIT_POINTS: EndCode = EndCode(0xC051);
    /// Number of word points for batch read/write out of range.
    pub const WORD_POINTS: EndCode = EndCode(0xC052);
    /// Number of bit points for random read/write out of range.
    pub const RANDOM_BIT_POINTS: EndCode = EndCode(0xC053);
    /// Number of word points for random read/write out of range.
    pub const RANDOM_WORD_POINTS: EndCode = EndCode(0xC054);
    /// The read or write request exceeds the maximum address.
    pub const ADDRESS_RANGE: EndCode = EndCode(0xC056);
    /// ASCII: request data length does not match the data.
    pub const ASCII_LENGTH: EndCode = EndCode(0xC058);
    /// Command or subcommand error.
    pub const COMMAND: EndCode = EndCode(0xC059);
    /// The specified device cannot be read or written.
    pub const DEVICE: EndCode = EndCode(0xC05B);
    /// Error in the request contents (bit access to a word device, ...).
    pub const REQUEST_CONTENTS: EndCode = EndCode(0xC05C);
    /// The request cannot be executed by the CPU module.
    pub const NOT_EXECUTABLE: EndCode = EndCode(0xC05F);
    /// Error in the data for bit devices (not 0/1).
    pub const BIT_DATA: EndCode = EndCode(0xC060);
    /// Binary: request data length does not match the data.
    pub const DATA_LENGTH: EndCode = EndCode(0xC061);
    /// Remote password error.
    pub const PASSWORD_MISMATCH: EndCode = EndCode(0xC200);
    /// The port is locked by the remote password.
    pub const PASSWORD_LOCKED: EndCode = EndCode(0xC201);
    /// CPU-detected: the request cannot be executed while the CPU is running.
    pub const CPU_RUNNING: EndCode = EndCode(0x4010);
    /// CPU-detected: the access range exceeds the buffer memory of the
    /// specified intelligent function module.
    pub const BUFFER_RANGE: EndCode = EndCode(0x4041);
    /// CPU-detected: no intelligent function module in the specified
    /// position.
    pub const NO_MODULE: EndCode = EndCode(0x4043);
    /// CPU-detected: the request destination (module I/O number `03E0`-
    /// `03E3`) is a CPU the multi-CPU system does not have.
    pub const NO_DESTINATION: EndCode = EndCode(0x4B00);

    /// Every end code softplc produces, normal completion first.
    pub const ALL: [EndCode; 20] = [
        Self::OK,
        Self::ASCII_DATA,
        Self::BIT_POINTS,
        Self::WORD_POINTS,
        Self::RANDOM_BIT_POINTS,
        Self::RANDOM_WORD_POINTS,
        Self::ADDRESS_RANGE,
        Self::ASCII_LENGTH,
        Self::COMMAND,
        Self::DEVICE,
        Self::REQUEST_CONTENTS,
        Self::NOT_EXECUTABLE,
        Self::BIT_DATA,
        Self::DATA_LENGTH,
        Self::PASSWORD_MISMATCH,
        Self::PASSWORD_LOCKED,
        Self::CPU_RUNNING,
        Self::BUFFER_RANGE,
        Self::NO_MODULE,
        Self::NO_DESTINATION,
    ];

    pub fn is_ok(self) -> bool {
        self.0 == 0
    }

    /// What the code means.
    pub fn description(self) -> &'static str {
        match self.0 {
            0x0000 => "normal completion",
            0xC050 => "ASCII data that cannot be converted to binary was received",
            0xC051 => "number of bit points for batch read/write out of range",
            0xC052 => "number of word points for batch read/write out of range",
            0xC053 => "number of bit points for random read/write out of range",
            0xC054 => "number of word points for random read/write out of range",
            0xC056 => "read or write request exceeds the maximum address",
            0xC058 => {
                "request data length after ASCII-to-binary conversion does not match the data"
            }
            0xC059 => "command or subcommand error",
            0xC05B => "the CPU module cannot read or write the specified device",
            0xC05C => "error in the request contents",
            0xC05F => "the request cannot be executed by the CPU module",
            0xC060 => "error in the data for bit devices",
            0xC061 => "request data length does not match the data",
            0xC200 => "remote password error",
            0xC201 => "the port is locked by the remote password",
            0x4010 => "the request cannot be executed while the CPU module is running",
            0x4041 => {
                "the access range exceeds the buffer memory of the intelligent function module"
            }
            0x4043 => "no intelligent function module in the specified position",
            0x4B00 => "the request destination CPU does not exist",
            _ => "error",
        }
    }
}

impl fmt::Display for EndCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04X}H ({})", self.0, self.description())
    }
}
