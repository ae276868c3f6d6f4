//! S.SEL, loop selector (000 §9.24).

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{area, def, result, upper_inh, Area, BlockMemory, Input, PcError, Sys};
use super::io::stage::{alarms, convert, limit, ALM_OUT, BB_OUT};
use super::settings::ProcessSettings;
use super::tag::{alm, bb, Inh, LoopTag, Mode, LOOP_TAG, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

static SEL: Doc = Doc {
    family: "process control: control",
    cite: "000 §9.24 L17898-18569, §5.2.3 L2466-2500",
    notes: "f32; E1/E2 by SVPTN.b0, change-rate and MH/ML limiter in the auto modes, \
            selector tracking En := MV (and the upper loop's TRKF when SVPTN marks En as its MV)",
};

pub static DEFS: &[Def] = &[def("S.SEL", 5, &SEL, Sel::compile).loop_memory(3, &LOOP_TAG)];

softplc_ir::layout! {
    /// The loop tag as S.SEL uses it (000 §9.24 L18300-18390).
    pub struct SelTag[128] {
        /// The selected PV (engineering units).
        pv: f32 @ 10,
        /// PV of input 1.
        pv1: f32 @ 14,
        /// PV of input 2.
        pv2: f32 @ 16,
        /// The selection number: b0 = E1 selected, b1 = E2 selected.
        slno: u16 @ 26,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.SEL.
    pub struct SelConsts[6] {
        /// NMAX: the output at MV = 100 % (100.0).
        nmax: f32 @ 0,
        /// NMIN: the output at MV = 0 % (0.0).
        nmin: f32 @ 2,
        /// TRK: 0 no tracking, 1 tracking.
        trk: u16 @ 4,
        /// SVPTN (1EH): b0 = e1 selects E2, b1/b2 = 1: E1/E2 not used,
        /// b3/b4 = 0: E1/E2 is the upper loop's MV.
        svptn: u16 @ 5,
    }
}

/// 000 §9.24 S.SEL `S.SEL S1 D1 S2 D2 S3` (L17898-18569), loop selector.
///
/// Operands: S1 +0 E1 (%), S3 +0 E2 (%); D1 +0 BW, +2 BB (BB1 alarm, BB2
/// output high, BB3 output low, BB4 change rate); S2 +0 NMAX (100.0), +2
/// NMIN (0.0), +4 TRK (0: no tracking, 1: tracking), +5 SVPTN (1EH; b0 = e1
/// selects E2, b1/b2 = 1: E1/E2 not used, b3/b4 = 0: E1/E2 is the upper
/// loop's MV; spec §1.8); D2 the loop tag: MODE +1, ALM +3 (SPA, DMLA, MHA,
/// MLA), INH +4 (ERRI, DMLI, MHI, MLI), +10 PV, MV +12, +14 PV1, +16 PV2,
/// MH +18, ML +20, RH +22, RL +24, +26 SLNO, DML +48.
///
/// Processing (L18420-18560): (7) loop stop (BW holds, DMLA = MHA = MLA = 0,
/// MODE := MAN, BB1..BB4 := 0). (1) PVn = (RH − RL)/100 × En + RL (→ PV1,
/// PV2). (2) e1 = 0 → PV = PV1, SLNO = b0; e1 = 1 → PV2, b1. (3) manual modes:
/// alarms and BB1..BB4 := 0, go to (5) with the operator's MV; auto modes:
/// T = 100/(RH − RL) × (PV − RL), then (4) the change-rate and MH/ML
/// limiter against MV as S.OUT1's (no ALM2, no T = MV exception; MV :=
/// the result). (5) BW = (NMAX − NMIN)/100 × MV + NMIN. (6) tracking, when
/// TRK = 1 and (a manual mode, or an auto mode with BB1 = 1): the selected
/// En := MV; when SVPTN marks that En as the upper loop's MV (b3/b4 = 0),
/// the upper loop's TRKF — the INH 8 words below En (+4 of the loop tag
/// whose +12 En names; spec §1.8) — is set as well, so that its S.OUT1
/// takes the tracked MV without a bump (this completes §5.2.3's example;
/// the manual's processing text only says En := MV).
///
/// Errors (4100; SD1503 per Table 14.2: 1 engineering conversion, 2 E1/E2
/// selection, 3 inverse conversion, 4 limiter, 5 output conversion, 6
/// tracking): a bad float is SD1502 = 1, RH = RL in an auto mode is 5 at 3,
/// an overflowing result 6. An upper INH below device number 0 is 4101.
#[derive(Debug)]
struct Sel {
    sys: Sys,
    inh: Inh,
    mode: Mode,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
    s3: Block,
    up1: Block,
    up3: Block,
}

impl Sel {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[5]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 3, "block memory");
        let s2 = area(a, 2, 6, "operation constants");
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        let s3 = area(a, 4, 2, "input data 2");
        let (s1, s3) = (s1?, s3?);
        Some(Box::new(Sel {
            sys,
            inh: Inh::new(&s),
            mode: Mode::new(&s),
            up1: upper_inh(a, 0)?,
            up3: upper_inh(a, 4)?,
            s1,
            d1: d1?,
            s2: s2?,
            d2: d2?,
            s3,
        }))
    }
}

/// What the tracking step asks of the upper loop.
enum Track {
    None,
    /// Set TRKF in the upper loop of input 1 (false) or 2 (true).
    Upper(bool),
}

impl Instr for Sel {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        let s2 = Area::of(cx.mem, &self.s2, 6)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        let s3 = Area::of(cx.mem, &self.s3, 2)?;
        let track = self.sys.run_with(cx.mem, |m| {
            if d2.get(m, LoopTag::alm) & alm::SPA != 0 {
                d2.set_bits(m, LoopTag::alm, ALM_OUT, false);
                d2.set(m, LoopTag::mode, Mode::MAN);
                d1.set_bits(m, BlockMemory::bb, BB_OUT, false);
                return Ok(Track::None);
            }
            // (1) engineering-value conversion.
            let rh = d2.real(m, LoopTag::rh, 1)?;
            let rl = d2.real(m, LoopTag::rl, 1)?;
            let e1 = s1.real(m, Input::e1, 1)?;
            let e2 = s3.real(m, Input::e1, 1)?;
            let pv1 = result((rh - rl) / 100.0 * e1 + rl, 1)?;
            let pv2 = result((rh - rl) / 100.0 * e2 + rl, 1)?;
            d2.set(m, SelTag::pv1, pv1);
            d2.set(m, SelTag::pv2, pv2);
            // (2) E1/E2 selection.
            let svptn = s2.get(m, SelConsts::svptn);
            let second = svptn & 1 != 0;
            let pv = if second { pv2 } else { pv1 };
            d2.set(m, SelTag::pv, pv);
            d2.set(m, SelTag::slno, if second { 2 } else { 1 });
            // (3) mode check.
            let mode = d2.get(m, LoopTag::mode);
            let manual = self.mode.manual(mode);
            if manual {
                d2.set_bits(m, LoopTag::alm, ALM_OUT, false);
                d1.set_bits(m, BlockMemory::bb, BB_OUT, false);
            } else if self.mode.auto(mode) {
                if rh == rl {
                    return Err(PcError::divide(3));
                }
                let t = result(100.0 / (rh - rl) * (pv - rl), 3)?;
                // (4) change rate, high/low limiter.
                let mv = d2.real(m, LoopTag::mv, 4)?;
                let dml = d2.real(m, LoopTag::dml, 4)?;
                let mh = d2.real(m, LoopTag::mh, 4)?;
                let ml = d2.real(m, LoopTag::ml, 4)?;
                let l = limit(t, mv, dml, mh, ml, 4)?;
                d2.set(m, LoopTag::mv, l.mv);
                let inh = d2.get(m, LoopTag::inh);
                let (mut almw, mut bbw) = (d2.get(m, LoopTag::alm), d1.get(m, BlockMemory::bb));
                alarms(self.inh, inh, &mut almw, &mut bbw, &l);
                d2.set(m, LoopTag::alm, almw);
                d1.set(m, BlockMemory::bb, bbw);
            } else {
                return Ok(Track::None);
            }
            // (5) output conversion.
            let nmax = s2.real(m, SelConsts::nmax, 5)?;
            let nmin = s2.real(m, SelConsts::nmin, 5)?;
            let mv = d2.real(m, LoopTag::mv, 5)?;
            d1.set(m, BlockMemory::bw, convert(nmax, nmin, mv, 5)?);
            // (6) tracking.
            let trk = s2.get(m, SelConsts::trk) == 1;
            if trk && (manual || d1.get(m, BlockMemory::bb) & bb::BB1 != 0) {
                let en = if second { s3 } else { s1 };
                en.set(m, Input::e1, mv);
                let upper = svptn & if second { 1 << 4 } else { 1 << 3 } == 0;
                if upper {
                    return Ok(Track::Upper(second));
                }
            }
            Ok(Track::None)
        })?;
        if let Track::Upper(second) = track {
            let up = cx
                .mem
                .block_start(if second { &self.up3 } else { &self.up1 }, 1)?;
            cx.mem.words[up] |= self.inh.trkf;
        }
        Ok(())
    }
}
