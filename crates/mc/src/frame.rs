//! QnA-compatible 3E and 4E frames, binary and ASCII, detected per frame.
//!
//! Request layout (binary; ASCII carries the same fields as hexadecimal text of
//! twice the width, most significant digit first):
//!
//! | field | 3E binary | 4E binary | 3E ASCII | 4E ASCII |
//! |---|---|---|---|---|
//! | subheader | `50 00` | `54 00` | `"5000"` | `"5400"` |
//! | serial number | — | 2 bytes LE | — | 4 chars |
//! | fixed | — | `00 00` | — | `"0000"` |
//! | network No. | 1 | 1 | 2 | 2 |
//! | PC No. | 1 | 1 | 2 | 2 |
//! | module I/O No. | 2 LE | 2 LE | 4 | 4 |
//! | module station No. | 1 | 1 | 2 | 2 |
//! | request data length | 2 LE | 2 LE | 4 | 4 |
//! | monitoring timer | 2 LE | 2 LE | 4 | 4 |
//! | command, subcommand | 2 + 2 LE | 2 + 2 LE | 4 + 4 | 4 + 4 |
//! | request data | … | … | … | … |
//!
//! The request data length counts the bytes (characters) from the monitoring
//! timer to the end. Responses use subheader `D0 00`/`D4 00` (`"D000"`/`"D400"`),
//! echo the serial number and the network, PC, I/O and station numbers, and carry
//! the response data length (from the end code on), the end code, and then the
//! response data or, for an error, the error information: network No., PC No.,
//! I/O No., station No. of the responding station, then the command and
//! subcommand of the request.
//!
//! softplc accepts any network/PC/I/O/station numbers and answers as the addressed
//! station (it is the only station). The monitoring timer (units of 250 ms,
//! 0 = wait forever) is decoded into [`Header::timer`] for the server to use.

use crate::codec::{parse_hex, BodyError, Reader, Writer};
use crate::command::Command;
use crate::end_code::EndCode;

/// Largest request data length accepted (bytes, or characters in ASCII). The
/// largest valid Q request, an ASCII batch write of 7168 bits, needs 7192.
/// Longer frames are [`FrameError::Malformed`]: the server cannot buffer them.
pub const MAX_DATA_LEN: usize = 8192;

/// Frame type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    E3,
    /// 4E frames carry a serial number the response echoes.
    E4 {
        serial: u16,
    },
}

/// Communication data code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataCode {
    Binary,
    Ascii,
}

/// The frame fields around a command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    pub frame: Frame,
    pub code: DataCode,
    pub network: u8,
    pub pc: u8,
    pub io: u16,
    pub station: u8,
    /// Monitoring timer, units of 250 ms (0 = wait forever). Requests only.
    pub timer: u16,
}

impl Default for Header {
    /// 3E binary to the own station: network 00, PC FF, I/O 03FF, station 00.
    fn default() -> Self {
        Header {
            frame: Frame::E3,
            code: DataCode::Binary,
            network: 0,
            pc: 0xFF,
            io: 0x03FF,
            station: 0,
            timer: 0,
        }
    }
}

/// A decoded request.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Request {
    pub header: Header,
    pub command: Command,
}

/// Why a request could not be decoded.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// The buffer ends before the frame does: read more and try again.
    #[error("incomplete frame")]
    Incomplete,
    /// The frame cannot be delimited or addressed (unknown subheader, bad header
    /// field, oversize length). No response is possible: close the connection.
    #[error("malformed frame at byte {offset}: {what}")]
    Malformed { offset: usize, what: &'static str },
    /// The frame is delimited and its header is known, but the request is in
    /// error: answer with [`Rejected::response`] and go on after
    /// [`Rejected::used`] bytes.
    #[error("request refused with end code {:04X}H at byte {}: {}", .0.end_code.0, .0.offset, .0.what)]
    Rejected(Box<Rejected>),
}

/// A delimited request refused with an end code.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rejected {
    pub header: Header,
    /// Command and subcommand as received (0 when the frame is too short to hold them).
    pub command: u16,
    pub subcommand: u16,
    pub end_code: EndCode,
    /// Offset in the frame of the offending field.
    pub offset: usize,
    pub what: &'static str,
    /// Length of the frame.
    pub used: usize,
}

impl Rejected {
    /// The error response to send.
    pub fn response(&self) -> Vec<u8> {
        encode_response(
            &self.header,
            &Response::Error {
                end_code: self.end_code,
                command: self.command,
                subcommand: self.subcommand,
            },
        )
    }
}

/// The outcome of a request.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Response {
    Ok(ResponseData),
    /// Abnormal completion: the error information names the request's command.
    Error {
        end_code: EndCode,
        command: u16,
        subcommand: u16,
    },
}

impl Response {
    pub fn end_code(&self) -> EndCode {
        match self {
            Response::Ok(_) => EndCode::OK,
            Response::Error { end_code, .. } => *end_code,
        }
    }
}

/// Response data of a normal completion.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ResponseData {
    /// Writes and remote operations.
    None,
    /// Word units: 2 bytes LE (4 hex characters) a word.
    Words(Vec<u16>),
    /// Bit units: binary two points a byte, the first in the high nibble, a
    /// trailing odd point followed by a 0 nibble; ASCII one `0`/`1` a point.
    Bits(Vec<bool>),
    /// Random read: the word points, then the double-word points (low word first).
    Random { words: Vec<u16>, dwords: Vec<u32> },
    /// Read CPU model: 16 characters (space padded) then the model code.
    CpuModel { name: [u8; 16], code: u16 },
    /// Loopback: length, then the data as received.
    Loopback(Vec<u8>),
}

// --- decoding requests ---

fn malformed(offset: usize, what: &'static str) -> FrameError {
    FrameError::Malformed { offset, what }
}

/// Reads header fields of fixed width, reporting short input as incomplete.
struct HeaderReader<'a> {
    buf: &'a [u8],
    pos: usize,
    code: DataCode,
}

impl HeaderReader<'_> {
    fn uint(&mut self, bytes: usize, what: &'static str) -> Result<u32, FrameError> {
        let n = self.code.width(bytes);
        let s = self
            .buf
            .get(self.pos..self.pos + n)
            .ok_or(FrameError::Incomplete)?;
        let v = match self.code {
            DataCode::Binary => s.iter().rev().fold(0u32, |v, b| (v << 8) | *b as u32),
            DataCode::Ascii => parse_hex(s).ok_or_else(|| malformed(self.pos, what))?,
        };
        self.pos += n;
        Ok(v)
    }
}

/// Decodes one request from the start of `buf`; returns it with the number of
/// bytes it occupies (the next frame, if any, starts there).
pub fn decode_request(buf: &[u8]) -> Result<(Request, usize), FrameError> {
    let code = match buf.first() {
        None => return Err(FrameError::Incomplete),
        Some(0x50) | Some(0x54) => DataCode::Binary,
        Some(b'5') => DataCode::Ascii,
        Some(_) => return Err(malformed(0, "unknown subheader")),
    };
    // Subheader and, for 4E, serial number and fixed zeros.
    let (frame, pos) = match code {
        DataCode::Binary => {
            let e4 = buf[0] == 0x54;
            match buf.get(1) {
                None => return Err(FrameError::Incomplete),
                Some(0) => {}
                Some(_) => return Err(malformed(1, "unknown subheader")),
            }
            if e4 {
                let s = buf.get(2..6).ok_or(FrameError::Incomplete)?;
                (
                    Frame::E4 {
                        serial: u16::from_le_bytes([s[0], s[1]]),
                    },
                    6,
                )
            } else {
                (Frame::E3, 2)
            }
        }
        DataCode::Ascii => {
            let avail = &buf[..buf.len().min(4)];
            let e4 = if b"5000".starts_with(avail) {
                false
            } else if b"5400".starts_with(avail) {
                true
            } else {
                let bad = avail
                    .iter()
                    .zip(if avail.get(1) == Some(&b'4') {
                        b"5400"
                    } else {
                        b"5000"
                    })
                    .position(|(a, b)| a != b)
                    .unwrap_or(0);
                return Err(malformed(bad, "unknown subheader"));
            };
            if avail.len() < 4 {
                return Err(FrameError::Incomplete);
            }
            if e4 {
                let s = buf.get(4..12).ok_or(FrameError::Incomplete)?;
                let serial = parse_hex(&s[..4]).ok_or_else(|| malformed(4, "serial number"))?;
                (
                    Frame::E4 {
                        serial: serial as u16,
                    },
                    12,
                )
            } else {
                (Frame::E3, 4)
            }
        }
    };
    let mut h = HeaderReader { buf, pos, code };
    let network = h.uint(1, "network number")? as u8;
    let pc = h.uint(1, "PC number")? as u8;
    let io = h.uint(2, "module I/O number")? as u16;
    let station = h.uint(1, "module station number")? as u8;
    let len_at = h.pos;
    let len = h.uint(2, "request data length")? as usize;
    if len > MAX_DATA_LEN {
        return Err(malformed(len_at, "request data length exceeds 8192"));
    }
    let body_at = h.pos;
    let used = body_at + len;
    if buf.len() < used {
        return Err(FrameError::Incomplete);
    }
    let mut header = Header {
        frame,
        code,
        network,
        pc,
        io,
        station,
        timer: 0,
    };
    let mut r = Reader::new(&buf[body_at..used], body_at, code);
    let reject = |header: Header, command: u16, subcommand: u16, e: BodyError| {
        FrameError::Rejected(Box::new(Rejected {
            header,
            command,
            subcommand,
            end_code: e.end_code,
            offset: e.offset,
            what: e.what,
            used,
        }))
    };
    header.timer = r
        .u16("monitoring timer")
        .map_err(|e| reject(header, 0, 0, e))?;
    let command = r.u16("command").map_err(|e| reject(header, 0, 0, e))?;
    let sub_at = r.offset();
    let subcommand = r
        .u16("subcommand")
        .map_err(|e| reject(header, command, 0, e))?;
    let cmd = Command::decode(command, subcommand, sub_at, &mut r)
        .map_err(|e| reject(header, command, subcommand, e))?;
    Ok((
        Request {
            header,
            command: cmd,
        },
        used,
    ))
}

// --- encoding ---

/// Writes the subheader through the station number, reserves the length field
/// and returns its position.
fn encode_head(out: &mut Vec<u8>, h: &Header, response: bool) -> usize {
    let code = h.code;
    let mut w = Writer {
        out,
        code,
        extended: false,
    };
    let sub: u8 = match (h.frame, response) {
        (Frame::E3, false) => 0x50,
        (Frame::E4 { .. }, false) => 0x54,
        (Frame::E3, true) => 0xD0,
        (Frame::E4 { .. }, true) => 0xD4,
    };
    match code {
        // The subheader reads in natural order in both codes: 50 00 / "5000".
        DataCode::Binary => w.raw(&[sub, 0]),
        DataCode::Ascii => w.raw(format!("{sub:02X}00").as_bytes()),
    }
    if let Frame::E4 { serial } = h.frame {
        w.u16(serial);
        w.u16(0);
    }
    w.u8(h.network);
    w.u8(h.pc);
    w.u16(h.io);
    w.u8(h.station);
    let at = w.out.len();
    w.u16(0);
    at
}

/// Fills in the length field at `at` with the length of what follows it.
fn patch_len(out: &mut [u8], at: usize, code: DataCode) {
    let width = code.width(2);
    let len = (out.len() - at - width) as u16;
    let mut v = Vec::with_capacity(width);
    Writer {
        out: &mut v,
        code,
        extended: false,
    }
    .u16(len);
    out[at..at + width].copy_from_slice(&v);
}

/// Encodes a request (the client side; used by tests and tools).
pub fn encode_request(req: &Request) -> Vec<u8> {
    let h = &req.header;
    let mut out = Vec::new();
    let at = encode_head(&mut out, h, false);
    let mut w = Writer {
        out: &mut out,
        code: h.code,
        extended: false,
    };
    w.u16(h.timer);
    let (command, subcommand) = req.command.codes();
    w.u16(command);
    w.u16(subcommand);
    req.command.encode_body(&mut w);
    patch_len(&mut out, at, h.code);
    out
}

/// Encodes the response to a request with header `h` (normal or error).
pub fn encode_response(h: &Header, resp: &Response) -> Vec<u8> {
    let mut out = Vec::new();
    let at = encode_head(&mut out, h, true);
    let mut w = Writer {
        out: &mut out,
        code: h.code,
        extended: false,
    };
    w.u16(resp.end_code().0);
    match resp {
        Response::Error {
            command,
            subcommand,
            ..
        } => {
            w.u8(h.network);
            w.u8(h.pc);
            w.u16(h.io);
            w.u8(h.station);
            w.u16(*command);
            w.u16(*subcommand);
        }
        Response::Ok(data) => match data {
            ResponseData::None => {}
            ResponseData::Words(v) => v.iter().for_each(|x| w.u16(*x)),
            ResponseData::Bits(v) => w.bits(v),
            ResponseData::Random { words, dwords } => {
                words.iter().for_each(|x| w.u16(*x));
                dwords.iter().for_each(|x| w.u32(*x));
            }
            ResponseData::CpuModel { name, code } => {
                w.raw(name);
                w.u16(*code);
            }
            ResponseData::Loopback(d) => {
                w.u16(d.len() as u16);
                w.raw(d);
            }
        },
    }
    patch_len(&mut out, at, h.code);
    out
}

// --- decoding responses (client side) ---

/// The error information block of an abnormal response.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ErrorInfo {
    pub network: u8,
    pub pc: u8,
    pub io: u16,
    pub station: u8,
    pub command: u16,
    pub subcommand: u16,
}

/// A decoded response frame. The response data is left as received: its layout
/// depends on the request (see [`ResponseFrame::words`], [`ResponseFrame::bits`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ResponseFrame {
    /// The echoed header fields (`timer` is 0).
    pub header: Header,
    pub end_code: EndCode,
    /// Response data after the end code (bytes, or characters in ASCII); empty
    /// for an error response.
    pub data: Vec<u8>,
    pub error: Option<ErrorInfo>,
}

impl ResponseFrame {
    /// The data as words (batch read in word units, random read words).
    pub fn words(&self) -> Option<Vec<u16>> {
        let width = self.header.code.width(2);
        let chunks = self.data.chunks_exact(width);
        if !chunks.remainder().is_empty() {
            return None;
        }
        chunks
            .map(|c| match self.header.code {
                DataCode::Binary => Some(u16::from_le_bytes([c[0], c[1]])),
                DataCode::Ascii => parse_hex(c).map(|v| v as u16),
            })
            .collect()
    }

    /// The data as `n` bit points (batch read in bit units).
    pub fn bits(&self, n: usize) -> Option<Vec<bool>> {
        let mut r = Reader::new(&self.data, 0, self.header.code);
        let v = r.bits(n).ok()?;
        r.finish().ok()?;
        Some(v)
    }
}

/// Decodes one response from the start of `buf` (the client side).
pub fn decode_response(buf: &[u8]) -> Result<(ResponseFrame, usize), FrameError> {
    let code = match buf.first() {
        None => return Err(FrameError::Incomplete),
        Some(0xD0) | Some(0xD4) => DataCode::Binary,
        Some(b'D') => DataCode::Ascii,
        Some(_) => return Err(malformed(0, "unknown subheader")),
    };
    let sub_len = code.width(2);
    let sub = buf.get(..sub_len).ok_or(FrameError::Incomplete)?;
    let e4 = match (code, sub) {
        (DataCode::Binary, [0xD0, 0]) | (DataCode::Ascii, b"D000") => false,
        (DataCode::Binary, [0xD4, 0]) | (DataCode::Ascii, b"D400") => true,
        _ => return Err(malformed(0, "unknown subheader")),
    };
    let mut h = HeaderReader {
        buf,
        pos: sub_len,
        code,
    };
    let frame = if e4 {
        let serial = h.uint(2, "serial number")? as u16;
        h.uint(2, "fixed value")?;
        Frame::E4 { serial }
    } else {
        Frame::E3
    };
    let network = h.uint(1, "network number")? as u8;
    let pc = h.uint(1, "PC number")? as u8;
    let io = h.uint(2, "module I/O number")? as u16;
    let station = h.uint(1, "module station number")? as u8;
    let len_at = h.pos;
    let len = h.uint(2, "response data length")? as usize;
    let body_at = h.pos;
    let used = body_at + len;
    if buf.len() < used {
        return Err(FrameError::Incomplete);
    }
    let mut r = Reader::new(&buf[body_at..used], body_at, code);
    let bad = |_| malformed(len_at, "response data length");
    let end_code = EndCode(r.u16("end code").map_err(bad)?);
    let header = Header {
        frame,
        code,
        network,
        pc,
        io,
        station,
        timer: 0,
    };
    let mut error = None;
    let mut data = Vec::new();
    if end_code.is_ok() {
        data = r.peek().to_vec();
    } else if r.remaining() > 0 {
        let e = (|| {
            Ok::<_, BodyError>(ErrorInfo {
                network: r.u8("")?,
                pc: r.u8("")?,
                io: r.u16("")?,
                station: r.u8("")?,
                command: r.u16("")?,
                subcommand: r.u16("")?,
            })
        })()
        .map_err(|_| malformed(body_at, "error information"))?;
        error = Some(e);
    }
    Ok((
        ResponseFrame {
            header,
            end_code,
            data,
            error,
        },
        used,
    ))
}
