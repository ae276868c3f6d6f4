//! Framing: Modbus-TCP (MBAP header), RTU (address + PDU + CRC-16) and ASCII
//! (`:` + hex + LRC + CR LF).
//!
//! Everything here is pure: [`decode`] takes the bytes a server has buffered and
//! says how many of them form the first frame, and [`Frame::encode`] builds the
//! bytes to send.
//!
//! # TCP
//! `transaction(2) protocol(2) = 0000 length(2) unit(1) PDU`, big endian; `length`
//! counts the unit byte and the PDU (2..=254, so a PDU is at most 253 bytes). A
//! protocol id other than 0 or a length outside 2..=254 is
//! [`FrameErrorKind::BadHeader`]; the server should close the connection, since
//! the stream can no longer be delimited.
//!
//! # RTU (spec/aplc.md §6.2)
//! `address(1) PDU CRC(2)`, the CRC-16 (polynomial A001, init FFFF) low byte first;
//! at most 256 bytes. A real RTU line is delimited by silence (3.5 character
//! times). [`decode`] does not see time, so it works out the length from the
//! function code of a *request*:
//!
//! | FC | request length on the wire |
//! |---|---|
//! | 1, 2, 3, 4, 5, 6, 8 | 8 |
//! | 15, 16 | 9 + byte count (byte 6) |
//! | 22 | 10 |
//! | 23 | 13 + byte count (byte 10) |
//! | anything else | the shortest prefix (4..=256 bytes) whose last two bytes are its CRC |
//!
//! FC 08 requests are taken with two data bytes, the form seed 002 documents for
//! every sub-function. A server that delimits frames by silence can instead pass
//! one whole frame to [`decode_exact`], which accepts any length.
//!
//! # ASCII (spec/aplc.md §6.2)
//! `:` then address, PDU and LRC as two hex characters each (upper or lower case
//! accepted, upper case sent), then CR LF; at most 513 characters. The LRC is the
//! two's complement of the byte sum of address and PDU. Bytes before a `:` are
//! junk, and a `:` inside a frame starts a new one (the old one is junk).

use std::fmt;

/// Transport of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Proto {
    Tcp,
    Rtu,
    Ascii,
}

impl Proto {
    pub const ALL: [Proto; 3] = [Proto::Tcp, Proto::Rtu, Proto::Ascii];

    /// Serial line (RTU or ASCII): unit ids are station addresses and 0 is broadcast.
    pub fn is_serial(self) -> bool {
        self != Proto::Tcp
    }
}

impl fmt::Display for Proto {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Proto::Tcp => "TCP",
            Proto::Rtu => "RTU",
            Proto::Ascii => "ASCII",
        })
    }
}

/// Largest PDU (function code + data): 253 bytes (RTU 256 − address − CRC).
pub const MAX_PDU: usize = 253;
/// Largest RTU frame (spec/aplc.md §6.2).
pub const MAX_RTU: usize = 256;
/// Largest ASCII frame in characters (spec/aplc.md §6.2).
pub const MAX_ASCII: usize = 513;
/// MBAP header length including the unit id.
pub const MBAP_LEN: usize = 7;

/// One Modbus application data unit with its transport fields stripped.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Frame {
    pub proto: Proto,
    /// MBAP transaction id (TCP); 0 on serial lines.
    pub transaction: u16,
    /// Unit id (TCP) or station address (serial; 0 = broadcast).
    pub unit: u8,
    /// Function code and data. Never empty after [`decode`].
    pub pdu: Vec<u8>,
}

impl Frame {
    pub fn new(proto: Proto, transaction: u16, unit: u8, pdu: Vec<u8>) -> Frame {
        Frame {
            proto,
            transaction,
            unit,
            pdu,
        }
    }

    /// The function code (0 for an empty PDU).
    pub fn function(&self) -> u8 {
        self.pdu.first().copied().unwrap_or(0)
    }

    /// A frame with the same transport fields and another PDU (a response).
    pub fn reply(&self, pdu: Vec<u8>) -> Frame {
        Frame {
            pdu,
            ..self.clone()
        }
    }

    /// The bytes on the wire.
    pub fn encode(&self) -> Vec<u8> {
        match self.proto {
            Proto::Tcp => {
                let mut out = Vec::with_capacity(MBAP_LEN + self.pdu.len());
                out.extend_from_slice(&self.transaction.to_be_bytes());
                out.extend_from_slice(&[0, 0]);
                out.extend_from_slice(&((self.pdu.len() + 1) as u16).to_be_bytes());
                out.push(self.unit);
                out.extend_from_slice(&self.pdu);
                out
            }
            Proto::Rtu => {
                let mut out = Vec::with_capacity(self.pdu.len() + 3);
                out.push(self.unit);
                out.extend_from_slice(&self.pdu);
                let crc = crc16(&out);
                out.extend_from_slice(&crc.to_le_bytes());
                out
            }
            Proto::Ascii => {
                let mut bin = Vec::with_capacity(self.pdu.len() + 2);
                bin.push(self.unit);
                bin.extend_from_slice(&self.pdu);
                bin.push(lrc(&bin));
                let mut out = Vec::with_capacity(bin.len() * 2 + 3);
                out.push(b':');
                for b in bin {
                    out.push(HEX[(b >> 4) as usize]);
                    out.push(HEX[(b & 15) as usize]);
                }
                out.extend_from_slice(b"\r\n");
                out
            }
        }
    }
}

const HEX: &[u8; 16] = b"0123456789ABCDEF";

/// Modbus CRC-16: polynomial 0xA001 (reflected 0x8005), initial value 0xFFFF.
/// Sent low byte first.
pub fn crc16(data: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in data {
        crc = crc16_step(crc, b);
    }
    crc
}

#[inline]
fn crc16_step(mut crc: u16, b: u8) -> u16 {
    crc ^= b as u16;
    for _ in 0..8 {
        crc = if crc & 1 != 0 {
            (crc >> 1) ^ 0xA001
        } else {
            crc >> 1
        };
    }
    crc
}

/// Modbus ASCII LRC: the two's complement of the 8-bit sum of the bytes.
pub fn lrc(data: &[u8]) -> u8 {
    data.iter()
        .fold(0u8, |s, &b| s.wrapping_add(b))
        .wrapping_neg()
}

/// Why bytes at the front of a buffer are not a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FrameErrorKind {
    /// RTU CRC or ASCII LRC mismatch (counted by FC 08 sub-function 0x0C).
    BadChecksum,
    /// RTU frame over 256 bytes or ASCII frame over 513 characters (counted by FC 08
    /// sub-function 0x12).
    Overrun,
    /// ASCII: characters outside a frame (before `:`, or a frame cut short by a new `:`).
    Junk,
    /// ASCII: a character that is not a hex digit, an odd number of digits, a frame
    /// shorter than address + function + LRC, or LF without CR.
    BadAscii,
    /// TCP: protocol id other than 0, or length outside 2..=254.
    BadHeader,
}

/// Garbage at the front of a buffer. Drop `skip` bytes and decode again (TCP:
/// better close the connection). Serial errors are never answered (spec/aplc.md
/// §6.5); pass the error to [`crate::Slave::frame_error`] so the FC 08 counters see it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
#[error("{proto} frame error at byte {offset}: {kind:?} (skip {skip} bytes)")]
pub struct FrameError {
    pub proto: Proto,
    pub kind: FrameErrorKind,
    /// Where in the buffer the problem was found.
    pub offset: usize,
    /// How many bytes to drop; at least 1 and at most the buffer length.
    pub skip: usize,
}

/// Decodes one request frame from the front of `buf`.
///
/// `Ok(Some((frame, used)))`: the first `used` bytes are `frame`.
/// `Ok(None)`: more bytes are needed (an RTU server that sees 3.5 character times
/// of silence instead should drop the bytes: an inter-character timeout).
/// `Err(e)`: drop `e.skip` bytes.
pub fn decode(proto: Proto, buf: &[u8]) -> Result<Option<(Frame, usize)>, FrameError> {
    match proto {
        Proto::Tcp => decode_tcp(buf),
        Proto::Rtu => decode_rtu(buf),
        Proto::Ascii => decode_ascii(buf),
    }
}

/// Decodes a buffer that must hold exactly one frame (an RTU frame delimited by
/// silence, a datagram). Unlike [`decode`], an RTU frame may have any length from
/// 4 to 256 bytes whatever its function code.
pub fn decode_exact(proto: Proto, buf: &[u8]) -> Result<Frame, FrameError> {
    let err = |kind, offset| FrameError {
        proto,
        kind,
        offset,
        skip: buf.len().max(1),
    };
    if proto == Proto::Rtu {
        if buf.len() > MAX_RTU {
            return Err(err(FrameErrorKind::Overrun, MAX_RTU));
        }
        if buf.len() < 4 {
            return Err(err(FrameErrorKind::BadChecksum, buf.len()));
        }
        let n = buf.len() - 2;
        if crc16(&buf[..n]) != u16::from_le_bytes([buf[n], buf[n + 1]]) {
            return Err(err(FrameErrorKind::BadChecksum, n));
        }
        return Ok(Frame::new(proto, 0, buf[0], buf[1..n].to_vec()));
    }
    match decode(proto, buf) {
        Ok(Some((f, used))) if used == buf.len() => Ok(f),
        Ok(Some((_, used))) => Err(err(
            match proto {
                Proto::Tcp => FrameErrorKind::BadHeader,
                _ => FrameErrorKind::Junk,
            },
            used,
        )),
        Ok(None) => Err(err(
            match proto {
                Proto::Tcp => FrameErrorKind::BadHeader,
                _ => FrameErrorKind::BadAscii,
            },
            buf.len(),
        )),
        Err(e) => Err(FrameError {
            skip: buf.len().max(1),
            ..e
        }),
    }
}

fn decode_tcp(buf: &[u8]) -> Result<Option<(Frame, usize)>, FrameError> {
    if buf.len() < 6 {
        return Ok(None);
    }
    let protocol = u16::from_be_bytes([buf[2], buf[3]]);
    let len = u16::from_be_bytes([buf[4], buf[5]]) as usize;
    if protocol != 0 || !(2..=MAX_PDU + 1).contains(&len) {
        return Err(FrameError {
            proto: Proto::Tcp,
            kind: FrameErrorKind::BadHeader,
            offset: if protocol != 0 { 2 } else { 4 },
            skip: buf.len(),
        });
    }
    let total = 6 + len;
    if buf.len() < total {
        return Ok(None);
    }
    let frame = Frame::new(
        Proto::Tcp,
        u16::from_be_bytes([buf[0], buf[1]]),
        buf[6],
        buf[7..total].to_vec(),
    );
    Ok(Some((frame, total)))
}

/// Request length on an RTU line from its first bytes, when the function code
/// fixes it: `Ok(Some(len))`, `Ok(None)` = need more bytes, `Err(())` = unknown.
fn rtu_request_len(buf: &[u8]) -> Result<Option<usize>, ()> {
    let Some(&fc) = buf.get(1) else {
        return Ok(None);
    };
    let counted = |at: usize, fixed: usize| Ok(buf.get(at).map(|&bc| fixed + bc as usize));
    match fc {
        1..=6 | 8 => Ok(Some(8)),
        15 | 16 => counted(6, 9),
        22 => Ok(Some(10)),
        23 => counted(10, 13),
        _ => Err(()),
    }
}

fn decode_rtu(buf: &[u8]) -> Result<Option<(Frame, usize)>, FrameError> {
    let err = |kind, offset, skip: usize| FrameError {
        proto: Proto::Rtu,
        kind,
        offset,
        skip: skip.clamp(1, buf.len().max(1)),
    };
    let len = match rtu_request_len(buf) {
        Ok(None) => return Ok(None),
        Ok(Some(len)) => len,
        Err(()) => {
            // Unknown function code: the shortest prefix that ends in its own CRC.
            let mut crc = crc16_step(0xFFFF, buf[0]);
            for n in 4..=buf.len().min(MAX_RTU) {
                crc = crc16_step(crc, buf[n - 3]);
                if crc == u16::from_le_bytes([buf[n - 2], buf[n - 1]]) {
                    let frame = Frame::new(Proto::Rtu, 0, buf[0], buf[1..n - 2].to_vec());
                    return Ok(Some((frame, n)));
                }
            }
            if buf.len() >= MAX_RTU {
                return Err(err(FrameErrorKind::Overrun, MAX_RTU, buf.len()));
            }
            return Ok(None);
        }
    };
    if len > MAX_RTU {
        return Err(err(FrameErrorKind::Overrun, MAX_RTU, len));
    }
    if buf.len() < len {
        return Ok(None);
    }
    let n = len - 2;
    if crc16(&buf[..n]) != u16::from_le_bytes([buf[n], buf[n + 1]]) {
        return Err(err(FrameErrorKind::BadChecksum, n, len));
    }
    Ok(Some((
        Frame::new(Proto::Rtu, 0, buf[0], buf[1..n].to_vec()),
        len,
    )))
}

fn hex_value(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c - b'0'),
        b'A'..=b'F' => Some(c - b'A' + 10),
        b'a'..=b'f' => Some(c - b'a' + 10),
        _ => None,
    }
}

fn decode_ascii(buf: &[u8]) -> Result<Option<(Frame, usize)>, FrameError> {
    let err = |kind, offset, skip: usize| FrameError {
        proto: Proto::Ascii,
        kind,
        offset,
        skip: skip.clamp(1, buf.len().max(1)),
    };
    if buf.is_empty() {
        return Ok(None);
    }
    if buf[0] != b':' {
        let skip = buf.iter().position(|&c| c == b':').unwrap_or(buf.len());
        return Err(err(FrameErrorKind::Junk, 0, skip));
    }
    // The frame runs to the first LF; a ':' before it restarts.
    let mut end = None;
    for (i, &c) in buf.iter().enumerate().skip(1) {
        match c {
            b':' => return Err(err(FrameErrorKind::Junk, i, i)),
            b'\n' => {
                end = Some(i);
                break;
            }
            _ => {}
        }
    }
    let Some(lf) = end else {
        if buf.len() >= MAX_ASCII {
            return Err(err(FrameErrorKind::Overrun, MAX_ASCII, buf.len()));
        }
        return Ok(None);
    };
    let used = lf + 1;
    if used > MAX_ASCII {
        return Err(err(FrameErrorKind::Overrun, MAX_ASCII, used));
    }
    if buf[lf - 1] != b'\r' {
        return Err(err(FrameErrorKind::BadAscii, lf - 1, used));
    }
    let hex = &buf[1..lf - 1];
    if !hex.len().is_multiple_of(2) || hex.len() < 6 {
        return Err(err(FrameErrorKind::BadAscii, lf - 1, used));
    }
    let mut bin = Vec::with_capacity(hex.len() / 2);
    for (k, pair) in hex.chunks_exact(2).enumerate() {
        match (hex_value(pair[0]), hex_value(pair[1])) {
            (Some(h), Some(l)) => bin.push(h << 4 | l),
            (None, _) => return Err(err(FrameErrorKind::BadAscii, 1 + 2 * k, used)),
            (_, None) => return Err(err(FrameErrorKind::BadAscii, 2 + 2 * k, used)),
        }
    }
    let (body, sum) = bin.split_at(bin.len() - 1);
    if lrc(body) != sum[0] {
        return Err(err(FrameErrorKind::BadChecksum, lf - 3, used));
    }
    Ok(Some((
        Frame::new(Proto::Ascii, 0, body[0], body[1..].to_vec()),
        used,
    )))
}
