//! Ramp generators RAMP, HACKLE, TRIANGLE (002 §6.11 L7819-8049; spec
//! aplc.md §4.14, decisions D9, D10, D20): `OP S1 S2 D1 S3 D2`, from S1 to
//! S2 in S3 scans (S3 > 0, else error 64) with the step (S2 − S1) / S3
//! rounded half away from zero; D1 the output (D or V), D2 the done bit.
//! A rising edge of the power flow starts from S1; a falling edge turns D2
//! OFF and holds D1.

use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr, LocalSlot};
use softplc_ir::local_state;
use softplc_ir::ops::{BitArg, WordArg};
use softplc_lang::compile::Args;
use softplc_lang::isa::{Def, Doc, Steps};

use crate::constant::Width;
use crate::devices::{parse_device, Dev};
use crate::num::{self, E_VALUE};
use crate::resolve::{ArgsExt, BitUse};

static DOC: Doc = Doc {
    family: "ramps",
    cite: "002 §6.11 L7819-8049",
    notes: "step rounded half away from zero (D20); RAMP stops at S2 with D2 ON; HACKLE: the scan reaching S2 shows S2 with D2 ON, the next restarts at S1 (tooth S3 + 1 scans, D10); TRIANGLE: period 2 × S3, D2 ON on the scan back at S1 (D9)",
};

pub static DEFS: &[Def] = &[
    // 002 §6.11.2 L7819 RAMP
    Def::app("RAMP", &DOC, |a| compile(a, Kind::Ramp))
        .always()
        .steps(Steps::Fixed(12)),
    // 002 §6.11.3 L7892 HACKLE
    Def::app("HACKLE", &DOC, |a| compile(a, Kind::Hackle))
        .always()
        .steps(Steps::Fixed(12)),
    // 002 §6.11.4 L7976 TRIANGLE
    Def::app("TRIANGLE", &DOC, |a| compile(a, Kind::Triangle))
        .always()
        .steps(Steps::Fixed(12)),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Ramp,
    Hackle,
    Triangle,
}

local_state! {
    struct RampState {
        prev: bool,
        /// Steps done in the current tooth or period.
        k: u32,
        /// RAMP reached S2 / HACKLE showed S2 on the previous scan.
        done: bool,
    }
}

#[derive(Debug)]
struct Ramp {
    kind: Kind,
    s1: WordArg,
    s2: WordArg,
    scans: WordArg,
    d1: WordArg,
    d2: BitArg,
    st: LocalSlot<RampState>,
}

fn compile(a: &mut Args<'_, '_>, kind: Kind) -> Option<Box<dyn Instr>> {
    if !a.count(&[5]) {
        return None;
    }
    let s1 = a.word_at(0, Width::W16, false);
    let s2 = a.word_at(1, Width::W16, false);
    let dv = matches!(parse_device(&a.text(2).to_ascii_uppercase()), Ok(Some(d)) if d.group.is_none() && matches!(d.dev, Dev::D | Dev::V));
    if !dv {
        a.error(
            2,
            format!(
                "`{}`: the output is D or V (APLC programming manual §6.11.2)",
                a.text(2)
            ),
        );
    }
    let d1 = a.word_at(2, Width::W16, true);
    let scans = a.word_at(3, Width::W16, false);
    let d2 = a.bit_at(4, BitUse::SetRst)?;
    if !dv {
        return None;
    }
    Some(Box::new(Ramp {
        kind,
        s1: s1?,
        s2: s2?,
        scans: scans?,
        d1: d1?,
        d2,
        st: a.local(),
    }))
}

impl Ramp {
    fn value(s1: i32, s2: i32, n: i32, k: i32) -> i32 {
        if k >= n {
            return s2;
        }
        let step = ((s2 - s1) as f64 / n as f64).round() as i32;
        let v = s1 + k * step;
        if s2 >= s1 {
            v.min(s2)
        } else {
            v.max(s2)
        }
    }
}

impl Instr for Ramp {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = num::read16(cx.mem, &self.s1)? as i32;
        let s2 = num::read16(cx.mem, &self.s2)? as i32;
        let n = num::read16(cx.mem, &self.scans)? as i32;
        if n <= 0 {
            return Err(E_VALUE);
        }
        let mut st = cx.local(&self.st);
        let rising = !st.prev;
        st.prev = true;
        if rising || self.kind == Kind::Hackle && st.done {
            st.k = 0;
            st.done = false;
        } else if !(self.kind == Kind::Ramp && st.done) {
            st.k += 1;
        }
        let k = st.k as i32;
        let (v, on) = match self.kind {
            Kind::Ramp | Kind::Hackle => {
                let v = Ramp::value(s1, s2, n, k);
                st.done = v == s2;
                (v, v == s2)
            }
            Kind::Triangle => {
                if k > 2 * n {
                    st.k = 1;
                }
                let k = st.k as i32;
                let v = if k <= n {
                    Ramp::value(s1, s2, n, k)
                } else {
                    Ramp::value(s2, s1, n, k - n)
                };
                (v, k == 2 * n)
            }
        };
        cx.mem.write16(&self.d1, v as u16)?;
        cx.mem.write_bit(&self.d2, on)?;
        cx.set_local(&self.st, st);
        Ok(())
    }

    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mut st = cx.local(&self.st);
        if st.prev {
            cx.mem.write_bit(&self.d2, false)?;
        }
        st.prev = false;
        cx.set_local(&self.st, st);
        Ok(())
    }
}
