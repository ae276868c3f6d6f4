//! Modbus slave (server) protocol handling for softplc: Modbus-TCP, RTU and
//! ASCII framing, the MELSEC-Q and APLC address maps, and function codes 01, 02,
//! 03, 04, 05, 06, 08, 15, 16, 22 and 23 served against a [`Cpu`].
//!
//! This crate does no I/O. A server buffers the bytes it receives and, at END
//! processing, calls [`Slave::handle`] (or [`decode`], [`serve`] and
//! [`Slave::frame_error`]) until the buffer holds no complete frame.
//!
//! ```
//! use softplc_core::engine::{Cpu, VirtualClock};
//! use softplc_modbus::{Map, Proto, Slave, Step};
//!
//! let prog = softplc_core::program::compile_il("t.il", "LD SM400\nOUT M8191\nEND\n", &Default::default()).unwrap();
//! let mut cpu = Cpu::new(prog, softplc_core::profile::default_config(), Box::new(VirtualClock::new()));
//! let d107 = softplc_core::access::DeviceSpec::parse("D107").unwrap();
//! cpu.write_device(&d107, "H022B").unwrap();
//! let (map, mut slave) = (Map::q_default(), Slave::new(1));
//! // RTU: station 1 reads holding registers 107-109 (D107-D109).
//! let request = [0x01, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x74, 0x17];
//! let Step::Served { used, response } = slave.handle(&map, Proto::Rtu, &request, &mut cpu) else {
//!     panic!()
//! };
//! assert_eq!(used, 8);
//! assert_eq!(response.unwrap()[..9], [0x01, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x00]);
//! ```
//!
//! # Why the framing is written here
//! rmodbus (Apache-2.0) was checked (0.13): its CRC and LRC functions are private,
//! and its frame parsing lives inside `server::ModbusFrame::parse`, fused with its
//! own policy — function codes 1-6, 15, 16 only (no 08, 22, 23), fixed limits (123
//! registers, not seed 002's 120), quantity checked before the function is known
//! to be allowed, unknown function codes answered without a CRC check, and request
//! lengths guessed as 8 bytes for every function other than 15/16. None of it can
//! be used without its storage and rules, and tokio-modbus brings an async runtime
//! into a pure crate. The framing is small (MBAP header; address + PDU + CRC-16;
//! `:` hex LRC CR LF), so it is written by hand in [`frame`], checked against the
//! Modbus specification's examples and seed 002's frames.
//!
//! # Function codes
//! | FC | name | table | quantity (Q / APLC) |
//! |---|---|---|---|
//! | 01 | read coils | coils | 1–2000 |
//! | 02 | read discrete inputs | discrete inputs | 1–2000 |
//! | 03 | read holding registers | holding | 1–125 |
//! | 04 | read input registers (Q only) | input | 1–125 |
//! | 05 | write single coil (FF00 / 0000, else 03) | coils | 1 |
//! | 06 | write single register | holding | 1 |
//! | 08 | diagnostics (below) | — | — |
//! | 15 | write multiple coils | coils | 1–1968 |
//! | 16 | write multiple registers | holding | 1–123 / 1–120 |
//! | 22 | mask write register (Q only) | holding | 1 |
//! | 23 | read/write multiple registers, write first (Q only) | holding | read 1–125, write 1–121 |
//!
//! Responses: FC 05, 06, 22 and 08 echo the request; FC 15 and 16 return address
//! and quantity; reads return a byte count and the data (bits LSB first, unused
//! high bits 0; registers big endian).
//!
//! # Exceptions (spec/aplc.md §6.3, §6.5)
//! Checked in this order (see [`serve`]):
//! 1. **01** function code not supported by the map's dialect (APLC: anything but
//!    01, 02, 03, 05, 06, 08, 15, 16), an unknown FC 08 sub-function, or a write to
//!    a read-only slave ([`Slave::read_only`]; 01 "not allowed in this state" rather
//!    than 04, so masters do not retry).
//! 2. **03** PDU length or byte count not matching the function, FC 05 value other
//!    than FF00/0000, FC 08 data other than 0000 (FF00 also for 0x01), quantity
//!    outside the limits above.
//! 3. **02 / 03** addresses: Q map — every address must be mapped (02), requests may
//!    cross adjacent ranges. APLC map — seed 002's order: unmapped start 02, odd
//!    start in C200–C255 02, odd quantity there 03, quantity over the device type's
//!    size 03, range past the end of the type 02; FC 06 into C200–C255 is 02.
//! 4. **04** the address is mapped but the CPU's device setting has fewer points
//!    (see [`Map::check_devices`]). Nothing is written then: writes are checked
//!    whole before any device changes.
//!
//! # Addressing and broadcast
//! - Serial (RTU/ASCII): a frame is served when its address is [`Slave::unit_id`];
//!   address 0 is broadcast; other addresses are ignored (but counted as bus
//!   messages).
//! - Broadcast (spec/aplc.md §6.5): FC 05, 06, 15, 16 (and 22) are executed;
//!   FC 08 sub-functions 0x01, 0x04, 0x0A are executed; everything else is dropped.
//!   A broadcast is never answered; an exception it raises is counted.
//! - TCP: any unit id is answered and echoed by default (the server is addressed by
//!   its IP address, Modbus-TCP V1.0b). With [`Slave::tcp_any_unit`] off only
//!   `unit_id`, 0 and 255 are answered. Unit 0 is not a broadcast on TCP.
//! - Listen-only (FC 08/0x04): nothing is executed or answered except 08/0x01,
//!   which leaves the mode, clears the counters and is answered with an echo (seed
//!   002's table; the Modbus specification sends no reply in that case).
//!
//! # FC 08 diagnostics (spec/aplc.md §6.6)
//! | sub | action | response |
//! |---|---|---|
//! | 0x00 | return query data (any data) | echo |
//! | 0x01 | restart communications: leave listen-only, clear counters (data 0000 or FF00) | echo |
//! | 0x04 | force listen-only | none |
//! | 0x0A | clear counters | echo |
//! | 0x0B | bus message count | count |
//! | 0x0C | bus communication (CRC/LRC) error count | count |
//! | 0x0D | slave exception count | count |
//! | 0x0E | slave message count | count |
//! | 0x0F | slave no-response count | count |
//! | 0x12 | bus character overrun count | count |
//!
//! Counters live in [`Slave::counters`] ([`Counters`] documents what each counts).
//! Over RTU a request for FC 08 is delimited as two data bytes (the only form
//! seed 002 uses); over TCP and ASCII, and with [`decode_exact`], 0x00 echoes
//! data of any length.
//!
//! # Maps
//! [`Map::q_default`] (contract §3), [`Map::aplc`] (seed 002) and the plc.toml
//! `[modbus]` schema are documented in [`map`].

pub mod frame;
pub mod map;
pub mod pdu;
pub mod slave;

pub use frame::{crc16, decode, decode_exact, lrc, Frame, FrameError, FrameErrorKind, Proto};
pub use map::{Chunk, Dialect, Limits, Map, Range, Table, MAP_KEYS};
pub use pdu::{is_write_function, Exception, Request};
pub use slave::{serve, Counters, Slave, Step, SLAVE_KEYS};

#[doc(no_inline)]
pub use softplc_core::engine::Cpu;
