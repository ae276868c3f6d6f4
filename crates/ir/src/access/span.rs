//! Spans: consecutive points of one device kind, range-checked once, read and
//! written as words or bits. The file-register block rule lives here.

use super::AccessError;
use crate::device::{DeviceKind, DeviceMemory, OutOfRange};

/// Points of one file-register block: R0-R32767 (004 §10.7).
pub const R_BLOCK: u32 = 32768;

/// The ZR number of R`n` in file-register block `block`: ZR(32768·block + n)
/// (004 §10.7). The one statement of the rule: program operands on R (through
/// `DeviceMemory`'s indexed operand reads), names and protocol spans use it.
#[inline]
pub const fn r_to_zr(block: u16, n: i64) -> i64 {
    block as i64 * R_BLOCK as i64 + n
}

/// The file-register block the memory's selector word holds (0 without one,
/// see [`crate::device::DeviceMap::set_r_block`]).
pub fn selected_block(mem: &DeviceMemory) -> u16 {
    mem.map.r_block().map_or(0, |w| mem.words[w as usize])
}

/// Which file-register block an R address means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RBlock {
    /// Block 0: R is the window onto ZR0-ZR32767. Device names on the command
    /// line and in scenarios, and the Modbus map's R range.
    First,
    /// The selected block, as a program's R operands: the MC protocol.
    Selected,
}

/// `len` consecutive points of one device kind, checked against the memory it
/// was resolved in. R keeps its name; its points are the ZR points of the
/// block it was resolved for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    kind: DeviceKind,
    number: u32,
    len: u32,
    /// Flat index of the first point in the bit or word array.
    start: usize,
}

impl Span {
    /// The device kind as named (R for a file register in a block).
    pub fn kind(&self) -> DeviceKind {
        self.kind
    }

    /// The first device number as named.
    pub fn number(&self) -> u32 {
        self.number
    }

    /// Points: bits of a bit device, words of a word device.
    pub fn len(&self) -> u32 {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn is_bit(&self) -> bool {
        self.kind.is_bit()
    }

    /// The span's name in errors: `D100` or `D100-D109`.
    pub fn name(&self) -> String {
        name(self.kind, self.number as i64, self.len)
    }

    /// Flat index of the first point in the bit or word array.
    pub(crate) fn start(&self) -> usize {
        self.start
    }

    fn range(&self) -> std::ops::Range<usize> {
        self.start..self.start + self.len as usize
    }
}

fn name(kind: DeviceKind, number: i64, len: u32) -> String {
    let one = |n: i64| match u32::try_from(n) {
        Ok(n) => kind.format(n),
        Err(_) => format!("{kind}{n}"),
    };
    if len <= 1 {
        one(number)
    } else {
        format!("{}-{}", one(number), one(number + len as i64 - 1))
    }
}

/// The first point of `number..number + len` outside `0..points`.
fn first_outside(kind: DeviceKind, number: i64, len: u32, points: u32) -> Option<OutOfRange> {
    (number < 0 || number + len as i64 > points as i64).then(|| OutOfRange {
        kind,
        number: if number < 0 {
            number
        } else {
            number.max(points as i64)
        },
        points,
    })
}

impl DeviceMemory {
    /// Resolves `len` points of `kind` from `number` (R in block `r`).
    pub fn span(
        &self,
        kind: DeviceKind,
        number: u32,
        len: u32,
        r: RBlock,
    ) -> Result<Span, AccessError> {
        self.locate_span(kind, number as i64, len, r)
            .map_err(|source| AccessError::Range {
                device: name(kind, number as i64, len),
                source,
            })
    }

    /// [`Self::span`] with a possibly negative (index-modified) number; the
    /// error is the first point outside.
    pub(crate) fn locate_span(
        &self,
        kind: DeviceKind,
        number: i64,
        len: u32,
        r: RBlock,
    ) -> Result<Span, OutOfRange> {
        if let Some(e) = first_outside(kind, number, len, self.map.points(kind)) {
            return Err(e);
        }
        let start = if kind == DeviceKind::R {
            let block = match r {
                RBlock::First => 0,
                RBlock::Selected => selected_block(self),
            };
            let zr = r_to_zr(block, number);
            let points = self.map.points(DeviceKind::ZR);
            if let Some(e) = first_outside(DeviceKind::ZR, zr, len, points) {
                return Err(e);
            }
            self.map.base(DeviceKind::ZR) as i64 + zr
        } else {
            // FD: a point's first word (points are 4 words apart).
            self.map.base(kind) as i64 + number * kind.words_per_point() as i64
        };
        Ok(Span {
            kind,
            number: number as u32,
            len,
            start: start as usize,
        })
    }

    /// The bits of a bit span. A span from another configuration is an error,
    /// never a panic.
    fn bit_slice(&self, s: &Span) -> Result<&[bool], AccessError> {
        if !s.is_bit() {
            return Err(AccessError::NotBit { device: s.name() });
        }
        self.bits.get(s.range()).ok_or_else(|| foreign(s))
    }

    fn word_slice(&self, s: &Span) -> Result<&[u16], AccessError> {
        self.words.get(s.range()).ok_or_else(|| foreign(s))
    }

    /// Reads a span as words: a word span's words; a bit span packed 16 points
    /// a word, the lowest device number in bit 0 (a short last word has its
    /// high bits 0).
    pub fn read_span_words(&self, s: &Span) -> Result<Vec<u16>, AccessError> {
        if s.is_bit() {
            let bits = self.bit_slice(s)?;
            Ok(bits
                .chunks(16)
                .map(|c| {
                    c.iter()
                        .enumerate()
                        .fold(0u16, |w, (i, &b)| w | (b as u16) << i)
                })
                .collect())
        } else {
            Ok(self.word_slice(s)?.to_vec())
        }
    }

    /// [`Self::read_span_words`] into `out` (its first `ceil(len / 16)`
    /// words for a bit span, `len` for a word span), allocating nothing.
    pub fn read_span_into(&self, s: &Span, out: &mut [u16]) -> Result<(), AccessError> {
        if s.is_bit() {
            let bits = self.bit_slice(s)?;
            let (n, given) = (bits.len().div_ceil(16), out.len() * 16);
            let out = out.get_mut(..n).ok_or_else(|| length(s, given))?;
            for (w, c) in out.iter_mut().zip(bits.chunks(16)) {
                *w = c
                    .iter()
                    .enumerate()
                    .fold(0u16, |w, (i, &b)| w | (b as u16) << i);
            }
        } else {
            let (words, given) = (self.word_slice(s)?, out.len());
            let out = out.get_mut(..words.len()).ok_or_else(|| length(s, given))?;
            out.copy_from_slice(words);
        }
        Ok(())
    }

    /// Reads a bit span (a word span is [`AccessError::NotBit`]).
    pub fn read_span_bits(&self, s: &Span) -> Result<Vec<bool>, AccessError> {
        Ok(self.bit_slice(s)?.to_vec())
    }

    /// Writes a span from words: one word a point of a word span; 16 points a
    /// word of a bit span, bit 0 first. `values` must fill the span exactly.
    pub fn write_span_words(&mut self, s: &Span, values: &[u16]) -> Result<(), AccessError> {
        if s.is_bit() {
            if values.len() * 16 != s.len as usize {
                return Err(length(s, values.len() * 16));
            }
            self.bit_slice(s)?;
            for (chunk, w) in self.bits[s.range()].chunks_mut(16).zip(values) {
                for (i, b) in chunk.iter_mut().enumerate() {
                    *b = w >> i & 1 != 0;
                }
            }
        } else {
            if values.len() != s.len as usize {
                return Err(length(s, values.len()));
            }
            self.word_slice(s)?;
            self.words[s.range()].copy_from_slice(values);
        }
        Ok(())
    }

    /// Writes a bit span; `values` must fill it exactly.
    pub fn write_span_bits(&mut self, s: &Span, values: &[bool]) -> Result<(), AccessError> {
        self.bit_slice(s)?;
        if values.len() != s.len as usize {
            return Err(length(s, values.len()));
        }
        self.bits[s.range()].copy_from_slice(values);
        Ok(())
    }
}

fn length(s: &Span, given: usize) -> AccessError {
    AccessError::Length {
        device: s.name(),
        points: s.len,
        given,
    }
}

/// A span resolved in a memory of another configuration.
pub(super) fn foreign(s: &Span) -> AccessError {
    AccessError::Range {
        device: s.name(),
        source: OutOfRange {
            kind: s.kind,
            number: s.number as i64 + s.len as i64 - 1,
            points: s.number + s.len - 1,
        },
    }
}
