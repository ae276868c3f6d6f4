//! Manual/auto transfer elements (000 §9.25-§9.26): S.BUMP, S.AMR. Not in
//! Table 14.2: every error reports SD1503 = 1.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, bit, def, history_in_block_memory, real, result, set_f, Areas, PcError, Sys,
};
use crate::{Args, ExecCtx, Instr};

static BUMP: Doc = Doc {
    family: "process control: manual/auto",
    cite: "000 §9.25 L18570-18786",
    notes:
        "manual: BW = E2, Xq = Xp = E2 − E1; auto: linear ramp of the deviation while |Xp| > a, \
            then first-order lag; T ≤ ΔT gives BW = E1",
};
static AMR: Doc = Doc {
    family: "process control: manual/auto",
    cite: "000 §9.26 L18787-19002",
    notes: "e1 = 0: BW = E3; e1 = 1: ±|E1|·ΔT / |E2|·ΔT on e2/e3 (bits b1/b2), clamped to d1/d2",
};

pub static DEFS: &[Def] = &[
    def("S.BUMP", 4, &BUMP, Bump::compile),
    def("S.AMR", 4, &AMR, Amr::compile),
];

/// 000 §9.25 S.BUMP L18570-18786.
///
/// 000 §9.25 S.BUMP `S.BUMP S1 D1 S2 D2`: S1 +0 E1 output setting value
/// (auto), +2 E2 output control value (manual), +4 e1 (b0: 0 manual, 1
/// auto); D1 +0 BW; S2 +0 T delay time (s), +2 a delay zone (%); D2 local +0
/// Xq initial deviation, +2 Xp deviation (L18720-18783).
/// * e1 = 0: BW = E2, Xq = Xp = E2 − E1.
/// * e1 = 1, |Xp| > a: Xp′ = Xp − ΔT/T × Xq, BW = E1 + Xp′, but BW = E1 when
///   |Xp| ≤ ΔT/T × |Xq|.
/// * e1 = 1, |Xp| ≤ a: Xp′ = T/(T + ΔT) × Xp, BW = E1 + Xp′, but BW = E1 when
///   |Xp| < 10⁻⁴.
/// * Xp := Xp′ in every auto execution; when T ≤ ΔT, BW = E1 (not an error,
///   spec §5), with Xp′ from the row, or 0 where the row divides by 0.
#[derive(Debug)]
struct Bump {
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl Bump {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 5, "input data");
        let d1 = area(a, 1, 2, "block memory");
        let s2 = area(a, 2, 4, "operation constants");
        let d2 = area(a, 3, 4, "local work memory");
        Some(Box::new(Bump {
            sys,
            s1: s1?,
            d1: d1?,
            s2: s2?,
            d2: d2?,
        }))
    }

    fn body(
        &self,
        m: &mut DeviceMemory,
        s1: usize,
        d1: usize,
        s2: usize,
        d2: usize,
    ) -> Result<(), PcError> {
        let e1 = real(m, s1, 1)?;
        let e2 = real(m, s1 + 2, 1)?;
        let auto = bit(m, s1 + 4, 0);
        let t = real(m, s2, 1)?;
        let zone = real(m, s2 + 2, 1)?;
        let dt = self.sys.dt(m, 1)?;
        if !auto {
            let x = result(e2 - e1, 1)?;
            set_f(m, d1, e2);
            set_f(m, d2, x);
            set_f(m, d2 + 2, x);
            return Ok(());
        }
        let xq = real(m, d2, 1)?;
        let xp = real(m, d2 + 2, 1)?;
        let (xn, bw) = if xp.abs() > zone {
            let step = dt / t * xq;
            let xn = xp - step;
            (xn, if xp.abs() <= step.abs() { e1 } else { e1 + xn })
        } else {
            let xn = t / (t + dt) * xp;
            (xn, if xp.abs() < 1e-4 { e1 } else { e1 + xn })
        };
        // T ≤ ΔT: BW = E1, not an error, also where the row divides by 0.
        let (xn, bw) = if t <= dt {
            (if xn.is_finite() { xn } else { 0.0 }, e1)
        } else {
            (xn, bw)
        };
        set_f(m, d1, result(bw, 1)?);
        set_f(m, d2 + 2, result(xn, 1)?);
        Ok(())
    }
}

impl Instr for Bump {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = cx.mem.block_start(&self.s1, 5)?;
        let d1 = cx.mem.block_start(&self.d1, 2)?;
        let s2 = cx.mem.block_start(&self.s2, 4)?;
        let d2 = cx.mem.block_start(&self.d2, 4)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2, d2))
    }
}

/// 000 §9.26 S.AMR L18787-19002.
///
/// 000 §9.26 S.AMR `S.AMR S1 D1 S2 D2(dmy)`: S1 +0 E1 increase rate, +2 E2
/// decrease rate, +4 E3 output setting value, +6 e1 (b0: 0 manual, 1 auto),
/// e2 (b1: increase), e3 (b2: decrease); D1 +0 BW; S2 +0 d1 upper limit, +2
/// d2 lower limit (L18975-18998).
/// * e1 = 0: BW = E3.
/// * e1 = 1, e2 = 1, e3 = 0: BW = BW + |E1|·ΔT, d1 when above d1.
/// * e1 = 1, e2 = 0, e3 = 1: BW = BW − |E2|·ΔT, d2 when below d2.
/// * e1 = 1, e2 = e3: BW holds.
#[derive(Debug)]
struct Amr {
    sys: Sys,
    areas: Areas,
}

impl Amr {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        history_in_block_memory(a)?;
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [7, 2, 4]);
        Some(Box::new(Amr { sys, areas: areas? }))
    }

    fn body(&self, m: &mut DeviceMemory, s1: usize, d1: usize, s2: usize) -> Result<(), PcError> {
        let up = real(m, s1, 1)?;
        let down = real(m, s1 + 2, 1)?;
        let e3 = real(m, s1 + 4, 1)?;
        let hi = real(m, s2, 1)?;
        let lo = real(m, s2 + 2, 1)?;
        let dt = self.sys.dt(m, 1)?;
        let bits = m.words[s1 + 6];
        let bw = if bits & 1 == 0 {
            e3
        } else {
            let bw = real(m, d1, 1)?;
            match (bits >> 1 & 1, bits >> 2 & 1) {
                (1, 0) => {
                    let v = result(bw + up.abs() * dt, 1)?;
                    if v > hi {
                        hi
                    } else {
                        v
                    }
                }
                (0, 1) => {
                    let v = result(bw - down.abs() * dt, 1)?;
                    if v < lo {
                        lo
                    } else {
                        v
                    }
                }
                _ => bw,
            }
        };
        set_f(m, d1, bw);
        Ok(())
    }
}

impl Instr for Amr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2))
    }
}
