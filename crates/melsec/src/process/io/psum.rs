//! S.PSUM, pulse integration.

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;

use crate::process::common::{area, Area, PcError, Sys};
use crate::process::settings::ProcessSettings;
use crate::process::tag::LOOP_WORDS;
use crate::{Args, ExecCtx, Instr};

softplc_ir::layout! {
    /// The loop tag as S.PSUM uses it (000 §8.7 L6700-6720).
    pub struct PsumTag[128] {
        /// Integral value, integer part (BIN32).
        sum1: i32 @ 10,
        /// Integral value, fraction part (BIN32, in units of 1/U).
        sum2: i32 @ 12,
        /// Past values: the last input E1n-1 (BIN32; this loop has no ALM2).
        last: u32 @ 116,
    }
}

softplc_ir::layout! {
    /// The input data (S1) of S.PSUM.
    pub struct PsumInput[3] {
        /// E1: the link-counter value (BIN32).
        e1: u32 @ 0,
        /// e1 = b0: integration start; e2 = b1: integration hold.
        ctl: u16 @ 2,
    }
}

softplc_ir::layout! {
    /// The block memory (D1) of S.PSUM.
    pub struct PsumBlock[4] {
        /// BW1: the integral value, integer part (BIN32).
        bw1: i32 @ 0,
        /// BW2: the integral value, fraction part (BIN32, in units of 1/U).
        bw2: i32 @ 2,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.PSUM.
    pub struct PsumConsts[5] {
        /// W: the weight per pulse (1 … 999).
        weight: i16 @ 0,
        /// U: the unit (1, 10, 100, 1000).
        unit: i16 @ 1,
        /// HILMT: the integration limit (1 … 2147483647).
        hilmt: i32 @ 2,
        /// SUMPTN: 0 reset to 0 over HILMT, 1 hold at HILMT.
        sumptn: u16 @ 4,
    }
}

/// S.PSUM's D2 as its loop memory.
pub static PSUM_TAG: softplc_ir::listing::LoopMemory = softplc_ir::listing::LoopMemory {
    name: "S.PSUM loop tag",
    fields: PsumTag::FIELDS,
    first: 0,
    stride: 0,
    count: None,
    settings: None,
};

/// 000 §8.7 S.PSUM `S.PSUM S1 D1 S2 D2` (L6424-6774), pulse integration.
///
/// Operands: S1 +0/+1 E1 (BIN32 link-counter value), +2 e1 = b0
/// integration start, e2 = b1 integration hold; D1 +0/+1 BW1 integer part,
/// +2/+3 BW2 fraction part (BIN32); S2 +0 W weight per pulse (1 … 999), +1
/// U unit (1, 10, 100, 1000), +2/+3 HILMT (1 … 2147483647), +4 SUMPTN (0:
/// reset to 0 over HILMT, 1: hold at HILMT); D2 +10 SUM1, +12 SUM2
/// (BIN32), +116/+117 E1n-1.
///
/// Processing: (1) with e1 = 1, e2 = 0 the increment T1 = E1 − E1n-1, the
/// first of the differences modulo 2^32, 2^24, 2^16 that is ≤ 32767 (the
/// counter width is not known; 0 when none is; DEC-13 — the alternative
/// takes the 32-bit difference as signed); E1n-1 := E1 on every execution.
/// (2) e1 = 0: T2 = T3 = 0; e1 = 1, e2 = 0: T4 = ⌊T1·W/U⌋, T5 = (T1·W) mod
/// U, T2 = SUM1 + T4 + ⌊(SUM2 + T5)/U⌋, T3 = (SUM2 + T5) mod U; e2 = 1: T2 =
/// SUM1, T3 = SUM2. (3) T2 ≥ HILMT: SUMPTN 0 → T2 mod HILMT and T3,
/// SUMPTN 1 → HILMT and 0; otherwise T2, T3 — into BW1/SUM1 and BW2/SUM2.
///
/// Errors (4100; SD1503 per Table 14.2: 1 increment, 2 integration, 3
/// output conversion): W or U out of its range is SD1502 = 3 at 2 (U = 0
/// is 5), HILMT < 1 or SUMPTN ∉ {0, 1} is 3 at 3 (DEC-36).
#[derive(Debug)]
pub(crate) struct Psum {
    sys: Sys,
    wrap: bool,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl Psum {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 3, "input data");
        let d1 = area(a, 1, 4, "block memory");
        let s2 = area(a, 2, 5, "operation constants");
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        Some(Box::new(Psum {
            sys,
            wrap: s.psum_wraparound,
            s1: s1?,
            d1: d1?,
            s2: s2?,
            d2: d2?,
        }))
    }

    /// The increment of a link counter going from `last` to `now` (DEC-13).
    fn increment(&self, now: u32, last: u32) -> i64 {
        let d = now.wrapping_sub(last);
        if !self.wrap {
            return d as i32 as i64;
        }
        [u32::MAX, 0xFF_FFFF, 0xFFFF]
            .iter()
            .map(|&mask| d & mask)
            .find(|&v| v <= 32767)
            .map_or(0, |v| v as i64)
    }
}

impl Instr for Psum {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 3)?;
        let d1 = Area::of(cx.mem, &self.d1, 4)?;
        let s2 = Area::of(cx.mem, &self.s2, 5)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        self.sys.run(cx.mem, |m| {
            let e1 = s1.get(m, PsumInput::e1);
            let (start, hold) = (s1.bit(m, PsumInput::ctl, 0), s1.bit(m, PsumInput::ctl, 1));
            // (1) input increment.
            let t1 = if start && !hold {
                self.increment(e1, d2.get(m, PsumTag::last))
            } else {
                0
            };
            d2.set(m, PsumTag::last, e1);
            // (2) integration.
            let (sum1, sum2) = (
                d2.get(m, PsumTag::sum1) as i64,
                d2.get(m, PsumTag::sum2) as i64,
            );
            let (t2, t3) = if !start {
                (0, 0)
            } else if hold {
                (sum1, sum2)
            } else {
                let weight = s2.get(m, PsumConsts::weight) as i64;
                let unit = s2.get(m, PsumConsts::unit) as i64;
                if unit == 0 {
                    return Err(PcError::divide(2));
                }
                if !(1..=999).contains(&weight) || ![1, 10, 100, 1000].contains(&unit) {
                    return Err(PcError::range(2));
                }
                let p = t1 * weight;
                let (t4, t5) = (p.div_euclid(unit), p.rem_euclid(unit));
                let f = sum2 + t5;
                (sum1 + t4 + f.div_euclid(unit), f.rem_euclid(unit))
            };
            // (3) output conversion.
            let hilmt = s2.get(m, PsumConsts::hilmt) as i64;
            let mode = s2.get(m, PsumConsts::sumptn);
            if hilmt < 1 || mode > 1 {
                return Err(PcError::range(3));
            }
            let (bw1, bw2) = if t2 < hilmt {
                (t2, t3)
            } else if mode == 0 {
                (t2 % hilmt, t3)
            } else {
                (hilmt, 0)
            };
            d1.set(m, PsumBlock::bw1, bw1 as i32);
            d1.set(m, PsumBlock::bw2, bw2 as i32);
            d2.set(m, PsumTag::sum1, bw1 as i32);
            d2.set(m, PsumTag::sum2, bw2 as i32);
            Ok(())
        })
    }
}
