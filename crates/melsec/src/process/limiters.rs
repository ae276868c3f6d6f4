//! Limiters and dead band (000 §9.17-§9.19, §9.22): S.LIMT, S.VLMT1,
//! S.VLMT2, S.DBND. The table rows are tried in order (S.LIMT: the limits
//! first); in a hysteresis band BW follows the row and BB1/BB2 keep their
//! values (the previous BB is D1+2 as found, DEC-8; its alternative is a
//! load error). Not in Table 14.2: SD1503 = 1.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    def, history_in_block_memory, result, Area, Areas, BlockMemory, Input, PcError, Sys,
};
use super::settings::ProcessSettings;
use crate::{Args, ExecCtx, Instr};

static LIMT: Doc = Doc {
    family: "process control: limiters",
    cite: "000 §9.17 L15327-15525",
    notes: "high/low limit with hysteresis HS1/HS2; HS < 0 is 4100 (SD1502 = 2)",
};
static VLMT: Doc = Doc {
    family: "process control: limiters",
    cite: "000 §9.18 L15526-15735, §9.19 L15736-15928",
    notes: "rate limits V1/V2 (%/s) × ΔT with hysteresis; S.VLMT2 holds BW while the rate is \
            exceeded (DEC-25); HS < 0 is 4100 (SD1502 = 2)",
};
static DBND: Doc = Doc {
    family: "process control: limiters",
    cite: "000 §9.22 L17152-17326",
    notes: "D2 ≤ E1 ≤ D1: BW = (D2 + D1)/2, BB1 = 1; else BW = E1, BB1 = 0",
};

pub static DEFS: &[Def] = &[
    def("S.LIMT", 4, &LIMT, Limit::compile_limt),
    def("S.VLMT1", 4, &VLMT, Limit::compile_vlmt1),
    def("S.VLMT2", 4, &VLMT, Limit::compile_vlmt2),
    def("S.DBND", 4, &DBND, Limit::compile_dbnd),
];

softplc_ir::layout! {
    /// The operation constants (S2) of S.LIMT, S.VLMT1 and S.VLMT2 (S.DBND:
    /// its two limits only).
    pub struct LimitConsts[8] {
        /// S.LIMT: HILMT; S.VLMT1/2: V1, the rising rate (%/s); S.DBND: D1,
        /// the upper limit.
        c0: f32 @ 0,
        /// S.LIMT: LOLMT; S.VLMT1/2: V2, the falling rate (%/s); S.DBND: D2,
        /// the lower limit.
        c1: f32 @ 2,
        /// HS1: the hysteresis of the upper (rising) row.
        hs1: f32 @ 4,
        /// HS2: the hysteresis of the lower (falling) row.
        hs2: f32 @ 6,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Limit,
    /// S.VLMT1, or S.VLMT2 with `vlmt2_literal = false`.
    Rate,
    /// S.VLMT2's literal table (DEC-25).
    RateHold,
    DeadBand,
}

/// 000 §9.17 S.LIMT L15327-15525, §9.18 S.VLMT1 L15526-15735, §9.19 S.VLMT2
/// L15736-15928, §9.22 S.DBND L17152-17326.
///
/// `S.x S1 D1 S2 D2(dmy)`: S1 +0 E1; D1 +0 BW, +2 BB (BB1 = b0, BB2 = b1).
/// * 000 §9.17 S.LIMT, S2 +0 HILMT, +2 LOLMT, +4 HS1, +6 HS2 (L15505-15515):
///   E1 ≥ HILMT → HILMT, BB1 = 1, BB2 = 0; E1 ≤ LOLMT → LOLMT, 0, 1;
///   LOLMT + HS2 ≤ E1 ≤ HILMT − HS1 → E1, 0, 0; otherwise E1, BB1/BB2 held.
///   The two limit rows are tried first, so with HS = 0 both limits are
///   alarms (the manual's relations are lost; the spec prints ≥ and ≤).
/// * 000 §9.18 S.VLMT1, S2 +0 V1, +2 V2, +4 HS1, +6 HS2 (L15715-15727):
///   rising (E1 ≥ BW): E1 − BW > V1·ΔT → BW + V1·ΔT, BB1 = 1, BB2 = 0;
///   E1 − BW ≤ V1·ΔT − HS1 → E1, 0, 0; otherwise E1, held. Falling (E1 <
///   BW) the same with BW − E1, V2, HS2 and BB2.
/// * 000 §9.19 S.VLMT2: the same rows, but BW = BW (held) in the "exceeded"
///   and "otherwise" rows (L15903-15921; DEC-25; `vlmt2_literal = false`
///   gives S.VLMT1's rows).
/// * 000 §9.22 S.DBND, S2 +0 D1 upper, +2 D2 lower (L17310-17320).
///
/// HS1 or HS2 < 0 is 4100 with SD1502 = 2.
#[derive(Debug)]
struct Limit {
    kind: Kind,
    sys: Sys,
    areas: Areas,
}

impl Limit {
    fn compile_limt(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Limit::compile(a, Kind::Limit)
    }

    fn compile_vlmt1(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Limit::compile(a, Kind::Rate)
    }

    fn compile_vlmt2(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        let s: ProcessSettings = a.setting();
        let kind = if s.vlmt2_literal {
            Kind::RateHold
        } else {
            Kind::Rate
        };
        Limit::compile(a, kind)
    }

    fn compile_dbnd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Limit::compile(a, Kind::DeadBand)
    }

    /// Words of S2.
    fn words(kind: Kind) -> u32 {
        if kind == Kind::DeadBand {
            4
        } else {
            8
        }
    }

    fn compile(a: &mut Args<'_, '_>, kind: Kind) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        if kind != Kind::DeadBand {
            history_in_block_memory(a)?;
        }
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [2, 3, Limit::words(kind)]);
        Some(Box::new(Limit {
            kind,
            sys,
            areas: areas?,
        }))
    }

    fn body(&self, m: &mut DeviceMemory, s1: Area, d1: Area, s2: Area) -> Result<(), PcError> {
        let e1 = s1.real(m, Input::e1, 1)?;
        let c0 = s2.real(m, LimitConsts::c0, 1)?;
        let c1 = s2.real(m, LimitConsts::c1, 1)?;
        // (BW, BB1/BB2 as b0/b1, or None to hold them).
        let (bw, bb) = match self.kind {
            Kind::DeadBand => {
                let (hi, lo) = (c0, c1);
                if lo <= e1 && e1 <= hi {
                    ((lo + hi) / 2.0, Some(1))
                } else {
                    (e1, Some(0))
                }
            }
            Kind::Limit => {
                let (hi, lo, hs1, hs2) = self.hysteresis(m, s2, c0, c1)?;
                if e1 >= hi {
                    (hi, Some(1))
                } else if e1 <= lo {
                    (lo, Some(2))
                } else if lo + hs2 <= e1 && e1 <= hi - hs1 {
                    (e1, Some(0))
                } else {
                    (e1, None)
                }
            }
            Kind::Rate | Kind::RateHold => {
                let (v1, v2, hs1, hs2) = self.hysteresis(m, s2, c0, c1)?;
                let dt = self.sys.dt(m, 1)?;
                let bw = d1.real(m, BlockMemory::bw, 1)?;
                let hold = self.kind == Kind::RateHold;
                if e1 >= bw {
                    let lim = v1 * dt;
                    if e1 - bw > lim {
                        (if hold { bw } else { bw + lim }, Some(1))
                    } else if e1 - bw <= lim - hs1 {
                        (e1, Some(0))
                    } else {
                        (if hold { bw } else { e1 }, None)
                    }
                } else {
                    let lim = v2 * dt;
                    if bw - e1 > lim {
                        (if hold { bw } else { bw - lim }, Some(2))
                    } else if bw - e1 <= lim - hs2 {
                        (e1, Some(0))
                    } else {
                        (if hold { bw } else { e1 }, None)
                    }
                }
            }
        };
        d1.set(m, BlockMemory::bw, result(bw, 1)?);
        if let Some(bb) = bb {
            let mask = if self.kind == Kind::DeadBand { 1 } else { 3 };
            d1.put_bits(m, BlockMemory::bb, mask, bb);
        }
        Ok(())
    }

    /// The two limits and HS1/HS2, which must not be negative.
    fn hysteresis(
        &self,
        m: &DeviceMemory,
        s2: Area,
        c0: f32,
        c1: f32,
    ) -> Result<(f32, f32, f32, f32), PcError> {
        let hs1 = s2.real(m, LimitConsts::hs1, 1)?;
        let hs2 = s2.real(m, LimitConsts::hs2, 1)?;
        if hs1 < 0.0 || hs2 < 0.0 {
            return Err(PcError::negative(1));
        }
        Ok((c0, c1, hs1, hs2))
    }
}

impl Instr for Limit {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2))
    }
}
