//! Basic instructions: comparison contacts, BIN and real arithmetic, conversion
//! and transfer (programming manual ch. 6). Real numbers follow 004 §2.8: the CPU
//! has no ±∞/NaN, so such inputs or results are operation errors.

use crate::device::DeviceMemory;
use crate::fault::Fault;
use crate::instr::{ExecCtx, Instr};
use crate::ops::{ArithOp, CmpOp, Compare, Num, WordArg};
use crate::word_op::{Binary, WordOp};

/// Evaluates a comparison contact (`LD=`, `ANDD>`, `ORE<=` …); signed compare for
/// BIN, IEEE compare for real.
#[inline]
pub fn compare(mem: &DeviceMemory, c: &Compare) -> Result<bool, Fault> {
    use std::cmp::Ordering;
    let ord = match c.num {
        Num::I16 => (mem.read16(&c.a)? as i16).cmp(&(mem.read16(&c.b)? as i16)),
        Num::I32 => (mem.read32(&c.a)? as i32).cmp(&(mem.read32(&c.b)? as i32)),
        Num::F32 => {
            let (a, b) = (mem.read_f32(&c.a)?, mem.read_f32(&c.b)?);
            a.partial_cmp(&b).unwrap_or(Ordering::Equal)
        }
    };
    Ok(test(c.op, ord))
}

/// Whether `ord` satisfies the comparison operator.
#[inline]
pub fn test(op: CmpOp, ord: std::cmp::Ordering) -> bool {
    match op {
        CmpOp::Eq => ord.is_eq(),
        CmpOp::Ne => ord.is_ne(),
        CmpOp::Gt => ord.is_gt(),
        CmpOp::Le => ord.is_le(),
        CmpOp::Lt => ord.is_lt(),
        CmpOp::Ge => ord.is_ge(),
    }
}

/// MOV / DMOV / EMOV (PM §6.4) on general operands (digits, index
/// modification, file registers); plain words are the inline `Op::MovK`,
/// `Op::MovW`, `Op::MovD`, `Op::MovDK`. EMOV copies the two words unchanged.
#[derive(Debug)]
pub struct Move {
    /// 1 or 2.
    pub words: u8,
    pub s: WordArg,
    pub d: WordArg,
}

impl Instr for Move {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        if self.words == 1 {
            let v = cx.mem.read16(&self.s)?;
            cx.mem.write16(&self.d, v)
        } else {
            let v = cx.mem.read32(&self.s)?;
            cx.mem.write32(&self.d, v)
        }
    }
}

/// `+ - * /` and their D and E forms (PM §6.2-6.3): see [`arith`].
#[derive(Debug)]
pub struct Arith {
    pub op: ArithOp,
    pub num: Num,
    pub s1: WordArg,
    pub s2: WordArg,
    pub d: WordArg,
}

impl Instr for Arith {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        arith(cx.mem, self.op, self.num, &self.s1, &self.s2, &self.d)
    }

    fn word_op(&self) -> Option<WordOp<'_>> {
        let op = match self.op {
            ArithOp::Add => Binary::Add,
            ArithOp::Sub => Binary::Sub,
            ArithOp::Mul | ArithOp::Div => return None,
        };
        let wide = match self.num {
            Num::I16 => false,
            Num::I32 => true,
            Num::F32 => return None,
        };
        Some(WordOp::Binary {
            op,
            wide,
            s1: &self.s1,
            s2: &self.s2,
            d: &self.d,
        })
    }
}

/// INC/DEC/DINC/DDEC (PM §6.3.5): they wrap, 32767 + 1 = -32768 (at 32 bits
/// likewise).
#[derive(Debug)]
pub struct Step {
    pub num: Num,
    pub delta: i32,
    pub d: WordArg,
    /// `delta` as a constant operand (for [`Instr::word_op`]).
    pub delta_arg: WordArg,
}

impl Step {
    pub fn new(num: Num, delta: i32, d: WordArg) -> Step {
        Step {
            num,
            delta,
            d,
            delta_arg: WordArg::Const(delta as u32),
        }
    }
}

impl Instr for Step {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        if self.num == Num::I16 {
            let v = (mem.read16(&self.d)? as i16).wrapping_add(self.delta as i16);
            mem.write16(&self.d, v as u16)
        } else {
            let v = (mem.read32(&self.d)? as i32).wrapping_add(self.delta);
            mem.write32(&self.d, v as u32)
        }
    }

    fn word_op(&self) -> Option<WordOp<'_>> {
        Some(WordOp::Binary {
            op: Binary::Add,
            wide: match self.num {
                Num::I16 => false,
                Num::I32 => true,
                Num::F32 => return None,
            },
            s1: &self.d,
            s2: &self.delta_arg,
            d: &self.d,
        })
    }
}

/// FLT / DFLT (PM §6.4): BIN to real.
#[derive(Debug)]
pub struct Flt {
    pub num: Num,
    pub s: WordArg,
    pub d: WordArg,
}

impl Instr for Flt {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let v = match self.num {
            Num::I16 => mem.read16(&self.s)? as i16 as f32,
            _ => mem.read32(&self.s)? as i32 as f32,
        };
        mem.write_f32(&self.d, v)
    }
}

/// INT / DINT (PM §6.4): real to BIN, rounded half away from zero (the CPU
/// rounds the first decimal place); outside the BIN range is an operation
/// error.
#[derive(Debug)]
pub struct Int {
    pub num: Num,
    pub s: WordArg,
    pub d: WordArg,
}

impl Instr for Int {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let v = (mem.read_f32(&self.s)? as f64).round();
        match self.num {
            Num::I16 if (-32768.0..=32767.0).contains(&v) => mem.write16(&self.d, v as i16 as u16),
            Num::I32 if (i32::MIN as f64..=i32::MAX as f64).contains(&v) => {
                mem.write32(&self.d, v as i32 as u32)
            }
            _ => Err(Fault::Operation),
        }
    }
}

/// `+ - * /` in BIN 16, BIN 32 and real. BIN add/subtract wrap (no error, as the
/// CPU); `*` gives a double-width product; `/` gives quotient and remainder, the
/// remainder taking the sign of the dividend; division by 0 is an operation error. With a
/// digit-specified destination `*` stores the low 32 bits of the product (K1-K8)
/// and `/` only the quotient, without the remainder.
fn arith(
    mem: &mut DeviceMemory,
    op: ArithOp,
    num: Num,
    s1: &WordArg,
    s2: &WordArg,
    d: &WordArg,
) -> Result<(), Fault> {
    match num {
        Num::I16 => {
            let (a, b) = (mem.read16(s1)? as i16, mem.read16(s2)? as i16);
            match op {
                ArithOp::Add => mem.write16(d, a.wrapping_add(b) as u16),
                ArithOp::Sub => mem.write16(d, a.wrapping_sub(b) as u16),
                ArithOp::Mul => mem.write_words(d, (a as i32 * b as i32) as u32 as u64, 2),
                ArithOp::Div => {
                    if b == 0 {
                        return Err(Fault::Operation);
                    }
                    let (q, r) = (a.wrapping_div(b), a.wrapping_rem(b));
                    if is_digits(d) {
                        return mem.write32(d, q as i32 as u32);
                    }
                    mem.write_words(d, (q as u16 as u64) | ((r as u16 as u64) << 16), 2)
                }
            }
        }
        Num::I32 => {
            let (a, b) = (mem.read32(s1)? as i32, mem.read32(s2)? as i32);
            match op {
                ArithOp::Add => mem.write32(d, a.wrapping_add(b) as u32),
                ArithOp::Sub => mem.write32(d, a.wrapping_sub(b) as u32),
                ArithOp::Mul => mem.write_words(d, (a as i64 * b as i64) as u64, 4),
                ArithOp::Div => {
                    if b == 0 {
                        return Err(Fault::Operation);
                    }
                    let (q, r) = (a.wrapping_div(b), a.wrapping_rem(b));
                    if is_digits(d) {
                        return mem.write32(d, q as u32);
                    }
                    mem.write_words(d, (q as u32 as u64) | ((r as u32 as u64) << 32), 4)
                }
            }
        }
        Num::F32 => {
            let (a, b) = (mem.read_f32(s1)?, mem.read_f32(s2)?);
            let v = match op {
                ArithOp::Add => a + b,
                ArithOp::Sub => a - b,
                ArithOp::Mul => a * b,
                ArithOp::Div if b == 0.0 => return Err(Fault::Operation),
                ArithOp::Div => a / b,
            };
            mem.write_f32(d, v)
        }
    }
}

fn is_digits(d: &WordArg) -> bool {
    match d {
        WordArg::Digits { .. } => true,
        WordArg::Indexed(ix) => matches!(ix.kind, crate::ops::IndexedKind::Digits(_)),
        _ => false,
    }
}
