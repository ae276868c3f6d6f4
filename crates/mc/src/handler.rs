//! Executes decoded requests against a [`Cpu`].
//!
//! - Bit devices read or written in word units pack 16 points a word, the lowest
//!   device number in bit 0, from any head number (the manuals suggest multiples
//!   of 16; softplc does not insist). Double words (random read/write) are two words, low
//!   word first (32 points of a bit device).
//! - Writes to X (and DX) go through [`Cpu::set_input`], so they survive the next
//!   input refresh, as an input module's signal would.
//! - R addresses the file-register block SD648 selects (R0-32767 of block n is
//!   ZR(32768·n)-ZR(32768·n+32767)).
//! - A range check covers the whole request before anything is written: a random
//!   write with one point out of range writes nothing.
//! - Remote RUN with a clear mode clears device memory only when the CPU was in
//!   STOP: every device but X (refreshed from the input image), SM/SD (system) and
//!   the file registers R/ZR; clear mode 01 keeps the latch ranges. Device initial
//!   values are then written again ([`Cpu::remote_run_clear`]).
//! - Every device access goes through `softplc_core::access` spans (R with
//!   [`RBlock::Selected`]) and the CPU's span writes.
//! - Buffer memory (0601/1601, and `U<n>\G<addr>` in the device extension
//!   specification) is the module's window in the device G
//!   (`DeviceMap::unit`). A unit with no intelligent function module answers
//!   `4043` and a range past the module's buffer memory `4041`, the CPU's
//!   codes for them ([`EndCode::NO_MODULE`], [`EndCode::BUFFER_RANGE`]);
//!   nothing is written then.
//! - A multi-CPU system ([`Station`], contract §6) answers as one station:
//!   the request destination module I/O number `03E0`-`03E3` addresses CPU
//!   1-4 and `03FF` (own station) CPU 1, as does any other number; a CPU
//!   the system does not have answers `4B00` ([`EndCode::NO_DESTINATION`]).
//!   Remote RESET follows the system's rules ([`Station::reset`]). A single
//!   CPU answers every I/O number itself.
//! - Remote password: with a password configured, a [`Session`] starts locked and
//!   refuses everything but unlock (1630) and loopback (0619) with `C201`. Unlock
//!   with the right password unlocks the session, a wrong one answers `C200`;
//!   lock (1631, with the right password) locks it again. Without a configured
//!   password, unlock and lock complete normally and change nothing.

use softplc_core::access::{AccessError, RBlock, Span};
use softplc_core::engine::{Cpu, CpuState, Refusal, RunClear};
use softplc_core::system::System;

use crate::command::{ClearMode, Command, Unit};
use crate::device::{Device, DeviceRef};
use crate::end_code::EndCode;
use crate::frame::{decode_request, encode_response, FrameError, Request, Response, ResponseData};
use softplc_core::device::{BufferError, DeviceKind};

/// Per-connection state.
#[derive(Clone, Debug, Default)]
pub struct Session {
    unlocked: bool,
    /// The client this connection is for the remote operations: a remote
    /// STOP or PAUSE it holds blocks other clients' (004 §7.6.5 (3)). One
    /// per host ([`Session::from_peer`]).
    client: u32,
}

impl Session {
    /// A new connection: locked if the CPU has a remote password. Its client
    /// for the remote operations is the local one (0).
    pub fn new() -> Session {
        Session::default()
    }

    /// A connection from `peer`: connections from one host are one client
    /// for the remote operations (a tool that reconnects keeps its remote
    /// STOP or PAUSE), another host is another client.
    pub fn from_peer(peer: std::net::IpAddr) -> Session {
        let client = match peer {
            std::net::IpAddr::V4(a) => u32::from(a),
            std::net::IpAddr::V6(a) => {
                let b = a.octets();
                b.chunks(4)
                    .fold(0, |h, c| h ^ u32::from_be_bytes([c[0], c[1], c[2], c[3]]))
            }
        };
        Session {
            unlocked: false,
            client,
        }
    }

    /// The client this connection is for the remote operations.
    pub fn client(&self) -> u32 {
        self.client
    }

    /// Whether the remote password has been unlocked on this connection.
    pub fn is_unlocked(&self) -> bool {
        self.unlocked
    }
}

/// Executes `req` on `cpu`. `password` is the CPU's remote password, if any.
pub fn handle(
    req: &Request,
    cpu: &mut Cpu,
    session: &mut Session,
    password: Option<&str>,
) -> Response {
    handle_station(req, cpu, session, password)
}

/// The CPUs one MC server answers for: a CPU, or a multi-CPU system's.
pub trait Station {
    /// Number of CPUs (1 for a single CPU).
    fn cpus(&self) -> usize;
    /// CPU `i` (0-based, `i < cpus()`).
    fn cpu_mut(&mut self, i: usize) -> &mut Cpu;
    /// Remote RESET of CPU `i` (in STOP, when its parameter allows it).
    fn remote_reset(&mut self, i: usize) -> std::result::Result<(), Refusal>;
}

impl Station for Cpu {
    fn cpus(&self) -> usize {
        1
    }

    fn cpu_mut(&mut self, _: usize) -> &mut Cpu {
        self
    }

    fn remote_reset(&mut self, _: usize) -> std::result::Result<(), Refusal> {
        Cpu::remote_reset(self)
    }
}

impl Station for System {
    fn cpus(&self) -> usize {
        self.len()
    }

    fn cpu_mut(&mut self, i: usize) -> &mut Cpu {
        System::cpu_mut(self, i)
    }

    /// CPU 1's RESET resets the whole system, another's brings the others
    /// down ([`System::reset`]).
    fn remote_reset(&mut self, i: usize) -> std::result::Result<(), Refusal> {
        System::remote_reset(self, i)
    }
}

/// What a driver runs, one CPU or a system: as the one or the other.
impl Station for softplc_core::system::Cpus {
    fn cpus(&self) -> usize {
        self.len()
    }

    fn cpu_mut(&mut self, i: usize) -> &mut Cpu {
        self.get_mut(i)
    }

    fn remote_reset(&mut self, i: usize) -> std::result::Result<(), Refusal> {
        softplc_core::system::Cpus::remote_reset(self, i)
    }
}

/// Request destination module I/O numbers of CPU 1-4 in a multi-CPU system.
pub const CPU_IO: std::ops::RangeInclusive<u16> = 0x03E0..=0x03E3;

/// The CPU (0-based) a frame's request destination module I/O number `io`
/// addresses among `cpus`: `03E0`-`03E3` are CPU 1-4, any other number
/// (`03FF`, the own station) CPU 1; a single CPU answers every number.
pub fn destination(io: u16, cpus: usize) -> Result<usize> {
    if cpus <= 1 || !CPU_IO.contains(&io) {
        return Ok(0);
    }
    let i = usize::from(io - CPU_IO.start());
    if i < cpus {
        Ok(i)
    } else {
        Err(EndCode::NO_DESTINATION)
    }
}

/// Executes `req` on the CPU of `station` its header addresses
/// ([`destination`]). `password` is the remote password, if any.
pub fn handle_station(
    req: &Request,
    station: &mut dyn Station,
    session: &mut Session,
    password: Option<&str>,
) -> Response {
    let (command, subcommand) = req.command.codes();
    match execute(req, station, session, password) {
        Ok(data) => Response::Ok(data),
        Err(end_code) => Response::Error {
            end_code,
            command,
            subcommand,
        },
    }
}

/// The end code of a refused remote RESET: `4010` outside STOP, `C05F`
/// when the parameter does not allow it (docs/mc-protocol.md).
fn refused_reset(r: Refusal) -> EndCode {
    match r {
        Refusal::ResetDisabled => EndCode::NOT_EXECUTABLE,
        _ => EndCode::CPU_RUNNING,
    }
}

/// What the server does with the bytes it has buffered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Served {
    /// No complete frame yet: read more.
    Incomplete,
    /// Send `response` and drop the first `used` bytes.
    Reply { response: Vec<u8>, used: usize },
    /// The stream cannot be understood: close the connection.
    Close { offset: usize, what: &'static str },
}

/// Decodes the frame at the start of `buf`, executes it and encodes the answer:
/// the whole per-frame work of an MC protocol server.
pub fn serve(buf: &[u8], cpu: &mut Cpu, session: &mut Session, password: Option<&str>) -> Served {
    match decode_request(buf) {
        Ok((req, used)) => {
            let resp = handle(&req, cpu, session, password);
            Served::Reply {
                response: encode_response(&req.header, &resp),
                used,
            }
        }
        Err(FrameError::Incomplete) => Served::Incomplete,
        Err(FrameError::Malformed { offset, what }) => Served::Close { offset, what },
        Err(FrameError::Rejected(r)) => Served::Reply {
            response: r.response(),
            used: r.used,
        },
    }
}

type Result<T> = std::result::Result<T, EndCode>;

/// `req` on the CPU of `station` its header addresses; with a remote
/// password, a session that has not unlocked may only unlock and loop back.
fn execute(
    req: &Request,
    station: &mut dyn Station,
    session: &mut Session,
    password: Option<&str>,
) -> Result<ResponseData> {
    let cmd = &req.command;
    let locked = password.is_some()
        && !session.unlocked
        && !matches!(cmd, Command::Unlock { .. } | Command::Loopback { .. });
    if locked {
        return Err(EndCode::PASSWORD_LOCKED);
    }
    let i = destination(req.header.io, station.cpus())?;
    run(cmd, station, i, session, password)
}

/// `cmd` on CPU `i` of `station`.
fn run(
    cmd: &Command,
    station: &mut dyn Station,
    i: usize,
    session: &mut Session,
    password: Option<&str>,
) -> Result<ResponseData> {
    let cpu = station.cpu_mut(i);
    use Command::*;
    Ok(match cmd {
        BatchRead { unit, head, points } => {
            let n = *points as usize;
            match unit {
                Unit::Word => ResponseData::Words(read_words(cpu, *head, n)?),
                Unit::Bit => ResponseData::Bits(read_bits(cpu, *head, n)?),
            }
        }
        BatchWriteWords { head, values } => {
            let w = prepare_words(cpu, *head, values.len())?;
            apply_words(cpu, w, values);
            ResponseData::None
        }
        BatchWriteBits { head, values } => {
            let w = prepare_bits(cpu, *head, values.len())?;
            apply_bits(cpu, w, values);
            ResponseData::None
        }
        RandomRead { words, dwords } => {
            let words = words
                .iter()
                .map(|d| Ok(read_words(cpu, *d, 1)?[0]))
                .collect::<Result<_>>()?;
            let dwords = dwords
                .iter()
                .map(|d| {
                    let w = read_words(cpu, *d, 2)?;
                    Ok(w[0] as u32 | (w[1] as u32) << 16)
                })
                .collect::<Result<_>>()?;
            ResponseData::Random { words, dwords }
        }
        RandomWriteWords { words, dwords } => {
            let ws = words
                .iter()
                .map(|(d, _)| prepare_words(cpu, *d, 1))
                .collect::<Result<Vec<_>>>()?;
            let ds = dwords
                .iter()
                .map(|(d, _)| prepare_words(cpu, *d, 2))
                .collect::<Result<Vec<_>>>()?;
            for (w, (_, v)) in ws.into_iter().zip(words) {
                apply_words(cpu, w, &[*v]);
            }
            for (w, (_, v)) in ds.into_iter().zip(dwords) {
                apply_words(cpu, w, &[*v as u16, (*v >> 16) as u16]);
            }
            ResponseData::None
        }
        RandomWriteBits { points } => {
            let ps = points
                .iter()
                .map(|(d, _)| prepare_bits(cpu, *d, 1))
                .collect::<Result<Vec<_>>>()?;
            for (w, (_, v)) in ps.into_iter().zip(points) {
                apply_bits(cpu, w, &[*v]);
            }
            ResponseData::None
        }
        RemoteRun { clear, force } => {
            let was_stopped = cpu.state() == CpuState::Stop;
            cpu.remote_run(session.client, *force)
                .map_err(|_| EndCode::NOT_EXECUTABLE)?;
            match (was_stopped, clear) {
                (true, ClearMode::OutsideLatch) => cpu.remote_run_clear(RunClear::OutsideLatch),
                (true, ClearMode::All) => cpu.remote_run_clear(RunClear::All),
                _ => {}
            }
            ResponseData::None
        }
        RemoteStop => {
            cpu.remote_stop(session.client, false)
                .map_err(|_| EndCode::NOT_EXECUTABLE)?;
            ResponseData::None
        }
        RemotePause { force } => {
            cpu.remote_pause(session.client, *force)
                .map_err(|_| EndCode::NOT_EXECUTABLE)?;
            ResponseData::None
        }
        RemoteLatchClear => {
            cpu.latch_clear(true).map_err(|_| EndCode::CPU_RUNNING)?;
            ResponseData::None
        }
        RemoteReset => {
            // A system's RESET may reach the other CPUs (`Station::remote_reset`).
            station.remote_reset(i).map_err(refused_reset)?;
            ResponseData::None
        }
        ReadCpuModel => {
            let profile = cpu.profile();
            let mut name = [b' '; 16];
            for (d, s) in name.iter_mut().zip(profile.model.bytes()) {
                *d = if s.is_ascii_graphic() { s } else { b' ' };
            }
            ResponseData::CpuModel {
                name,
                code: profile.doors.mc.unwrap_or(0),
            }
        }
        Unlock { password: given } => {
            if let Some(p) = password {
                if p.as_bytes() != given.as_slice() {
                    return Err(EndCode::PASSWORD_MISMATCH);
                }
                session.unlocked = true;
            }
            ResponseData::None
        }
        Lock { password: given } => {
            if let Some(p) = password {
                if p.as_bytes() != given.as_slice() {
                    return Err(EndCode::PASSWORD_MISMATCH);
                }
                session.unlocked = false;
            }
            ResponseData::None
        }
        Loopback { data } => ResponseData::Loopback(data.clone()),
        BufferRead {
            start,
            bytes,
            module,
        } => {
            let s = buffer_span(cpu, *module, *start, *bytes as usize / 2)?;
            ResponseData::Words(cpu.memory().read_span_words(&s).map_err(end_code)?)
        }
        BufferWrite {
            start,
            module,
            values,
        } => {
            let s = buffer_span(cpu, *module, *start, values.len())?;
            apply_words(cpu, s, values);
            ResponseData::None
        }
        Extended(c) => return run(c, station, i, session, password),
    })
}

// --- device access: through `softplc_core::access` ---

/// Resolves `points` consecutive points of `d` (bits for a bit device, words
/// for a word device), R in the block SD648 selects; `C056` past the end.
/// Buffer memory `U<n>\G<addr>` is the module's ([`unit_span`]).
fn locate(cpu: &Cpu, d: DeviceRef, points: usize) -> Result<Span> {
    if d.device == Device::G {
        let unit = d.unit.ok_or(EndCode::DEVICE)?;
        return unit_span(cpu, unit, d.number, points);
    }
    let points = u32::try_from(points).map_err(|_| EndCode::ADDRESS_RANGE)?;
    cpu.span(d.device.kind(), d.number, points, RBlock::Selected)
        .map_err(end_code)
}

/// `words` words of buffer memory from word `address` of the module with
/// unit number `unit`: `4043` without an intelligent function module there,
/// `4041` past its buffer memory.
fn unit_span(cpu: &Cpu, unit: u16, address: u32, words: usize) -> Result<Span> {
    let words = u32::try_from(words).map_err(|_| EndCode::BUFFER_RANGE)?;
    let g = cpu
        .memory()
        .map
        .buffer(unit as u32, address, words)
        .map_err(|e| match e {
            BufferError::NoModule => EndCode::NO_MODULE,
            BufferError::Past { .. } => EndCode::BUFFER_RANGE,
        })?;
    cpu.span(DeviceKind::G, g, words, RBlock::First)
        .map_err(|_| EndCode::BUFFER_RANGE)
}

/// The buffer-memory span of 0601/1601: byte address `start` is word
/// `start / 2` (decoding made it even).
fn buffer_span(cpu: &Cpu, module: u16, start: u32, words: usize) -> Result<Span> {
    unit_span(cpu, module, start / 2, words)
}

fn end_code(e: AccessError) -> EndCode {
    match e {
        AccessError::NotBit { .. } => EndCode::REQUEST_CONTENTS,
        _ => EndCode::ADDRESS_RANGE,
    }
}

fn read_words(cpu: &Cpu, d: DeviceRef, n: usize) -> Result<Vec<u16>> {
    let s = prepare_words(cpu, d, n)?;
    cpu.memory().read_span_words(&s).map_err(end_code)
}

fn read_bits(cpu: &Cpu, d: DeviceRef, n: usize) -> Result<Vec<bool>> {
    let s = prepare_bits(cpu, d, n)?;
    cpu.memory().read_span_bits(&s).map_err(end_code)
}

/// Checks a write of `n` words at `d` (16 points a word of a bit device).
fn prepare_words(cpu: &Cpu, d: DeviceRef, n: usize) -> Result<Span> {
    locate(cpu, d, if d.device.is_bit() { 16 * n } else { n })
}

/// Checks a write of `n` bits at `d`.
fn prepare_bits(cpu: &Cpu, d: DeviceRef, n: usize) -> Result<Span> {
    if !d.device.is_bit() {
        return Err(EndCode::REQUEST_CONTENTS);
    }
    locate(cpu, d, n)
}

/// Writes a checked span; X goes through the input image.
fn apply_words(cpu: &mut Cpu, s: Span, values: &[u16]) {
    // Checked by `prepare_words` for exactly these values: cannot fail.
    let _ = cpu.write_span_words(&s, values);
}

fn apply_bits(cpu: &mut Cpu, s: Span, values: &[bool]) {
    let _ = cpu.write_span_bits(&s, values);
}
