//! A serial device or pty through the `serialport` crate, with the port's
//! baud, data bits, parity and stop bits. Reads never block: the
//! communication phase takes what has arrived at each END and stamps it
//! with the CPU's clock. Linux ptys ignore parity (contract §3.3).

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::time::Duration;

use serialport::{DataBits, SerialPort, StopBits};
use softplc_aplc::comm::{Parity, PortConfig};

use crate::line::{Line, Stamped, Timing};

pub struct SerialLine {
    port: Box<dyn SerialPort>,
    timing: Timing,
    busy_until: u64,
}

impl SerialLine {
    /// Opens `path` with the settings of `c`.
    pub fn open(path: &str, c: &PortConfig) -> Result<SerialLine, String> {
        let parity = match c.parity {
            Parity::None => serialport::Parity::None,
            Parity::Even => serialport::Parity::Even,
            Parity::Odd => serialport::Parity::Odd,
        };
        let port = serialport::new(path, c.baud)
            .data_bits(if c.data_bits == 7 {
                DataBits::Seven
            } else {
                DataBits::Eight
            })
            .parity(parity)
            .stop_bits(if c.stop_bits == 2 {
                StopBits::Two
            } else {
                StopBits::One
            })
            .timeout(Duration::ZERO)
            .open()
            .or_else(|e| {
                // A pty refuses parity (EINVAL); it ignores it anyway.
                if c.parity == Parity::None {
                    return Err(e);
                }
                serialport::new(path, c.baud).timeout(Duration::ZERO).open()
            })
            .map_err(|e| format!("PORT{}: {path}: {e}", c.port))?;
        Ok(SerialLine {
            port,
            timing: Timing::of(c),
            busy_until: 0,
        })
    }
}

impl Line for SerialLine {
    fn send(&mut self, now_us: u64, bytes: &[u8]) -> io::Result<u64> {
        self.port.write_all(bytes)?;
        self.port.flush()?;
        let start = now_us.max(self.busy_until);
        self.busy_until = start + bytes.len() as u64 * self.timing.char_us;
        Ok(self.busy_until)
    }

    fn receive(&mut self, now_us: u64, out: &mut VecDeque<Stamped>) -> io::Result<()> {
        let mut buf = [0u8; 512];
        loop {
            let waiting = self.port.bytes_to_read().unwrap_or(0);
            if waiting == 0 {
                return Ok(());
            }
            match self.port.read(&mut buf) {
                Ok(0) => return Ok(()),
                Ok(n) => out.extend(buf[..n].iter().map(|b| (now_us, *b))),
                Err(e) if e.kind() == io::ErrorKind::TimedOut => return Ok(()),
                Err(e) => return Err(e),
            }
        }
    }
}
