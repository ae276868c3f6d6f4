//! The output stage of S.OUT1 (000 §8.2 L4330-4506), S.OUT2 (§8.3) and
//! S.DUTY (§8.5 L5806-5996), and the change-rate / high-low limiter that
//! S.SEL (§9.24) uses too.
//!
//! Loop-tag words ([`LoopTag`] fields) this stage reads and writes — the contract
//! the PID family relies on:
//! * +1 MODE (MAN on loop stop), +3 ALM (SPA read; DMLA, MHA, MLA written),
//!   +4 INH (DMLI, MHI, MLI, ERRI read; **TRKF** (DEC-6 b14) set to 1 in the
//!   manual modes, consumed and cleared on the next auto execution);
//! * +12 MV (read; written by the limiter in the auto modes), +18 MH, +20 ML,
//!   +48 DML, +54 I (TI, reset windup), **+62 MVP** (S: MVP := MV on TRKF,
//!   then MVP := ΔMV + MVP, then the reset windup);
//! * +116 **ALM2** (whole word: MHA2 = b1, MLA2 = b0 per DEC-7, other bits 0;
//!   written on every limiter pass, cleared in the manual modes and on loop
//!   stop; MHA2/MLA2 ignore INH/ERRI).
//!
//! E1 (S1) is the PID's BW, ΔMV in %.

use softplc_ir::device::DeviceMemory;
use softplc_ir::layout::At;

use crate::process::common::{result, Area, Input, PcError, Sys};
use crate::process::settings::ProcessSettings;
use crate::process::tag::{alm, bb, put, Alm2, Inh, LoopTag, Mode};

softplc_ir::layout! {
    /// The operation constants (S2) of S.OUT1, S.OUT2 and S.MOUT: the output
    /// range of the conversion BW = (NMAX − NMIN)/100 × MV + NMIN.
    pub struct OutputRange[4] {
        /// NMAX: the output at MV = 100 % (default 100.0).
        nmax: f32 @ 0,
        /// NMIN: the output at MV = 0 % (default 0.0).
        nmin: f32 @ 2,
    }
}

/// The BB bits of the output instructions: BB1 alarm, BB2 high, BB3 low,
/// BB4 change rate.
pub(crate) const BB_OUT: u16 = bb::BB1 | bb::BB2 | bb::BB3 | bb::BB4;
/// The ALM bits the output stage owns.
pub(crate) const ALM_OUT: u16 = alm::DMLA | alm::MHA | alm::MLA;

/// The BB word of an output instruction: its block memory and the field
/// (S.OUT1/S.OUT2 +2, S.DUTY +1).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bb(pub Area, pub At<u16>);

impl Bb {
    fn get(self, m: &DeviceMemory) -> u16 {
        self.0.get(m, self.1)
    }

    fn set(self, m: &mut DeviceMemory, v: u16) {
        self.0.set(m, self.1, v)
    }

    fn clear(self, m: &mut DeviceMemory, bits: u16) {
        self.0.set_bits(m, self.1, bits, false)
    }
}

/// What the settings make of the loop-tag bits, resolved at compile.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Kit {
    pub sys: Sys,
    pub s: ProcessSettings,
    pub inh: Inh,
    pub alm2: Alm2,
    pub mode: Mode,
}

impl Kit {
    pub fn new(sys: Sys, s: ProcessSettings) -> Kit {
        Kit {
            sys,
            s,
            inh: Inh::new(&s),
            alm2: Alm2::new(&s),
            mode: Mode::new(&s),
        }
    }
}

/// The result of the change-rate and high/low limiter, before inhibits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Limited {
    /// The change-rate limiter's result T1.
    pub t1: f32,
    /// The new MV.
    pub mv: f32,
    pub high: bool,
    pub low: bool,
    pub rate: bool,
}

/// 000 §8.2 (3) (also §8.3 (2), §8.5 (3), §9.24 (4)): change-rate limit of
/// `t` against the present `mv` by DML (|T − MV| ≤ DML → T; above → MV + DML;
/// below → MV − DML), then the high/low limit (T1 > MH → MH; T1 < ML → ML;
/// otherwise T1).
pub(crate) fn limit(
    t: f32,
    mv: f32,
    dml: f32,
    mh: f32,
    ml: f32,
    step: u16,
) -> Result<Limited, PcError> {
    let d = result(t - mv, step)?;
    let (t1, rate) = if d.abs() <= dml {
        (t, false)
    } else if d > dml {
        (result(mv + dml, step)?, true)
    } else {
        (result(mv - dml, step)?, true)
    };
    let (mv, high, low) = if t1 > mh {
        (mh, true, false)
    } else if t1 < ml {
        (ml, false, true)
    } else {
        (t1, false, false)
    };
    Ok(Limited {
        t1,
        mv,
        high,
        low,
        rate,
    })
}

/// Writes the limiter's alarms: DMLA/BB4, MHA/BB2, MLA/BB3, each 0 when its
/// inhibit (DMLI, MHI, MLI) or ERRI is set; BB1 = BB2 ∨ BB3 ∨ BB4.
pub(crate) fn alarms(inh: Inh, inh_word: u16, alm_w: &mut u16, bb_w: &mut u16, l: &Limited) {
    let r = inh.apply(inh_word, alm_w, alm::DMLA, bb_w, bb::BB4, l.rate);
    let h = inh.apply(inh_word, alm_w, alm::MHA, bb_w, bb::BB2, l.high);
    let lo = inh.apply(inh_word, alm_w, alm::MLA, bb_w, bb::BB3, l.low);
    put(bb_w, bb::BB1, r || h || lo);
}

/// How the stage ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Flow {
    /// Loop stop (SPA = 1): alarms cleared, MODE := MAN, the output held.
    Stopped,
    /// SEA = 1 with SM1501 ON: BB1..BB4 := 0, MV and the output held.
    Held,
    /// MODE has no bit of either group: nothing is done.
    Idle,
    /// Go on to the output conversion (a manual mode with the operator's MV,
    /// or an auto mode after the limiter).
    Output,
}

/// The loop stop and the mode judgment shared by the three output
/// instructions; `velocity` adds the ALM2 clearing and the TRKF setting of
/// S.OUT1/S.DUTY. Returns `None` when an auto mode goes on to the limiter.
fn judge(k: &Kit, m: &mut DeviceMemory, bb: Bb, d2: Area, velocity: bool) -> Option<Flow> {
    let alm_w = d2.get(m, LoopTag::alm);
    let alm2 = k.alm2.mha2 | k.alm2.mla2;
    if alm_w & alm::SPA != 0 {
        d2.set(m, LoopTag::alm, alm_w & !ALM_OUT);
        if velocity {
            d2.set_bits(m, LoopTag::alm2, alm2, false);
        }
        d2.set(m, LoopTag::mode, Mode::MAN);
        bb.clear(m, BB_OUT);
        return Some(Flow::Stopped);
    }
    let mode = d2.get(m, LoopTag::mode);
    if k.mode.manual(mode) {
        d2.set(m, LoopTag::alm, alm_w & !ALM_OUT);
        bb.clear(m, BB_OUT);
        if velocity {
            d2.set_bits(m, LoopTag::alm2, alm2, false);
            d2.set_bits(m, LoopTag::inh, k.inh.trkf, true);
        }
        return Some(Flow::Output);
    }
    if !k.mode.auto(mode) {
        return Some(Flow::Idle);
    }
    if alm_w & alm::SEA != 0 && k.sys.hold_output(m) {
        bb.clear(m, BB_OUT);
        return Some(Flow::Held);
    }
    None
}

/// The limiter pass of the auto modes on the temporary MV `t`, skipped when
/// T = MV (DEC-10); `velocity` writes ALM2. Returns the limiter's result
/// when it ran (for the reset windup).
fn limiter(
    k: &Kit,
    m: &mut DeviceMemory,
    bb: Bb,
    d2: Area,
    t: f32,
    velocity: bool,
) -> Result<Option<Limited>, PcError> {
    let mv = d2.real(m, LoopTag::mv, 2)?;
    if t == mv && k.s.output_tracking_skips_limits {
        return Ok(None);
    }
    let dml = d2.real(m, LoopTag::dml, 2)?;
    let mh = d2.real(m, LoopTag::mh, 2)?;
    let ml = d2.real(m, LoopTag::ml, 2)?;
    let l = limit(t, mv, dml, mh, ml, 2)?;
    d2.set(m, LoopTag::mv, l.mv);
    let inh_w = d2.get(m, LoopTag::inh);
    let (mut alm_w, mut bb_w) = (d2.get(m, LoopTag::alm), bb.get(m));
    alarms(k.inh, inh_w, &mut alm_w, &mut bb_w, &l);
    d2.set(m, LoopTag::alm, alm_w);
    bb.set(m, bb_w);
    if velocity {
        let a2 = if l.high { k.alm2.mha2 } else { 0 } | if l.low { k.alm2.mla2 } else { 0 };
        d2.set(m, LoopTag::alm2, a2);
    }
    Ok(Some(l))
}

/// S.OUT1 (6), (1)-(4) and S.DUTY (7), (1)-(4): loop stop, mode judgment,
/// input addition with TRKF, change-rate/high-low limiter (skipped when
/// T = MV, DEC-10), reset windup (DEC-11). `s1` holds ΔMV, `bb` is the
/// BB word, `d2` the loop tag. SD1503: 1 input addition, 2 limiter, 3
/// reset windup.
pub(crate) fn velocity(
    k: &Kit,
    m: &mut DeviceMemory,
    s1: Area,
    bb: Bb,
    d2: Area,
) -> Result<Flow, PcError> {
    if let Some(f) = judge(k, m, bb, d2, true) {
        return Ok(f);
    }
    // (2) input addition.
    let mut e = s1.real(m, Input::e1, 1)?;
    let mut mvp = d2.real(m, LoopTag::mvp, 1)?;
    if d2.get(m, LoopTag::inh) & k.inh.trkf != 0 {
        mvp = d2.real(m, LoopTag::mv, 1)?;
        e = 0.0;
        d2.set_bits(m, LoopTag::inh, k.inh.trkf, false);
    }
    let t = result(e + mvp, 1)?;
    d2.set(m, LoopTag::mvp, t);
    // (3) change rate, high/low limiter.
    let Some(l) = limiter(k, m, bb, d2, t, true)? else {
        return Ok(Flow::Output);
    };
    // (4) reset windup: skipped when TI = 0.
    // T1 > MH or T1 < ML: the limiter's high/low result, MV the limit.
    let ti = d2.real(m, LoopTag::i, 3)?;
    if ti != 0.0 && (l.high || l.low) {
        let mvp = if k.s.reset_windup_first_order {
            let dt = k.sys.dt(m, 3)?;
            result(t - dt / ti * (t - l.mv), 3)?
        } else {
            l.mv
        };
        d2.set(m, LoopTag::mvp, mvp);
    }
    Ok(Flow::Output)
}

/// S.OUT2 (4), (1), (2): loop stop, mode judgment, change-rate/high-low
/// limiter on E1 = MV (skipped when E1 = MV, DEC-10). SD1503 2.
pub(crate) fn positional(
    k: &Kit,
    m: &mut DeviceMemory,
    s1: Area,
    bb: Bb,
    d2: Area,
) -> Result<Flow, PcError> {
    if let Some(f) = judge(k, m, bb, d2, false) {
        return Ok(f);
    }
    let t = s1.real(m, Input::e1, 2)?;
    limiter(k, m, bb, d2, t, false)?;
    Ok(Flow::Output)
}

/// The output conversion BW = (NMAX − NMIN)/100 × MV + NMIN (000 §8.2 (5)).
pub(crate) fn convert(nmax: f32, nmin: f32, mv: f32, step: u16) -> Result<f32, PcError> {
    result((nmax - nmin) / 100.0 * mv + nmin, step)
}
