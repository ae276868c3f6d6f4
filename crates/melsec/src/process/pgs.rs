//! S.PGS, program setter (000 §9.23).

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{area, def, dummy, result, Area, BlockMemory, PcError, Sys};
use super::settings::ProcessSettings;
use super::tag::{alm, bb, Inh, LoopTag, Mode, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

static PGS: Doc = Doc {
    family: "process control: control",
    cite: "000 §9.23 L17327-17897",
    notes: "f32; SV counts elapsed time by ΔT, MV interpolated over up to 16 points; \
            hold/return type in AUT/CAB, cyclic in CAS/CCB/CSV, stopped in the other modes",
};

pub static DEFS: &[Def] = &[def("S.PGS", 4, &PGS, Pgs::compile).loop_memory(3, &PGS_TAG)];

softplc_ir::layout! {
    /// The loop tag as S.PGS uses it (000 §9.23 L17640-17765).
    pub struct PgsTag[128] {
        /// Number of points PTNO (0 … 16).
        ptno: i16 @ 10,
        /// Elapsed time SV, s.
        sv: f32 @ 14,
        /// Operation type: 0 hold, 1 return (AUT, CAB).
        kind: i16 @ 16,
        /// SV1 (s); SVi is `sv1.nth(i − 1)`, +22 … +52.
        sv1: f32 @ 22,
        /// MV1 (%); MVi is `mv1.nth(i − 1)`, +54 … +84.
        mv1: f32 @ 54,
    }
}

/// S.PGS's D2 as its loop memory.
pub static PGS_TAG: softplc_ir::listing::LoopMemory = softplc_ir::listing::LoopMemory {
    name: "S.PGS loop tag",
    fields: PgsTag::FIELDS,
    first: 0,
    stride: 0,
    count: None,
    settings: None,
};

const BB_PGS: u16 = bb::BB1 | bb::BB2 | bb::BB3;

/// 000 §9.23 S.PGS `S.PGS S1(dmy) D1 S2(dmy) D2` (L17327-17897), program
/// setter.
///
/// Operands: S1, S2 dummies; D1 +0 BW (%), +2 BB (BB1 alarm, BB2 output
/// high, BB3 output low); D2 the loop tag: MODE +1, ALM +3 (SPA, MHA, MLA),
/// INH +4 (ERRI, MHI, MLI), +10 PTNO (0 … 16), MV +12, +14 SV (elapsed
/// time, s), +16 TYPE (0 hold, 1 return), MH +18, ML +20, SV1 … SV16 at
/// +22 … +52, MV1 … MV16 at +54 … +84.
///
/// Processing (L17790-17897): (2) loop stop (SPA = 1) or PTNO = 0: BW
/// holds, MHA = MLA = 0, MODE := MAN, BB1..BB3 := 0, end. In MAN, CMB, CMV,
/// LCM, LCA, LCC the program is stopped at the present SV and MV: BW = MV,
/// MHA, MLA, BB1..BB3 := 0. In the other modes: (3) SV' = SV + ΔT (→ SV);
/// (4) SV' ≤ SV1 → MVPGS = MV1; SVi-1 < SV' ≤ SVi → MVPGS = (MVi − MVi-1)/
/// (SVi − SVi-1) × (SV' − SVi-1) + MVi-1; at the end (SV' ≥ SV_PTNO)
/// MVPGS = MV_PTNO and: AUT/CAB with TYPE 0 (hold) MODE := MAN, SV stays;
/// TYPE 1 (return) MODE := MAN, SV := 0; CAS/CCB/CSV (cyclic) SV := 0 and
/// MVPGS = MV1, no mode change. (5) MV = MVPGS limited to ML … MH (MHA =
/// BB2, MLA = BB3 on limiting, subject to MHI/MLI/ERRI; BB1 = BB2 ∨ BB3),
/// BW = MV.
///
/// Errors (4100; SD1503 per Table 14.2: 2 SV count-up, 3 MVPGS, 4 output):
/// a bad float is SD1502 = 1 at the step reading it; PTNO ∉ 0 … 16 or TYPE
/// ∉ {0, 1} is 3 at 3 (DEC-36); an overflowing result 6.
#[derive(Debug)]
struct Pgs {
    sys: Sys,
    inh: Inh,
    mode: Mode,
    d1: Block,
    d2: Block,
}

impl Pgs {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = dummy(a, 0);
        let d1 = area(a, 1, 3, "block memory");
        let s2 = dummy(a, 2);
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        s1?;
        s2?;
        Some(Box::new(Pgs {
            sys,
            inh: Inh::new(&s),
            mode: Mode::new(&s),
            d1: d1?,
            d2: d2?,
        }))
    }
}

/// How the program ends at SV' ≥ SV_PTNO.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Hold,
    Return,
    Cyclic,
}

impl Instr for Pgs {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        self.sys.run(cx.mem, |m| {
            let ptno = d2.get(m, PgsTag::ptno);
            if d2.get(m, LoopTag::alm) & alm::SPA != 0 || ptno == 0 {
                d2.set_bits(m, LoopTag::alm, alm::MHA | alm::MLA, false);
                d2.set(m, LoopTag::mode, Mode::MAN);
                d1.set_bits(m, BlockMemory::bb, BB_PGS, false);
                return Ok(());
            }
            let mode = d2.get(m, LoopTag::mode);
            let kind = if mode & (Mode::AUT | Mode::CAB) != 0 {
                Kind::Hold
            } else if self.mode.cascade(mode) {
                Kind::Cyclic
            } else {
                if self.mode.manual(mode) || self.mode.auto(mode) {
                    // Stopped at the present SV and MV (MAN, CMB, CMV, LCM, LCA, LCC).
                    d2.set_bits(m, LoopTag::alm, alm::MHA | alm::MLA, false);
                    d1.set_bits(m, BlockMemory::bb, BB_PGS, false);
                    let mv = d2.real(m, LoopTag::mv, 4)?;
                    d1.set(m, BlockMemory::bw, mv);
                }
                return Ok(());
            };
            // (3) SV count-up.
            let dt = self.sys.dt(m, 2)?;
            let sv = result(d2.real(m, PgsTag::sv, 2)? + dt, 2)?;
            d2.set(m, PgsTag::sv, sv);
            // (4) MVPGS.
            let kind = match (kind, d2.get(m, PgsTag::kind)) {
                (Kind::Cyclic, _) => Kind::Cyclic,
                (_, 0) => Kind::Hold,
                (_, 1) => Kind::Return,
                _ => return Err(PcError::range(3)),
            };
            if !(1..=16).contains(&ptno) {
                return Err(PcError::range(3));
            }
            let n = ptno as usize;
            let svi = |m: &softplc_ir::device::DeviceMemory, i: usize| {
                d2.real(m, PgsTag::sv1.nth(i - 1), 3)
            };
            let mvi = |m: &softplc_ir::device::DeviceMemory, i: usize| {
                d2.real(m, PgsTag::mv1.nth(i - 1), 3)
            };
            let mvpgs = if sv >= svi(m, n)? {
                match kind {
                    Kind::Hold => {
                        d2.set(m, LoopTag::mode, Mode::MAN);
                        mvi(m, n)?
                    }
                    Kind::Return => {
                        d2.set(m, LoopTag::mode, Mode::MAN);
                        d2.set(m, PgsTag::sv, 0.0);
                        mvi(m, n)?
                    }
                    Kind::Cyclic => {
                        d2.set(m, PgsTag::sv, 0.0);
                        mvi(m, 1)?
                    }
                }
            } else if sv <= svi(m, 1)? {
                mvi(m, 1)?
            } else {
                let mut v = mvi(m, n)?;
                for i in 2..=n {
                    let (s1, s0) = (svi(m, i)?, svi(m, i - 1)?);
                    if sv <= s1 {
                        let (m1, m0) = (mvi(m, i)?, mvi(m, i - 1)?);
                        v = result((m1 - m0) / (s1 - s0) * (sv - s0) + m0, 3)?;
                        break;
                    }
                }
                v
            };
            // (5) output with the high/low limit.
            let mh = d2.real(m, LoopTag::mh, 4)?;
            let ml = d2.real(m, LoopTag::ml, 4)?;
            let (mv, high, low) = if mvpgs > mh {
                (mh, true, false)
            } else if mvpgs < ml {
                (ml, false, true)
            } else {
                (mvpgs, false, false)
            };
            let inh = d2.get(m, LoopTag::inh);
            let (mut almw, mut bbw) = (d2.get(m, LoopTag::alm), d1.get(m, BlockMemory::bb));
            let h = self
                .inh
                .apply(inh, &mut almw, alm::MHA, &mut bbw, bb::BB2, high);
            let l = self
                .inh
                .apply(inh, &mut almw, alm::MLA, &mut bbw, bb::BB3, low);
            super::tag::put(&mut bbw, bb::BB1, h || l);
            d2.set(m, LoopTag::alm, almw);
            d1.set(m, BlockMemory::bb, bbw);
            d2.set(m, LoopTag::mv, mv);
            d1.set(m, BlockMemory::bw, mv);
            Ok(())
        })
    }
}
