//! Field-level reading and writing shared by requests and responses. Binary fields
//! are little-endian; ASCII fields are the same values as upper-case hexadecimal
//! text, most significant digit first.

use crate::device::{Device, DeviceRef};
use crate::end_code::EndCode;
use crate::frame::DataCode;

/// Why a request body was refused: the end code to answer with, where and what.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct BodyError {
    pub end_code: EndCode,
    /// Absolute offset in the frame.
    pub offset: usize,
    pub what: &'static str,
}

pub(crate) type BodyResult<T> = Result<T, BodyError>;

pub(crate) fn hex_digit(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c - b'0'),
        b'A'..=b'F' => Some(c - b'A' + 10),
        b'a'..=b'f' => Some(c - b'a' + 10),
        _ => None,
    }
}

/// Parses `text` as hexadecimal (at most 8 digits).
pub(crate) fn parse_hex(text: &[u8]) -> Option<u32> {
    let mut v = 0u32;
    for &c in text {
        v = (v << 4) | hex_digit(c)? as u32;
    }
    Some(v)
}

/// A cursor over a request body (the part after the command and subcommand).
pub(crate) struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
    /// Absolute offset of `buf[0]` in the frame.
    base: usize,
    code: DataCode,
}

impl<'a> Reader<'a> {
    pub fn new(buf: &'a [u8], base: usize, code: DataCode) -> Self {
        Reader {
            buf,
            pos: 0,
            base,
            code,
        }
    }

    pub fn offset(&self) -> usize {
        self.base + self.pos
    }

    pub fn code(&self) -> DataCode {
        self.code
    }

    /// The bytes not read yet.
    pub fn peek(&self) -> &'a [u8] {
        &self.buf[self.pos..]
    }

    pub fn remaining(&self) -> usize {
        self.buf.len() - self.pos
    }

    pub fn error(&self, end_code: EndCode, what: &'static str) -> BodyError {
        BodyError {
            end_code,
            offset: self.offset(),
            what,
        }
    }

    fn length_error(&self, what: &'static str) -> BodyError {
        let end_code = match self.code {
            DataCode::Binary => EndCode::DATA_LENGTH,
            DataCode::Ascii => EndCode::ASCII_LENGTH,
        };
        self.error(end_code, what)
    }

    /// Takes `n` raw bytes (characters in ASCII).
    pub fn take(&mut self, n: usize, what: &'static str) -> BodyResult<&'a [u8]> {
        if self.remaining() < n {
            return Err(self.length_error(what));
        }
        let s = &self.buf[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// An unsigned field of `bytes` binary bytes (2·`bytes` ASCII characters).
    fn uint(&mut self, bytes: usize, what: &'static str) -> BodyResult<u32> {
        match self.code {
            DataCode::Binary => {
                let s = self.take(bytes, what)?;
                Ok(s.iter().rev().fold(0u32, |v, b| (v << 8) | *b as u32))
            }
            DataCode::Ascii => {
                let at = self.offset();
                let s = self.take(2 * bytes, what)?;
                parse_hex(s).ok_or(BodyError {
                    end_code: EndCode::ASCII_DATA,
                    offset: at,
                    what,
                })
            }
        }
    }

    pub fn u8(&mut self, what: &'static str) -> BodyResult<u8> {
        Ok(self.uint(1, what)? as u8)
    }

    pub fn u16(&mut self, what: &'static str) -> BodyResult<u16> {
        Ok(self.uint(2, what)? as u16)
    }

    pub fn u32(&mut self, what: &'static str) -> BodyResult<u32> {
        self.uint(4, what)
    }

    /// A device specification: binary number (3 bytes) then code (1 byte); ASCII
    /// code (2 characters) then number (6 characters, in the device's numbering).
    pub fn device(&mut self) -> BodyResult<DeviceRef> {
        match self.code {
            DataCode::Binary => {
                let s = self.take(4, "device")?;
                let number = s[0] as u32 | (s[1] as u32) << 8 | (s[2] as u32) << 16;
                let device = Device::from_binary(s[3]).ok_or(BodyError {
                    end_code: EndCode::DEVICE,
                    offset: self.offset() - 1,
                    what: "unknown device code",
                })?;
                Ok(DeviceRef { device, number })
            }
            DataCode::Ascii => {
                let at = self.offset();
                let s = self.take(8, "device")?;
                let device = Device::from_ascii([s[0], s[1]]).ok_or(BodyError {
                    end_code: EndCode::DEVICE,
                    offset: at,
                    what: "unknown device code",
                })?;
                let digits = &s[2..];
                let number = if device.is_hex() {
                    parse_hex(digits)
                } else {
                    digits.iter().try_fold(0u32, |v, c| {
                        c.is_ascii_digit().then(|| v * 10 + (c - b'0') as u32)
                    })
                };
                let number = number.ok_or(BodyError {
                    end_code: EndCode::ASCII_DATA,
                    offset: at + 2,
                    what: "device number is not a number in the device's numbering",
                })?;
                Ok(DeviceRef { device, number })
            }
        }
    }

    /// `n` bit values: binary packs two points a byte, the first in the high
    /// nibble; ASCII has one character `0`/`1` a point.
    pub fn bits(&mut self, n: usize) -> BodyResult<Vec<bool>> {
        let mut v = Vec::with_capacity(n);
        match self.code {
            DataCode::Binary => {
                let at = self.offset();
                let s = self.take(n.div_ceil(2), "bit data")?;
                for i in 0..n {
                    let nib = if i % 2 == 0 {
                        s[i / 2] >> 4
                    } else {
                        s[i / 2] & 0xF
                    };
                    if nib > 1 {
                        return Err(BodyError {
                            end_code: EndCode::BIT_DATA,
                            offset: at + i / 2,
                            what: "bit data other than 0 or 1",
                        });
                    }
                    v.push(nib == 1);
                }
            }
            DataCode::Ascii => {
                let at = self.offset();
                let s = self.take(n, "bit data")?;
                for (i, c) in s.iter().enumerate() {
                    let code = match c {
                        b'0' | b'1' => {
                            v.push(*c == b'1');
                            continue;
                        }
                        c if hex_digit(*c).is_some() => EndCode::BIT_DATA,
                        _ => EndCode::ASCII_DATA,
                    };
                    return Err(BodyError {
                        end_code: code,
                        offset: at + i,
                        what: "bit data other than 0 or 1",
                    });
                }
            }
        }
        Ok(v)
    }

    /// One ON/OFF value of a random write in bit units (binary 1 byte, ASCII 2
    /// characters), 0 or 1.
    pub fn bit_value(&mut self) -> BodyResult<bool> {
        let at = self.offset();
        match self.u8("set/reset value")? {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(BodyError {
                end_code: EndCode::BIT_DATA,
                offset: at,
                what: "set/reset value other than 00 or 01",
            }),
        }
    }

    /// Fails unless the body has been consumed exactly.
    pub fn finish(&self) -> BodyResult<()> {
        if self.remaining() != 0 {
            return Err(self.length_error("data after the end of the request"));
        }
        Ok(())
    }
}

/// Appends fields in the frame's data code.
pub(crate) struct Writer<'a> {
    pub out: &'a mut Vec<u8>,
    pub code: DataCode,
}

const HEX: &[u8; 16] = b"0123456789ABCDEF";

impl Writer<'_> {
    fn uint(&mut self, v: u32, bytes: usize) {
        match self.code {
            DataCode::Binary => self.out.extend_from_slice(&v.to_le_bytes()[..bytes]),
            DataCode::Ascii => {
                for i in (0..2 * bytes).rev() {
                    self.out.push(HEX[(v >> (4 * i)) as usize & 0xF]);
                }
            }
        }
    }

    pub fn u8(&mut self, v: u8) {
        self.uint(v as u32, 1)
    }

    pub fn u16(&mut self, v: u16) {
        self.uint(v as u32, 2)
    }

    pub fn u32(&mut self, v: u32) {
        self.uint(v, 4)
    }

    pub fn raw(&mut self, s: &[u8]) {
        self.out.extend_from_slice(s)
    }

    pub fn device(&mut self, d: &DeviceRef) {
        match self.code {
            DataCode::Binary => {
                self.out
                    .extend_from_slice(&(d.number & 0xFF_FFFF).to_le_bytes()[..3]);
                self.out.push(d.device.binary_code());
            }
            DataCode::Ascii => {
                self.out.extend_from_slice(&d.device.ascii_code());
                let s = if d.device.is_hex() {
                    format!("{:06X}", d.number & 0xFF_FFFF)
                } else {
                    format!("{:06}", d.number % 1_000_000)
                };
                self.out.extend_from_slice(s.as_bytes());
            }
        }
    }

    pub fn bits(&mut self, v: &[bool]) {
        match self.code {
            DataCode::Binary => {
                for pair in v.chunks(2) {
                    let hi = (pair[0] as u8) << 4;
                    let lo = pair.get(1).map_or(0, |b| *b as u8);
                    self.out.push(hi | lo);
                }
            }
            DataCode::Ascii => self
                .out
                .extend(v.iter().map(|b| if *b { b'1' } else { b'0' })),
        }
    }

    pub fn bit_value(&mut self, v: bool) {
        self.u8(v as u8)
    }
}
