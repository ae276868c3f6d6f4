//! Places: a plain device name resolved once to its storage, for callers that
//! read or write the same device every scan (the scenario loop's bindings,
//! expectations and traces) without resolving its name again.

use super::span::Span;
use super::AccessError;
use crate::device::DeviceMemory;

/// Where a plain device name's value lives: a bit, a bit of a word, one or
/// two words (low word first), or the 4·n bits of a digit-specified bit
/// device (`K4M0`), checked against the memory it was resolved in.
/// Read and written as the raw bits [`super::DeviceSpec::raw`] reads;
/// found by [`super::DeviceSpec::place`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Place {
    span: Span,
    shape: Shape,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Shape {
    Bit,
    WordBit(u8),
    /// The span's words (1 or 2).
    Words,
    /// The span's bits (4 to 32), the lowest device number in bit 0.
    Digits,
}

impl Place {
    pub(super) fn new(span: Span, shape: Shape) -> Place {
        Place { span, shape }
    }

    /// The points it covers: the bit, the word holding the bit, or the words.
    pub fn span(&self) -> &Span {
        &self.span
    }

    /// A bit device's point (not a bit of a word).
    pub fn is_bit(&self) -> bool {
        self.shape == Shape::Bit
    }

    /// A digit-specified name's bits (`K4M0`).
    pub fn is_digits(&self) -> bool {
        self.shape == Shape::Digits
    }

    /// The bit of a word (`D0.3` is 3).
    pub fn word_bit(&self) -> Option<u8> {
        match self.shape {
            Shape::WordBit(b) => Some(b),
            _ => None,
        }
    }
}

impl DeviceMemory {
    /// The raw bits at `p`, as [`super::DeviceSpec::raw`] reads its name: a bit as
    /// 0/1, words low word first. A place from another configuration is an
    /// error, never a panic.
    #[inline]
    pub fn read_place(&self, p: &Place) -> Result<u64, AccessError> {
        let start = p.span.start();
        match p.shape {
            Shape::Bit => match self.bits.get(start) {
                Some(&b) => Ok(b as u64),
                None => Err(foreign(p)),
            },
            Shape::WordBit(b) => match self.words.get(start) {
                Some(&w) => Ok((w >> b & 1) as u64),
                None => Err(foreign(p)),
            },
            Shape::Words => match self.words.get(start..start + p.span.len() as usize) {
                Some(&[w]) => Ok(w as u64),
                Some(&[lo, hi]) => Ok(lo as u64 | (hi as u64) << 16),
                _ => Err(foreign(p)),
            },
            Shape::Digits => match self.bits.get(start..start + p.span.len() as usize) {
                Some(bits) => Ok(bits
                    .iter()
                    .enumerate()
                    .fold(0, |v, (i, &b)| v | (b as u64) << i)),
                None => Err(foreign(p)),
            },
        }
    }

    /// Writes raw bits to `p` (the lowest bit for a bit, low word first for
    /// words, the lowest 4·n for digits; bits beyond the place are ignored:
    /// whether a value fits the digits is the caller's to check).
    #[inline]
    pub fn write_place(&mut self, p: &Place, raw: u64) -> Result<(), AccessError> {
        let start = p.span.start();
        match p.shape {
            Shape::Bit => match self.bits.get_mut(start) {
                Some(b) => *b = raw & 1 != 0,
                None => return Err(foreign(p)),
            },
            Shape::WordBit(bit) => match self.words.get_mut(start) {
                Some(w) => *w = *w & !(1 << bit) | ((raw & 1) as u16) << bit,
                None => return Err(foreign(p)),
            },
            Shape::Words => match self.words.get_mut(start..start + p.span.len() as usize) {
                Some([w]) => *w = raw as u16,
                Some([lo, hi]) => {
                    *lo = raw as u16;
                    *hi = (raw >> 16) as u16;
                }
                _ => return Err(foreign(p)),
            },
            Shape::Digits => match self.bits.get_mut(start..start + p.span.len() as usize) {
                Some(bits) => {
                    for (i, b) in bits.iter_mut().enumerate() {
                        *b = raw >> i & 1 != 0;
                    }
                }
                None => return Err(foreign(p)),
            },
        }
        Ok(())
    }
}

/// A place resolved in a memory of another configuration.
#[cold]
fn foreign(p: &Place) -> AccessError {
    super::span::foreign(&p.span)
}
