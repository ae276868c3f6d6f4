//! Serving requests against the CPU: addressing, broadcast, listen-only, FC 08
//! diagnostics and counters, exceptions, device access.

use softplc_core::access::{RBlock, Span};
use softplc_core::engine::Cpu;

use crate::frame::{decode, Frame, FrameError, FrameErrorKind, Proto};
use crate::map::{Chunk, Map, Table};
use crate::pdu::{is_write_function, Exception, Request};

/// FC 08 diagnostic counters (spec/aplc.md §6.6). Each is 16 bits and wraps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Counters {
    /// 0x0B: frames seen with a good checksum, for any station.
    pub bus_messages: u16,
    /// 0x0C: frames with a bad CRC (RTU) or LRC (ASCII).
    pub bus_errors: u16,
    /// 0x0D: exceptions detected, including in broadcasts (which are not answered).
    pub exceptions: u16,
    /// 0x0E: frames addressed to this slave, broadcasts included.
    pub slave_messages: u16,
    /// 0x0F: frames addressed to this slave that got no response (broadcasts,
    /// listen-only mode, sub-function 0x04).
    pub no_responses: u16,
    /// 0x12: character overruns (RTU frame over 256 bytes, ASCII over 513 characters).
    pub overruns: u16,
}

fn bump(c: &mut u16) {
    *c = c.wrapping_add(1);
}

/// One slave: its station address, modes and counters. Keep one per port (serial)
/// or one for the TCP server; the map is shared.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Slave {
    /// Serial station address (1..=247) and the TCP unit id when `tcp_any_unit` is off.
    pub unit_id: u8,
    /// Writes (FC 5, 6, 15, 16, 22, 23) and FC 08 sub-function 04 (force
    /// listen-only) get exception 01.
    pub read_only: bool,
    /// TCP: answer every unit id (default). Off: answer only `unit_id`, 0 and 255;
    /// other unit ids get no response.
    pub tcp_any_unit: bool,
    /// Listen-only mode (FC 08 sub-function 0x04); left by sub-function 0x01.
    pub listen_only: bool,
    pub counters: Counters,
}

/// Keys of `[modbus]` read by [`Slave::from_toml`].
pub const SLAVE_KEYS: [&str; 3] = ["unit_id", "read_only", "tcp_any_unit"];

impl Default for Slave {
    fn default() -> Self {
        Slave::new(1)
    }
}

/// What [`Slave::handle`] did with the front of a buffer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Step {
    /// No complete frame yet.
    NeedMore,
    /// A frame of `used` bytes was served; send `response` if any.
    Served {
        used: usize,
        response: Option<Vec<u8>>,
    },
    /// Garbage (already counted): drop `error.skip` bytes. TCP: close the connection.
    Error(FrameError),
}

impl Slave {
    pub fn new(unit_id: u8) -> Slave {
        Slave {
            unit_id,
            read_only: false,
            tcp_any_unit: true,
            listen_only: false,
            counters: Counters::default(),
        }
    }

    /// Reads `unit_id` (1-247, default 1), `read_only` (default false) and
    /// `tcp_any_unit` (default true) from the `[modbus]` table.
    pub fn from_toml(table: &toml::Table) -> Result<Slave, String> {
        Slave::from_toml_with(table, 1)
    }

    /// As [`Slave::from_toml`] with another default unit address (8 on an
    /// APLC-TCP, L10686, contract §3).
    pub fn from_toml_with(table: &toml::Table, default_unit: u8) -> Result<Slave, String> {
        let mut s = Slave::new(default_unit);
        if let Some(v) = table.get("unit_id") {
            match v.as_integer() {
                Some(n @ 1..=247) => s.unit_id = n as u8,
                _ => return Err("[modbus] unit_id: expected an integer 1-247".into()),
            }
        }
        for (key, field) in [
            ("read_only", &mut s.read_only),
            ("tcp_any_unit", &mut s.tcp_any_unit),
        ] {
            if let Some(v) = table.get(key) {
                *field = v
                    .as_bool()
                    .ok_or_else(|| format!("[modbus] {key}: expected true or false"))?;
            }
        }
        Ok(s)
    }

    /// Counts a framing error in the FC 08 counters (bad CRC/LRC → 0x0C, overrun
    /// → 0x12).
    pub fn frame_error(&mut self, e: &FrameError) {
        match e.kind {
            FrameErrorKind::BadChecksum => bump(&mut self.counters.bus_errors),
            FrameErrorKind::Overrun => bump(&mut self.counters.overruns),
            _ => {}
        }
    }

    /// Decodes the first frame of `buf` and serves it: [`decode`] +
    /// [`Slave::frame_error`] + [`serve`].
    pub fn handle(&mut self, map: &Map, proto: Proto, buf: &[u8], cpu: &mut Cpu) -> Step {
        match decode(proto, buf) {
            Ok(None) => Step::NeedMore,
            Ok(Some((frame, used))) => Step::Served {
                used,
                response: serve(self, map, &frame, cpu),
            },
            Err(e) => {
                self.frame_error(&e);
                Step::Error(e)
            }
        }
    }
}

/// What executing a request came to.
enum Outcome {
    Reply(Vec<u8>),
    Exception(Exception),
    /// No response and nothing counted as an exception: a broadcast read, a
    /// sub-function not allowed by broadcast, sub-function 0x04.
    Silent,
}

/// Serves one decoded request frame against the CPU. Returns the response bytes,
/// or `None` when no response is due: another station (serial), a broadcast
/// (serial unit 0), listen-only mode, or FC 08 sub-function 0x04.
///
/// Order of checks: addressing; listen-only (only 08/0001 passes); function code
/// not in the map (01); broadcast of a non-broadcast function (dropped); read-only
/// slave and a write (01); PDU length, byte count, FC 05 value (03); quantity
/// limits (03); addresses (02, with seed 002's 02/03 order in the APLC map);
/// devices missing in the CPU (04); then the request runs, writes before reads.
pub fn serve(slave: &mut Slave, map: &Map, frame: &Frame, cpu: &mut Cpu) -> Option<Vec<u8>> {
    bump(&mut slave.counters.bus_messages);
    let serial = frame.proto.is_serial();
    let broadcast = serial && frame.unit == 0;
    let addressed = if serial {
        broadcast || frame.unit == slave.unit_id
    } else {
        slave.tcp_any_unit || matches!(frame.unit, 0 | 255) || frame.unit == slave.unit_id
    };
    if !addressed {
        return None;
    }
    bump(&mut slave.counters.slave_messages);
    let fc = frame.function();
    // Only a well-formed 08/0001 (data 0000 or FF00) reaches a listen-only slave.
    let restart = matches!(frame.pdu[..], [8, 0, 1, 0 | 0xFF, 0]);
    if slave.listen_only && !restart {
        bump(&mut slave.counters.no_responses);
        return None;
    }
    if broadcast {
        bump(&mut slave.counters.no_responses);
    }
    match execute(slave, map, &frame.pdu, broadcast, cpu) {
        Outcome::Reply(pdu) => (!broadcast).then(|| frame.reply(pdu).encode()),
        Outcome::Exception(e) => {
            bump(&mut slave.counters.exceptions);
            (!broadcast).then(|| frame.reply(e.pdu(fc)).encode())
        }
        Outcome::Silent => {
            if !broadcast {
                bump(&mut slave.counters.no_responses);
            }
            None
        }
    }
}

/// FC 08 sub-functions accepted by broadcast (spec/aplc.md §6.5).
const BROADCAST_DIAGNOSTICS: [u16; 3] = [0x01, 0x04, 0x0A];

fn execute(slave: &mut Slave, map: &Map, pdu: &[u8], broadcast: bool, cpu: &mut Cpu) -> Outcome {
    let fc = pdu.first().copied().unwrap_or(0);
    if !map.supports(fc) {
        return Outcome::Exception(Exception::IllegalFunction);
    }
    if broadcast {
        let allowed = match fc {
            5 | 6 | 15 | 16 | 22 => true,
            8 => {
                pdu.len() >= 3
                    && BROADCAST_DIAGNOSTICS.contains(&u16::from_be_bytes([pdu[1], pdu[2]]))
            }
            _ => false,
        };
        if !allowed {
            return Outcome::Silent;
        }
    }
    if slave.read_only && is_write_function(fc) {
        return Outcome::Exception(Exception::IllegalFunction);
    }
    let req = match Request::parse(pdu) {
        Ok(r) => r,
        Err(e) => return Outcome::Exception(e),
    };
    let result = match req {
        Request::Diagnostics { sub, data } => return diagnostics(slave, pdu, sub, &data),
        req => access(map, &req, pdu, cpu),
    };
    match result {
        Ok(p) => Outcome::Reply(p),
        Err(e) => Outcome::Exception(e),
    }
}

fn diagnostics(slave: &mut Slave, pdu: &[u8], sub: u16, data: &[u8]) -> Outcome {
    let zero = data == [0, 0];
    let c = &mut slave.counters;
    let count = match sub {
        0x00 => return Outcome::Reply(pdu.to_vec()),
        0x01 => {
            if data != [0, 0] && data != [0xFF, 0] {
                return Outcome::Exception(Exception::IllegalDataValue);
            }
            slave.listen_only = false;
            slave.counters = Counters::default();
            return Outcome::Reply(pdu.to_vec());
        }
        0x04 | 0x0A if !zero => return Outcome::Exception(Exception::IllegalDataValue),
        // Listen-only silences the slave: a read-only slave refuses it, as a
        // write (no client may change what a read-only slave does for others).
        0x04 if slave.read_only => return Outcome::Exception(Exception::IllegalFunction),
        0x04 => {
            slave.listen_only = true;
            return Outcome::Silent;
        }
        0x0A => {
            slave.counters = Counters::default();
            return Outcome::Reply(pdu.to_vec());
        }
        0x0B => c.bus_messages,
        0x0C => c.bus_errors,
        0x0D => c.exceptions,
        0x0E => c.slave_messages,
        0x0F => c.no_responses,
        0x12 => c.overruns,
        _ => return Outcome::Exception(Exception::IllegalFunction),
    };
    if !zero {
        return Outcome::Exception(Exception::IllegalDataValue);
    }
    let mut out = pdu[..3].to_vec();
    out.extend_from_slice(&count.to_be_bytes());
    Outcome::Reply(out)
}

fn check_quantity(q: usize, max: u16) -> Result<u16, Exception> {
    if (1..=max as usize).contains(&q) {
        Ok(q as u16)
    } else {
        Err(Exception::IllegalDataValue)
    }
}

/// Device reads and writes (every function but 08).
fn access(map: &Map, req: &Request, pdu: &[u8], cpu: &mut Cpu) -> Result<Vec<u8>, Exception> {
    let lim = &map.limits;
    let fc = req.function();
    match req {
        Request::ReadCoils { address, quantity }
        | Request::ReadDiscreteInputs { address, quantity } => {
            let q = check_quantity(*quantity as usize, lim.read_bits)?;
            let table = if fc == 1 {
                Table::Coils
            } else {
                Table::DiscreteInputs
            };
            let chunks = map.resolve(table, *address, q, false)?;
            present(&chunks, cpu)?;
            let bits = read_bits(&chunks, cpu);
            let mut out = vec![fc, bits.len().div_ceil(8) as u8];
            out.extend(pack_bits(&bits));
            Ok(out)
        }
        Request::ReadHoldingRegisters { address, quantity }
        | Request::ReadInputRegisters { address, quantity } => {
            let q = check_quantity(*quantity as usize, lim.read_registers)?;
            let table = if fc == 3 {
                Table::HoldingRegisters
            } else {
                Table::InputRegisters
            };
            let chunks = map.resolve(table, *address, q, false)?;
            present(&chunks, cpu)?;
            Ok(register_reply(fc, &read_words(&chunks, cpu)))
        }
        Request::WriteSingleCoil { address, value } => {
            let on = match value {
                0xFF00 => true,
                0x0000 => false,
                _ => return Err(Exception::IllegalDataValue),
            };
            let chunks = map.resolve(Table::Coils, *address, 1, true)?;
            present(&chunks, cpu)?;
            write_bits(&chunks, &[on], cpu);
            Ok(pdu.to_vec())
        }
        Request::WriteSingleRegister { address, value } => {
            let chunks = map.resolve(Table::HoldingRegisters, *address, 1, true)?;
            present(&chunks, cpu)?;
            write_words(&chunks, &[*value], cpu);
            Ok(pdu.to_vec())
        }
        Request::WriteMultipleCoils {
            address,
            quantity,
            bits,
        } => {
            let q = check_quantity(*quantity as usize, lim.write_bits)?;
            let chunks = map.resolve(Table::Coils, *address, q, false)?;
            present(&chunks, cpu)?;
            let values: Vec<bool> = (0..q as usize)
                .map(|i| bits[i / 8] >> (i % 8) & 1 != 0)
                .collect();
            write_bits(&chunks, &values, cpu);
            Ok(pdu[..5].to_vec())
        }
        Request::WriteMultipleRegisters { address, values } => {
            let q = check_quantity(values.len(), lim.write_registers)?;
            let chunks = map.resolve(Table::HoldingRegisters, *address, q, false)?;
            present(&chunks, cpu)?;
            write_words(&chunks, values, cpu);
            Ok(pdu[..5].to_vec())
        }
        Request::MaskWriteRegister {
            address,
            and_mask,
            or_mask,
        } => {
            let chunks = map.resolve(Table::HoldingRegisters, *address, 1, true)?;
            present(&chunks, cpu)?;
            let cur = read_words(&chunks, cpu)[0];
            let new = (cur & and_mask) | (or_mask & !and_mask);
            write_words(&chunks, &[new], cpu);
            Ok(pdu.to_vec())
        }
        Request::ReadWriteMultipleRegisters {
            read_address,
            read_quantity,
            write_address,
            values,
        } => {
            let rq = check_quantity(*read_quantity as usize, lim.rw_read_registers)?;
            let wq = check_quantity(values.len(), lim.rw_write_registers)?;
            let w = map.resolve(Table::HoldingRegisters, *write_address, wq, false)?;
            let r = map.resolve(Table::HoldingRegisters, *read_address, rq, false)?;
            present(&w, cpu)?;
            present(&r, cpu)?;
            write_words(&w, values, cpu);
            Ok(register_reply(fc, &read_words(&r, cpu)))
        }
        Request::Diagnostics { .. } => Err(Exception::IllegalFunction),
    }
}

fn register_reply(fc: u8, words: &[u16]) -> Vec<u8> {
    let mut out = Vec::with_capacity(2 + 2 * words.len());
    out.push(fc);
    out.push((words.len() * 2) as u8);
    for w in words {
        out.extend_from_slice(&w.to_be_bytes());
    }
    out
}

/// Bits LSB first, 8 to a byte, unused high bits 0 (spec/aplc.md §6.5).
fn pack_bits(bits: &[bool]) -> Vec<u8> {
    bits.chunks(8)
        .map(|c| {
            c.iter()
                .enumerate()
                .fold(0u8, |b, (i, &on)| b | (on as u8) << i)
        })
        .collect()
}

/// The devices a piece reaches, as one access span (R is the block-0 window
/// R0-R32767 of the map): `Ok(None)` when the whole piece lies past the
/// range's [`Range::limit`](crate::Range::limit) (it reads OFF/0), `Err`
/// when the CPU does not have them all.
fn span(c: &Chunk, cpu: &Cpu) -> Result<Option<Span>, ()> {
    let first = c.range.device(c.offset);
    let mut last = c.range.device(c.offset + c.len - 1);
    if let Some(limit) = c.range.limit {
        if first >= limit {
            return Ok(None);
        }
        last = last.min(limit - 1);
    }
    cpu.span(c.range.kind, first, last - first + 1, RBlock::First)
        .map(Some)
        .map_err(|_| ())
}

/// Exception 04 when a piece reaches devices the CPU does not have.
fn present(chunks: &[Chunk], cpu: &Cpu) -> Result<(), Exception> {
    for c in chunks {
        span(c, cpu).map_err(|_| Exception::ServerDeviceFailure)?;
    }
    Ok(())
}

/// A write to device `n` of `range` takes effect.
fn takes_write(range: &crate::Range, n: u32) -> bool {
    range.is_writable(n) && range.limit.is_none_or(|l| n < l)
}

/// Every (range, offset) of the pieces, in request order.
fn addresses<'a>(chunks: &'a [Chunk<'a>]) -> impl Iterator<Item = (&'a Chunk<'a>, u32)> + 'a {
    chunks
        .iter()
        .flat_map(|c| (c.offset..c.offset + c.len).map(move |o| (c, o)))
}

/// The points of every piece, read through its span (checked by [`present`]).
fn read_points<T: Copy + Default>(
    chunks: &[Chunk],
    cpu: &Cpu,
    read: impl Fn(&Span) -> Option<Vec<T>>,
) -> Vec<T> {
    let mut out = Vec::new();
    for c in chunks {
        let first = c.range.device(c.offset);
        let points = match span(c, cpu) {
            Ok(Some(s)) => read(&s).unwrap_or_default(),
            _ => Vec::new(),
        };
        for o in c.offset..c.offset + c.len {
            let i = (c.range.device(o) - first) as usize;
            out.push(points.get(i).copied().unwrap_or_default());
        }
    }
    out
}

fn read_bits(chunks: &[Chunk], cpu: &Cpu) -> Vec<bool> {
    read_points(chunks, cpu, |s| cpu.memory().read_span_bits(s).ok())
}

fn write_bits(chunks: &[Chunk], values: &[bool], cpu: &mut Cpu) {
    for ((c, o), &v) in addresses(chunks).zip(values) {
        let n = c.range.device(o);
        if !takes_write(c.range, n) {
            continue;
        }
        // X through the input image, so the value survives the next input refresh.
        if let Ok(s) = cpu.span(c.range.kind, n, 1, RBlock::First) {
            let _ = cpu.write_span_bits(&s, &[v]);
        }
    }
}

fn read_words(chunks: &[Chunk], cpu: &Cpu) -> Vec<u16> {
    let words = read_points(chunks, cpu, |s| cpu.memory().read_span_words(s).ok());
    addresses(chunks)
        .zip(words)
        // Pairs over 16-bit devices: the high word (even offset) is 0.
        .map(|((c, o), v)| {
            if c.range.pairs && !c.range.pair_words && o.is_multiple_of(2) {
                0
            } else {
                v
            }
        })
        .collect()
}

fn write_words(chunks: &[Chunk], values: &[u16], cpu: &mut Cpu) {
    for ((c, o), &v) in addresses(chunks).zip(values) {
        let n = c.range.device(o);
        let zero_extended = c.range.pairs && !c.range.pair_words;
        if !takes_write(c.range, n) || (zero_extended && o.is_multiple_of(2)) {
            continue;
        }
        if let Ok(s) = cpu.span(c.range.kind, n, 1, RBlock::First) {
            let _ = cpu.write_span_words(&s, &[v]);
        }
    }
}
