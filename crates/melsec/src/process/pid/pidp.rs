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

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;

use super::front::{
    derivative, past, put, run, set_bits, tag, tag_pos, word, Areas, Front, Halt, Operands, Pattern,
};
use super::gains;
use crate::process::common::{real, result, set_f, PcError};
use crate::process::tag::{alm, LoopTag};
use crate::{Args, ExecCtx, Instr};

const BB1: u16 = 1;
const BB2: u16 = 2;
const BB3: u16 = 4;
const BB4: u16 = 8;
const BB5: u16 = 16;

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
        let pat = Pattern::read(m, a.s2, 4, 4)?;
        let svn = f.sv(m, a, pat, mode)?;
        let sv1 = f.track(m, a, pat, mode, svn)?;
        let (dv, kp) = f.gain(m, a, pat, sv1)?;
        let e1 = real(m, a.s1, 5)?;
        let ct = tag(m, a.d2, LoopTag::ct, 5)?;
        let (md, td, ti) = gains(m, a, 5)?;
        let d2 = a.d2;
        let i1 = real(m, d2 + past::W100, 5)?;
        let b1 = real(m, d2 + past::B1, 5)?;
        let pv1 = real(m, d2 + past::PV, 5)?;
        set_f(m, d2 + past::PV1, pv1);
        set_f(m, d2 + past::PV, e1);
        let x = result(e1 - pv1, 5)?;
        let x = if pat.forward { x } else { -x };
        let bn = if td == 0.0 || f.mode.no_derivative(mode) {
            0.0
        } else {
            derivative(md, td, ct, x, b1, 5)?
        };
        let inc = self.increment(m, d2, mode, ct, ti, dv)?;
        let i_n = result(i1 + inc, 5)?;
        set_f(m, d2 + past::W100, i_n);
        set_f(m, d2 + past::B1, bn);
        let t = result(kp * (dv + i_n + bn), 5)?;
        let dvls = real(m, a.s2 + 2, 6)?;
        f.check(m, a, dv, dvls, BB2, 6)?;
        Ok(Some(t))
    }

    /// (CT/TI)·DVn after the S.PIDP freeze rules.
    fn increment(
        &self,
        m: &DeviceMemory,
        d2: usize,
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
            let trkf = word(m, d2, LoopTag::inh) & f.inh.trkf != 0;
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
        let mv = tag(m, d2, LoopTag::mv, 7)?;
        if t == mv && f.s.output_tracking_skips_limits {
            return Ok(());
        }
        let dml = tag_pos(m, d2, LoopTag::dml, 7)?;
        let mh = tag(m, d2, LoopTag::mh, 7)?;
        let ml = tag(m, d2, LoopTag::ml, 7)?;
        let inh = word(m, d2, LoopTag::inh);
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
        put(m, d2, LoopTag::mv, out);
        let rate = rate && f.inh.allows(inh, alm::DMLA);
        let (h, l) = (
            high && f.inh.allows(inh, alm::MHA),
            low && f.inh.allows(inh, alm::MLA),
        );
        let ai = d2 + LoopTag::alm.offset();
        set_bits(m, ai, alm::DMLA, rate);
        set_bits(m, ai, alm::MHA, h);
        set_bits(m, ai, alm::MLA, l);
        let alm2 = if high { f.alm2.mha2 } else { 0 } | if low { f.alm2.mla2 } else { 0 };
        m.words[d2 + LoopTag::alm2.offset()] = alm2;
        set_bits(m, a.d1 + 2, BB5, rate);
        set_bits(m, a.d1 + 2, BB3, h);
        set_bits(m, a.d1 + 2, BB4, l);
        Ok(())
    }

    fn body(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), Halt> {
        let f = &self.f;
        let d2 = a.d2;
        if f.stopped(m, d2) {
            m.words[d2 + LoopTag::alm2.offset()] = 0;
            set_bits(m, a.d1 + 2, BB1 | BB2 | BB3 | BB4 | BB5, false);
            f.stop(
                m,
                d2,
                alm::DVLA | alm::MHA | alm::MLA | alm::DMLA,
                Some(LoopTag::ct),
            )?;
            return Ok(());
        }
        let mode = word(m, d2, LoopTag::mode);
        let t = self.compute(m, a, mode)?;
        let bb = a.d1 + 2;
        if f.mode.manual(mode) {
            set_bits(
                m,
                d2 + LoopTag::alm.offset(),
                alm::MHA | alm::MLA | alm::DMLA,
                false,
            );
            m.words[d2 + LoopTag::alm2.offset()] = 0;
            set_bits(m, bb, BB3 | BB4 | BB5, false);
            let b2 = m.words[bb] & BB2 != 0;
            set_bits(m, bb, BB1, b2);
        } else {
            let t = match t {
                Some(t) => t,
                None => tag(m, d2, LoopTag::mv, 7)?,
            };
            self.limit(m, a, t)?;
            let any = m.words[bb] & (BB2 | BB3 | BB4 | BB5) != 0;
            set_bits(m, bb, BB1, any);
        }
        let mv = tag(m, d2, LoopTag::mv, 8)?;
        let nmax = real(m, a.s2 + 7, 8)?;
        let nmin = real(m, a.s2 + 9, 8)?;
        set_f(m, a.d1, result((nmax - nmin) / 100.0 * mv + nmin, 8)?);
        Ok(())
    }
}

impl Instr for Pidp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let a = self.ops.resolve(cx.mem)?;
        run(&self.f.sys, cx.mem, |m| self.body(m, &a))
    }
}
