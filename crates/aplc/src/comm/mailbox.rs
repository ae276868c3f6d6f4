//! The hidden words (kind SW, no APLC name reaches them) through which the
//! communication instructions hand requests to the communication phase
//! after END and the phase hands serial interrupt events back. One block of
//! [`SIZE`] words per port, PORT1 first; offsets below.

/// Words per port.
pub const SIZE: u32 = 1024;

/// What the port runs (written at power-on and STOP→RUN from its settings):
/// 0 not configured, or [`MASTER`], [`SLAVE`], [`FREE`].
pub const PROTOCOL: u32 = 0;
pub const MASTER: u16 = 1;
pub const SLAVE: u16 = 2;
pub const FREE: u16 = 3;

/// 1 while a `Modbus` request waits to be sent (the phase takes it).
pub const MB_REQ: u32 = 1;
/// The D number of S3, the reply buffer.
pub const MB_DEST: u32 = 2;
/// Request bytes (address, function, data), at [`MB_BYTES`].
pub const MB_LEN: u32 = 3;
/// EVRD: 1 + the D number that takes the register read (0: none).
pub const MB_VALUE: u32 = 12;
/// 1 while an `XMT` waits to be sent; its byte count; its bytes at [`TX_BYTES`].
pub const TX_REQ: u32 = 4;
pub const TX_LEN: u32 = 5;
/// 1 when `RCV` armed the receiver; its D number and maximum count; the
/// activation time in ms (low word, high word) for the frame timeout.
pub const RX_ARM: u32 = 6;
pub const RX_DEST: u32 = 7;
pub const RX_MAX: u32 = 8;
pub const RX_T0: u32 = 9;
/// Serial events that occurred (bit 0 char TX, 1 char RX, 2 frame TX, 3
/// frame RX); the interrupt dispatcher takes and clears them.
pub const EVENTS: u32 = 11;
/// The request bytes of `Modbus`, one per word (at most 256).
pub const MB_BYTES: u32 = 16;
/// The bytes of `XMT`, one per word.
pub const TX_BYTES: u32 = MB_BYTES + 256;
/// Most bytes one XMT sends (softplc's limit; the manual gives none).
pub const TX_MAX: u32 = 512;

/// The mailbox of `port` (1 or 2): its first SW number.
pub const fn base(port: u8) -> u32 {
    (port as u32 - 1) * SIZE
}
