//! S.PHPL, high/low alarm check (000 §9.8).

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, def, dummy, rate_count, real, result, set_f, window, PcError, Sys, Window,
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

const ALM: usize = LoopTag::alm.offset();
const INH: usize = LoopTag::inh.offset();
const PV: usize = LoopTag::pv.offset();
const RH: usize = LoopTag::rh.offset();
const RL: usize = LoopTag::rl.offset();
const HS: usize = LoopTag::hs.offset();
const CTIM: usize = LoopTag::ctim.offset();
const DPL: usize = LoopTag::dpl.offset();
const REF: usize = LoopTag::rate_ref.offset();
const FLAG: usize = LoopTag::rate_flag.offset();
const COUNT: usize = LoopTag::rate_count.offset();

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
        let s1 = cx.mem.block_start(&self.s1, 2)?;
        let d1 = cx.mem.block_start(&self.d1, 3)?;
        let d2 = cx.mem.block_start(&self.d2, LOOP_WORDS)?;
        self.sys.run(cx.mem, |m| {
            let bbi = d1 + 2;
            if m.words[d2 + ALM] & alm::SPA != 0 {
                let pv = real(m, d2 + PV, 5)?;
                let rh = real(m, d2 + RH, 5)?;
                let rl = real(m, d2 + RL, 5)?;
                set_f(m, d1, percent(pv, rh, rl, 5)?);
                m.words[bbi] &= !BB_PHPL;
                m.words[d2 + ALM] &= !ALM_PHPL;
                if !self.s.early_end_skips_counters {
                    // DEC-4's alternative: the window advances, nothing is evaluated.
                    let n = rate_count(real(m, d2 + CTIM, 3)?, self.sys.dt(m, 3)?, 3)?;
                    let w = window(m, d2 + FLAG, d2 + COUNT, n, &self.s)?;
                    if matches!(w, Window::Start | Window::Evaluate { retake: true }) {
                        let e1 = real(m, s1, 3)?;
                        set_f(m, d2 + REF, e1);
                    }
                }
                return Ok(());
            }
            // (1) engineering-value inverse conversion of the limits.
            let rh = real(m, d2 + RH, 1)?;
            let rl = real(m, d2 + RL, 1)?;
            let mut lim = [0.0f32; 4];
            for (k, v) in lim.iter_mut().enumerate() {
                *v = percent(real(m, d2 + LoopTag::ph.offset() + 2 * k, 1)?, rh, rl, 1)?;
            }
            let [ph, pl, hh, ll] = lim;
            // (2) high/low checks.
            let e1 = real(m, s1, 2)?;
            let hs = real(m, d2 + HS, 2)?;
            let inh = m.words[d2 + INH];
            let (mut almw, mut bbw) = (m.words[d2 + ALM], m.words[bbi]);
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
            m.words[d2 + ALM] = almw;
            m.words[bbi] = bbw;
            // (3) change-rate check.
            let ctim = real(m, d2 + CTIM, 3)?;
            let dt = self.sys.dt(m, 3)?;
            let n = rate_count(ctim, dt, 3)?;
            match window(m, d2 + FLAG, d2 + COUNT, n, &self.s)? {
                Window::Skip | Window::Hold => {}
                Window::Start => set_f(m, d2 + REF, e1),
                Window::Evaluate { retake } => {
                    let dpl = real(m, d2 + DPL, 3)?;
                    let d = result(e1 - real(m, d2 + REF, 3)?, 3)?;
                    self.inh
                        .apply(inh, &mut almw, alm::DPPA, &mut bbw, bb::BB4, d >= dpl);
                    self.inh
                        .apply(inh, &mut almw, alm::DPNA, &mut bbw, bb::BB5, d <= -dpl);
                    if retake {
                        set_f(m, d2 + REF, e1);
                    }
                }
            }
            let mut any = bbw & (bb::BB2 | bb::BB3 | bb::BB4 | bb::BB5) != 0;
            if !self.s.phpl_bb1_or {
                any |= hha || lla;
            }
            put(&mut bbw, bb::BB1, any);
            m.words[d2 + ALM] = almw;
            m.words[bbi] = bbw;
            // (4) engineering-value conversion.
            set_f(m, d2 + PV, result((rh - rl) / 100.0 * e1 + rl, 4)?);
            set_f(m, d1, e1);
            Ok(())
        })
    }
}
