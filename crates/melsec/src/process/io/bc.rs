//! S.BC, batch counter.

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;

use crate::process::common::{area, dummy, rate_count, window, Area, BitBlockMemory, Sys, Window};
use crate::process::settings::ProcessSettings;
use crate::process::tag::{alm, bb, put, Inh, LoopTag, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

softplc_ir::layout! {
    /// The loop tag as S.BC reads it (000 §8.6 L6260-6311): BIN32 where
    /// the PID loops keep floats.
    pub struct BcTag[128] {
        /// Set value 1 (BIN32).
        sv1: i32 @ 14,
        /// Set value 2 (BIN32).
        sv2: i32 @ 16,
        /// High alarm value (BIN32).
        ph: i32 @ 26,
        /// Change-rate check time, s (float).
        ctim: f32 @ 42,
        /// Change-rate alarm value (BIN32).
        dpl: i32 @ 44,
        /// Past values: the reference sample Xn-m (BIN32).
        reference: i32 @ 126,
    }
}

softplc_ir::layout! {
    /// The input data (S1) of S.BC.
    pub struct BcInput[2] {
        /// E1: the count (BIN32, 0 … 2147483647).
        e1: i32 @ 0,
    }
}

/// S.BC's D2 as its loop memory.
pub static BC_TAG: softplc_ir::listing::LoopMemory = softplc_ir::listing::LoopMemory {
    name: "S.BC loop tag",
    fields: BcTag::FIELDS,
    first: 0,
    stride: 0,
    count: None,
    settings: None,
};

/// 000 §8.6 S.BC `S.BC S1 D1 S2(dmy) D2` (L5997-6423), batch counter.
///
/// Operands: S1 +0/+1 E1 (BIN32, 0 … 2147483647); D1 +0 BW1 = b0, BW2 = b1
/// (other bits left alone), +1 BB (BB1 alarm, BB2 high alarm, BB3 change
/// rate alarm); S2 dummy; D2: ALM +3 (PHA, DPPA), INH +4 (ERRI, PHI, DPPI),
/// +14 SV1, +16 SV2, +26 PH, +44 DPL (BIN32), +42 CTIM (float s), past values
/// +124 preset flag, +125 counter, +126/+127 Xn-m (BIN32). S.BC has no
/// MODE and no loop stop.
///
/// Processing: (1) E1 > PH → PHA = BB2 = 1, else 0. (2) change rate with
/// m = int(CTIM/ΔT) (m = 0: nothing is done): the window of DEC-18 (the
/// start execution takes Xn-m; every m-th execution after it evaluates
/// (Xn − Xn-m) ≥ DPL → DPPA = BB3 = 1, else 0, and re-takes Xn-m; in
/// between the alarm holds). BB1 = BB2 ∨ BB3. (3) E1 < 0 → BW1 = BW2 = 0;
/// otherwise BW1 = E1 ≥ SV1, BW2 = E1 ≥ SV2. Comparisons are signed 32-bit,
/// the difference without overflow.
///
/// Errors (4100; SD1503 per Table 14.2: 1 high check, 2 change-rate check,
/// 3 output conversion): bad CTIM or ΔT float is SD1502 = 1, CTIM or ΔT < 0
/// is 2, ΔT = 0 is 5, m > 32767 is 4 (all at 2).
#[derive(Debug)]
pub(crate) struct Bc {
    sys: Sys,
    s: ProcessSettings,
    inh: Inh,
    s1: Block,
    d1: Block,
    d2: Block,
}

impl Bc {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 2, "block memory");
        let s2 = dummy(a, 2);
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        s2?;
        Some(Box::new(Bc {
            sys,
            s,
            inh: Inh::new(&s),
            s1: s1?,
            d1: d1?,
            d2: d2?,
        }))
    }
}

impl Instr for Bc {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 2)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        self.sys.run(cx.mem, |m| {
            let e1 = s1.get(m, BcInput::e1);
            let (ph, sv1, sv2, dpl) = (
                d2.get(m, BcTag::ph),
                d2.get(m, BcTag::sv1),
                d2.get(m, BcTag::sv2),
                d2.get(m, BcTag::dpl),
            );
            let inh = d2.get(m, LoopTag::inh);
            let (mut almw, mut bbw) = (d2.get(m, LoopTag::alm), d1.get(m, BitBlockMemory::bb));
            // (1) high check.
            self.inh
                .apply(inh, &mut almw, alm::PHA, &mut bbw, bb::BB2, e1 > ph);
            d2.set(m, LoopTag::alm, almw);
            d1.set(m, BitBlockMemory::bb, bbw);
            // (2) change-rate check.
            let ctim = d2.real(m, BcTag::ctim, 2)?;
            let dt = self.sys.dt(m, 2)?;
            let n = rate_count(ctim, dt, 2)?;
            let flag = d2.index(LoopTag::rate_flag);
            let counter = d2.index(LoopTag::rate_count);
            match window(m, flag, counter, n, &self.s)? {
                Window::Skip | Window::Hold => {}
                Window::Start => d2.set(m, BcTag::reference, e1),
                Window::Evaluate { retake } => {
                    let d = e1 as i64 - d2.get(m, BcTag::reference) as i64;
                    self.inh.apply(
                        inh,
                        &mut almw,
                        alm::DPPA,
                        &mut bbw,
                        bb::BB3,
                        d >= dpl as i64,
                    );
                    if retake {
                        d2.set(m, BcTag::reference, e1);
                    }
                }
            }
            let any = bbw & (bb::BB2 | bb::BB3) != 0;
            put(&mut bbw, bb::BB1, any);
            d2.set(m, LoopTag::alm, almw);
            d1.set(m, BitBlockMemory::bb, bbw);
            // (3) output conversion.
            let mut bw = d1.get(m, BitBlockMemory::bw);
            put(&mut bw, 1, e1 >= 0 && e1 >= sv1);
            put(&mut bw, 2, e1 >= 0 && e1 >= sv2);
            d1.set(m, BitBlockMemory::bw, bw);
            Ok(())
        })
    }
}
