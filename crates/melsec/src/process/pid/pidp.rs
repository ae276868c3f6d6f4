//! 000 §9.3 S.PIDP L8678-9749 (spec §4.11): position-type PID with its own
//! output stage. S2 +0 MTD (8.0), +2 DVLS (2.0), +4 PN, +5 TRK, +6 SVPTN,
//! **+7/+8 NMAX (100.0), +9/+10 NMIN (0.0)** (odd offsets as printed,
//! L8970-8980). D1 +0 BW (engineering output), +2 BB: BB1 alarm, BB2
//! deviation large, BB3 output high, BB4 output low, BB5 output rate. Past
//! values +100 In-1, +102 Bn-1, +104 PVn, +106 PVn-1, ALM2 +116 (written).
//!
//! Order: (9) loop stop (BW holds; DVLA, MHA, MLA, DMLA, MHA2, MLA2, BB1..BB5
//! := 0; MODE := MAN) → (10) control cycle (not reached: T = MV, go to (6))
//! → (1) SV → (2) tracking → (3) gain → (4) `Bn = Bn-1 + c × [±(PVn −
//! PVn-1) − (CT/TD)·Bn-1]`, `In = In-1 + (CT/TI)·DVn`, `T = KP × (DVn + In +
//! Bn)` → (5) deviation check (DVLA, BB2) → (6) mode: M-group clears MHA,
//! MLA, DMLA, MHA2, MLA2, BB3..BB5, BB1 := BB2 and goes to (8); A-group →
//! (7) rate and high/low limiter on T against MV (skipped when T = MV,
//! DEC-10), MHA2/MLA2 ignoring INH → (8) BW = (NMAX − NMIN)/100 × MV + NMIN.
//! In the A-group BB1 = BB2 ∨ BB3 ∨ BB4 ∨ BB5.
//!
//! Integral increment := 0 when TI = 0, or MHA2 = 1 with a positive
//! increment, or MLA2 = 1 with a negative one (firmware ≤ 07031: MHA/MLA);
//! firmware ≥ 07032 also in MAN/LCM/CMV, and when SD1508 b0 = 1, INH.TRKF = 1
//! and the mode is not MAN/LCM/CMV (L9569-9607, DEC-15). S.PIDP neither sets
//! nor clears TRKF (the manual gives it no such step).

use crate::process::common::Area;
use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;

use super::front::{
    derivative, run, tag_pos, Areas, Front, Halt, Operands, Pattern, PatternFields, PidPast,
};
use super::gains;
use crate::process::common::{result, BlockMemory, Input, PcError};
use crate::process::tag::bb::{BB1, BB2, BB3, BB4, BB5};
use crate::process::tag::{alm, LoopTag};
use crate::{Args, ExecCtx, Instr};

softplc_ir::layout! {
    /// The operation constants (S2) of S.PIDP (000 §9.3 L8970-8980; the
    /// odd offsets as printed).
    pub struct PidpConsts[11] {
        /// MTD: the derivative gain (8.0).
        mtd: f32 @ 0,
        /// DVLS: the deviation alarm hysteresis (2.0).
        dvls: f32 @ 2,
        /// PN: 0 reverse, 1 forward action.
        pn: u16 @ 4,
        /// TRK: 1 tracking.
        trk: u16 @ 5,
        /// SVPTN: b0 = 1 E2 not used, b1 = 0 E2 is the upper loop's MV.
        svptn: u16 @ 6,
        /// NMAX: the output at MV = 100 % (100.0).
        nmax: f32 @ 7,
        /// NMIN: the output at MV = 0 % (0.0).
        nmin: f32 @ 9,
    }
}

softplc_ir::layout! {
    /// The past value of S.PIDP's own in the loop tag (the others are
    /// [`PidPast`]'s).
    pub struct PidpPast[128] {
        /// In-1: the last integral term.
        i1: f32 @ 100,
    }
}

const PATTERN: PatternFields = PatternFields {
    pn: Some(PidpConsts::pn),
    trk: PidpConsts::trk,
    svptn: PidpConsts::svptn,
};

#[derive(Debug)]
pub struct Pidp {
    f: Front,
    ops: Operands,
}

impl Pidp {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        let ops = Operands::compile(a, 2, 3, 11)?;
        let f = Front::new(a)?;
        Some(Box::new(Pidp { f, ops }))
    }

    /// (1)-(5): T, or None when the control cycle is not reached.
    fn compute(&self, m: &mut DeviceMemory, a: &Areas, mode: u16) -> Result<Option<f32>, Halt> {
        let f = &self.f;
        if !f.cycle(m, a.d2, LoopTag::ct)?.reached {
            return Ok(None);
        }
        let pat = Pattern::read(m, a.s2, PATTERN, 4)?;
        let svn = f.sv(m, a, pat, mode)?;
        let sv1 = f.track(m, a, pat, mode, svn)?;
        let (dv, kp) = f.gain(m, a, pat, sv1)?;
        let e1 = a.s1.real(m, Input::e1, 5)?;
        let ct = a.d2.real(m, LoopTag::ct, 5)?;
        let (md, td, ti) = gains(m, a, 5)?;
        let d2 = a.d2;
        let i1 = d2.real(m, PidpPast::i1, 5)?;
        let b1 = d2.real(m, PidPast::b1, 5)?;
        let pv1 = d2.real(m, PidPast::pv, 5)?;
        d2.set(m, PidPast::pv1, pv1);
        d2.set(m, PidPast::pv, e1);
        let x = result(e1 - pv1, 5)?;
        let x = if pat.forward { x } else { -x };
        let bn = if td == 0.0 || f.mode.no_derivative(mode) {
            0.0
        } else {
            derivative(md, td, ct, x, b1, 5)?
        };
        let inc = self.increment(m, d2, mode, ct, ti, dv)?;
        let i_n = result(i1 + inc, 5)?;
        d2.set(m, PidpPast::i1, i_n);
        d2.set(m, PidPast::b1, bn);
        let t = result(kp * (dv + i_n + bn), 5)?;
        let dvls = a.s2.real(m, PidpConsts::dvls, 6)?;
        f.check(m, a, dv, dvls, BB2, 6)?;
        Ok(Some(t))
    }

    /// (CT/TI)·DVn after the S.PIDP freeze rules.
    fn increment(
        &self,
        m: &DeviceMemory,
        d2: Area,
        mode: u16,
        ct: f32,
        ti: f32,
        dv: f32,
    ) -> Result<f32, PcError> {
        let f = &self.f;
        if ti == 0.0 {
            return Ok(0.0);
        }
        let inc = result(ct / ti * dv, 5)?;
        let (h, l) = f.limits(m, d2);
        if (h && inc > 0.0) || (l && inc < 0.0) {
            return Ok(0.0);
        }
        if f.s.firmware_serial_ge_07032 {
            let manual = f.mode.no_derivative(mode);
            let trkf = d2.get(m, LoopTag::inh) & f.inh.trkf != 0;
            if manual || (f.sys.options(m) & 1 != 0 && trkf) {
                return Ok(0.0);
            }
        }
        Ok(inc)
    }

    /// (7) rate and high/low limiter (processing No. 7).
    fn limit(&self, m: &mut DeviceMemory, a: &Areas, t: f32) -> Result<(), PcError> {
        let f = &self.f;
        let d2 = a.d2;
        let mv = d2.real(m, LoopTag::mv, 7)?;
        if t == mv && f.s.output_tracking_skips_limits {
            return Ok(());
        }
        let dml = tag_pos(m, d2, LoopTag::dml, 7)?;
        let mh = d2.real(m, LoopTag::mh, 7)?;
        let ml = d2.real(m, LoopTag::ml, 7)?;
        let inh = d2.get(m, LoopTag::inh);
        let d = result(t - mv, 7)?;
        let (t1, rate) = if d > dml {
            (result(mv + dml, 7)?, true)
        } else if d < -dml {
            (result(mv - dml, 7)?, true)
        } else {
            (t, false)
        };
        let (out, high, low) = if t1 > mh {
            (mh, true, false)
        } else if t1 < ml {
            (ml, false, true)
        } else {
            (t1, false, false)
        };
        d2.set(m, LoopTag::mv, out);
        let rate = rate && f.inh.allows(inh, alm::DMLA);
        let (h, l) = (
            high && f.inh.allows(inh, alm::MHA),
            low && f.inh.allows(inh, alm::MLA),
        );
        d2.set_bits(m, LoopTag::alm, alm::DMLA, rate);
        d2.set_bits(m, LoopTag::alm, alm::MHA, h);
        d2.set_bits(m, LoopTag::alm, alm::MLA, l);
        let alm2 = if high { f.alm2.mha2 } else { 0 } | if low { f.alm2.mla2 } else { 0 };
        d2.set(m, LoopTag::alm2, alm2);
        a.d1.set_bits(m, BlockMemory::bb, BB5, rate);
        a.d1.set_bits(m, BlockMemory::bb, BB3, h);
        a.d1.set_bits(m, BlockMemory::bb, BB4, l);
        Ok(())
    }

    fn body(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), Halt> {
        let f = &self.f;
        let d2 = a.d2;
        if f.stopped(m, d2) {
            d2.set(m, LoopTag::alm2, 0);
            a.d1.set_bits(m, BlockMemory::bb, BB1 | BB2 | BB3 | BB4 | BB5, false);
            f.stop(
                m,
                d2,
                alm::DVLA | alm::MHA | alm::MLA | alm::DMLA,
                Some(LoopTag::ct),
            )?;
            return Ok(());
        }
        let mode = d2.get(m, LoopTag::mode);
        let t = self.compute(m, a, mode)?;
        let d1 = a.d1;
        let bb = BlockMemory::bb;
        if f.mode.manual(mode) {
            d2.set_bits(m, LoopTag::alm, alm::MHA | alm::MLA | alm::DMLA, false);
            d2.set(m, LoopTag::alm2, 0);
            d1.set_bits(m, bb, BB3 | BB4 | BB5, false);
            let b2 = d1.get(m, bb) & BB2 != 0;
            d1.set_bits(m, bb, BB1, b2);
        } else {
            let t = match t {
                Some(t) => t,
                None => d2.real(m, LoopTag::mv, 7)?,
            };
            self.limit(m, a, t)?;
            let any = d1.get(m, bb) & (BB2 | BB3 | BB4 | BB5) != 0;
            d1.set_bits(m, bb, BB1, any);
        }
        let mv = d2.real(m, LoopTag::mv, 8)?;
        let nmax = a.s2.real(m, PidpConsts::nmax, 8)?;
        let nmin = a.s2.real(m, PidpConsts::nmin, 8)?;
        d1.set(
            m,
            BlockMemory::bw,
            result((nmax - nmin) / 100.0 * mv + nmin, 8)?,
        );
        Ok(())
    }
}

impl Instr for Pidp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = self.ops.resolve(cx.mem)?;
        run(&self.f.sys, cx.mem, |m| self.body(m, &a))
    }
}
