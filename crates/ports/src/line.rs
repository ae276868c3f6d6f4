//! A line: bytes out and bytes in, each received byte with the time it
//! arrived, so RTU silence and the free port's timeouts are measured on the
//! line's own clock (virtual time for a [`crate::VirtualLine`], the CPU's
//! clock for a [`crate::SerialLine`]).

use std::collections::VecDeque;
use std::io;

use softplc_aplc::comm::{Mode, PortConfig, Protocol};

/// One received byte and its arrival time (µs).
pub type Stamped = (u64, u8);

pub trait Line: Send {
    /// Starts sending `bytes` at `now_us`, after what is still being sent;
    /// returns the time the last byte has left.
    fn send(&mut self, now_us: u64, bytes: &[u8]) -> io::Result<u64>;
    /// Appends the bytes received by `now_us` to `out`.
    fn receive(&mut self, now_us: u64, out: &mut VecDeque<Stamped>) -> io::Result<()>;
}

/// Character timing of a port's settings (spec aplc.md §6.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    /// One character on the line, µs (start, data, parity and stop bits).
    pub char_us: u64,
    /// The silence that ends a frame: 3.5 characters in RTU (L10446-10459),
    /// the 1 s inter-character timeout of ASCII (L10461-10470); for the
    /// free port 3.5 characters (its own timeouts are the program's).
    pub silence_us: u64,
}

impl Timing {
    pub fn of(c: &PortConfig) -> Timing {
        let char_us = (c.char_bits() as u64 * 1_000_000).div_ceil(c.baud as u64);
        let ascii = c.protocol != Protocol::Free && c.mode == Mode::Ascii;
        Timing {
            char_us,
            silence_us: if ascii {
                1_000_000
            } else {
                (7 * char_us).div_ceil(2)
            },
        }
    }
}
