//! Modbus RTU and ASCII slave on a serial device or pty (contract §3
//! `--modbus-rtu`). A reader thread cuts frames from the line — by the function
//! code's length (RTU) or CR LF (ASCII) and, when the line goes quiet, by the
//! silence between frames — and the engine serves each one at END processing.

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::os::fd::AsFd;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

use nix::sys::termios::{self, BaudRate, ControlFlags, SetArg, SpecialCharacterIndices};
use softplc_modbus::{Map, Proto, Slave};

use crate::engine::EngineHandle;

/// Line settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineSettings {
    pub baud: u32,
    pub parity: Parity,
    pub stop_bits: u8,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parity {
    None,
    Even,
    Odd,
}

impl Default for LineSettings {
    fn default() -> Self {
        LineSettings {
            baud: 9600,
            parity: Parity::None,
            stop_bits: 1,
        }
    }
}

fn baud(b: u32) -> Result<BaudRate, String> {
    Ok(match b {
        1200 => BaudRate::B1200,
        2400 => BaudRate::B2400,
        4800 => BaudRate::B4800,
        9600 => BaudRate::B9600,
        19200 => BaudRate::B19200,
        38400 => BaudRate::B38400,
        57600 => BaudRate::B57600,
        115200 => BaudRate::B115200,
        _ => return Err(format!("baud rate {b} is not supported")),
    })
}

/// Opens the device in raw mode with the line settings; reads return after
/// 100 ms of silence so partial frames can be dropped and stop is noticed.
pub fn open(path: &Path, line: LineSettings) -> Result<File, String> {
    let f = OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let mut t = termios::tcgetattr(f.as_fd())
        .map_err(|e| format!("{}: not a serial line: {e}", path.display()))?;
    termios::cfmakeraw(&mut t);
    termios::cfsetspeed(&mut t, baud(line.baud)?).map_err(|e| e.to_string())?;
    t.control_flags
        .remove(ControlFlags::PARENB | ControlFlags::PARODD | ControlFlags::CSTOPB);
    match line.parity {
        Parity::None => {}
        Parity::Even => t.control_flags.insert(ControlFlags::PARENB),
        Parity::Odd => t
            .control_flags
            .insert(ControlFlags::PARENB | ControlFlags::PARODD),
    }
    if line.stop_bits == 2 {
        t.control_flags.insert(ControlFlags::CSTOPB);
    }
    t.control_flags
        .insert(ControlFlags::CLOCAL | ControlFlags::CREAD);
    t.control_chars[SpecialCharacterIndices::VMIN as usize] = 0;
    t.control_chars[SpecialCharacterIndices::VTIME as usize] = 1;
    termios::tcsetattr(f.as_fd(), SetArg::TCSANOW, &t).map_err(|e| e.to_string())?;
    Ok(f)
}

/// Starts the slave on an opened line; it runs until `stop` is set.
pub fn spawn(
    mut line: File,
    proto: Proto,
    map: Map,
    slave: Slave,
    engine: EngineHandle,
    stop: Arc<AtomicBool>,
) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let map = Arc::new(map);
        let mut slave = Some(slave);
        let mut buf: Vec<u8> = Vec::with_capacity(512);
        let mut chunk = [0u8; 256];
        while !stop.load(Ordering::Relaxed) {
            let n = match line.read(&mut chunk) {
                Ok(n) => n,
                Err(_) => {
                    std::thread::sleep(std::time::Duration::from_millis(50));
                    0
                }
            };
            if n == 0 {
                // Silence: whatever is buffered is an incomplete frame.
                buf.clear();
                continue;
            }
            buf.extend_from_slice(&chunk[..n]);
            loop {
                match softplc_modbus::decode(proto, &buf) {
                    Ok(None) => break,
                    Err(e) => {
                        if let Some(s) = slave.as_mut() {
                            s.frame_error(&e);
                        }
                        let skip = e.skip.max(1).min(buf.len());
                        buf.drain(..skip);
                    }
                    Ok(Some((frame, used))) => {
                        buf.drain(..used.min(buf.len()));
                        let Some(mut s) = slave.take() else { return };
                        let m = map.clone();
                        let Ok((reply, s)) = engine.call(move |st| {
                            if softplc_modbus::is_write_function(frame.function()) {
                                st.wrote = true;
                            }
                            let r = softplc_modbus::serve(&mut s, &m, &frame, &mut st.cpu);
                            (r, s)
                        }) else {
                            return;
                        };
                        slave = Some(s);
                        if let Some(r) = reply {
                            if line.write_all(&r).is_err() {
                                return;
                            }
                        }
                    }
                }
                if buf.is_empty() {
                    break;
                }
            }
        }
    })
}
