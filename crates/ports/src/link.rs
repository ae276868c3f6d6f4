//! Two PLCs' serial ports wired to each other in virtual time (a scenario's
//! `[[link]]`): what one end sends arrives at the other one character time
//! per byte after it starts, as on a real cable at the ports' common baud
//! rate and format (the settings of both ends must agree; the caller checks
//! them). The two ends are driven by the same single-threaded run loop in
//! time order, so a byte is never read before the time it arrives.

use std::collections::VecDeque;
use std::io;
use std::sync::{Arc, Mutex};

use crate::line::{Line, Stamped, Timing};

/// One end of a linked pair ([`link`]).
pub struct LinkEnd {
    timing: Timing,
    /// 0 or 1: this end reads `wires[side]` and writes the other.
    side: usize,
    /// When this end's transmitter is free again.
    tx_free: u64,
    /// Bytes on their way to end 0 and to end 1, by arrival time.
    wires: Arc<Mutex<[VecDeque<Stamped>; 2]>>,
}

/// A cable between two ports with the character timing `timing`.
pub fn link(timing: Timing) -> (LinkEnd, LinkEnd) {
    let wires = Arc::new(Mutex::new([VecDeque::new(), VecDeque::new()]));
    let end = |side| LinkEnd {
        timing,
        side,
        tx_free: 0,
        wires: Arc::clone(&wires),
    };
    (end(0), end(1))
}

fn poisoned() -> io::Error {
    io::Error::other("the linked line's other end failed")
}

impl Line for LinkEnd {
    fn send(&mut self, now_us: u64, bytes: &[u8]) -> io::Result<u64> {
        let mut t = now_us.max(self.tx_free);
        let mut wires = self.wires.lock().map_err(|_| poisoned())?;
        let out = &mut wires[1 - self.side];
        for b in bytes {
            t += self.timing.char_us;
            out.push_back((t, *b));
        }
        self.tx_free = t;
        Ok(t)
    }

    fn receive(&mut self, now_us: u64, out: &mut VecDeque<Stamped>) -> io::Result<()> {
        let mut wires = self.wires.lock().map_err(|_| poisoned())?;
        let incoming = &mut wires[self.side];
        while let Some(&(t, b)) = incoming.front() {
            if t > now_us {
                break;
            }
            out.push_back((t, b));
            incoming.pop_front();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_arrive_one_character_time_apart_at_the_other_end() {
        // 9600 baud 8N1: 10 bits a character, 1042 µs (rounded up).
        let timing = Timing {
            char_us: 1042,
            silence_us: 3647,
        };
        let (mut a, mut b) = link(timing);
        assert_eq!(a.send(1000, &[1, 2, 3]).unwrap(), 1000 + 3 * 1042);
        // A second frame queues behind the first on the same transmitter.
        assert_eq!(a.send(1500, &[4]).unwrap(), 1000 + 4 * 1042);
        let mut got = VecDeque::new();
        b.receive(3083, &mut got).unwrap();
        assert_eq!(got, VecDeque::from([(2042, 1)]));
        b.receive(5168, &mut got).unwrap();
        assert_eq!(
            got,
            VecDeque::from([(2042, 1), (3084, 2), (4126, 3), (5168, 4)])
        );
        // Nothing came back to the sender.
        let mut back = VecDeque::new();
        a.receive(10_000, &mut back).unwrap();
        assert!(back.is_empty());
    }
}
