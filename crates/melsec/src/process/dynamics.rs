//! Dynamic elements (000 ch. 9): S.LLAG, S.I, S.D, S.DED. "Previous"
//! values are the block memory D1 as found (DEC-8; its undescribed
//! alternative is a load error, `common::history_in_block_memory`); no
//! instruction here is in
//! Table 14.2, so every error reports SD1503 = 1 (L23918).

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, count, count_word, def, dummy, history_in_block_memory, only_default, result,
    tick_started, Area, BlockMemory, InputCtl, PcError, Sys,
};
use super::settings::ProcessSettings;
use super::tag::bb;
use crate::{Args, ExecCtx, Instr};

static LLAG: Doc = Doc {
    family: "process control: dynamics",
    cite: "000 §9.9 L13519-13698",
    notes: "f32 backward Euler (1 + T2·s)/(1 + T1·s); T1 + ΔT = 0 gives 0; E1n-1 := E1 on every \
            execution (DEC-20)",
};
static I: Doc = Doc {
    family: "process control: dynamics",
    cite: "000 §9.10 L13699-13860",
    notes: "Yn = ΔT/T × E1 + Yn-1 with Yn-1 = BW as found (DEC-8); T = 0 holds; e1 = 1 presets Ys",
};
static D: Doc = Doc {
    family: "process control: dynamics",
    cite: "000 §9.11 L13861-14035",
    notes: "T/(ΔT + T) × (Yn-1 + E1 − E1n-1); ΔT + T = 0 gives 0; E1n-1 := E1 always (DEC-20)",
};
static DED: Doc = Doc {
    family: "process control: dynamics",
    cite: "000 §9.12 L14036-14344",
    notes: "BW(t) = E1(t − ST·SN) at each sampling instant, fill value per OCHG, BB1 while \
            filling (DEC-21 … DEC-24); SN ∉ 0..48 is 4100 (SD1502 = 3)",
};

pub static DEFS: &[Def] = &[
    def("S.LLAG", 4, &LLAG, Lag::compile_llag),
    def("S.I", 4, &I, Lag::compile_i),
    def("S.D", 4, &D, Lag::compile_d),
    def("S.DED", 4, &DED, Ded::compile),
];

softplc_ir::layout! {
    /// The operation constants (S2) of S.LLAG, S.I and S.D.
    pub struct LagConsts[4] {
        /// S.LLAG: T1, the lag time; S.I, S.D: T.
        t1: f32 @ 0,
        /// S.LLAG: T2, the lead time; S.I, S.D: Ys, the preset value.
        t2: f32 @ 2,
    }
}

softplc_ir::layout! {
    /// The local work memory (D2) of S.LLAG and S.D.
    pub struct LagWork[2] {
        /// E1n-1: the previous input.
        e1: f32 @ 0,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LagKind {
    LeadLag,
    Integral,
    Derivative,
}

/// 000 §9.9 S.LLAG L13519-13698, §9.10 S.I L13699-13860, §9.11 S.D
/// L13861-14035.
///
/// 000 §9.9 S.LLAG, §9.10 S.I, §9.11 S.D, `S.x S1 D1 S2 D2`: S1 +0 E1, +2
/// e1 (b0); D1 +0 BW; S2 +0 T1 (S.LLAG lag) or T, +2 T2 (S.LLAG lead) or Ys;
/// D2 local +0 E1n-1 (S.LLAG, S.D; a dummy for S.I, L13758). In the
/// manual's order (L13686-13694, L13845-13853, L14022-14030):
/// * S.LLAG, e1 = 0: BW = 1/(ΔT + T1) × {T2·(E1 − E1n-1) + T1·BW + ΔT·E1},
///   0 when T1 + ΔT = 0; e1 = 1: BW = E1.
/// * S.I, e1 = 0: BW = ΔT/T × E1 + BW (T = 0: BW holds); e1 = 1: BW = Ys.
/// * S.D, e1 = 0: BW = T/(ΔT + T) × (BW + E1 − E1n-1), 0 when ΔT + T = 0;
///   e1 = 1: BW = Ys.
///
/// E1n-1 := E1 at the end of every execution (DEC-20; the alternative,
/// `lag_tracks_input_always = false`, only on e1 = 0 executions).
#[derive(Debug)]
struct Lag {
    kind: LagKind,
    always: bool,
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Option<Block>,
}

impl Lag {
    fn compile_llag(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Lag::compile(a, LagKind::LeadLag)
    }

    fn compile_i(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Lag::compile(a, LagKind::Integral)
    }

    fn compile_d(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Lag::compile(a, LagKind::Derivative)
    }

    fn compile(a: &mut Args<'_, '_>, kind: LagKind) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        history_in_block_memory(a)?;
        let s: ProcessSettings = a.setting();
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 3, "input data");
        let d1 = area(a, 1, 2, "block memory");
        let s2 = area(a, 2, 4, "operation constants");
        let d2 = if kind == LagKind::Integral {
            dummy(a, 3)?;
            None
        } else {
            Some(area(a, 3, 2, "local work memory")?)
        };
        Some(Box::new(Lag {
            kind,
            always: s.lag_tracks_input_always,
            sys,
            s1: s1?,
            d1: d1?,
            s2: s2?,
            d2,
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
        let dt = self.sys.dt(m, 1)?;
        let e1 = s1.real(m, InputCtl::e1, 1)?;
        let on = s1.bit(m, InputCtl::ctl, 0);
        let c0 = s2.real(m, LagConsts::t1, 1)?;
        let c1 = s2.real(m, LagConsts::t2, 1)?;
        let y = d1.real(m, BlockMemory::bw, 1)?;
        let e1p = if self.kind == LagKind::Integral {
            0.0
        } else {
            d2.real(m, LagWork::e1, 1)?
        };
        let bw = match (self.kind, on) {
            (LagKind::LeadLag, true) => e1,
            (LagKind::LeadLag, false) => {
                let (t1, t2) = (c0, c1);
                if t1 + dt == 0.0 {
                    0.0
                } else {
                    1.0 / (dt + t1) * (t2 * (e1 - e1p) + t1 * y + dt * e1)
                }
            }
            (LagKind::Integral, false) => {
                let t = c0;
                if t == 0.0 {
                    y
                } else {
                    dt / t * e1 + y
                }
            }
            (LagKind::Derivative, false) => {
                let t = c0;
                if dt + t == 0.0 {
                    0.0
                } else {
                    t / (dt + t) * (y + e1 - e1p)
                }
            }
            (_, true) => c1,
        };
        d1.set(m, BlockMemory::bw, result(bw, 1)?);
        if self.kind != LagKind::Integral && (self.always || !on) {
            d2.set(m, LagWork::e1, e1);
        }
        Ok(())
    }
}

impl Instr for Lag {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 3)?;
        let d1 = Area::of(cx.mem, &self.d1, 2)?;
        let s2 = Area::of(cx.mem, &self.s2, 4)?;
        let d2 = match &self.d2 {
            Some(b) => Area::of(cx.mem, b, 2)?,
            None => Area(0),
        };
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2, d2))
    }
}

softplc_ir::layout! {
    /// The operation constants (S2) of S.DED.
    pub struct DedConsts[6] {
        /// ST: the sampling period, s.
        st: f32 @ 0,
        /// SN: the number of samples (BIN16, 0..48).
        sn: i16 @ 2,
        /// Ys: the fill value with OCHG = 1.
        ys: f32 @ 3,
        /// OCHG = b0: the fill value at the start (0: E1, 1: Ys).
        ochg: u16 @ 5,
    }
}

softplc_ir::layout! {
    /// The local work memory (D2) of S.DED: 3 words, then the SN samples.
    pub struct DedWork[3] {
        /// e1′: the previous e1 (b0).
        e1: u16 @ 0,
        /// The sampling-period counter.
        count: u16 @ 1,
        /// The samples stored.
        stored: u16 @ 2,
    }
}

softplc_ir::layout! {
    /// The dead-time table of S.DED (oldest first), after [`DedWork`] in D2.
    pub struct DedTable[2] {
        /// The oldest sample; sample k is `sample.nth(k)`.
        sample: f32 @ 0,
    }
}

/// 000 §9.12 S.DED L14036-14344.
///
/// 000 §9.12 S.DED `S.DED S1 D1 S2 D2`: S1 +0 E1, +2 e1 (b0); D1 +0 BW, +2
/// BB (BB1 = b0, "data not yet complete"); S2 +0 ST (s), +2 SN (BIN16
/// 0..48), +3 Ys, +5 OCHG (b0); D2 local +0 e1′ (previous e1), +1 period
/// counter, +2 samples stored, +3 … +2SN+2 the dead-time table (oldest
/// first), 3 + 2·SN words.
///
/// * e1 = 1: BW = E1, BB1 = 0, no sampling, stored count := 0 (DEC-23).
/// * SN = 0: BW = E1, BB1 = 0 (L14337).
/// * The start execution (the e1 1→0 edge, or the first e1 = 0 execution
///   with nothing stored, DEC-22) loads the counter with N = round(ST/ΔT),
///   writes the fill value at the edge (OCHG = 0: E1, 1: Ys, DEC-24; none
///   without an edge), BB1 := 1 and takes the first sample.
/// * Each N-th execution after it outputs the oldest sample once SN are
///   stored (BB1 := 0, else BW and BB1 hold), then pushes E1, dropping the
///   oldest: BW(t) = E1(t − ST·SN) (DEC-21; the alternative pushes first).
///
/// Errors: SN ∉ 0..48 is SD1502 = 3; ST/ΔT over 32767 is 4, ΔT = 0 is 5, ST
/// or ΔT < 0 is 2; a bad float 1 (SD1503 = 1 for all).
#[derive(Debug)]
struct Ded {
    s: ProcessSettings,
    sys: Sys,
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
}

impl Ded {
    fn compile(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        history_in_block_memory(a)?;
        let s: ProcessSettings = a.setting();
        if !only_default(a, s.ded_start_without_edge, "ded_start_without_edge", 22)
            | !only_default(a, s.ded_bypass_resets, "ded_bypass_resets", 23)
        {
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 3, "input data");
        let d1 = area(a, 1, 3, "block memory");
        let s2 = area(a, 2, 6, "operation constants");
        let d2 = area(a, 3, 3, "local work memory");
        Some(Box::new(Ded {
            s,
            sys,
            s1: s1?,
            d1: d1?,
            s2: s2?,
            d2: d2?,
        }))
    }

    /// Outputs the oldest of the `stored` samples once the table holds `sn`.
    fn output(
        m: &mut DeviceMemory,
        d1: Area,
        table: Area,
        stored: usize,
        sn: usize,
    ) -> Result<(), PcError> {
        if stored >= sn {
            let oldest = table.real(m, DedTable::sample, 1)?;
            d1.set(m, BlockMemory::bw, oldest);
        }
        d1.set_bits(m, BlockMemory::bb, bb::BB1, stored < sn);
        Ok(())
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
        let e1 = s1.real(m, InputCtl::e1, 1)?;
        let on = s1.bit(m, InputCtl::ctl, 0);
        let st = s2.real(m, DedConsts::st, 1)?;
        let ys = s2.real(m, DedConsts::ys, 1)?;
        let dt = self.sys.dt(m, 1)?;
        let edge = d2.bit(m, DedWork::e1, 0);
        if on || sn == 0 {
            d1.set(m, BlockMemory::bw, e1);
            d1.set_bits(m, BlockMemory::bb, bb::BB1, false);
            d2.set(m, DedWork::stored, 0);
            d2.set(m, DedWork::e1, on as u16);
            return Ok(());
        }
        let table = d2.row(1, DedWork::WORDS);
        // A count above SN (SN lowered, a stale area) counts as SN.
        let mut stored = (d2.get(m, DedWork::stored) as usize).min(sn);
        let start = edge || stored == 0;
        let s = &self.s;
        let counter = d2.index(DedWork::count);
        let t = tick_started(m, counter, start, s, || count(st, dt, false, s, 1))?;
        if t.start {
            stored = 0;
            if edge {
                let fill_e1 = s2.bit(m, DedConsts::ochg, 0) != s.ded_ochg_fill;
                d1.set(m, BlockMemory::bw, if fill_e1 { e1 } else { ys });
            }
            d1.set_bits(m, BlockMemory::bb, bb::BB1, true);
        }
        if t.reached && s.ded_output_before_push {
            Ded::output(m, d1, table, stored, sn)?;
        }
        if t.begins() {
            if stored == sn {
                // Drop the oldest: samples 1 … SN−1 move down by one.
                let at = |k: usize| table.index(DedTable::sample.nth(k));
                m.words.copy_within(at(1)..at(sn), at(0));
                stored -= 1;
            }
            table.set(m, DedTable::sample.nth(stored), e1);
            stored += 1;
            d2.set(m, DedWork::stored, stored as u16);
            if !s.ded_output_before_push {
                Ded::output(m, d1, table, stored, sn)?;
            }
        }
        d2.set(m, DedWork::e1, 0);
        Ok(())
    }
}

impl Instr for Ded {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let s1 = Area::of(cx.mem, &self.s1, 3)?;
        let d1 = Area::of(cx.mem, &self.d1, 3)?;
        let s2 = Area::of(cx.mem, &self.s2, 6)?;
        let sn = match count_word(cx.mem, s2, DedConsts::sn, 0, 48, 1) {
            Ok(n) => n,
            Err(e) => return Err(self.sys.fail(cx.mem, e)),
        };
        let words = DedWork::WORDS + DedTable::sample.nth(sn).offset();
        let d2 = Area::of(cx.mem, &self.d2, words as u32)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, s2, d2, sn))
    }
}
