//! Programming manual (common instructions) §7.13 data control: LIMIT, DLIMIT,
//! BAND, DBAND, ZONE, DZONE (signed BIN 16/32).
//!
//! PM = QCPU (Q mode)/QnACPU Programming Manual (Common Instructions).
//!
//! Every operand but the output may be a constant. Results of BAND and ZONE
//! that leave the signed range wrap around (e.g. BAND −32768 − 10 = 32758): the
//! CPU computes them in 16 (32) bits and the manual lists no overflow error.

use super::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("LIMIT", &DATA_CONTROL, |a| {
        compile(a, Kind::Limit, Num::I16)
    }),
    Def::app("DLIMIT", &DATA_CONTROL, |a| {
        compile(a, Kind::Limit, Num::I32)
    }),
    Def::app("BAND", &DATA_CONTROL, |a| compile(a, Kind::Band, Num::I16)),
    Def::app("DBAND", &DATA_CONTROL, |a| compile(a, Kind::Band, Num::I32)),
    Def::app("ZONE", &DATA_CONTROL, |a| compile(a, Kind::Zone, Num::I16)),
    Def::app("DZONE", &DATA_CONTROL, |a| compile(a, Kind::Zone, Num::I32)),
];

static DATA_CONTROL: Doc = Doc {
    family: "data control",
    cite: "PM §7.13",
    notes: "lower > upper → 4100 (LIMIT, BAND)",
};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Limit,
    Band,
    Zone,
}

/// PM §7.13.1-3 `S1 S2 S3 D` (16-bit, or 32-bit for the D forms):
///
/// - LIMIT(P)/DLIMIT(P), upper/lower limit control: S1 lower limit, S2 upper
///   limit, S3 input; D = S1 when S3 < S1, S2 when S3 > S2, S3 otherwise.
/// - BAND(P)/DBAND(P), dead band control: S1 lower, S2 upper limit of the dead
///   band, S3 input; D = 0 when S1 ≤ S3 ≤ S2, S3 − S1 below it, S3 − S2 above
///   it (wrapping).
/// - ZONE(P)/DZONE(P), zone control: S1 negative bias, S2 positive bias, S3
///   input; D = 0 when S3 = 0, S3 + S2 when S3 > 0, S3 + S1 when S3 < 0
///   (wrapping).
///
/// Errors: LIMIT and BAND with S1 > S2 (lower limit above the upper): 4100,
/// D unchanged. ZONE has no data error (the manual lists none). Index
/// modification out of range: 4101.
#[derive(Debug)]
struct Limits {
    kind: Kind,
    wide: bool,
    s1: WordArg,
    s2: WordArg,
    s3: WordArg,
    d: WordArg,
}

fn compile(a: &mut Args<'_, '_>, kind: Kind, num: Num) -> Option<Box<dyn Instr>> {
    if !a.count(&[4]) {
        return None;
    }
    let s1 = a.word_src(0, num);
    let s2 = a.word_src(1, num);
    let s3 = a.word_src(2, num);
    let d = a.word_dest(3, num, num.words());
    Some(Box::new(Limits {
        kind,
        wide: num == Num::I32,
        s1: s1?,
        s2: s2?,
        s3: s3?,
        d: d?,
    }))
}

impl Limits {
    /// Computes the output from the three inputs, all sign-extended to i64;
    /// the caller truncates to the operand width (wrap-around).
    fn output(&self, lo: i64, hi: i64, x: i64) -> Result<i64, Fault> {
        match self.kind {
            Kind::Limit | Kind::Band if lo > hi => Err(Fault::Operation),
            Kind::Limit => Ok(x.clamp(lo, hi)),
            Kind::Band if x < lo => Ok(x - lo),
            Kind::Band if x > hi => Ok(x - hi),
            Kind::Band => Ok(0),
            Kind::Zone if x > 0 => Ok(x + hi),
            Kind::Zone if x < 0 => Ok(x + lo),
            Kind::Zone => Ok(0),
        }
    }
}

impl Instr for Limits {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        if self.wide {
            let r = |a| mem.read32(a).map(|v| v as i32 as i64);
            let (s1, s2, s3) = (r(&self.s1)?, r(&self.s2)?, r(&self.s3)?);
            let v = self.output(s1, s2, s3)?;
            mem.write32(&self.d, v as u32)
        } else {
            let r = |a| mem.read16(a).map(|v| v as i16 as i64);
            let (s1, s2, s3) = (r(&self.s1)?, r(&self.s2)?, r(&self.s3)?);
            let v = self.output(s1, s2, s3)?;
            mem.write16(&self.d, v as u16)
        }
    }
}
