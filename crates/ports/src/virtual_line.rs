//! A line in virtual time to a simulated peer: every byte takes its
//! character time at the port's baud and format, both ways, so a scenario is
//! deterministic byte for byte and time for time.

use std::collections::VecDeque;
use std::io;

use crate::line::{Line, Stamped, Timing};

/// The device at the other end of a [`VirtualLine`].
pub trait Peer: Send {
    /// The PLC sent `bytes` (one write: a frame), the last of them arrived
    /// at `at_us`. Returns what the peer answers and how long after `at_us`
    /// it starts sending.
    fn receive(&mut self, at_us: u64, bytes: &[u8]) -> Option<(u64, Vec<u8>)>;
    /// What the peer sends on its own by `now_us`: (start time, bytes).
    fn poll(&mut self, _now_us: u64) -> Option<(u64, Vec<u8>)> {
        None
    }
}

pub struct VirtualLine {
    timing: Timing,
    peer: Box<dyn Peer>,
    /// When the PLC's transmitter and the peer's are free again.
    tx_free: u64,
    peer_free: u64,
    /// Bytes on their way to the PLC, by arrival time.
    incoming: VecDeque<Stamped>,
}

impl VirtualLine {
    pub fn new(timing: Timing, peer: Box<dyn Peer>) -> VirtualLine {
        VirtualLine {
            timing,
            peer,
            tx_free: 0,
            peer_free: 0,
            incoming: VecDeque::new(),
        }
    }

    fn peer_sends(&mut self, start: u64, bytes: &[u8]) {
        let mut t = start.max(self.peer_free);
        for b in bytes {
            t += self.timing.char_us;
            self.incoming.push_back((t, *b));
        }
        self.peer_free = t;
        self.incoming.make_contiguous().sort_by_key(|(t, _)| *t);
    }
}

impl Line for VirtualLine {
    fn send(&mut self, now_us: u64, bytes: &[u8]) -> io::Result<u64> {
        let start = now_us.max(self.tx_free);
        let end = start + bytes.len() as u64 * self.timing.char_us;
        self.tx_free = end;
        if let Some((delay, answer)) = self.peer.receive(end, bytes) {
            self.peer_sends(end + delay, &answer);
        }
        Ok(end)
    }

    fn receive(&mut self, now_us: u64, out: &mut VecDeque<Stamped>) -> io::Result<()> {
        while let Some((start, bytes)) = self.peer.poll(now_us) {
            self.peer_sends(start, &bytes);
        }
        while let Some(&(t, b)) = self.incoming.front() {
            if t > now_us {
                break;
            }
            out.push_back((t, b));
            self.incoming.pop_front();
        }
        Ok(())
    }
}
