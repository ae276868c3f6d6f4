//! Reading and writing resolved operands. Index-modified operands are bounds
//! checked here: an effective device outside its range is `Fault::Range`, never a panic,
//! except file registers wholly outside the registered range, which the CPU
//! reads and writes with no error (004 §10.7.5 (1)).

use crate::access::r_to_zr;
use crate::device::DeviceMemory;
use crate::fault::Fault;
use crate::ops::{BitArg, BitBlock, Block, Indexed, IndexedKind, Window, WordArg};

impl DeviceMemory {
    /// Flat index of an index-modified operand spanning `span` points.
    #[inline]
    fn indexed(&self, ix: &Indexed, span: u32) -> Result<usize, Fault> {
        let z = match ix.z {
            Indexed::NONE => 0,
            z => self.words[z as usize] as i16 as i64,
        };
        // R: the block the selector word holds.
        let block = match ix.window {
            Window::Device | Window::FileRegister => 0,
            Window::SelectedBlock => crate::access::selected_block(self),
            Window::NoModule => return Err(Fault::NoModule),
            Window::Refused(f) => return Err(f),
        };
        let n = r_to_zr(block, ix.number as i64 + z);
        if n < 0 || n + span as i64 > ix.points as i64 {
            return self.outside(ix, n, span);
        }
        Ok((ix.base as i64 + n) as usize)
    }

    /// An effective device past its range. File registers (R, ZR) wholly
    /// outside the registered range are no error: they read 0 and writes
    /// are ignored (004 §10.7.5 (1), L7180-7194). Anything else, and an
    /// operand that starts inside the file registers and runs past their
    /// end (one access softplc cannot split), is `Fault::Range`.
    #[cold]
    fn outside(&self, ix: &Indexed, n: i64, span: u32) -> Result<usize, Fault> {
        let file_register = matches!(ix.window, Window::SelectedBlock | Window::FileRegister);
        if file_register && n >= ix.points as i64 {
            return self.outside_file_registers(span);
        }
        Err(Fault::Range)
    }

    fn indexed_words(&self, ix: &Indexed, words: u32) -> Result<usize, Fault> {
        let span = match ix.kind {
            IndexedKind::Digits(n) => 4 * n as u32,
            IndexedKind::Word => words,
            IndexedKind::Bit | IndexedKind::WordBit(_) => 1,
        };
        self.indexed(ix, span)
    }

    /// Flat word index of the first of `n` words of a block operand; a block that
    /// would run past the last point of its device is `Fault::Range`.
    pub fn block_start(&self, b: &Block, n: u32) -> Result<usize, Fault> {
        match &b.start {
            WordArg::Word(i) if *i as u64 + n as u64 <= b.limit as u64 => Ok(*i as usize),
            WordArg::Indexed(ix) => self.indexed(ix, n),
            _ => Err(Fault::Range),
        }
    }

    /// Flat bit index of the first of `n` bits of a bit block (`Fault::Range` past the end).
    pub fn bit_block_start(&self, b: &BitBlock, n: u32) -> Result<usize, Fault> {
        match &b.start {
            BitArg::Bit(i) if *i as u64 + n as u64 <= b.limit as u64 => Ok(*i as usize),
            BitArg::Indexed(ix) => self.indexed(ix, n),
            _ => Err(Fault::Range),
        }
    }

    /// Reads a 16-bit operand. Plain words and constants inline at the call;
    /// the rest out of line, so the common case costs no call.
    #[inline(always)]
    pub fn read16(&self, a: &WordArg) -> Result<u16, Fault> {
        match a {
            WordArg::Word(i) => Ok(self.words[*i as usize]),
            WordArg::Const(k) => Ok(*k as u16),
            _ => self.read16_general(a),
        }
    }

    #[inline(never)]
    fn read16_general(&self, a: &WordArg) -> Result<u16, Fault> {
        Ok(match a {
            WordArg::Word(i) => self.words[*i as usize],
            WordArg::Const(k) => *k as u16,
            WordArg::Digits { bit, n } => self.pack_bits(*bit as usize, 4 * *n as usize) as u16,
            WordArg::Indexed(ix) => {
                let i = self.indexed_words(ix, 1)?;
                match ix.kind {
                    IndexedKind::Digits(n) => self.pack_bits(i, 4 * n as usize) as u16,
                    _ => self.words[i],
                }
            }
        })
    }

    /// Reads a 32-bit operand (low word first).
    #[inline]
    pub fn read32(&self, a: &WordArg) -> Result<u32, Fault> {
        Ok(match a {
            WordArg::Word(i) => {
                let i = *i as usize;
                self.words[i] as u32 | (self.words[i + 1] as u32) << 16
            }
            WordArg::Const(k) => *k,
            WordArg::Digits { bit, n } => self.pack_bits(*bit as usize, 4 * *n as usize),
            WordArg::Indexed(ix) => {
                let i = self.indexed_words(ix, 2)?;
                match ix.kind {
                    IndexedKind::Digits(n) => self.pack_bits(i, 4 * n as usize),
                    _ => self.words[i] as u32 | (self.words[i + 1] as u32) << 16,
                }
            }
        })
    }

    /// Reads a real operand: ±∞ and NaN are not real numbers for the CPU (004 §2.8)
    /// and give `Fault::Operation`; denormals read as 0.
    #[inline]
    pub fn read_f32(&self, a: &WordArg) -> Result<f32, Fault> {
        let bits = self.read32(a)?;
        let exp = (bits >> 23) & 0xFF;
        match exp {
            0xFF => Err(Fault::Operation),
            0 => Ok(0.0),
            _ => Ok(f32::from_bits(bits)),
        }
    }

    /// Writes a 16-bit operand; a digit-specified destination takes the low 4·n
    /// bits. A plain word inline at the call, the rest out of line.
    #[inline(always)]
    pub fn write16(&mut self, a: &WordArg, v: u16) -> Result<(), Fault> {
        match a {
            WordArg::Word(i) => {
                self.words[*i as usize] = v;
                Ok(())
            }
            _ => self.write16_general(a, v),
        }
    }

    #[inline(never)]
    fn write16_general(&mut self, a: &WordArg, v: u16) -> Result<(), Fault> {
        match a {
            WordArg::Word(i) => self.words[*i as usize] = v,
            WordArg::Const(_) => {}
            WordArg::Digits { bit, n } => {
                self.unpack_bits(*bit as usize, 4 * *n as usize, v as u32)
            }
            WordArg::Indexed(ix) => {
                let i = self.indexed_words(ix, 1)?;
                match ix.kind {
                    IndexedKind::Digits(n) => self.unpack_bits(i, 4 * n as usize, v as u32),
                    _ => self.words[i] = v,
                }
            }
        }
        Ok(())
    }

    /// Writes a 32-bit operand (low word first).
    #[inline]
    pub fn write32(&mut self, a: &WordArg, v: u32) -> Result<(), Fault> {
        match a {
            WordArg::Word(i) => {
                let i = *i as usize;
                self.words[i] = v as u16;
                self.words[i + 1] = (v >> 16) as u16;
            }
            WordArg::Const(_) => {}
            WordArg::Digits { bit, n } => self.unpack_bits(*bit as usize, 4 * *n as usize, v),
            WordArg::Indexed(ix) => {
                let i = self.indexed_words(ix, 2)?;
                match ix.kind {
                    IndexedKind::Digits(n) => self.unpack_bits(i, 4 * n as usize, v),
                    _ => {
                        self.words[i] = v as u16;
                        self.words[i + 1] = (v >> 16) as u16;
                    }
                }
            }
        }
        Ok(())
    }

    /// Writes `n` words (n = 1..4) from the low end of `v`; the destination of the
    /// 16- and 32-bit `*` and `/` results. A digit-specified destination gets the
    /// low 32 bits (K1-K8).
    pub fn write_words(&mut self, a: &WordArg, v: u64, n: u32) -> Result<(), Fault> {
        let base = match a {
            WordArg::Word(i) => *i as usize,
            WordArg::Indexed(ix) if ix.kind == IndexedKind::Word => self.indexed_words(ix, n)?,
            _ => return self.write32(a, v as u32),
        };
        for k in 0..n as usize {
            self.words[base + k] = (v >> (16 * k)) as u16;
        }
        Ok(())
    }

    /// Writes a real result: overflow (±∞, NaN) is `Fault::Operation`; underflow becomes 0.
    #[inline]
    pub fn write_f32(&mut self, a: &WordArg, v: f32) -> Result<(), Fault> {
        if !v.is_finite() {
            return Err(Fault::Operation);
        }
        let v = if v.abs() < f32::MIN_POSITIVE { 0.0 } else { v };
        self.write32(a, v.to_bits())
    }

    #[inline]
    pub fn read_bit(&self, a: &BitArg) -> Result<bool, Fault> {
        Ok(match a {
            BitArg::Bit(i) => self.bits[*i as usize],
            BitArg::WordBit { word, bit } => self.words[*word as usize] >> bit & 1 != 0,
            BitArg::Indexed(ix) => {
                let i = self.indexed(ix, 1)?;
                match ix.kind {
                    IndexedKind::WordBit(b) => self.words[i] >> b & 1 != 0,
                    _ => self.bits[i],
                }
            }
        })
    }

    #[inline]
    pub fn write_bit(&mut self, a: &BitArg, v: bool) -> Result<(), Fault> {
        let set = |w: &mut u16, b: u8| {
            if v {
                *w |= 1 << b
            } else {
                *w &= !(1 << b)
            }
        };
        match a {
            BitArg::Bit(i) => self.bits[*i as usize] = v,
            BitArg::WordBit { word, bit } => set(&mut self.words[*word as usize], *bit),
            BitArg::Indexed(ix) => {
                let i = self.indexed(ix, 1)?;
                match ix.kind {
                    IndexedKind::WordBit(b) => set(&mut self.words[i], b),
                    _ => self.bits[i] = v,
                }
            }
        }
        Ok(())
    }
}
