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

/// An ASCII device number at byte `offset`: hex or decimal digits as the
/// device numbers them.
fn ascii_number(device: Device, digits: &[u8], offset: usize) -> Result<u32, BodyError> {
    let number = if device.is_hex() {
        parse_hex(digits)
    } else {
        digits.iter().try_fold(0u32, |v, c| {
            c.is_ascii_digit().then(|| v * 10 + (c - b'0') as u32)
        })
    };
    number.ok_or(BodyError {
        end_code: EndCode::ASCII_DATA,
        offset,
        what: "device number is not a number in the device's numbering",
    })
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
    /// Devices come in the device extension specification (subcommands
    /// 0080/0081).
    extended: bool,
}

impl<'a> Reader<'a> {
    pub fn new(buf: &'a [u8], base: usize, code: DataCode) -> Self {
        Reader {
            buf,
            pos: 0,
            base,
            code,
            extended: false,
        }
    }

    /// Reads the following devices in the device extension specification.
    pub fn set_extended(&mut self, extended: bool) {
        self.extended = extended;
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
    /// In an extended request, the device extension specification
    /// ([`Self::extended_device`]).
    pub fn device(&mut self) -> BodyResult<DeviceRef> {
        if self.extended {
            return self.extended_device();
        }
        self.plain_device()
    }

    fn plain_device(&mut self) -> BodyResult<DeviceRef> {
        match self.code {
            DataCode::Binary => {
                let s = self.take(4, "device")?;
                let number = s[0] as u32 | (s[1] as u32) << 8 | (s[2] as u32) << 16;
                let device = Device::from_binary(s[3]).ok_or(BodyError {
                    end_code: EndCode::DEVICE,
                    offset: self.offset() - 1,
                    what: "unknown device code",
                })?;
                Ok(DeviceRef::new(device, number))
            }
            DataCode::Ascii => {
                let at = self.offset();
                let s = self.take(8, "device")?;
                let device = Device::from_ascii([s[0], s[1]]).ok_or(BodyError {
                    end_code: EndCode::DEVICE,
                    offset: at,
                    what: "unknown device code",
                })?;
                let number = ascii_number(device, &s[2..], at + 2)?;
                Ok(DeviceRef::new(device, number))
            }
        }
    }

    /// A device in the device extension specification of the Q/L format
    /// (SLMP Reference Manual SH-080956ENG, Appendix 1 "Read/Write by Device
    /// Extension Specification"):
    ///
    /// | binary (11 bytes) | ASCII (20 characters) |
    /// |---|---|
    /// | device modification (2) | `00` (2) |
    /// | device number (3) | extension specification: `U` + unit (3 hex), or `0000` (4) |
    /// | device code (1) | extension specification modification `000` (3) |
    /// | extension specification modification (2) | device code (2) |
    /// | extension specification: the unit, or 0 (2) | device number (6) |
    /// | direct memory specification: `F8` module access, `00` (1) | device modification `000` (3) |
    ///
    /// `U<unit>\G<n>` is the module access device G (`AB`, `G*`) with the
    /// unit (start I/O number / 16); any other device of the plain
    /// specification is itself with extension 0. Index modification (Z) and
    /// indirect specification are not supported (`C05C`); link direct
    /// devices (`J`, `F9`) and the CPU buffer memory (`FA`) are not devices
    /// of this CPU (`C05B`).
    fn extended_device(&mut self) -> BodyResult<DeviceRef> {
        let at = self.offset();
        let unsupported = |offset| {
            BodyError {
            end_code: EndCode::REQUEST_CONTENTS,
            offset,
            what: "index modification and indirect specification are not supported in the device extension",
        }
        };
        let no_device = |offset, what| BodyError {
            end_code: EndCode::DEVICE,
            offset,
            what,
        };
        let (device, number, unit) = match self.code {
            DataCode::Binary => {
                let s = self.take(11, "device extension specification")?;
                if s[0] != 0 || s[1] != 0 {
                    return Err(unsupported(at));
                }
                if s[6] != 0 || s[7] != 0 {
                    return Err(unsupported(at + 6));
                }
                let number = s[2] as u32 | (s[3] as u32) << 8 | (s[4] as u32) << 16;
                let extension = u16::from_le_bytes([s[8], s[9]]);
                let device = if s[5] == Device::G.binary_code() {
                    Some(Device::G)
                } else {
                    Device::from_binary(s[5])
                };
                let device = device.ok_or(no_device(at + 5, "unknown device code"))?;
                let unit = match (s[10], device) {
                    (0xF8, Device::G) => Some(extension),
                    (0x00, d) if d != Device::G && extension == 0 => None,
                    (0xF9, _) => return Err(no_device(at + 10, "link direct devices (J\\) are not devices of this CPU")),
                    (0xFA, _) => return Err(no_device(at + 10, "the CPU buffer memory is not a device of this CPU")),
                    _ => {
                        return Err(BodyError {
                            end_code: EndCode::REQUEST_CONTENTS,
                            offset: at + 10,
                            what: "the direct memory specification does not match the device (F8 and G for U\\G, 00 and extension 0 otherwise)",
                        })
                    }
                };
                (device, number, unit)
            }
            DataCode::Ascii => {
                let s = self.take(20, "device extension specification")?;
                if &s[..2] != b"00" {
                    return Err(unsupported(at));
                }
                let unit = match s[2] {
                    b'U' | b'u' => Some(parse_hex(&s[3..6]).ok_or(BodyError {
                        end_code: EndCode::ASCII_DATA,
                        offset: at + 3,
                        what: "the unit of U\\G is 3 hexadecimal digits",
                    })? as u16),
                    b'J' | b'j' => {
                        return Err(no_device(
                            at + 2,
                            "link direct devices (J\\) are not devices of this CPU",
                        ))
                    }
                    _ if &s[2..6] == b"0000" => None,
                    _ => return Err(unsupported(at + 2)),
                };
                if &s[6..9] != b"000" {
                    return Err(unsupported(at + 6));
                }
                if &s[17..20] != b"000" {
                    return Err(unsupported(at + 17));
                }
                let code = [s[9], s[10]];
                let device = if matches!(code, [b'G', b'*'] | [b'G', b' ']) {
                    Device::G
                } else {
                    Device::from_ascii(code).ok_or(no_device(at + 9, "unknown device code"))?
                };
                let number = ascii_number(device, &s[11..17], at + 11)?;
                (device, number, unit)
            }
        };
        match (device, unit) {
            (Device::G, None) => Err(no_device(
                at,
                "buffer memory G needs a module: U<unit>\\G<address>",
            )),
            (d, Some(_)) if d != Device::G => Err(BodyError {
                end_code: EndCode::REQUEST_CONTENTS,
                offset: at,
                what: "the extension U<unit> takes the module access device G only",
            }),
            _ => Ok(DeviceRef {
                device,
                number,
                unit,
            }),
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
    /// Devices go in the device extension specification (0080/0081).
    pub extended: bool,
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
        if self.extended {
            return self.extended_device(d);
        }
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

    /// The device extension specification (see [`Reader::extended_device`]).
    fn extended_device(&mut self, d: &DeviceRef) {
        match self.code {
            DataCode::Binary => {
                self.out.extend_from_slice(&[0, 0]);
                self.out
                    .extend_from_slice(&(d.number & 0xFF_FFFF).to_le_bytes()[..3]);
                self.out.push(d.device.binary_code());
                self.out.extend_from_slice(&[0, 0]);
                self.out
                    .extend_from_slice(&d.unit.unwrap_or(0).to_le_bytes());
                self.out.push(if d.unit.is_some() { 0xF8 } else { 0 });
            }
            DataCode::Ascii => {
                let extension = match d.unit {
                    Some(u) => format!("U{:03X}", u & 0xFFF),
                    None => "0000".to_string(),
                };
                let number = if d.device.is_hex() {
                    format!("{:06X}", d.number & 0xFF_FFFF)
                } else {
                    format!("{:06}", d.number % 1_000_000)
                };
                self.out.extend_from_slice(b"00");
                self.out.extend_from_slice(extension.as_bytes());
                self.out.extend_from_slice(b"000");
                self.out.extend_from_slice(&d.device.ascii_code());
                self.out.extend_from_slice(number.as_bytes());
                self.out.extend_from_slice(b"000");
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
