//! Compensation instructions (000 ch. 10): S.FG, S.IFG, S.FLT, S.SUM, S.TPC,
//! S.ENG, S.IENG.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, count, count_word, def, history_in_block_memory, only_default, result, tick_started,
    Area, Areas, BlockMemory, Input, InputCtl, PcError, Sys,
};
use super::settings::ProcessSettings;
use super::tag::bb;
use crate::{Args, ExecCtx, Instr};

static FG: Doc = Doc {
    family: "process control: compensation",
    cite: "000 §10.1 L19006-19237, §10.2 L19280-19465",
    notes: "broken line through the user's (Xi, Yi) table in D2 (4·SN words), SN = 0 not \
            executed, a decreasing point ends the table; SN ∉ 0..48 is 4100 (SD1502 = 3)",
};
static FLT: Doc = Doc {
    family: "process control: compensation",
    cite: "000 §10.3 L19466-19680",
    notes: "mean of the last SN samples every round(ST/ΔT) executions, output once full, BB1 \
            while filling; restarts on an ST/SN change (DEC-26)",
};
static SUM: Doc = Doc {
    family: "process control: compensation",
    cite: "000 §10.4 L19681-19852",
    notes: "BW + E1·ΔT/T above the low cut, T = 1/60/3600 s by RANGE; RANGE ∉ 1..3 is 4100 \
            (SD1502 = 3)",
};
static TPC: Doc = Doc {
    family: "process control: compensation",
    cite: "000 §10.5 L19857-20078",
    notes: "BW = E1 × A1 × A2, A1 = (B1 + T′)/(B1 + E2), A2 = (B2 + E3)/(B2 + P′) (DEC-27)",
};

static ENG: Doc = Doc {
    family: "process control: compensation",
    cite: "000 §10.6 L20079-20244, §10.7 L20245-20421",
    notes: "f32; S.IENG with RH = RL gives 0, with RH < RL the formula (DEC-28)",
};

pub static DEFS: &[Def] = &[
    def("S.FG", 4, &FG, Fg::compile_fg),
    def("S.IFG", 4, &FG, Fg::compile_ifg),
    def("S.FLT", 4, &FLT, Flt::compile),
    def("S.SUM", 4, &SUM, Sum::compile),
    def("S.TPC", 4, &TPC, Tpc::compile),
    def("S.ENG", 4, &ENG, Eng::compile_eng),
    def("S.IENG", 4, &ENG, Eng::compile_ieng),
];

softplc_ir::layout! {
    /// The operation constants (S2) of S.ENG and S.IENG.
    pub struct EngConsts[4] {
        /// RH: the engineering high value.
        rh: f32 @ 0,
        /// RL: the engineering low value.
        rl: f32 @ 2,
    }
}

/// 000 §10.6 S.ENG `S.ENG S1 D1 S2 D2(dmy)`: BW = (RH − RL)/100 × E1 + RL;
/// 000 §10.7 S.IENG: BW = 100/(RH − RL) × (E1 − RL) %, 0 when RH = RL
/// (L20408-20416), the formula also when RH < RL (DEC-28; the alternative
/// holds BW). S1 +0 E1; D1 +0 BW; S2 +0 RH, +2 RL. Errors: a bad float is
/// 4100 with SD1502 = 1, SD1503 = 1 (DEC-36).
#[derive(Debug)]
struct Eng {
    inverse: bool,
    decreasing: bool,
    sys: Sys,
    areas: Areas,
}

impl Eng {
    fn compile_eng(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Eng::compile(a, false)
    }

    fn compile_ieng(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Eng::compile(a, true)
    }

    fn compile(a: &mut Args<'_, '_>, inverse: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [2, 2, 4]);
        Some(Box::new(Eng {
            inverse,
            decreasing: s.ieng_decreasing,
            sys,
            areas: areas?,
        }))
    }
}

impl Instr for Eng {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| {
            let e1 = s1.real(m, Input::e1, 1)?;
            let rh = s2.real(m, EngConsts::rh, 1)?;
            let rl = s2.real(m, EngConsts::rl, 1)?;
            let bw = if !self.inverse {
                (rh - rl) / 100.0 * e1 + rl
            } else if rh == rl {
                0.0
            } else if rh < rl && !self.decreasing {
                return Ok(());
            } else {
                100.0 / (rh - rl) * (e1 - rl)
            };
            d1.set(m, BlockMemory::bw, result(bw, 1)?);
            Ok(())
        })
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.FG and S.IFG.
    pub struct FgConsts[1] {
        /// SN: the number of points (BIN16, 0..48).
        sn: i16 @ 0,
    }
}

softplc_ir::layout! {
    /// One point of the S.FG/S.IFG table (D2 holds SN of them).
    pub struct FgPoint[4] {
        /// Xi.
        x: f32 @ 0,
        /// Yi.
        y: f32 @ 2,
    }
}

/// 000 §10.1 S.FG L19006-19237, §10.2 S.IFG L19280-19465.
///
/// 000 §10.1 S.FG, §10.2 S.IFG `S.x S1 D1 S2 D2`: S1 +0 E1; D1 +0 BW; S2 +0
/// SN (BIN16, 0..48); D2 the user's table, Xi at +4(i−1), Yi at +4(i−1)+2
/// (4·SN words). S.FG (L19206-19223): E1 ≤ X1 → Y1; Xi-1 < E1 ≤ Xi → BW =
/// (Yi − Yi-1)/(Xi − Xi-1) × (E1 − Xi-1) + Yi-1; E1 > Xn → Yn. SN = 0: not
/// executed. Xi-1 > Xi makes n = i − 1 (the rest is ignored); of equal Xi the
/// smallest i is taken. S.IFG (L19433-19450) is the same with X and Y
/// swapped. SN ∉ 0..48 is 4100 with SD1502 = 3.
#[derive(Debug)]
struct Fg {
    inverse: bool,
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl Fg {
    fn compile_fg(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Fg::compile(a, false)
    }

    fn compile_ifg(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Fg::compile(a, true)
    }

    fn compile(a: &mut Args<'_, '_>, inverse: bool) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 2, "block memory");
        let s2 = area(a, 2, 1, "operation constants");
        let d2 = area(a, 3, 4, "breakpoint table");
        Some(Box::new(Fg {
            inverse,
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
        d2: Area,
        n: usize,
    ) -> Result<(), PcError> {
        let e1 = s1.real(m, Input::e1, 1)?;
        // The compared and the interpolated coordinate of point i.
        let (cx, cy) = if self.inverse {
            (FgPoint::y, FgPoint::x)
        } else {
            (FgPoint::x, FgPoint::y)
        };
        let x = |m: &DeviceMemory, i: usize| d2.row(i, FgPoint::WORDS).real(m, cx, 1);
        let y = |m: &DeviceMemory, i: usize| d2.row(i, FgPoint::WORDS).real(m, cy, 1);
        let mut xp = x(m, 0)?;
        let mut bw = None;
        if e1 <= xp {
            bw = Some(y(m, 0)?);
        } else {
            for i in 1..n {
                let xi = x(m, i)?;
                if xi < xp {
                    bw = Some(y(m, i - 1)?);
                    break;
                }
                if e1 <= xi {
                    let (yp, yi) = (y(m, i - 1)?, y(m, i)?);
                    bw = Some((yi - yp) / (xi - xp) * (e1 - xp) + yp);
                    break;
                }
                xp = xi;
            }
        }
        let bw = match bw {
            Some(v) => v,
            None => y(m, n - 1)?,
        };
        d1.set(m, BlockMemory::bw, result(bw, 1)?);
        Ok(())
    }
}

impl Instr for Fg {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 2)?;
        let s2 = Area::of(cx.mem, &self.s2, 1)?;
        let n = match count_word(cx.mem, s2, FgConsts::sn, 0, 48, 1) {
            Ok(0) => return Ok(()),
            Ok(n) => n,
            Err(e) => return Err(self.sys.fail(cx.mem, e)),
        };
        let d2 = Area::of(cx.mem, &self.d2, (n * FgPoint::WORDS) as u32)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, d2, n))
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.FLT.
    pub struct FltConsts[3] {
        /// ST: the sampling period, s.
        st: f32 @ 0,
        /// SN: the number of samples (BIN16, 0..48).
        sn: i16 @ 2,
    }
}

softplc_ir::layout! {
    /// The local work memory (D2) of S.FLT: 8 words, then the SN samples.
    pub struct FltWork[8] {
        /// ST′: the ST of the last start.
        st: f32 @ 0,
        /// SN′: the SN of the last start.
        sn: u16 @ 2,
        /// i: the sampling-period counter.
        count: u16 @ 3,
        /// n1: the samples stored.
        stored: u16 @ 4,
        /// n2: the next table slot.
        next: u16 @ 5,
    }
}

softplc_ir::layout! {
    /// The sample table of S.FLT, after [`FltWork`] in D2.
    pub struct FltTable[2] {
        /// The first sample; sample k is `sample.nth(k)`.
        sample: f32 @ 0,
    }
}

/// 000 §10.3 S.FLT L19466-19680.
///
/// 000 §10.3 S.FLT `S.FLT S1 D1 S2 D2`: S1 +0 E1; D1 +0 BW, +2 BB (BB1 = b0,
/// 1 while the table is not full, L19663-19665); S2 +0 ST (s), +2 SN (BIN16,
/// 0..48); D2 local +0 ST′, +2 SN′ (the last ST and SN), +3 i (period
/// counter), +4 n1 (samples stored), +5 n2 (the next table slot), +6/+7
/// unused, +8 … +2SN+7 the table (8 + 2·SN words).
/// * SN = 0: BW and BB := 0, end (L19669).
/// * (ST, SN) ≠ (ST′, SN′), which includes a cleared area: a start (DEC-26):
///   ST′/SN′ stored, the table emptied, the counter loaded with N =
///   round(ST/ΔT) (L19656), the first sample taken.
/// * Every N-th execution after it takes the next sample, the oldest dropped
///   when full. Once SN are stored, BW := their mean (summed oldest first,
///   ÷ SN) and BB1 := 0 on each sample; before, BW holds and BB1 = 1.
///
/// Errors: SN ∉ 0..48 is SD1502 = 3; ST/ΔT over 32767 is 4, ΔT = 0 is 5, ST
/// or ΔT < 0 is 2 (SD1503 = 1).
#[derive(Debug)]
struct Flt {
    s: ProcessSettings,
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl Flt {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        history_in_block_memory(a)?;
        let s: ProcessSettings = a.setting();
        if !only_default(a, s.flt_restart_on_change, "flt_restart_on_change", 26) {
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 2, "input data");
        let d1 = area(a, 1, 3, "block memory");
        let s2 = area(a, 2, 3, "operation constants");
        let d2 = area(a, 3, 8, "local work memory");
        Some(Box::new(Flt {
            s,
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
        sn: usize,
    ) -> Result<(), PcError> {
        let e1 = s1.real(m, Input::e1, 1)?;
        let st = s2.real(m, FltConsts::st, 1)?;
        let dt = self.sys.dt(m, 1)?;
        let changed = d2.get(m, FltWork::st).to_bits() != st.to_bits()
            || d2.get(m, FltWork::sn) as usize != sn;
        if sn == 0 {
            d1.set(m, BlockMemory::bw, 0.0);
            d1.set(m, BlockMemory::bb, 0);
            d2.set(m, FltWork::st, st);
            d2.set(m, FltWork::sn, 0);
            d2.set(m, FltWork::stored, 0);
            return Ok(());
        }
        let s = &self.s;
        let counter = d2.index(FltWork::count);
        let t = tick_started(m, counter, changed, s, || count(st, dt, false, s, 1))?;
        if t.start {
            d2.set(m, FltWork::st, st);
            d2.set(m, FltWork::sn, sn as u16);
            d2.set(m, FltWork::stored, 0);
            d2.set(m, FltWork::next, 0);
        }
        if !t.begins() {
            return Ok(());
        }
        let table = d2.row(1, FltWork::WORDS);
        // Stale or foreign counts are taken modulo the table (no panic).
        let next = d2.get(m, FltWork::next) as usize % sn;
        table.set(m, FltTable::sample.nth(next), e1);
        let stored = (d2.get(m, FltWork::stored) as usize + 1).min(sn);
        d2.set(m, FltWork::stored, stored as u16);
        d2.set(m, FltWork::next, ((next + 1) % sn) as u16);
        if stored < sn {
            d1.set_bits(m, BlockMemory::bb, bb::BB1, true);
            return Ok(());
        }
        let mut sum = 0f32;
        for k in 0..sn {
            sum += table.real(m, FltTable::sample.nth((next + 1 + k) % sn), 1)?;
        }
        d1.set(m, BlockMemory::bw, result(sum / sn as f32, 1)?);
        d1.set_bits(m, BlockMemory::bb, bb::BB1, false);
        Ok(())
    }
}

impl Instr for Flt {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 2)?;
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        let s2 = Area::of(cx.mem, &self.s2, 3)?;
        let sn = match count_word(cx.mem, s2, FltConsts::sn, 0, 48, 1) {
            Ok(n) => n,
            Err(e) => return Err(self.sys.fail(cx.mem, e)),
        };
        let words = FltWork::WORDS + FltTable::sample.nth(sn).offset();
        let d2 = Area::of(cx.mem, &self.d2, words as u32)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2, d2, sn))
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.SUM.
    pub struct SumConsts[5] {
        /// ILC: the input low cut.
        ilc: f32 @ 0,
        /// A: the initial value.
        init: f32 @ 2,
        /// RANGE: 1 per s, 2 per min, 3 per h (BIN16).
        range: u16 @ 4,
    }
}

/// 000 §10.4 S.SUM L19681-19852.
///
/// 000 §10.4 S.SUM `S.SUM S1 D1 S2 D2(dmy)`: S1 +0 E1, +2 e1 (b0); D1 +0 BW;
/// S2 +0 ILC input low cut, +2 A initial value, +4 RANGE (BIN16: 1 /s, 2
/// /min, 3 /h). e1 = 0: BW = A; e1 = 1: E1 ≤ ILC holds BW, E1 > ILC gives BW
/// = BW + E1 × ΔT/T with T = 1, 60, 3600 (L19831-19845). RANGE ∉ 1..3 is 4100
/// with SD1502 = 3.
#[derive(Debug)]
struct Sum {
    sys: Sys,
    areas: Areas,
}

impl Sum {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        history_in_block_memory(a)?;
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [3, 2, 5]);
        Some(Box::new(Sum { sys, areas: areas? }))
    }

    fn body(&self, m: &mut DeviceMemory, s1: Area, d1: Area, s2: Area) -> Result<(), PcError> {
        let t = match s2.get(m, SumConsts::range) {
            1 => 1.0,
            2 => 60.0,
            3 => 3600.0,
            _ => return Err(PcError::range(1)),
        };
        let e1 = s1.real(m, InputCtl::e1, 1)?;
        let ilc = s2.real(m, SumConsts::ilc, 1)?;
        let init = s2.real(m, SumConsts::init, 1)?;
        let dt = self.sys.dt(m, 1)?;
        let bw = if !s1.bit(m, InputCtl::ctl, 0) {
            init
        } else if e1 <= ilc {
            return Ok(());
        } else {
            d1.real(m, BlockMemory::bw, 1)? + e1 * dt / t
        };
        d1.set(m, BlockMemory::bw, result(bw, 1)?);
        Ok(())
    }
}

impl Instr for Sum {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2))
    }
}

softplc_ir::layout! {
    /// The input data (S1) of S.TPC.
    pub struct TpcInput[7] {
        /// E1: the differential pressure.
        e1: f32 @ 0,
        /// E2: the temperature.
        e2: f32 @ 2,
        /// E3: the pressure.
        e3: f32 @ 4,
        /// e1 = b0: E2 used; e2 = b1: E3 used.
        ctl: u16 @ 6,
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.TPC.
    pub struct TpcConsts[8] {
        /// T′: the design temperature.
        t: f32 @ 0,
        /// B1: the temperature offset (273.15).
        b1: f32 @ 2,
        /// P′: the design pressure.
        p: f32 @ 4,
        /// B2: the pressure offset (10332).
        b2: f32 @ 6,
    }
}

/// 000 §10.5 S.TPC L19857-20078.
///
/// 000 §10.5 S.TPC `S.TPC S1 D1 S2 D2(dmy)`: S1 +0 E1 differential pressure,
/// +2 E2 temperature, +4 E3 pressure, +6 e1 (b0: E2 used), e2 (b1: E3 used);
/// D1 +0 BW; S2 +0 T′ design temperature, +2 B1 (273.15), +4 P′ design
/// pressure, +6 B2 (10332). BW = E1 × A1 × A2 (L20044-20070), A1 = (B1 +
/// T′)/(B1 + E2) when E2 is used, else 1; A2 = (B2 + E3)/(B2 + P′) when E3 is
/// used, else 1 (DEC-27; `tpc_reconstructed = false` gives the
/// numerator-first reading (B1 + E2)/(B1 + T′) and (B2 + P′)/(B2 + E3)). A
/// zero denominator is 4100 with SD1502 = 5.
#[derive(Debug)]
struct Tpc {
    reconstructed: bool,
    sys: Sys,
    areas: Areas,
}

impl Tpc {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let areas = Areas::compile(a, [7, 2, 8]);
        Some(Box::new(Tpc {
            reconstructed: s.tpc_reconstructed,
            sys,
            areas: areas?,
        }))
    }

    /// A1 (`inverse` false) or A2 (true) of DEC-27: (B + design)/(B +
    /// measured) or its reciprocal, whichever the reading gives.
    fn ratio(
        &self,
        design: f32,
        measured: f32,
        offset: f32,
        inverse: bool,
    ) -> Result<f32, PcError> {
        let (num, den) = if self.reconstructed != inverse {
            (offset + design, offset + measured)
        } else {
            (offset + measured, offset + design)
        };
        if den == 0.0 {
            return Err(PcError::divide(1));
        }
        result(num / den, 1)
    }

    fn body(&self, m: &mut DeviceMemory, s1: Area, d1: Area, s2: Area) -> Result<(), PcError> {
        let e1 = s1.real(m, TpcInput::e1, 1)?;
        let e2 = s1.real(m, TpcInput::e2, 1)?;
        let e3 = s1.real(m, TpcInput::e3, 1)?;
        let t = s2.real(m, TpcConsts::t, 1)?;
        let b1 = s2.real(m, TpcConsts::b1, 1)?;
        let p = s2.real(m, TpcConsts::p, 1)?;
        let b2 = s2.real(m, TpcConsts::b2, 1)?;
        let a1 = if s1.bit(m, TpcInput::ctl, 0) {
            self.ratio(t, e2, b1, false)?
        } else {
            1.0
        };
        let a2 = if s1.bit(m, TpcInput::ctl, 1) {
            self.ratio(p, e3, b2, true)?
        } else {
            1.0
        };
        d1.set(m, BlockMemory::bw, result(e1 * a1 * a2, 1)?);
        Ok(())
    }
}

impl Instr for Tpc {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let (s1, d1, s2) = self.areas.starts(cx.mem)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2))
    }
}
