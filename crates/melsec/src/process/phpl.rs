//! S.PHPL, high/low alarm check (000 §9.8).

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, def, dummy, rate_count, result, window, Area, BlockMemory, Input, PcError, Sys, Window,
};
use super::settings::ProcessSettings;
use super::tag::{alm, bb, put, Inh, LoopTag, LOOP_TAG, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

static PHPL: Doc = Doc {
    family: "process control: control",
    cite: "000 §9.8 L12747-13518",
    notes: "f32; PH/PL/HH/LL with hysteresis HS, change-rate window of m = int(CTIM/ΔT) \
            (DEC-18), BB1 = BB2 ∨ BB3 ∨ BB4 ∨ BB5 (DEC-19), PV written",
};

pub static DEFS: &[Def] = &[def("S.PHPL", 4, &PHPL, Phpl::compile).loop_memory(3, &LOOP_TAG)];

/// The alarms S.PHPL owns.
const ALM_PHPL: u16 = alm::DPNA | alm::DPPA | alm::LLA | alm::HHA | alm::PLA | alm::PHA;
const BB_PHPL: u16 = bb::BB1 | bb::BB2 | bb::BB3 | bb::BB4 | bb::BB5;

/// 000 §9.8 S.PHPL `S.PHPL S1 D1 S2(dmy) D2` (L12747-13518), high/low alarm
/// check.
///
/// Operands: S1 +0 E1 (%, normally S.IN's BW); D1 +0 BW (%), +2 BB (BB1
/// alarm, BB2 high, BB3 low, BB4 positive change rate, BB5 negative); S2
/// dummy; D2 the loop tag: ALM +3 (SPA, HHA, LLA, PHA, PLA, DPPA, DPNA), INH
/// +4 (ERRI and the matching inhibits), PV +10 (written), RH +22, RL +24, PH
/// +26, PL +28, HH +30, LL +32 (engineering units), HS +40 (%), CTIM +42 (s),
/// DPL +44 (%); past values +124 preset flag, +125 counter, +126/+127 E1n-m.
///
/// Processing (L13289-13508): (5) loop stop (SPA = 1): BW = 100/(RH − RL) ×
/// (PV − RL), BB1..BB5 and the six alarms := 0, end (the window does not
/// move, DEC-4; the alternative advances it and re-takes E1n-m). (1) X' = 100/(RH − RL) × (X − RL) for PH, PL, HH, LL.
/// (2) E1 ≥ PH' → PHA = BB2 = 1, E1 ≤ PH' − HS → 0, between: held; E1 ≤ PL'
/// → PLA = BB3 = 1, E1 ≥ PL' + HS → 0; HHA and LLA the same with no BB bit;
/// each 0 under its inhibit or ERRI. (3) change rate, m = int(CTIM/ΔT)
/// (m = 0: nothing, the alarms hold): the DEC-18 window — the start
/// execution takes E1n-m, each m-th execution after it evaluates E1 − E1n-m
/// (≥ DPL → DPPA = BB4 = 1, else 0; ≤ −DPL → DPNA = BB5 = 1, else 0) and
/// re-takes it, the alarms hold in between (the alternative evaluates on
/// every execution). BB1 = BB2 ∨ BB3 ∨ BB4 ∨ BB5 (DEC-19; the alternative
/// adds HHA ∨ LLA). (4) PV = (RH − RL)/100 × E1 + RL; BW = E1.
///
/// Errors (4100; SD1503 per Table 14.2: 1 inverse conversion, 2 high/low
/// check, 3 change-rate check, 4 engineering conversion, 5 loop stop): a bad
/// float is SD1502 = 1, RH = RL is 5 (at 1, or 5 on loop stop), CTIM or ΔT
/// < 0 is 2, ΔT = 0 is 5, m > 32767 is 4 (at 3).
#[derive(Debug)]
struct Phpl {
    sys: Sys,
    s: ProcessSettings,
    inh: Inh,
    s1: Block,
    d1: Block,
    d2: Block,
}

impl Phpl {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 3, "block memory");
        let s2 = dummy(a, 2);
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        s2?;
        Some(Box::new(Phpl {
            sys,
            s,
            inh: Inh::new(&s),
            s1: s1?,
            d1: d1?,
            d2: d2?,
        }))
    }
}

/// 100/(RH − RL) × (x − RL).
fn percent(x: f32, rh: f32, rl: f32, step: u16) -> Result<f32, PcError> {
    if rh == rl {
        return Err(PcError::divide(step));
    }
    result(100.0 / (rh - rl) * (x - rl), step)
}

/// A hysteresis row triple: 1 on `set`, 0 on `reset`, else the last value.
fn hyst(set: bool, reset: bool, last: bool) -> bool {
    set || (!reset && last)
}

impl Instr for Phpl {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        let (flag, counter) = (d2.index(LoopTag::rate_flag), d2.index(LoopTag::rate_count));
        self.sys.run(cx.mem, |m| {
            if d2.get(m, LoopTag::alm) & alm::SPA != 0 {
                let pv = d2.real(m, LoopTag::pv, 5)?;
                let rh = d2.real(m, LoopTag::rh, 5)?;
                let rl = d2.real(m, LoopTag::rl, 5)?;
                d1.set(m, BlockMemory::bw, percent(pv, rh, rl, 5)?);
                d1.set_bits(m, BlockMemory::bb, BB_PHPL, false);
                d2.set_bits(m, LoopTag::alm, ALM_PHPL, false);
                if !self.s.early_end_skips_counters {
                    // DEC-4's alternative: the window advances, nothing is evaluated.
                    let ctim = d2.real(m, LoopTag::ctim, 3)?;
                    let n = rate_count(ctim, self.sys.dt(m, 3)?, 3)?;
                    let w = window(m, flag, counter, n, &self.s)?;
                    if matches!(w, Window::Start | Window::Evaluate { retake: true }) {
                        let e1 = s1.real(m, Input::e1, 3)?;
                        d2.set(m, LoopTag::rate_ref, e1);
                    }
                }
                return Ok(());
            }
            // (1) engineering-value inverse conversion of the limits.
            let rh = d2.real(m, LoopTag::rh, 1)?;
            let rl = d2.real(m, LoopTag::rl, 1)?;
            let mut lim = [0.0f32; 4];
            let fields = [LoopTag::ph, LoopTag::pl, LoopTag::hh, LoopTag::ll];
            for (v, f) in lim.iter_mut().zip(fields) {
                *v = percent(d2.real(m, f, 1)?, rh, rl, 1)?;
            }
            let [ph, pl, hh, ll] = lim;
            // (2) high/low checks.
            let e1 = s1.real(m, Input::e1, 2)?;
            let hs = d2.real(m, LoopTag::hs, 2)?;
            let inh = d2.get(m, LoopTag::inh);
            let (mut almw, mut bbw) = (d2.get(m, LoopTag::alm), d1.get(m, BlockMemory::bb));
            let mut none = 0u16;
            let was = |bit: u16| almw & bit != 0;
            let pha = hyst(e1 >= ph, e1 <= result(ph - hs, 2)?, was(alm::PHA));
            let pla = hyst(e1 <= pl, e1 >= result(pl + hs, 2)?, was(alm::PLA));
            let hha = hyst(e1 >= hh, e1 <= result(hh - hs, 2)?, was(alm::HHA));
            let lla = hyst(e1 <= ll, e1 >= result(ll + hs, 2)?, was(alm::LLA));
            self.inh
                .apply(inh, &mut almw, alm::PHA, &mut bbw, bb::BB2, pha);
            self.inh
                .apply(inh, &mut almw, alm::PLA, &mut bbw, bb::BB3, pla);
            let hha = self.inh.apply(inh, &mut almw, alm::HHA, &mut none, 0, hha);
            let lla = self.inh.apply(inh, &mut almw, alm::LLA, &mut none, 0, lla);
            d2.set(m, LoopTag::alm, almw);
            d1.set(m, BlockMemory::bb, bbw);
            // (3) change-rate check.
            let ctim = d2.real(m, LoopTag::ctim, 3)?;
            let dt = self.sys.dt(m, 3)?;
            let n = rate_count(ctim, dt, 3)?;
            match window(m, flag, counter, n, &self.s)? {
                Window::Skip | Window::Hold => {}
                Window::Start => d2.set(m, LoopTag::rate_ref, e1),
                Window::Evaluate { retake } => {
                    let dpl = d2.real(m, LoopTag::dpl, 3)?;
                    let d = result(e1 - d2.real(m, LoopTag::rate_ref, 3)?, 3)?;
                    self.inh
                        .apply(inh, &mut almw, alm::DPPA, &mut bbw, bb::BB4, d >= dpl);
                    self.inh
                        .apply(inh, &mut almw, alm::DPNA, &mut bbw, bb::BB5, d <= -dpl);
                    if retake {
                        d2.set(m, LoopTag::rate_ref, e1);
                    }
                }
            }
            let mut any = bbw & (bb::BB2 | bb::BB3 | bb::BB4 | bb::BB5) != 0;
            if !self.s.phpl_bb1_or {
                any |= hha || lla;
            }
            put(&mut bbw, bb::BB1, any);
            d2.set(m, LoopTag::alm, almw);
            d1.set(m, BlockMemory::bb, bbw);
            // (4) engineering-value conversion.
            d2.set(m, LoopTag::pv, result((rh - rl) / 100.0 * e1 + rl, 4)?);
            d1.set(m, BlockMemory::bw, e1);
            Ok(())
        })
    }
}
