//! Manual/auto transfer elements (000 §9.25-§9.26): S.BUMP, S.AMR. Not in
//! Table 14.2: every error reports SD1503 = 1.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, def, history_in_block_memory, result, Area, Areas, BlockMemory, PcError, Sys,
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

softplc_ir::layout! {
    /// The input data (S1) of S.BUMP.
    pub struct BumpInput[5] {
        /// E1: the output setting value (auto).
        e1: f32 @ 0,
        /// E2: the output control value (manual).
        e2: f32 @ 2,
        /// e1 = b0: 0 manual, 1 auto.
        ctl: u16 @ 4,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.BUMP.
    pub struct BumpConsts[4] {
        /// T: the delay time, s.
        t: f32 @ 0,
        /// a: the delay zone, %.
        zone: f32 @ 2,
    }
}

softplc_ir::layout! {
    /// The local work memory (D2) of S.BUMP.
    pub struct BumpWork[4] {
        /// Xq: the initial deviation.
        xq: f32 @ 0,
        /// Xp: the deviation.
        xp: f32 @ 2,
    }
}

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
        s1: Area,
        d1: Area,
        s2: Area,
        d2: Area,
    ) -> Result<(), PcError> {
        let e1 = s1.real(m, BumpInput::e1, 1)?;
        let e2 = s1.real(m, BumpInput::e2, 1)?;
        let auto = s1.bit(m, BumpInput::ctl, 0);
        let t = s2.real(m, BumpConsts::t, 1)?;
        let zone = s2.real(m, BumpConsts::zone, 1)?;
        let dt = self.sys.dt(m, 1)?;
        if !auto {
            let x = result(e2 - e1, 1)?;
            d1.set(m, BlockMemory::bw, e2);
            d2.set(m, BumpWork::xq, x);
            d2.set(m, BumpWork::xp, x);
            return Ok(());
        }
        let xq = d2.real(m, BumpWork::xq, 1)?;
        let xp = d2.real(m, BumpWork::xp, 1)?;
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
        d1.set(m, BlockMemory::bw, result(bw, 1)?);
        d2.set(m, BumpWork::xp, result(xn, 1)?);
        Ok(())
    }
}

impl Instr for Bump {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 5)?;
        let d1 = Area::of(cx.mem, &self.d1, 2)?;
        let s2 = Area::of(cx.mem, &self.s2, 4)?;
        let d2 = Area::of(cx.mem, &self.d2, 4)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2, d2))
    }
}

softplc_ir::layout! {
    /// The input data (S1) of S.AMR.
    pub struct AmrInput[7] {
        /// E1: the increase rate.
        up: f32 @ 0,
        /// E2: the decrease rate.
        down: f32 @ 2,
        /// E3: the output setting value.
        e3: f32 @ 4,
        /// e1 = b0 (0 manual, 1 auto), e2 = b1 (increase), e3 = b2 (decrease).
        ctl: u16 @ 6,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.AMR.
    pub struct AmrConsts[4] {
        /// d1: the upper limit.
        hi: f32 @ 0,
        /// d2: the lower limit.
        lo: f32 @ 2,
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

    fn body(&self, m: &mut DeviceMemory, s1: Area, d1: Area, s2: Area) -> Result<(), PcError> {
        let up = s1.real(m, AmrInput::up, 1)?;
        let down = s1.real(m, AmrInput::down, 1)?;
        let e3 = s1.real(m, AmrInput::e3, 1)?;
        let hi = s2.real(m, AmrConsts::hi, 1)?;
        let lo = s2.real(m, AmrConsts::lo, 1)?;
        let dt = self.sys.dt(m, 1)?;
        let bits = s1.get(m, AmrInput::ctl);
        let bw = if bits & 1 == 0 {
            e3
        } else {
            let bw = d1.real(m, BlockMemory::bw, 1)?;
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
        d1.set(m, BlockMemory::bw, bw);
        Ok(())
    }
}

impl Instr for Amr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2))
    }
}
