//! S.DUTY, time-proportional ON/OFF output.

use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;

use super::stage::{velocity, Bb, Flow, Kit};
use crate::process::common::{area, count, dummy, tick, Area, BitBlockMemory, PcError, Sys};
use crate::process::settings::ProcessSettings;
use crate::process::tag::{LoopTag, LOOP_WORDS};
use crate::{Args, ExecCtx, Instr};

/// 000 §8.5 S.DUTY `S.DUTY S1 D1 S2(dmy) D2` (L5307-5996), time-proportional
/// ON/OFF output.
///
/// Operands: S1 +0 E1 = ΔMV (%); D1 +0 BW1 = b0 (ON/OFF; the other bits are
/// left alone), +1 BB (BB1 alarm, BB2 output high, BB3 output low, BB4
/// change rate); S2 dummy; D2 the loop tag as S.OUT1 (MODE, ALM, INH with
/// TRKF, MV +12, MH, ML, DML, I +54, MVP +62, ALM2 +116) plus CTDUTY +68
/// (1.0 s) and the past values +118 period-counter preset flag, +119 period
/// counter, +120 output counter, +121 output-ON counter.
///
/// Processing: (7) loop stop, (1) mode judgment, (2) input addition, (3)
/// change-rate/high-low limiter (only when T ≠ MV, DEC-10), (4) reset windup
/// (DEC-11) exactly as S.OUT1 (`super::stage`); the manual modes go on to
/// (5) with the operator's MV. (5) ON-time conversion: the period counter
/// (spec §1.3.1, N = round(CTDUTY/ΔT), DEC-1 … DEC-3) — on a reach the ON
/// counter := round(MV/100 × N) (halves up, 0 … 32767; DEC-12) and the
/// output counter := 0, otherwise the output counter + 1. (6) BW1 = output
/// counter < ON counter. So the first period after clearing is OFF; loop
/// stop and the SM1501 hold end before (5) (DEC-4: the counters do not move;
/// the alternative advances the period and the output counter).
///
/// Errors (4100; SD1503 per Table 14.2: 1 input addition, 2 limiter, 3
/// reset windup, 4 ON-time conversion): a bad float is SD1502 = 1, ΔT or
/// CTDUTY < 0 is 2, ΔT = 0 is 5, CTDUTY/ΔT > 32767 is 4 (at 4).
#[derive(Debug)]
pub(crate) struct Duty {
    k: Kit,
    s1: Block,
    d1: Block,
    d2: Block,
}

impl Duty {
    pub fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        if !s.duty_on_count_rounds {
            a.error(
                usize::MAX,
                "S.DUTY: `duty_on_count_rounds = false` has no described alternative \
                 (Process Control Instructions manual §8.5 rounds the ON counter)",
            );
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 2, "block memory");
        let s2 = dummy(a, 2);
        let d2 = area(a, 3, LOOP_WORDS, "loop tag");
        s2?;
        Some(Box::new(Duty {
            k: Kit::new(sys, s),
            s1: s1?,
            d1: d1?,
            d2: d2?,
        }))
    }

    /// (5) ON-time conversion (and the counter part alone for an early end
    /// under the DEC-4 alternative, `recompute` false).
    fn period(
        &self,
        m: &mut softplc_ir::device::DeviceMemory,
        d2: Area,
        recompute: bool,
    ) -> Result<(), PcError> {
        let s = &self.k.s;
        let ct = d2.real(m, LoopTag::ctduty, 4)?;
        let dt = self.k.sys.dt(m, 4)?;
        let mut n = 0u16;
        let (flag, counter) = (d2.index(LoopTag::duty_flag), d2.index(LoopTag::duty_count));
        let t = tick(m, flag, counter, s, || {
            n = count(ct, dt, false, s, 4)?;
            Ok(n)
        })?;
        if t.reached {
            if recompute {
                let mv = d2.real(m, LoopTag::mv, 4)?;
                let on = (mv / 100.0 * n as f32 + 0.5).floor();
                d2.set(m, LoopTag::duty_on, on.clamp(0.0, 32767.0) as u16);
            }
            d2.set(m, LoopTag::duty_out, 0);
        } else {
            let out = d2.get(m, LoopTag::duty_out);
            d2.set(m, LoopTag::duty_out, out.saturating_add(1));
        }
        Ok(())
    }
}

impl Instr for Duty {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 2)?;
        let d2 = Area::of(cx.mem, &self.d2, LOOP_WORDS)?;
        self.k.sys.run(cx.mem, |m| {
            match velocity(&self.k, m, s1, Bb(d1, BitBlockMemory::bb), d2)? {
                Flow::Output => {}
                Flow::Idle => return Ok(()),
                Flow::Stopped | Flow::Held => {
                    if !self.k.s.early_end_skips_counters {
                        self.period(m, d2, false)?;
                    }
                    return Ok(());
                }
            }
            self.period(m, d2, true)?;
            // (6) output conversion.
            let on = d2.get(m, LoopTag::duty_out) < d2.get(m, LoopTag::duty_on);
            d1.set_bits(m, BitBlockMemory::bw, 1, on);
            Ok(())
        })
    }
}
