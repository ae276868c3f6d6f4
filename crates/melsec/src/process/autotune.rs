//! Auto-tuning (000 ch. 13): S.AT1, Ziegler-Nichols step response.
//!
//! 000 §13.1 S.AT1 L22617-23567 (spec §4.37) `S.AT1 S1 D1 S2 D2 D3`: S1 +0
//! E1 (PV, %), +2 e1 (b0: 1 start, 0 stop). D1 +0 BB only: BB1 alarm (b0),
//! BB2 input high, BB3 input low, BB4 output high, BB5 output low, BB6
//! timeout, BB7 operation mode, BB8 identification, BB16 (b15) AT complete.
//! S2 +0 PN. D2 the loop tag: MODE, ALM (SPA, HHA, LLA, PHA, PLA), MV +12,
//! MH +18, ML +20, P/I/D +52/+54/+56 (written), AT1STEPMV +70, AT1ST +72,
//! AT1TOUT1 +74, AT1TOUT2 +76. D3 22 words of local memory: +0/+1 sampling
//! counter flag/counter, +2/+3 timeout, +4/+5 post-max-slope timeout, +6
//! step flag, +7 samples since the step, +8/9 PV0, +10/11 PVn-1, +12/13 the
//! maximum slope (per sample, signed), +14/15 the sample count at the
//! maximum (float), +16/17 PV at the maximum, +18/19 R, +20/21 L.
//!
//! (1) (e1, BB16): (0,0) clears BB2..BB8 and restores MV if the step was
//! made; (0,1) clears BB16; (1,1) ends; (1,0) → (2) loop stop: BB16, restore
//! → (3) A-group: BB7, BB16, restore → (4) PHA/HHA: BB2, PLA/LLA: BB3, BB16,
//! MV not restored → (5) AT1TOUT1 reached: BB6, BB16, MV not restored → (6)
//! AT1TOUT2 reached since the last maximum → (10) → (7) the step: T1 = MV +
//! AT1STEPMV, > MH: BB4, < ML: BB5 (BB16, MV unchanged), else MV := T1,
//! sample 0 (PV0 = PVn-1 = E1) and the sampling counter starts (DEC-32) →
//! (8) sampling period reached → (9) T2 = E1 − PVn-1, the extreme slope in
//! the expected direction (rising for PN = 0 with a positive step or PN = 1
//! with a negative one) restarts the post-max-slope counter → (10) R′ =
//! max/AT1ST, R = |R′|/100 (stored per DEC-33), b = PVmax − R′ × count ×
//! AT1ST, L = (PV0 − b)/R′; R = 0 or L ≤ 0: BB8, BB16, restore → (11) ZN by
//! the current I and D: P 1/(R·L) × |STEP|/100; PI 0.9/(R·L) × …, TI 3.33·L;
//! PID 1.2/(R·L) × …, TI 2·L, TD 0.5·L; BB16, restore. Every restore clears
//! the step flag and every ending the counter flags (DEC-34); BB1 = BB2 ∨ …
//! ∨ BB8 after every execution (DEC-35).

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use softplc_ir::layout::At;

use super::common::{area, count, def, result, tick, Area, InputCtl, PcError, Sys};
use super::settings::ProcessSettings;
use super::tag::{alm, LoopTag, Mode, LOOP_TAG};
use crate::{Args, ExecCtx, Instr};

static AT1: Doc = Doc {
    family: "process control: auto-tuning",
    cite: "000 §13.1 L22617-23567",
    notes: "ZN step response on MAN loops; sample 0 at the step (DEC-32), R = abs(R′)/100 stored \
            (DEC-33), MV restored once (DEC-34), BB1 = BB2 ∨ … ∨ BB8 (DEC-35)",
};

pub static DEFS: &[Def] = &[def("S.AT1", 5, &AT1, At1::compile).loop_memory(3, &LOOP_TAG)];

const BB2: u16 = 1 << 1;
const BB3: u16 = 1 << 2;
const BB4: u16 = 1 << 3;
const BB5: u16 = 1 << 4;
const BB6: u16 = 1 << 5;
const BB7: u16 = 1 << 6;
const BB8: u16 = 1 << 7;
const BB16: u16 = 1 << 15;
const ALARMS: u16 = BB2 | BB3 | BB4 | BB5 | BB6 | BB7 | BB8;

softplc_ir::layout! {
    /// The block memory (D1) of S.AT1: BB only.
    pub struct At1Block[1] {
        /// BB1 alarm (b0), BB2 input high, BB3 input low, BB4 output high,
        /// BB5 output low, BB6 timeout, BB7 operation mode, BB8
        /// identification, BB16 (b15) AT complete.
        bb: u16 @ 0,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.AT1.
    pub struct At1Consts[1] {
        /// PN: 0 reverse, 1 forward action.
        pn: u16 @ 0,
    }
}

softplc_ir::layout! {
    /// The local work memory (D3) of S.AT1.
    pub struct At1Work[22] {
        /// The sampling counter's preset flag.
        sample_flag: u16 @ 0,
        /// The sampling counter.
        sample: u16 @ 1,
        /// The AT1TOUT1 counter's preset flag.
        tout_flag: u16 @ 2,
        /// The AT1TOUT1 counter.
        tout: u16 @ 3,
        /// The post-max-slope (AT1TOUT2) counter's preset flag.
        post_flag: u16 @ 4,
        /// The post-max-slope counter.
        post: u16 @ 5,
        /// 1 when the MV step was made.
        stepped: u16 @ 6,
        /// The samples since the step.
        count: u16 @ 7,
        /// PV0: PV at the step.
        pv0: f32 @ 8,
        /// PVn-1.
        pv1: f32 @ 10,
        /// The maximum slope (per sample, signed).
        max: f32 @ 12,
        /// The sample count at the maximum.
        max_count: f32 @ 14,
        /// PV at the maximum.
        max_pv: f32 @ 16,
        /// R (DEC-33).
        r: f32 @ 18,
        /// L.
        l: f32 @ 20,
    }
}

#[derive(Debug)]
struct At1 {
    s: ProcessSettings,
    mode: Mode,
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
    d3: Block,
}

#[derive(Clone, Copy)]
struct Areas {
    s1: Area,
    d1: Area,
    s2: Area,
    d2: Area,
    d3: Area,
}

impl At1 {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[5]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 3, "input data");
        let d1 = area(a, 1, 1, "block memory");
        let s2 = area(a, 2, 1, "operation constants");
        let d2 = area(a, 3, 128, "loop memory");
        let d3 = area(a, 4, 22, "local work memory");
        if !s.at1_bb1_or {
            a.error(
                0,
                "S.AT1: at1_bb1_or = false asks for a BB1 the manual does not describe \
                 (Process Control Instructions manual §13.1 names BB1 \"alarm\" only); only \
                 BB1 = BB2 ∨ … ∨ BB8 is implemented",
            );
            return None;
        }
        Some(Box::new(At1 {
            s,
            mode: Mode::new(&s),
            sys,
            s1: s1?,
            d1: d1?,
            s2: s2?,
            d2: d2?,
            d3: d3?,
        }))
    }

    /// MV := MV − AT1STEPMV when the step was made; the step flag := 0
    /// (DEC-34).
    fn restore(&self, m: &mut DeviceMemory, a: &Areas, step: u16) -> Result<(), PcError> {
        if a.d3.get(m, At1Work::stepped) == 1 {
            let mv = a.d2.real(m, LoopTag::mv, step)?;
            let st = a.d2.real(m, LoopTag::at1_step_mv, step)?;
            a.d2.set(m, LoopTag::mv, result(mv - st, step)?);
            if self.s.at1_restore_clears_flags {
                a.d3.set(m, At1Work::stepped, 0);
            }
        }
        Ok(())
    }

    /// An ending: the bits `bits` and BB16 := 1, the counter flags cleared
    /// (DEC-34).
    fn end(&self, m: &mut DeviceMemory, a: &Areas, bits: u16) {
        a.d1.set_bits(m, At1Block::bb, bits | BB16, true);
        self.clear_flags(m, a);
    }

    fn clear_flags(&self, m: &mut DeviceMemory, a: &Areas) {
        if self.s.at1_restore_clears_flags {
            for k in [At1Work::sample_flag, At1Work::tout_flag, At1Work::post_flag] {
                a.d3.set(m, k, 0);
            }
        }
    }

    /// Starts (or restarts) the counter of D3 whose preset flag and count
    /// are `flag` and `counter`.
    fn start(
        &self,
        m: &mut DeviceMemory,
        a: &Areas,
        (flag, counter): (At<u16>, At<u16>),
        p: f32,
        dt: f32,
        step: u16,
    ) -> Result<(), PcError> {
        let s = self.s;
        a.d3.set(m, flag, 0);
        tick(m, a.d3.index(flag), a.d3.index(counter), &s, || {
            count(p, dt, false, &s, step)
        })?;
        Ok(())
    }

    fn body(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), PcError> {
        let e1_on = a.s1.bit(m, InputCtl::ctl, 0);
        let done = a.d1.get(m, At1Block::bb) & BB16 != 0;
        match (e1_on, done) {
            (false, false) => {
                a.d1.set_bits(m, At1Block::bb, ALARMS, false);
                self.restore(m, a, 1)?;
                self.clear_flags(m, a);
                return Ok(());
            }
            (false, true) => {
                a.d1.set_bits(m, At1Block::bb, BB16, false);
                return Ok(());
            }
            (true, true) => return Ok(()),
            (true, false) => {}
        }
        let d2 = a.d2;
        let al = d2.get(m, LoopTag::alm);
        if al & alm::SPA != 0 {
            self.restore(m, a, 1)?;
            self.end(m, a, 0);
            return Ok(());
        }
        if !self.mode.manual(d2.get(m, LoopTag::mode)) {
            self.restore(m, a, 1)?;
            self.end(m, a, BB7);
            return Ok(());
        }
        if al & (alm::PHA | alm::HHA) != 0 {
            self.end(m, a, BB2);
            return Ok(());
        }
        if al & (alm::PLA | alm::LLA) != 0 {
            self.end(m, a, BB3);
            return Ok(());
        }
        let s = self.s;
        let dt = self.sys.dt(m, 2)?;
        let tout1 = d2.real(m, LoopTag::at1_tout1, 2)?;
        let d3 = a.d3;
        let (flag, counter) = (d3.index(At1Work::tout_flag), d3.index(At1Work::tout));
        let t = tick(m, flag, counter, &s, || count(tout1, dt, false, &s, 2))?;
        if t.reached {
            self.end(m, a, BB6);
            return Ok(());
        }
        if d3.get(m, At1Work::post_flag) != 0 {
            let dt = self.sys.dt(m, 3)?;
            let tout2 = d2.real(m, LoopTag::at1_tout2, 3)?;
            let (flag, counter) = (d3.index(At1Work::post_flag), d3.index(At1Work::post));
            let t = tick(m, flag, counter, &s, || count(tout2, dt, false, &s, 3))?;
            if t.reached {
                return self.identify(m, a);
            }
        }
        let ast = d2.real(m, LoopTag::at1_st, 5)?;
        if d3.get(m, At1Work::stepped) != 1 {
            let mv = d2.real(m, LoopTag::mv, 4)?;
            let step = d2.real(m, LoopTag::at1_step_mv, 4)?;
            let mh = d2.real(m, LoopTag::mh, 4)?;
            let ml = d2.real(m, LoopTag::ml, 4)?;
            let e1 = a.s1.real(m, InputCtl::e1, 4)?;
            let t1 = result(mv + step, 4)?;
            if t1 > mh {
                self.end(m, a, BB4);
                return Ok(());
            }
            if t1 < ml {
                self.end(m, a, BB5);
                return Ok(());
            }
            d2.set(m, LoopTag::mv, t1);
            d3.set(m, At1Work::stepped, 1);
            d3.set(m, At1Work::count, 0);
            d3.set(m, At1Work::pv0, e1);
            d3.set(m, At1Work::pv1, e1);
            for k in [
                At1Work::max,
                At1Work::max_count,
                At1Work::max_pv,
                At1Work::r,
                At1Work::l,
            ] {
                d3.set(m, k, 0.0);
            }
            if s.at1_step_starts_sampling {
                let sampling = (At1Work::sample_flag, At1Work::sample);
                self.start(m, a, sampling, ast, dt, 5)?;
            }
            return Ok(());
        }
        let (flag, counter) = (d3.index(At1Work::sample_flag), d3.index(At1Work::sample));
        let t = tick(m, flag, counter, &s, || count(ast, dt, false, &s, 5))?;
        if !t.reached {
            return Ok(());
        }
        // (9) observation.
        let n = d3.get(m, At1Work::count).saturating_add(1);
        d3.set(m, At1Work::count, n);
        let e1 = a.s1.real(m, InputCtl::e1, 6)?;
        let pv1 = d3.real(m, At1Work::pv1, 6)?;
        let t2 = result(e1 - pv1, 6)?;
        d3.set(m, At1Work::pv1, e1);
        let step = d2.real(m, LoopTag::at1_step_mv, 6)?;
        let pn = a.s2.get(m, At1Consts::pn);
        if pn > 1 {
            return Err(PcError::range(6));
        }
        let forward = pn == 1;
        let rising = (!forward && step > 0.0) || (forward && step < 0.0);
        let max = d3.real(m, At1Work::max, 6)?;
        if (rising && t2 > max) || (!rising && t2 < max) {
            d3.set(m, At1Work::max, t2);
            d3.set(m, At1Work::max_count, n as f32);
            d3.set(m, At1Work::max_pv, e1);
            let tout2 = d2.real(m, LoopTag::at1_tout2, 3)?;
            let post = (At1Work::post_flag, At1Work::post);
            self.start(m, a, post, tout2, dt, 3)?;
        }
        Ok(())
    }

    /// (10) identification and (11) the PID constants.
    fn identify(&self, m: &mut DeviceMemory, a: &Areas) -> Result<(), PcError> {
        let (d2, d3) = (a.d2, a.d3);
        let ast = d2.real(m, LoopTag::at1_st, 7)?;
        if ast == 0.0 {
            return Err(PcError::divide(7));
        }
        let max = d3.real(m, At1Work::max, 7)?;
        let r1 = result(max / ast, 7)?;
        let r = r1.abs() / 100.0;
        d3.set(m, At1Work::r, if self.s.at1_stores_r { r } else { r1 });
        if r == 0.0 {
            self.restore(m, a, 7)?;
            self.end(m, a, BB8);
            return Ok(());
        }
        let pv0 = d3.real(m, At1Work::pv0, 7)?;
        let pvm = d3.real(m, At1Work::max_pv, 7)?;
        let cnt = d3.real(m, At1Work::max_count, 7)?;
        let b = result(pvm - r1 * (cnt * ast), 7)?;
        let l = result((pv0 - b) / r1, 7)?;
        d3.set(m, At1Work::l, l);
        if l <= 0.0 {
            self.restore(m, a, 7)?;
            self.end(m, a, BB8);
            return Ok(());
        }
        let ti = d2.real(m, LoopTag::i, 8)?;
        let td = d2.real(m, LoopTag::d, 8)?;
        let step = d2.real(m, LoopTag::at1_step_mv, 8)?;
        let (c, ti, td) = if ti == 0.0 {
            (1.0, 0.0, 0.0)
        } else if td == 0.0 {
            (0.9, 3.33 * l, 0.0)
        } else {
            (1.2, 2.0 * l, 0.5 * l)
        };
        let kp = result(c / (r * l) * (step.abs() / 100.0), 8)?;
        d2.set(m, LoopTag::p, kp);
        d2.set(m, LoopTag::i, result(ti, 8)?);
        d2.set(m, LoopTag::d, result(td, 8)?);
        self.restore(m, a, 8)?;
        self.end(m, a, 0);
        Ok(())
    }
}

impl Instr for At1 {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let m = &*cx.mem;
        let a = Areas {
            s1: Area::of(m, &self.s1, 3)?,
            d1: Area::of(m, &self.d1, 1)?,
            s2: Area::of(m, &self.s2, 1)?,
            d2: Area::of(m, &self.d2, LoopTag::WORDS as u32)?,
            d3: Area::of(m, &self.d3, At1Work::WORDS as u32)?,
        };
        self.sys.run(cx.mem, |m| {
            self.body(m, &a)?;
            // DEC-35: BB1 = BB2 ∨ … ∨ BB8 at the end of every execution.
            let bb = a.d1.get(m, At1Block::bb);
            a.d1.set_bits(m, At1Block::bb, 1, bb & ALARMS != 0);
            Ok(())
        })
    }
}
