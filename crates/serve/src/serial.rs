//! Modbus RTU and ASCII slave on a serial device or pty (contract §3
//! `--modbus-rtu`). A reader thread cuts frames from the line — by the function
//! code's length (RTU) or CR LF (ASCII) and, when the line goes quiet, by the
//! silence between frames — and the engine serves each one at END processing.
//! A line that hangs up is reported once and reopened with a growing wait.

use std::fs::{File, OpenOptions};
use std::io::{ErrorKind, Read, Write};
use std::os::fd::AsFd;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use nix::errno::Errno;
use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
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

/// An opened serial line, with what it takes to open it again after a
/// hang-up.
pub struct SerialLine {
    file: File,
    path: PathBuf,
    settings: LineSettings,
}

/// Opens the device in raw mode with the line settings; reads never block
/// (the slave waits for data with `poll`).
pub fn open(path: &Path, line: LineSettings) -> Result<SerialLine, String> {
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
    t.control_chars[SpecialCharacterIndices::VTIME as usize] = 0;
    termios::tcsetattr(f.as_fd(), SetArg::TCSANOW, &t).map_err(|e| e.to_string())?;
    Ok(SerialLine {
        file: f,
        path: path.to_path_buf(),
        settings: line,
    })
}

/// The silence that ends a frame (and drops an incomplete one); also how
/// often the reader notices `stop`.
const SILENCE: Duration = Duration::from_millis(100);
/// The first wait before reopening a line that hung up, doubled after each
/// failed attempt up to [`REOPEN_MAX`].
const REOPEN_FIRST: Duration = Duration::from_millis(100);
const REOPEN_MAX: Duration = Duration::from_secs(5);

/// What waiting on the line gave.
enum Input {
    Bytes(usize),
    /// [`SILENCE`] without a byte.
    Silence,
    /// The other end hung up (a pty whose master closed, a USB adapter
    /// unplugged): every read would return at once with nothing.
    HungUp(String),
}

/// Waits up to [`SILENCE`] for bytes and reads them.
fn receive(file: &mut File, chunk: &mut [u8]) -> Input {
    let events = {
        let mut fds = [PollFd::new(file.as_fd(), PollFlags::POLLIN)];
        match poll(&mut fds, PollTimeout::from(SILENCE.as_millis() as u16)) {
            Ok(0) | Err(Errno::EINTR) => return Input::Silence,
            Ok(_) => fds[0].revents().unwrap_or(PollFlags::empty()),
            Err(e) => return Input::HungUp(e.to_string()),
        }
    };
    if events.intersects(PollFlags::POLLHUP | PollFlags::POLLERR | PollFlags::POLLNVAL)
        && !events.contains(PollFlags::POLLIN)
    {
        return Input::HungUp("hang-up".to_string());
    }
    match file.read(chunk) {
        // Readable, yet nothing to read: end of file.
        Ok(0) => Input::HungUp("end of file".to_string()),
        Ok(n) => Input::Bytes(n),
        Err(e) if matches!(e.kind(), ErrorKind::Interrupted | ErrorKind::WouldBlock) => {
            Input::Silence
        }
        Err(e) => Input::HungUp(e.to_string()),
    }
}

/// Starts the slave on an opened line; it runs until `stop` is set. When
/// the line hangs up the slave says so once, then reopens the device with
/// a growing wait (0.1 s doubled up to 5 s) and says when it serves again.
pub fn spawn(
    line: SerialLine,
    proto: Proto,
    map: Map,
    slave: Slave,
    engine: EngineHandle,
    stop: Arc<AtomicBool>,
) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let SerialLine {
            file,
            path,
            settings,
        } = line;
        let name = path.display().to_string();
        let mut file = Some(file);
        let mut wait = REOPEN_FIRST;
        let map = Arc::new(map);
        let mut slave = Some(slave);
        let mut buf: Vec<u8> = Vec::with_capacity(512);
        let mut chunk = [0u8; 256];
        while !stop.load(Ordering::Relaxed) {
            let Some(f) = file.as_mut() else {
                sleep_unless_stopped(wait, &stop);
                match open(&path, settings) {
                    Ok(l) => {
                        eprintln!("softplc: {name}: line reopened, serving again");
                        file = Some(l.file);
                        wait = REOPEN_FIRST;
                    }
                    Err(_) => wait = (wait * 2).min(REOPEN_MAX),
                }
                continue;
            };
            let n = match receive(f, &mut chunk) {
                Input::Bytes(n) => n,
                Input::Silence => {
                    // Whatever is buffered is an incomplete frame.
                    buf.clear();
                    continue;
                }
                Input::HungUp(why) => {
                    eprintln!(
                        "softplc: {name}: the line hung up ({why}); reopening it every \
                         {REOPEN_FIRST:?} to {REOPEN_MAX:?}"
                    );
                    file = None;
                    buf.clear();
                    continue;
                }
            };
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
                                st.mark_wrote(0);
                            }
                            let r = softplc_modbus::serve(&mut s, &m, &frame, st.cpu_mut());
                            (r, s)
                        }) else {
                            return;
                        };
                        slave = Some(s);
                        if let Some(r) = reply {
                            if let Err(e) = f.write_all(&r) {
                                eprintln!(
                                    "softplc: {name}: the line hung up ({e}); reopening it \
                                     every {REOPEN_FIRST:?} to {REOPEN_MAX:?}"
                                );
                                file = None;
                                buf.clear();
                                break;
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

/// Sleeps `d` in short steps, returning early once `stop` is set.
fn sleep_unless_stopped(d: Duration, stop: &AtomicBool) {
    let end = std::time::Instant::now() + d;
    while !stop.load(Ordering::Relaxed) {
        let left = end.saturating_duration_since(std::time::Instant::now());
        if left.is_zero() {
            return;
        }
        std::thread::sleep(left.min(SILENCE));
    }
}
