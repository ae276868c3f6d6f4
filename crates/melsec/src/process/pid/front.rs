//! The common front end of the control instructions (000 §9.1-§9.6, §9.20-
//! §9.21; spec §4.8): operands `S1 D1 S2 D2 S3`, the loop stop, the
//! control-cycle judgment on +96/+97 (DEC-1 … DEC-4), the SV setting with the
//! cascade engineering conversion (DEC-14), tracking with the E2 write-back
//! and the upper loop's TRKF at S3 − 8 (spec §1.7-§1.8), the deviation and
//! the gap gain K, KP = K × P, the deviation alarm DVLA with its DVLS
//! hysteresis under INH/ERRI (DEC-6), and the firmware-dependent integral
//! freeze (DEC-15: MHA2/MLA2 of ALM2 +116 per DEC-7, or MHA/MLA).

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::fault::Fault;
use softplc_ir::layout::At;
use softplc_ir::ops::{Block, WordArg};

use crate::process::common::{self, area, result, Area, BlockMemory, Input, PcError, Sys, Tick};
use crate::process::settings::ProcessSettings;
use crate::process::tag::{alm, Alm2, Inh, LoopTag, Mode, UPPER_INH_BELOW};
use crate::Args;

softplc_ir::layout! {
    /// The past values of the velocity-form PID family in the loop tag (000
    /// §9.1 *3, L7384-7403; spec §3). S.PIDP, S.SPI, S.BPI and S.R declare
    /// their own meanings of +98 … +101 next to their code.
    pub struct PidPast[128] {
        /// Bn-1: the last derivative term.
        b1: f32 @ 102,
        /// PVn.
        pv: f32 @ 104,
        /// PVn-1.
        pv1: f32 @ 106,
        /// PVn-2.
        pv2: f32 @ 108,
        /// DVn-1.
        dv1: f32 @ 110,
        /// S.2PID: DVn-2.
        dv2: f32 @ 112,
        /// S.2PID: Dn-1, the last derivative term on PV.
        d1: f32 @ 114,
    }
}

/// Why an execution stopped: a process-control operation error (4100 with
/// SD1502/SD1503) or an operand past its device (4101).
#[derive(Debug)]
pub enum Halt {
    Pc(PcError),
    Fault(Fault),
}

impl From<PcError> for Halt {
    fn from(e: PcError) -> Halt {
        Halt::Pc(e)
    }
}

/// Runs a body that may stop on either kind of error.
pub fn run(
    sys: &Sys,
    m: &mut DeviceMemory,
    body: impl FnOnce(&mut DeviceMemory) -> Result<(), Halt>,
) -> Result<(), Fault> {
    match body(m) {
        Ok(()) => Ok(()),
        Err(Halt::Pc(e)) => Err(sys.fail(m, e)),
        Err(Halt::Fault(f)) => Err(f),
    }
}

/// A float parameter of the loop tag `d2` that must not be negative
/// (detail 1 when it is not a number, 2 when negative; DEC-36).
#[inline]
pub fn tag_pos(m: &DeviceMemory, d2: Area, f: At<f32>, step: u16) -> Result<f32, PcError> {
    positive(d2.real(m, f, step)?, step)
}

/// `v`, or detail 2 when it is negative (DEC-36).
#[inline]
pub fn positive(v: f32, step: u16) -> Result<f32, PcError> {
    if v < 0.0 {
        Err(PcError::negative(step))
    } else {
        Ok(v)
    }
}

/// The operands `S1 D1 S2 D2 S3` of a control instruction: areas of the
/// given sizes, D2 the 128-word loop memory, S3 the set value E2 (2 words, or
/// a dummy such as SD1506), and where S3's device starts (for S3 − 8).
#[derive(Clone, Debug)]
pub struct Operands {
    s1: Block,
    d1: Block,
    s2: Block,
    d2: Block,
    s3: Block,
    s3_base: u32,
    words: [u32; 3],
}

/// The operands for one execution: S1 ([`Input`]), D1 ([`BlockMemory`]),
/// S2 (each instruction's constants), D2 ([`LoopTag`]), S3 ([`Input`]: E2).
#[derive(Clone, Copy, Debug)]
pub struct Areas {
    pub s1: Area,
    pub d1: Area,
    pub s2: Area,
    pub d2: Area,
    pub s3: Area,
    /// The upper loop's INH (S3 − 8, spec §1.8), when it lies in S3's device.
    pub upper: Option<usize>,
}

impl Operands {
    /// Compiles the five operands with S1, D1 and S2 of `s1`, `d1` and `s2`
    /// words.
    pub fn compile(a: &mut Args<'_, '_>, s1: u32, d1: u32, s2: u32) -> Option<Operands> {
        if !a.count(&[5]) {
            return None;
        }
        let b1 = area(a, 0, s1, "input data");
        let b2 = area(a, 1, d1, "block memory");
        let b3 = area(a, 2, s2, "operation constants");
        let b4 = area(a, 3, 128, "loop memory");
        let b5 = area(a, 4, 2, "set value");
        let s3 = b5?;
        let s3_base = device_base(a, &s3);
        Some(Operands {
            s1: b1?,
            d1: b2?,
            s2: b3?,
            d2: b4?,
            s3,
            s3_base,
            words: [s1, d1, s2],
        })
    }

    /// The areas (4101 when an indexed area runs past its device).
    pub fn resolve(&self, m: &DeviceMemory) -> Result<Areas, Fault> {
        let s3 = Area::of(m, &self.s3, 2)?;
        Ok(Areas {
            s1: Area::of(m, &self.s1, self.words[0])?,
            d1: Area::of(m, &self.d1, self.words[1])?,
            s2: Area::of(m, &self.s2, self.words[2])?,
            d2: Area::of(m, &self.d2, LoopTag::WORDS as u32)?,
            s3,
            upper: s3
                .0
                .checked_sub(UPPER_INH_BELOW as usize)
                .filter(|&u| u >= self.s3_base as usize),
        })
    }
}

/// Flat index of device number 0 of the block's device.
fn device_base(a: &Args<'_, '_>, b: &Block) -> u32 {
    if let WordArg::Indexed(ix) = &b.start {
        return ix.base;
    }
    let map = a.map();
    DeviceKind::ALL
        .iter()
        .find(|k| !k.is_bit() && map.points(**k) > 0 && map.base(**k) + map.points(**k) == b.limit)
        .map_or(b.limit, |k| map.base(*k))
}

/// The operation-constant words every control instruction has: PN, TRK and
/// SVPTN (spec §1.8), range-checked (detail 3).
#[derive(Clone, Copy, Debug)]
pub struct Pattern {
    /// PN = 1: forward action.
    pub forward: bool,
    pub trk: bool,
    /// SVPTN b0 = 0: E2 is used.
    pub e2_used: bool,
    /// SVPTN b1 = 0: E2 is the upper loop's MV.
    pub e2_upper_mv: bool,
}

/// Where an instruction's S2 keeps PN, TRK and SVPTN (fields of its
/// operation-constant layout; S.R has no PN).
#[derive(Clone, Copy, Debug)]
pub struct PatternFields {
    pub pn: Option<At<u16>>,
    pub trk: At<u16>,
    pub svptn: At<u16>,
}

impl Pattern {
    /// Reads PN, TRK and SVPTN from S2; a value out of range is detail 3 at
    /// the step that uses it (PN: gain 4, TRK and SVPTN: SV setting 2).
    /// Without a PN field the action is reverse.
    pub fn read(
        m: &DeviceMemory,
        s2: Area,
        f: PatternFields,
        pn_step: u16,
    ) -> Result<Pattern, PcError> {
        let pn = f.pn.map_or(0, |pn| s2.get(m, pn));
        let trk = s2.get(m, f.trk);
        let svptn = s2.get(m, f.svptn);
        if trk > 1 || svptn > 3 {
            return Err(PcError::range(2));
        }
        if pn > 1 {
            return Err(PcError::range(pn_step));
        }
        Ok(Pattern {
            forward: pn == 1,
            trk: trk == 1,
            e2_used: svptn & 1 == 0,
            e2_upper_mv: svptn & 2 == 0,
        })
    }
}

/// The decisions and system devices a control instruction captures at
/// compile.
#[derive(Clone, Copy, Debug)]
pub struct Front {
    pub s: ProcessSettings,
    pub inh: Inh,
    pub alm2: Alm2,
    pub mode: Mode,
    pub sys: Sys,
}

impl Front {
    pub fn new(a: &Args<'_, '_>) -> Option<Front> {
        let s: ProcessSettings = a.setting();
        Some(Front {
            s,
            inh: Inh::new(&s),
            alm2: Alm2::new(&s),
            mode: Mode::new(&s),
            sys: Sys::new(a)?,
        })
    }

    /// Whether the loop is stopped (ALM.SPA = 1, 000 §5.1.1).
    pub fn stopped(&self, m: &DeviceMemory, d2: Area) -> bool {
        d2.get(m, LoopTag::alm) & alm::SPA != 0
    }

    /// The loop-stop actions every control instruction shares: MODE := MAN
    /// and the ALM bits in `clear` := 0; under the alternative of DEC-4 the
    /// control-cycle counter (period `period`, when the instruction counts
    /// with [`Front::cycle`]) still advances.
    pub fn stop(
        &self,
        m: &mut DeviceMemory,
        d2: Area,
        clear: u16,
        period: Option<At<f32>>,
    ) -> Result<(), PcError> {
        d2.set(m, LoopTag::mode, Mode::MAN);
        d2.set_bits(m, LoopTag::alm, clear, false);
        if let (false, Some(p)) = (self.s.early_end_skips_counters, period) {
            self.cycle(m, d2, p)?;
        }
        Ok(())
    }

    /// The control-cycle judgment (processing No. 1): one execution of the
    /// +96/+97 counter with N = round(period/ΔT) (DEC-1 … DEC-3).
    pub fn cycle(&self, m: &mut DeviceMemory, d2: Area, period: At<f32>) -> Result<Tick, PcError> {
        let dt = self.sys.dt(m, 1)?;
        let p = d2.real(m, period, 1)?;
        let s = self.s;
        common::tick(
            m,
            d2.index(LoopTag::ct_flag),
            d2.index(LoopTag::ct_count),
            &s,
            || common::count(p, dt, false, &s, 1),
        )
    }

    /// (1) SV setting (processing No. 2): in the cascade group with E2 used
    /// SVn = (RH − RL)/100 × E2 + RL, written to SV +14 (DEC-14); otherwise
    /// SVn = SV.
    pub fn sv(
        &self,
        m: &mut DeviceMemory,
        a: &Areas,
        pat: Pattern,
        mode: u16,
    ) -> Result<f32, PcError> {
        if self.mode.cascade(mode) && pat.e2_used {
            let e2 = a.s3.real(m, Input::e1, 2)?;
            let rh = a.d2.real(m, LoopTag::rh, 2)?;
            let rl = a.d2.real(m, LoopTag::rl, 2)?;
            let svn = result((rh - rl) / 100.0 * e2 + rl, 2)?;
            if self.s.cascade_writes_sv {
                a.d2.set(m, LoopTag::sv, svn);
            }
            Ok(svn)
        } else {
            a.d2.real(m, LoopTag::sv, 2)
        }
    }

    /// (2) Tracking (processing No. 3): SVn′ = 100/(RH − RL) × (SVn − RL);
    /// with TRK = 1, E2 used and a tracking-eligible mode, E2 := SVn′ and,
    /// when E2 is the upper loop's MV, the upper loop's INH.TRKF := 1.
    pub fn track(
        &self,
        m: &mut DeviceMemory,
        a: &Areas,
        pat: Pattern,
        mode: u16,
        svn: f32,
    ) -> Result<f32, Halt> {
        let rh = a.d2.real(m, LoopTag::rh, 3)?;
        let rl = a.d2.real(m, LoopTag::rl, 3)?;
        if rh == rl {
            return Err(PcError::divide(3).into());
        }
        let sv1 = result(100.0 / (rh - rl) * (svn - rl), 3)?;
        self.write_back(m, a, pat, mode, sv1)?;
        Ok(sv1)
    }

    /// The write-back half of tracking: E2 := `value` and the upper loop's
    /// TRKF when the conditions hold (4101 when S3 − 8 is not a device).
    pub fn write_back(
        &self,
        m: &mut DeviceMemory,
        a: &Areas,
        pat: Pattern,
        mode: u16,
        value: f32,
    ) -> Result<(), Halt> {
        if pat.trk && pat.e2_used && self.mode.tracking(mode) {
            if pat.e2_upper_mv {
                let Some(u) = a.upper else {
                    return Err(Halt::Fault(Fault::Range));
                };
                m.words[u] |= self.inh.trkf;
            }
            a.s3.set(m, Input::e1, value);
        }
        Ok(())
    }

    /// (3) Gain (processing No. 4): DV = E1 − SVn′ (PN = 1) or SVn′ − E1,
    /// written to DV +16; K = GG when |DV| ≤ GW, else 1 − (1 − GG) × GW/|DV|;
    /// returns (DV, KP = K × P).
    pub fn gain(
        &self,
        m: &mut DeviceMemory,
        a: &Areas,
        pat: Pattern,
        sv1: f32,
    ) -> Result<(f32, f32), PcError> {
        let dv = self.deviation(m, a, pat, sv1, 4)?;
        let gw = tag_pos(m, a.d2, LoopTag::gw, 4)?;
        let gg = tag_pos(m, a.d2, LoopTag::gg, 4)?;
        let p = tag_pos(m, a.d2, LoopTag::p, 4)?;
        let k = if dv.abs() <= gw {
            gg
        } else {
            1.0 - (1.0 - gg) * gw / dv.abs()
        };
        Ok((dv, result(k * p, 4)?))
    }

    /// DV from E1 and SVn′, stored at +16.
    pub fn deviation(
        &self,
        m: &mut DeviceMemory,
        a: &Areas,
        pat: Pattern,
        sv1: f32,
        step: u16,
    ) -> Result<f32, PcError> {
        let e1 = a.s1.real(m, Input::e1, step)?;
        let dv = result(if pat.forward { e1 - sv1 } else { sv1 - e1 }, step)?;
        a.d2.set(m, LoopTag::dv, dv);
        Ok(dv)
    }

    /// The deviation check: |DV| ≥ DVL → 1; DVL − DVLS < |DV| < DVL → the
    /// previous state (the BB bit `bb` of D1, DEC-8); |DV| ≤ DVL − DVLS →
    /// 0; 0 while DVLI or ERRI. Writes ALM.DVLA and the BB bit.
    pub fn check(
        &self,
        m: &mut DeviceMemory,
        a: &Areas,
        dv: f32,
        dvls: f32,
        bb: u16,
        step: u16,
    ) -> Result<bool, PcError> {
        let dvl = tag_pos(m, a.d2, LoopTag::dvl, step)?;
        let dvls = positive(dvls, step)?;
        let prev = a.d1.get(m, BlockMemory::bb) & bb != 0;
        let d = dv.abs();
        let on = if d >= dvl {
            true
        } else if d <= dvl - dvls {
            false
        } else {
            prev
        };
        let on = on && self.inh.allows(a.d2.get(m, LoopTag::inh), alm::DVLA);
        a.d2.set_bits(m, LoopTag::alm, alm::DVLA, on);
        a.d1.set_bits(m, BlockMemory::bb, bb, on);
        Ok(on)
    }

    /// The output-limit alarms the integral freeze looks at (DEC-15): MHA2 /
    /// MLA2 of ALM2 +116 (DEC-7) on firmware ≥ 07032, MHA / MLA of ALM before.
    pub fn limits(&self, m: &DeviceMemory, d2: Area) -> (bool, bool) {
        if self.s.firmware_serial_ge_07032 {
            let w = d2.get(m, LoopTag::alm2);
            (w & self.alm2.mha2 != 0, w & self.alm2.mla2 != 0)
        } else {
            let w = d2.get(m, LoopTag::alm);
            (w & alm::MHA != 0, w & alm::MLA != 0)
        }
    }

    /// The integral increment of the velocity forms after the freeze rules
    /// (000 §9.1 L7611-7680): `ratio` = CT (or BT)/TI; 0 when TI = 0, or when
    /// [MHA2 or MLA2] (old firmware: MHA or MLA) = 1 and MVP > MH with a
    /// positive increment, or MVP < ML with a negative one.
    pub fn integral(
        &self,
        m: &DeviceMemory,
        d2: Area,
        period: f32,
        ti: f32,
        dv: f32,
        step: u16,
    ) -> Result<f32, PcError> {
        if ti == 0.0 {
            return Ok(0.0);
        }
        let inc = result(period / ti * dv, step)?;
        let (h, l) = self.limits(m, d2);
        if h || l {
            let mvp = d2.real(m, LoopTag::mvp, step)?;
            let mh = d2.real(m, LoopTag::mh, step)?;
            let ml = d2.real(m, LoopTag::ml, step)?;
            if (mvp > mh && inc > 0.0) || (mvp < ml && inc < 0.0) {
                return Ok(0.0);
            }
        }
        Ok(inc)
    }
}

/// The incomplete derivative `Bn = Bn-1 + MD·TD/(MD·CT + TD) × [x −
/// (CT/TD)·Bn-1]` (spec §4.9, verified by derivation), `x` the second (or
/// first) difference the instruction differentiates.
#[inline]
pub fn derivative(md: f32, td: f32, ct: f32, x: f32, b1: f32, step: u16) -> Result<f32, PcError> {
    result(b1 + md * td / (md * ct + td) * (x - ct / td * b1), step)
}
