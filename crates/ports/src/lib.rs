//! softplc-ports: the APLC-TCP's PORT1/PORT2 (seed 002 chapter 10
//! L10312-10694, §6.10 L8063-8546; spec aplc.md §6, contract §3.3).
//!
//! [`Ports::after_end`] is the communication phase of the scan cycle
//! (L914-941: program, communication, housekeeping), called after each
//! scan's END with the CPU's clock: it takes what the `Modbus`, `XMT` and
//! `RCV` instructions left in their port's mailbox (`softplc_aplc::comm`),
//! sends it on the port's [`Line`], reads what arrived and writes the
//! replies, the flags, SD125-SD128 and SD139/SD144, and the serial
//! interrupt events. A port set to `modbus-slave` answers with seed 002's
//! map ([`softplc_modbus::Map::aplc`]) at its station (SD135/SD140).
//!
//! Lines: [`SerialLine`] (a serial device or pty, the `serialport` crate)
//! and [`VirtualLine`] (virtual time: every byte takes its character time)
//! to a simulated [`Peer`]: a Modbus slave device ([`peers::SimSlave`]) or
//! a scripted free-port device ([`peers::Script`]).
//!
//! Nothing here panics on what arrives on a line: malformed frames become
//! the manual's error codes and the scan goes on.

#![forbid(unsafe_code)]

pub mod door;
pub mod line;
pub mod link;
pub mod master;
pub mod peers;
pub mod serial;
pub mod virtual_line;

use std::collections::VecDeque;

use softplc_aplc::comm::{
    mailbox, Protocol, Regs, DONE_CHAR_TIMEOUT, DONE_END_CHAR, DONE_FRAME_TIMEOUT, DONE_MAX_COUNT,
    DONE_USER_ABORT, IDLE, RX_DONE, RX_ENABLE, SD_CODE, SD_COUNT, SD_LAST, SD_TX_CHAR, TX_DONE,
    TX_ENABLE,
};
use softplc_core::device::DeviceKind::{self, D, SD, SM, SW};
use softplc_core::engine::{Cpu, CpuState};
use softplc_modbus::{Map, Proto, Slave};

use door::{bit, set_bit, set_word, set_words, word};
pub use line::{Line, Stamped, Timing};
pub use link::{link, LinkEnd};
pub use serial::SerialLine;
use softplc_aplc::comm::modbus::E_PARAMETER;
pub use softplc_aplc::comm::{Mode, PortConfig, Val};
pub use virtual_line::{Peer, VirtualLine};

/// The ports of one CPU.
#[derive(Default)]
pub struct Ports {
    ports: Vec<Port>,
    errors: Errors,
    serial: bool,
}

/// Line errors waiting for [`Ports::take_errors`]: at most [`Errors::KEPT`],
/// then only counted, so a line that keeps failing while nobody asks (a run
/// that never drains them) does not grow memory scan by scan.
#[derive(Default)]
struct Errors {
    kept: Vec<String>,
    more: usize,
}

impl Errors {
    const KEPT: usize = 64;

    fn push(&mut self, port: u8, e: impl std::fmt::Display) {
        if self.kept.len() < Self::KEPT {
            self.kept.push(format!("PORT{port}: {e}"));
        } else {
            self.more += 1;
        }
    }

    fn take(&mut self) -> Vec<String> {
        let mut out = std::mem::take(&mut self.kept);
        if self.more > 0 {
            out.push(format!(
                "{} more line errors",
                std::mem::take(&mut self.more)
            ));
        }
        out
    }
}

struct Port {
    cfg: PortConfig,
    timing: Timing,
    line: Box<dyn Line>,
    rx: VecDeque<Stamped>,
    role: Role,
    /// Modbus RTU: 3.5 characters of silence before a frame (L10446-10459);
    /// 0 otherwise.
    gap: u64,
    /// When the line has been quiet for `gap`: no frame starts earlier.
    quiet_from: u64,
}

enum Role {
    Master(Option<Pending>),
    Slave(SlaveRun),
    Free(FreeRun),
}

/// A request on the line, waiting for its reply.
struct Pending {
    req: Vec<u8>,
    dest: u32,
    /// EVRD: the D that takes the register read.
    value: Option<u32>,
    wire: Vec<u8>,
    deadline: u64,
    tries_left: u16,
    buf: Vec<u8>,
    last_rx: u64,
}

struct SlaveRun {
    slave: Slave,
    map: Map,
    buf: Vec<u8>,
    last_rx: u64,
}

#[derive(Default)]
struct FreeRun {
    tx_end: Option<u64>,
    count: u16,
    last_rx: u64,
}

/// Serial event bits of the mailbox (char TX, char RX, frame TX, frame RX).
const EV_CHAR_TX: u16 = 1;
const EV_CHAR_RX: u16 = 2;
const EV_FRAME_TX: u16 = 4;
const EV_FRAME_RX: u16 = 8;

impl Ports {
    pub fn new() -> Ports {
        Ports::default()
    }

    /// Adds a port on `line`.
    pub fn add(&mut self, cfg: PortConfig, line: Box<dyn Line>) {
        let role = match cfg.protocol {
            Protocol::ModbusMaster => Role::Master(None),
            Protocol::ModbusSlave => Role::Slave(SlaveRun {
                slave: Slave::new(cfg.address),
                map: Map::aplc(),
                buf: Vec::new(),
                last_rx: 0,
            }),
            Protocol::Free => Role::Free(FreeRun::default()),
        };
        let timing = Timing::of(&cfg);
        let rtu = cfg.protocol != Protocol::Free && cfg.mode == Mode::Rtu;
        self.ports.push(Port {
            gap: if rtu { timing.silence_us } else { 0 },
            quiet_from: 0,
            timing,
            cfg,
            line,
            rx: VecDeque::new(),
            role,
        });
    }

    /// Adds a port on a [`VirtualLine`] to `peer`.
    pub fn add_virtual(&mut self, cfg: PortConfig, peer: Box<dyn Peer>) {
        let line = VirtualLine::new(Timing::of(&cfg), peer);
        self.add(cfg, Box::new(line));
    }

    /// Opens a [`SerialLine`] for every port with a device: `device` of its
    /// settings, or `paths[port - 1]` (`--port1`/`--port2`), which wins. A
    /// port bound to nothing is on a line where nothing answers.
    pub fn open(configs: &[PortConfig], paths: [Option<&str>; 2]) -> Result<Ports, String> {
        let mut ports = Ports::new();
        for (k, path) in paths.iter().enumerate() {
            if path.is_some() && !configs.iter().any(|c| c.port as usize == k + 1) {
                return Err(format!(
                    "--port{}: PORT{} has no settings ([port{}] in plc.toml, with its protocol)",
                    k + 1,
                    k + 1,
                    k + 1
                ));
            }
        }
        for c in configs {
            let path = paths[c.port as usize - 1].or(c.device.as_deref());
            match path {
                Some(p) => {
                    ports.add(c.clone(), Box::new(SerialLine::open(p, c)?));
                    ports.serial = true;
                }
                None => ports.add_virtual(c.clone(), Box::new(peers::Silent)),
            }
        }
        Ok(ports)
    }

    pub fn is_empty(&self) -> bool {
        self.ports.is_empty()
    }

    /// True when a port is on a real serial line (a batch run then keeps
    /// virtual time with the wall clock, so the peer sees real timing).
    pub fn has_serial(&self) -> bool {
        self.serial
    }

    /// Line errors since the last call (a line that fails stays quiet: the
    /// master times out, the scan goes on).
    pub fn take_errors(&mut self) -> Vec<String> {
        self.errors.take()
    }

    /// The communication phase: run after each scan's END.
    pub fn after_end(&mut self, cpu: &mut Cpu) {
        let now = cpu.now_us();
        let running = cpu.state() == CpuState::Run;
        for p in &mut self.ports {
            if let Err(e) = p.line.receive(now, &mut p.rx) {
                self.errors.push(p.cfg.port, e);
            }
            if let Some((t, _)) = p.rx.back() {
                p.quiet_from = p.quiet_from.max(t + p.gap);
            }
            let r = match &mut p.role {
                Role::Slave(_) => p.slave(cpu, now),
                // Master and free port work in RUN only (L10361); STOP drops
                // what was under way.
                _ if !running => {
                    p.rx.clear();
                    p.role = match p.role {
                        Role::Master(_) => Role::Master(None),
                        _ => Role::Free(FreeRun::default()),
                    };
                    Ok(())
                }
                Role::Master(_) => p.master(cpu, now),
                Role::Free(_) => p.free(cpu, now),
            };
            if let Err(e) = r {
                self.errors.push(p.cfg.port, e);
            }
        }
    }
}

/// A transaction's end: the reply, or the error code and what goes to S3.
type Outcome = Result<Vec<u8>, (u16, Vec<u8>)>;

fn retried(code: u16) -> bool {
    matches!(
        code,
        master::E_TIMEOUT | master::E_FRAME | master::E_CHECKSUM
    )
}

impl Port {
    fn regs(&self) -> Regs {
        Regs::of(self.cfg.port)
    }

    fn mb(&self, off: u32) -> u32 {
        mailbox::base(self.cfg.port) + off
    }

    fn timeout_us(&self, cpu: &Cpu) -> u64 {
        match word(cpu, SD, self.regs().sd_timeout) {
            0 => 1_000_000,
            ms => ms as u64 * 1000,
        }
    }

    fn master(&mut self, cpu: &mut Cpu, now: u64) -> std::io::Result<()> {
        let r = self.regs();
        let mode = self.cfg.mode;
        let timeout = self.timeout_us(cpu);
        let base = self.mb(0);
        let Role::Master(pending) = &mut self.role else {
            return Ok(());
        };
        if pending.is_none() {
            if word(cpu, SW, base + mailbox::MB_REQ) != 1 {
                self.rx.clear();
                return Ok(());
            }
            set_word(cpu, SW, base + mailbox::MB_REQ, 0);
            let len = word(cpu, SW, base + mailbox::MB_LEN).min(256) as u32;
            let req: Vec<u8> = (0..len)
                .map(|k| word(cpu, SW, base + mailbox::MB_BYTES + k) as u8)
                .collect();
            let dest = word(cpu, SW, base + mailbox::MB_DEST) as u32;
            let value = word(cpu, SW, base + mailbox::MB_VALUE)
                .checked_sub(1)
                .map(u32::from);
            if req.len() < 6 {
                // Not a request the instructions leave: a parameter error.
                finish(cpu, r, dest, Err((E_PARAMETER, &[])));
                return Ok(());
            }
            self.rx.clear();
            let wire = master::encode(mode, &req);
            let sent = send(&mut *self.line, &mut self.quiet_from, self.gap, now, &wire);
            if req[0] == 0 {
                // A broadcast write: done once sent, no reply (spec §6.5).
                finish(cpu, r, dest, Ok(&[]));
                return sent.map(|_| ());
            }
            let sent_at = *sent.as_ref().unwrap_or(&now);
            *pending = Some(Pending {
                req,
                dest,
                value,
                wire,
                deadline: sent_at + timeout,
                tries_left: word(cpu, SD, r.sd_retries).min(100),
                buf: Vec::new(),
                last_rx: sent_at,
            });
            sent?;
        }
        let Role::Master(Some(p)) = &mut self.role else {
            return Ok(());
        };
        while let Some((t, b)) = self.rx.pop_front() {
            if p.buf.len() < 1024 {
                p.buf.push(b);
            }
            p.last_rx = t;
        }
        let outcome: Option<Outcome> = if let Some(n) = master::complete(mode, &p.buf) {
            Some(match master::unframe(mode, &p.buf[..n]) {
                Err(code) => Err((code, Vec::new())),
                Ok(reply) => match master::check(&p.req, &reply) {
                    Ok(()) => Ok(reply),
                    Err((code, true)) => Err((code, reply)),
                    Err((code, false)) => Err((code, Vec::new())),
                },
            })
        } else if !p.buf.is_empty()
            && (now >= p.last_rx + self.timing.silence_us || now >= p.deadline)
        {
            // Cut short: the line went silent, or the timeout ran out before
            // the frame was whole.
            Some(Err((master::E_FRAME, Vec::new())))
        } else if now >= p.deadline {
            Some(Err((master::E_TIMEOUT, Vec::new())))
        } else {
            None
        };
        let Some(outcome) = outcome else {
            return Ok(());
        };
        if let Err((code, _)) = &outcome {
            if retried(*code) && p.tries_left > 0 {
                p.tries_left -= 1;
                p.buf.clear();
                let sent = send(
                    &mut *self.line,
                    &mut self.quiet_from,
                    self.gap,
                    now,
                    &p.wire,
                );
                let at = *sent.as_ref().unwrap_or(&now);
                p.deadline = at + timeout;
                p.last_rx = at;
                return sent.map(|_| ());
            }
        }
        let (dest, value) = (p.dest, p.value);
        self.role = Role::Master(None);
        self.rx.clear();
        match &outcome {
            Ok(reply) => {
                // EVRD: the register's value (reply: station, 03, 02, hi, lo).
                if let (Some(d), [_, 3, 2, hi, lo]) = (value, reply.as_slice()) {
                    set_word(cpu, D, d, u16::from_be_bytes([*hi, *lo]));
                }
                finish(cpu, r, dest, Ok(reply))
            }
            Err((code, reply)) => finish(cpu, r, dest, Err((*code, reply))),
        }
        Ok(())
    }

    fn slave(&mut self, cpu: &mut Cpu, now: u64) -> std::io::Result<()> {
        let proto = match self.cfg.mode {
            Mode::Rtu => Proto::Rtu,
            Mode::Ascii => Proto::Ascii,
        };
        let station = word(cpu, SD, self.regs().sd_station);
        let silence = self.timing.silence_us;
        let Role::Slave(s) = &mut self.role else {
            return Ok(());
        };
        if (1..=247).contains(&station) {
            s.slave.unit_id = station as u8;
        }
        let fresh = !self.rx.is_empty();
        for (t, b) in self.rx.drain(..) {
            if s.buf.len() < 1024 {
                s.buf.push(b);
            }
            s.last_rx = t;
        }
        let mut replies = Vec::new();
        loop {
            match softplc_modbus::decode(proto, &s.buf) {
                Ok(None) => break,
                Err(e) => {
                    s.slave.frame_error(&e);
                    let skip = e.skip.clamp(1, s.buf.len());
                    s.buf.drain(..skip);
                }
                Ok(Some((frame, used))) => {
                    s.buf.drain(..used.min(s.buf.len()));
                    if let Some(r) = softplc_modbus::serve(&mut s.slave, &s.map, &frame, cpu) {
                        replies.push(r);
                    }
                }
            }
            if s.buf.is_empty() {
                break;
            }
        }
        // An RTU frame cut short: the silence after it ends it (L10622-10628).
        if !fresh && !s.buf.is_empty() && now >= s.last_rx + silence {
            s.buf.clear();
        }
        for r in replies {
            send(&mut *self.line, &mut self.quiet_from, self.gap, now, &r)?;
        }
        Ok(())
    }

    fn free(&mut self, cpu: &mut Cpu, now: u64) -> std::io::Result<()> {
        let r = self.regs();
        let mut events = 0u16;
        let sm = |off: u32| r.sm_free + off;
        let sd = |off: u32| r.sd_free + off;
        let mut result = Ok(());
        // Transmit.
        let tx_req = word(cpu, SW, self.mb(mailbox::TX_REQ)) == 1;
        let Role::Free(f) = &mut self.role else {
            return Ok(());
        };
        if f.tx_end.is_none() && tx_req {
            set_word(cpu, SW, mailbox::base(self.cfg.port) + mailbox::TX_REQ, 0);
            let base = mailbox::base(self.cfg.port);
            let n = word(cpu, SW, base + mailbox::TX_LEN).min(mailbox::TX_MAX as u16) as u32;
            let bytes: Vec<u8> = (0..n)
                .map(|k| word(cpu, SW, base + mailbox::TX_BYTES + k) as u8)
                .collect();
            match self.line.send(now, &bytes) {
                Ok(end) => f.tx_end = Some(end),
                Err(e) => {
                    f.tx_end = Some(now);
                    result = Err(e);
                }
            }
            if let Some(b) = bytes.last() {
                set_word(cpu, SD, sd(SD_TX_CHAR), *b as u16);
            }
        }
        if let Some(end) = f.tx_end {
            if !bit(cpu, SM, sm(TX_ENABLE)) {
                f.tx_end = None; // the program cleared TX enable: aborted
            } else if now >= end {
                f.tx_end = None;
                set_bit(cpu, SM, sm(TX_ENABLE), false);
                set_bit(cpu, SM, sm(TX_DONE), true);
                events |= EV_CHAR_TX | EV_FRAME_TX;
            }
        }
        // Receive.
        let base = mailbox::base(self.cfg.port);
        if word(cpu, SW, base + mailbox::RX_ARM) != 1 {
            self.rx.clear();
            f.count = 0;
        } else {
            let done = if !bit(cpu, SM, sm(RX_ENABLE)) {
                Some(DONE_USER_ABORT)
            } else {
                let mode = word(cpu, SD, sd(0));
                let on = |b: u16| mode & 1 << b != 0;
                let start = on(7).then(|| word(cpu, SD, sd(1)) as u8);
                let end = on(8).then(|| word(cpu, SD, sd(2)) as u8);
                let ct = Some(word(cpu, SD, sd(3)) as u64 * 1000).filter(|t| on(9) && *t > 0);
                let ft = Some(word(cpu, SD, sd(4)) as u64 * 1000).filter(|t| on(10) && *t > 0);
                let packed = on(12);
                let dest = word(cpu, SW, base + mailbox::RX_DEST) as u32;
                let max = word(cpu, SW, base + mailbox::RX_MAX);
                let t0 = (word(cpu, SW, base + mailbox::RX_T0) as u64
                    | (word(cpu, SW, base + mailbox::RX_T0 + 1) as u64) << 16)
                    * 1000;
                let mut done = None;
                while let Some(&(t, b)) = self.rx.front() {
                    if let Some(ct) = ct {
                        if f.count > 0 && t > f.last_rx + ct {
                            done = Some(DONE_CHAR_TIMEOUT);
                            break;
                        }
                    }
                    self.rx.pop_front();
                    if t < t0 || (start.is_some_and(|s| s != b) && f.count == 0) {
                        continue;
                    }
                    let k = f.count as u32;
                    let value = if packed && k % 2 == 1 {
                        word(cpu, D, dest + k / 2) & 0xFF | (b as u16) << 8
                    } else {
                        b as u16
                    };
                    set_word(cpu, D, dest + if packed { k / 2 } else { k }, value);
                    f.count += 1;
                    f.last_rx = t;
                    set_word(cpu, SD, sd(SD_LAST), b as u16);
                    set_word(cpu, SD, sd(SD_COUNT), f.count);
                    events |= EV_CHAR_RX;
                    if end == Some(b) && !(start.is_some() && f.count == 1) {
                        done = Some(DONE_END_CHAR);
                        break;
                    }
                    if f.count >= max {
                        done = Some(DONE_MAX_COUNT);
                        break;
                    }
                }
                done.or_else(|| {
                    if ct.is_some_and(|ct| f.count > 0 && now >= f.last_rx + ct) {
                        Some(DONE_CHAR_TIMEOUT)
                    } else if ft.is_some_and(|ft| now >= t0 + ft) {
                        Some(DONE_FRAME_TIMEOUT)
                    } else {
                        None
                    }
                })
            };
            if let Some(code) = done {
                set_word(cpu, SD, sd(SD_CODE), code);
                set_bit(cpu, SM, sm(RX_ENABLE), false);
                set_bit(cpu, SM, sm(RX_DONE), true);
                set_word(cpu, SW, base + mailbox::RX_ARM, 0);
                f.count = 0;
                events |= EV_FRAME_RX;
            }
        }
        let idle = !bit(cpu, SM, sm(TX_ENABLE)) && !bit(cpu, SM, sm(RX_ENABLE));
        set_bit(cpu, SM, sm(IDLE), idle);
        if events != 0 && r.events.is_some() {
            let at = base + mailbox::EVENTS;
            let old = word(cpu, SW, at);
            set_word(cpu, SW, at, old | events);
        }
        result
    }
}

/// Sends a frame once the line has been quiet for `gap` (Modbus RTU); a
/// serial line writes at once (the END period keeps frames apart there).
fn send(
    line: &mut dyn Line,
    quiet_from: &mut u64,
    gap: u64,
    now: u64,
    bytes: &[u8],
) -> std::io::Result<u64> {
    let end = line.send(now.max(*quiet_from), bytes)?;
    *quiet_from = end + gap;
    Ok(end)
}

/// Ends a master transaction: the reply to S3, done or error flag and code,
/// the port idle again.
fn finish(cpu: &mut Cpu, r: Regs, dest: u32, outcome: Result<&[u8], (u16, &[u8])>) {
    let reply = match outcome {
        Ok(b) | Err((_, b)) => b,
    };
    let words: Vec<u16> = reply.iter().map(|b| *b as u16).collect();
    set_words(cpu, D, dest, &words);
    match outcome {
        Ok(_) => set_bit(cpu, SM, r.sm_done, true),
        Err((code, _)) => {
            set_bit(cpu, SM, r.sm_error, true);
            set_word(cpu, SD, r.sd_error, code);
        }
    }
    set_bit(cpu, SM, r.sm_free + IDLE, true);
}

/// The storage kind of the mailboxes (for tests and tools).
pub const MAILBOX_KIND: DeviceKind = SW;

#[cfg(test)]
mod tests {
    use super::Errors;

    #[test]
    fn line_errors_are_kept_up_to_a_bound_then_counted() {
        let mut e = Errors::default();
        for k in 0..Errors::KEPT + 10 {
            e.push(1, format!("error {k}"));
        }
        assert_eq!(e.kept.len(), Errors::KEPT);
        let out = e.take();
        assert_eq!(out.len(), Errors::KEPT + 1);
        assert_eq!(out[0], "PORT1: error 0");
        assert_eq!(out[Errors::KEPT], "10 more line errors");
        // Taken: empty again, and counting starts over.
        e.push(2, "late");
        assert_eq!(e.take(), ["PORT2: late"]);
    }
}
