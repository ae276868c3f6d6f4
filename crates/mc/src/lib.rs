//! MELSEC communication protocol (MC protocol / SLMP) for softplc: the frame
//! codec and the command handler of a MELSEC-Q CPU's built-in Ethernet port.
//!
//! This crate does no I/O. A server reads bytes into a buffer and calls
//! [`serve`] (or [`decode_request`], [`handle`] and [`encode_response`]) at END
//! processing; one [`Session`] per connection holds the remote password state.
//!
//! ```
//! use softplc_core::engine::{Cpu, VirtualClock};
//! use softplc_mc::{serve, Served, Session};
//!
//! let prog = softplc_core::program::compile_il("t.il", "LD X0\nOUT Y0\nEND\n", &Default::default()).unwrap();
//! let mut cpu = Cpu::new(prog, softplc_core::profile::default_config(), Box::new(VirtualClock::new()));
//! let mut session = Session::new();
//! // 3E binary: batch read D100-D102 in word units (what pymcprotocol sends).
//! let frame = [
//!     0x50, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x0C, 0x00, 0x04, 0x00, //
//!     0x01, 0x04, 0x00, 0x00, 0x64, 0x00, 0x00, 0xA8, 0x03, 0x00,
//! ];
//! let Served::Reply { response, used } = serve(&frame, &mut cpu, &mut session, None) else {
//!     panic!()
//! };
//! assert_eq!(used, frame.len());
//! assert_eq!(response, [0xD0, 0x00, 0x00, 0xFF, 0xFF, 0x03, 0x00, 0x08, 0x00, 0x00, 0x00, 0, 0, 0, 0, 0, 0]);
//! ```
//!
//! # Frames
//! QnA-compatible 3E and 4E frames, binary or ASCII, detected per frame from the
//! subheader (`50 00`, `54 00`, `"5000"`, `"5400"`); see [`frame`]. A frame that
//! cannot be delimited is [`FrameError::Malformed`] (close the connection); a
//! delimited frame with a bad request is [`FrameError::Rejected`] and gets an
//! error response with an end code.
//!
//! # Commands
//! | command | subcommands | what |
//! |---|---|---|
//! | `0401` | `0000` word units, `0001` bit units | batch read |
//! | `1401` | `0000` word units, `0001` bit units | batch write |
//! | `0403` | `0000` | random read (words and double words) |
//! | `1402` | `0000` word units, `0001` bit units | random write |
//! | `1001` | `0000` | remote RUN (mode 0001/0003, clear mode 00/01/02) |
//! | `1002` | `0000` | remote STOP |
//! | `1003` | `0000` | remote PAUSE (mode 0001/0003) |
//! | `1005` | `0000` | remote latch clear (STOP only) |
//! | `1006` | `0000` | remote RESET (STOP only) |
//! | `0101` | `0000` | read CPU model: the configured model (default `Q06HCPU`, code `0042`) |
//! | `1630` | `0000` | remote password unlock |
//! | `1631` | `0000` | remote password lock |
//! | `0619` | `0000` | loopback test |
//! | `0601` | `0000` | intelligent function module buffer memory batch read (start byte address, bytes, module number = start I/O number / 16) |
//! | `1601` | `0000` | intelligent function module buffer memory batch write |
//! | `0401`, `1401`, `0403`, `1402` | `0080` word units, `0081` bit units | the same with the device extension specification: `U<n>\G<addr>` (module access device G, `AB`/`G*`) and the plain devices |
//!
//! Anything else answers `C059`. Request formats and per-request limits are in
//! [`command`].
//!
//! # Multi-CPU systems
//! One server answers for every CPU of a system ([`Station`]): the request
//! destination module I/O number `03E0`-`03E3` addresses CPU 1-4, `03FF`
//! (and any other number) CPU 1; see [`handle_station`].
//!
//! # Devices
//! | device | binary | ASCII | numbering | device | binary | ASCII | numbering |
//! |---|---|---|---|---|---|---|---|
//! | X | `9C` | `X*` | hex | TN | `C2` | `TN` | dec |
//! | Y | `9D` | `Y*` | hex | SS | `C7` | `SS` | dec |
//! | M | `90` | `M*` | dec | SC | `C6` | `SC` | dec |
//! | L | `92` | `L*` | dec | SN | `C8` | `SN` | dec |
//! | F | `93` | `F*` | dec | CS | `C4` | `CS` | dec |
//! | V | `94` | `V*` | dec | CC | `C3` | `CC` | dec |
//! | B | `A0` | `B*` | hex | CN | `C5` | `CN` | dec |
//! | SB | `A1` | `SB` | hex | D | `A8` | `D*` | dec |
//! | S | `98` | `S*` | dec | W | `B4` | `W*` | hex |
//! | SM | `91` | `SM` | dec | SW | `B5` | `SW` | hex |
//! | TS | `C1` | `TS` | dec | SD | `A9` | `SD` | dec |
//! | TC | `C0` | `TC` | dec | Z | `CC` | `Z*` | dec |
//! | DX | `A2` | `DX` | hex | R | `AF` | `R*` | dec |
//! | DY | `A3` | `DY` | hex | ZR | `B0` | `ZR` | hex |
//!
//! SS/SC/SN are softplc's STS/STC/STN; DX/DY address X/Y. Buffer memory
//! `U<n>\G<addr>` is G (`AB`, `G*`, decimal) in the device extension
//! specification only. See [`device`].
//!
//! # End codes
//! | code | meaning |
//! |---|---|
//! | `0000` | normal completion |
//! | `C050` | ASCII data not convertible to binary |
//! | `C051` | batch bit points outside 1–7168 |
//! | `C052` | batch word points outside 1–960, buffer memory bytes outside 2–1920 |
//! | `C053` | random write bit points outside 1–188 |
//! | `C054` | random read points outside 1–192, random write weight over 1920 |
//! | `C056` | device range exceeded |
//! | `C058` | ASCII request data length mismatch |
//! | `C059` | unknown command or subcommand |
//! | `C05B` | unknown device code |
//! | `C05C` | bit access to a word device, bad mode/clear mode, loopback or password length, odd buffer-memory address or bytes, index modification in the device extension |
//! | `C05F` | remote RUN with a stop error held, remote PAUSE in STOP |
//! | `C060` | bit data other than 0/1 |
//! | `C061` | binary request data length mismatch |
//! | `C200` | wrong remote password |
//! | `C201` | connection locked by the remote password |
//! | `4010` | remote latch clear/RESET while not in STOP |
//! | `4041` | buffer memory past the module's last word |
//! | `4043` | buffer memory of a unit with no intelligent function module |
//! | `4B00` | a multi-CPU system: the request destination module I/O number `03E0`-`03E3` names a CPU it does not have |
//!
//! Sources and decisions: [`end_code`].

#![forbid(unsafe_code)]

mod codec;
pub mod command;
pub mod device;
pub mod end_code;
pub mod frame;
pub mod handler;

pub use command::{ClearMode, Command, Unit};
pub use device::{Device, DeviceRef};
pub use end_code::EndCode;
pub use frame::{
    decode_request, decode_response, encode_request, encode_response, DataCode, ErrorInfo, Frame,
    FrameError, Header, Rejected, Request, Response, ResponseData, ResponseFrame,
};
pub use handler::{destination, handle, handle_station, serve, Served, Session, Station};
