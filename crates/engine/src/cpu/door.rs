//! The door for writers outside the scan (CLI, simulator, MC, Modbus): device
//! names, spans and typed values through `softplc_ir::access`, with the input
//! image kept: a write to X survives the next input refresh, as an input
//! module's signal would.

use super::*;
use softplc_ir::access::{AccessError, DeviceSpec, Place, RBlock, Span, Value};
use softplc_ir::device::OutOfRange;

impl Cpu {
    /// Reads a device by name (`D10:f32`, `K4M0`, `TN0`).
    pub fn read_device(&self, spec: &DeviceSpec) -> Result<Value, String> {
        spec.read(&self.rt.mem)
    }

    /// Writes a device by name from text (`--set D0=H1F`). Writes to X go to the
    /// input image as well, so the value survives the next input refresh.
    pub fn write_device(&mut self, spec: &DeviceSpec, value: &str) -> Result<(), String> {
        spec.write(&mut self.rt.mem, value)?;
        self.mirror_spec(spec);
        self.force_spec(spec);
        self.note(DoorEvent::Text { spec, value });
        Ok(())
    }

    /// Writes a typed value to a device by name ([`DeviceSpec::write_value`]);
    /// X goes to the input image as well.
    pub fn write_value(&mut self, spec: &DeviceSpec, value: &Value) -> Result<(), AccessError> {
        spec.write_value(&mut self.rt.mem, value)?;
        self.mirror_spec(spec);
        self.force_spec(spec);
        self.note(DoorEvent::Value { spec, value });
        Ok(())
    }

    /// Reads the raw bits at a place resolved once ([`DeviceSpec::place`]),
    /// as [`DeviceSpec::raw`] reads its name, without resolving it again.
    #[inline]
    pub fn read_place(&self, p: &Place) -> Result<u64, AccessError> {
        self.rt.mem.read_place(p)
    }

    /// Writes raw bits to a place resolved once, as [`Self::write_value`]
    /// writes the same value by name (whether a value fits a digit-specified
    /// name's digits is the caller's to check): X goes to the input image as
    /// well, a forced point keeps its forced value, and the journal is told
    /// the point write it is (bits, or words of R in block 0).
    #[inline]
    pub fn write_place(&mut self, p: &Place, raw: u64) -> Result<(), AccessError> {
        self.rt.mem.write_place(p, raw)?;
        let s = *p.span();
        if s.is_bit() {
            self.mirror(s.kind(), s.number(), s.len());
            if !self.rt.forces.is_empty() {
                self.force_written(Some((s.kind(), s.number(), s.len())));
            }
        } else if !self.rt.forces.is_empty() {
            self.force_written(None);
        }
        if self.has_journal() {
            self.note_place(p, raw);
        }
        Ok(())
    }

    /// Tells the journal a write to `p` as the point write that replays it:
    /// a bit or the digits' bits, else the place's words as they now are (a
    /// bit of a word carries its word).
    #[cold]
    fn note_place(&mut self, p: &Place, raw: u64) {
        let s = *p.span();
        let (kind, number) = (s.kind(), s.number());
        if p.is_bit() {
            self.note(DoorEvent::Bit {
                kind,
                n: number as i64,
                value: raw & 1 != 0,
            });
            return;
        }
        if p.is_digits() {
            let mut bits = [false; 32];
            let len = (s.len() as usize).min(bits.len());
            for (i, b) in bits[..len].iter_mut().enumerate() {
                *b = raw >> i & 1 != 0;
            }
            self.note(DoorEvent::Bits {
                kind,
                number,
                block: RBlock::First,
                values: &bits[..len],
            });
            return;
        }
        let mut words = [0u16; 2];
        let len = (s.len() as usize).min(words.len());
        if self.rt.mem.read_span_into(&s, &mut words[..len]).is_ok() {
            self.note(DoorEvent::Words {
                kind,
                number,
                len: s.len(),
                block: RBlock::First,
                values: &words[..len],
            });
        }
    }

    /// Resolves `len` points of `kind` from `number`, R in block `r`.
    pub fn span(
        &self,
        kind: DeviceKind,
        number: u32,
        len: u32,
        r: RBlock,
    ) -> Result<Span, AccessError> {
        self.rt.mem.span(kind, number, len, r)
    }

    /// Writes a span from words (16 points a word for a bit span); X goes to
    /// the input image as well.
    pub fn write_span_words(&mut self, s: &Span, values: &[u16]) -> Result<(), AccessError> {
        self.rt.mem.write_span_words(s, values)?;
        self.mirror(s.kind(), s.number(), s.len());
        if !self.rt.forces.is_empty() {
            self.force_written(Some((s.kind(), s.number(), s.len())));
        }
        if self.has_journal() {
            let (kind, number, len, block) = (s.kind(), s.number(), s.len(), self.block_of(s));
            self.note(DoorEvent::Words {
                kind,
                number,
                len,
                block,
                values,
            });
        }
        Ok(())
    }

    /// Writes a bit span; X goes to the input image as well.
    pub fn write_span_bits(&mut self, s: &Span, values: &[bool]) -> Result<(), AccessError> {
        self.rt.mem.write_span_bits(s, values)?;
        self.mirror(s.kind(), s.number(), s.len());
        if !self.rt.forces.is_empty() {
            self.force_written(Some((s.kind(), s.number(), s.len())));
        }
        if self.has_journal() {
            let (kind, number, block) = (s.kind(), s.number(), self.block_of(s));
            self.note(DoorEvent::Bits {
                kind,
                number,
                block,
                values,
            });
        }
        Ok(())
    }

    /// Writes word `n` of `kind` (a tool's or a test's point write; R is
    /// block 0's, as in names).
    pub fn set_word(&mut self, kind: DeviceKind, n: i64, v: u16) -> Result<(), OutOfRange> {
        self.rt.mem.set_word(kind, n, v)?;
        self.note(DoorEvent::Word { kind, n, value: v });
        Ok(())
    }

    /// Writes bit `n` of `kind`; X goes to the input image as well and a
    /// forced point keeps its forced value.
    pub fn set_bit(&mut self, kind: DeviceKind, n: i64, v: bool) -> Result<(), OutOfRange> {
        self.rt.mem.set_bit(kind, n, v)?;
        // In range: the write above checked `n`.
        let n = n as u32;
        self.mirror(kind, n, 1);
        if !self.rt.forces.is_empty() {
            self.force_written(Some((kind, n, 1)));
        }
        self.note(DoorEvent::Bit {
            kind,
            n: n as i64,
            value: v,
        });
        Ok(())
    }

    /// Sets input X`n` as an input module would: it reaches X at the next input
    /// refresh and stays until set again.
    pub fn set_input(&mut self, n: u32, on: bool) {
        if let Some(b) = self.rt.inputs.get_mut(n as usize) {
            let was = std::mem::replace(b, on);
            self.input_changed(n, was, on);
        }
        let _ = self.rt.mem.set_bit(DeviceKind::X, n as i64, on);
        if !self.rt.forces.is_empty() {
            self.force_written(Some((DeviceKind::X, n, 1)));
        }
        self.note(DoorEvent::Input { n, on });
    }

    /// The input image's X`n`: what the input module presents (OFF past
    /// the last X).
    pub fn input(&self, n: u32) -> bool {
        self.rt.inputs.get(n as usize).copied().unwrap_or(false)
    }

    /// The file-register block span `s` was resolved in (block 0 unless it
    /// is an R span resolved in another selected block).
    fn block_of(&self, s: &Span) -> RBlock {
        let first = self
            .rt
            .mem
            .span(s.kind(), s.number(), s.len(), RBlock::First);
        match first {
            Ok(f) if f == *s => RBlock::First,
            _ => RBlock::Selected,
        }
    }

    /// Forced values win over a write by name (see [`super::force`]).
    fn force_spec(&mut self, spec: &DeviceSpec) {
        if !self.rt.forces.is_empty() {
            self.force_written(spec.bit_span());
        }
    }

    /// Copies X written by name into the input image (bit and digit-specified
    /// names without index modification, as before the door).
    fn mirror_spec(&mut self, spec: &DeviceSpec) {
        if let Some((kind, first, count)) = spec.bit_span() {
            self.mirror(kind, first, count);
        }
    }

    /// Copies X`first`..X`first + count` from device memory into the input image.
    fn mirror(&mut self, kind: DeviceKind, first: u32, count: u32) {
        if kind != DeviceKind::X {
            return;
        }
        for n in first..first + count {
            if let (Some(b), Ok(v)) = (
                self.rt.inputs.get_mut(n as usize),
                self.rt.mem.get_bit(DeviceKind::X, n as i64),
            ) {
                let was = *b;
                *b = v;
                self.input_changed(n, was, v);
            }
        }
    }
}

/// X`n`'s bit in [`Cpu`]'s records of changed inputs (X0-X63; 0 beyond).
fn input_bit(n: u32) -> u64 {
    1u64.checked_shl(n).unwrap_or(0)
}

impl Cpu {
    /// Records a change of the input image's X`n` (the pulse catch and the
    /// edge interrupts of the scan to come see it even if it is undone).
    fn input_changed(&mut self, n: u32, was: bool, is: bool) {
        match (was, is) {
            (false, true) => self.input_rises |= input_bit(n),
            (true, false) => self.input_falls |= input_bit(n),
            _ => {}
        }
    }
}
