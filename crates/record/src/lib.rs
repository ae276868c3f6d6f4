//! `softplc serve --record` and `softplc replay` (docs/recording.md): a
//! served session's changes from outside — writes by MC, Modbus, HTTP,
//! OPC UA and the serial ports, forcing, RUN/STOP/PAUSE/RESET — with the
//! END they took effect at, and every engine-clock reading the CPU took, so
//! that a replay in virtual time ends with the device values the live CPU
//! had at its last recorded END.
//!
//! - [`recorder`]: the recording side (the clock, the Cpu door's journal,
//!   one frame per END written by a thread of its own);
//! - [`format`]: the file (length + CRC frames, append-only);
//! - [`event`]: a change as recorded and as made again;
//! - [`replay`]: the replay clock and the player.

pub mod event;
pub mod format;
pub mod recorder;
pub mod replay;

pub use event::{Change, Event, Source};
pub use format::{FormatError, Header, SourceFile};
pub use recorder::Recorder;
pub use replay::{Ending, Player, ReplayClock};
