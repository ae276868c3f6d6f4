//! 32-bit and REAL values of the APLC: the HIGH word in the first
//! (lower-numbered) register (L1771, L2048), on top of the low-word-first
//! access of `softplc_ir`. A bit group holds its value bit by bit, without
//! word order. Execution error codes (Appendix 6, L11239-11289).

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::ops::{IndexedKind, WordArg};

/// 64: illegal operand value.
pub const E_VALUE: Fault = Fault::Operation;
/// 65: operand device number out of range.
pub const E_RANGE: Fault = Fault::Range;
/// 69: divide by zero.
pub const E_DIV0: Fault = Fault::Family(ErrorCode(69));
/// 73: special module address invalid.
pub const E_MODULE: Fault = Fault::Family(ErrorCode(73));

fn is_pair(a: &WordArg) -> bool {
    match a {
        WordArg::Word(_) => true,
        WordArg::Indexed(ix) => ix.kind == IndexedKind::Word,
        _ => false,
    }
}

#[inline]
pub fn read32(mem: &DeviceMemory, a: &WordArg) -> Result<u32, Fault> {
    let v = mem.read32(a)?;
    Ok(if is_pair(a) { v.rotate_left(16) } else { v })
}

#[inline]
pub fn write32(mem: &mut DeviceMemory, a: &WordArg, v: u32) -> Result<(), Fault> {
    mem.write32(a, if is_pair(a) { v.rotate_left(16) } else { v })
}

/// A REAL operand; NaN and infinities are an illegal value (64).
#[inline]
pub fn read_real(mem: &DeviceMemory, a: &WordArg) -> Result<f32, Fault> {
    let f = f32::from_bits(read32(mem, a)?);
    if f.is_finite() {
        Ok(f)
    } else {
        Err(E_VALUE)
    }
}

#[inline]
pub fn read16(mem: &DeviceMemory, a: &WordArg) -> Result<i16, Fault> {
    Ok(mem.read16(a)? as i16)
}
