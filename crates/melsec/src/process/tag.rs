//! The loop tag (000 §3.3.5, L1586-1969; spec/process-control.md §3): the 128
//! words at an instruction's D2 that every instruction of one loop shares,
//! +0..+95 loop-tag memory and +96..+127 the past-value area the instructions
//! own. One declaration serves the instructions, the monitor and the docs.
//! Instruction-specific meanings of the same words (S.PGS, S.BC, S.R, S.SEL …)
//! are declared by those instructions next to their code.

use super::settings::ProcessSettings;

/// Words of a loop tag (96 loop-tag memory + 32 past values; 000 §3.3.1).
pub const LOOP_WORDS: u32 = 128;

/// The loop tag as the loop memory of the instructions of a PID-type loop
/// (their D2), for faceplates and OPC UA.
pub static LOOP_TAG: softplc_ir::listing::LoopMemory = softplc_ir::listing::LoopMemory {
    name: "loop tag",
    fields: LoopTag::FIELDS,
    first: 0,
    stride: 0,
    count: None,
    settings: None,
};

softplc_ir::layout! {
    /// The loop-tag memory of a PID-type loop (spec §3, defaults in docs).
    pub struct LoopTag[128] {
        /// Operation mode, one bit set (default 8H = MAN; see [`Mode`]).
        mode: u16 @ 1,
        /// Alarms (default 4000H: SPA, the loop is stopped; see [`alm`]).
        alm: u16 @ 3,
        /// Alarm inhibits, ERRI and TRKF (default 4000H; see [`Inh`]).
        inh: u16 @ 4,
        /// Process value, engineering units (S.PHPL writes it).
        pv: f32 @ 10,
        /// Manipulated value, % (-10..110).
        mv: f32 @ 12,
        /// Set value, engineering units.
        sv: f32 @ 14,
        /// Deviation, % (the PID family writes it).
        dv: f32 @ 16,
        /// Output high limit, % (default 100).
        mh: f32 @ 18,
        /// Output low limit, % (default 0).
        ml: f32 @ 20,
        /// Engineering high (default 100).
        rh: f32 @ 22,
        /// Engineering low (default 0).
        rl: f32 @ 24,
        /// High alarm value (default 100).
        ph: f32 @ 26,
        /// Low alarm value (default 0).
        pl: f32 @ 28,
        /// High-high alarm value (default 100).
        hh: f32 @ 30,
        /// Low-low alarm value (default 0).
        ll: f32 @ 32,
        /// S.IN digital filter coefficient α, 0..1 (default 0.2).
        filter: f32 @ 38,
        /// S.PHPL alarm hysteresis, % (default 0).
        hs: f32 @ 40,
        /// Change-rate check time, s (default 0).
        ctim: f32 @ 42,
        /// Change-rate alarm value, % (default 100).
        dpl: f32 @ 44,
        /// Control cycle CT, s (default 1; S.SPI: operation time ST).
        ct: f32 @ 46,
        /// Output change-rate limit, % per execution (default 100).
        dml: f32 @ 48,
        /// Deviation alarm limit, % (default 100).
        dvl: f32 @ 50,
        /// Proportional gain P (default 1).
        p: f32 @ 52,
        /// Integral time TI, s (default 10).
        i: f32 @ 54,
        /// Derivative time TD, s (default 0).
        d: f32 @ 56,
        /// Gap width, % (default 0).
        gw: f32 @ 58,
        /// Gap gain (default 1).
        gg: f32 @ 60,
        /// Internal MV accumulator, % (S.OUT1/S.DUTY).
        mvp: f32 @ 62,
        /// S.2PID α (default 0).
        alpha: f32 @ 64,
        /// S.2PID β (default 1).
        beta: f32 @ 66,
        /// S.DUTY output period, s (default 1).
        ctduty: f32 @ 68,
        /// S.AT1 step MV, % (default 0).
        at1_step_mv: f32 @ 70,
        /// S.AT1 sampling period, s (default 1).
        at1_st: f32 @ 72,
        /// S.AT1 overall timeout, s (default 100).
        at1_tout1: f32 @ 74,
        /// S.AT1 timeout after the maximum slope, s (default 10).
        at1_tout2: f32 @ 76,
        /// Past values: control-cycle counter preset flag (PID family, S.R, S.ONF*).
        ct_flag: u16 @ 96,
        /// Past values: control-cycle counter.
        ct_count: u16 @ 97,
        /// Past values: ALM2 (MHA2/MLA2, which ignore INH; see [`Alm2`]).
        alm2: u16 @ 116,
        /// Past values: S.DUTY output-period counter preset flag.
        duty_flag: u16 @ 118,
        /// Past values: S.DUTY output-period counter.
        duty_count: u16 @ 119,
        /// Past values: S.DUTY output counter (executions since the period began).
        duty_out: u16 @ 120,
        /// Past values: S.DUTY output-ON counter.
        duty_on: u16 @ 121,
        /// Past values: change-rate monitor counter preset flag (S.PHPL, S.BC).
        rate_flag: u16 @ 124,
        /// Past values: change-rate monitor counter (S.PHPL, S.BC).
        rate_count: u16 @ 125,
        /// Past values: the change-rate reference E1n-m (S.PHPL; S.BC keeps a
        /// BIN32 there).
        rate_ref: f32 @ 126,
    }
}

/// How far below the MV (+12) that an instruction's input operand names lies
/// the INH (+4) of the same loop tag, where an instruction sets the upper
/// loop's TRKF (spec §1.8).
pub const UPPER_INH_BELOW: u32 = (LoopTag::mv.offset() - LoopTag::inh.offset()) as u32;

/// The documented defaults of the loop-tag memory (spec §3), as
/// (offset, words) pairs a loop-tag initialiser writes.
pub fn defaults() -> [u16; 96] {
    let mut w = [0u16; 96];
    LoopTag::mode.set(&mut w, 0x8);
    LoopTag::alm.set(&mut w, 0x4000);
    LoopTag::inh.set(&mut w, 0x4000);
    for (f, v) in [
        (LoopTag::mh, 100.0),
        (LoopTag::rh, 100.0),
        (LoopTag::ph, 100.0),
        (LoopTag::hh, 100.0),
        (LoopTag::filter, 0.2),
        (LoopTag::dpl, 100.0),
        (LoopTag::ct, 1.0),
        (LoopTag::dml, 100.0),
        (LoopTag::dvl, 100.0),
        (LoopTag::p, 1.0),
        (LoopTag::i, 10.0),
        (LoopTag::gg, 1.0),
        (LoopTag::beta, 1.0),
        (LoopTag::ctduty, 1.0),
        (LoopTag::at1_st, 1.0),
        (LoopTag::at1_tout1, 100.0),
        (LoopTag::at1_tout2, 10.0),
    ] {
        f.set(&mut w, v);
    }
    w
}

/// ALM bits (000 Table 3.1; spec §1.6, reconstructed positions). INH bits
/// 0-11 inhibit the ALM bit of the same number.
pub mod alm {
    pub const MLA: u16 = 1 << 0;
    pub const MHA: u16 = 1 << 1;
    pub const DVLA: u16 = 1 << 2;
    pub const DPNA: u16 = 1 << 3;
    pub const DPPA: u16 = 1 << 4;
    pub const PLA: u16 = 1 << 5;
    pub const PHA: u16 = 1 << 6;
    pub const LLA: u16 = 1 << 7;
    pub const HHA: u16 = 1 << 8;
    pub const SEA: u16 = 1 << 9;
    pub const OOPA: u16 = 1 << 10;
    pub const DMLA: u16 = 1 << 11;
    /// Loop stop request (the user sets it; default 4000H).
    pub const SPA: u16 = 1 << 14;
}

/// BB bits of the block memory (BB1 … BB16 = b0 … b15). BB1 is, unless an
/// instruction says otherwise, the OR of its other alarm BB bits.
pub mod bb {
    pub const BB1: u16 = 1 << 0;
    pub const BB2: u16 = 1 << 1;
    pub const BB3: u16 = 1 << 2;
    pub const BB4: u16 = 1 << 3;
    pub const BB5: u16 = 1 << 4;
}

/// The INH flags above the inhibit bits, placed per DEC-6.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Inh {
    /// Inhibits every alarm.
    pub erri: u16,
    /// The tracking flag.
    pub trkf: u16,
}

impl Inh {
    pub fn new(s: &ProcessSettings) -> Inh {
        if s.inh_erri_b15 {
            Inh {
                erri: 1 << 15,
                trkf: 1 << 14,
            }
        } else {
            Inh {
                erri: 1 << 14,
                trkf: 1 << 15,
            }
        }
    }

    /// Whether the alarm `bit` (an [`alm`] bit) is detected under `inh`.
    pub fn allows(self, inh: u16, bit: u16) -> bool {
        inh & (self.erri | bit) == 0
    }

    /// Applies one alarm result (spec §1.6, the "*1" footnotes of every
    /// instruction): ALM `alm_bit` and block-memory `bb_bit` (0 for an alarm
    /// with no BB bit, e.g. HHA/LLA) become `on`, or 0 when the alarm's
    /// inhibit (the INH bit of the same number) or ERRI is set. Returns the
    /// value written.
    pub fn apply(
        self,
        inh: u16,
        alm: &mut u16,
        alm_bit: u16,
        bb: &mut u16,
        bb_bit: u16,
        on: bool,
    ) -> bool {
        let on = on && self.allows(inh, alm_bit);
        put(alm, alm_bit, on);
        put(bb, bb_bit, on);
        on
    }
}

/// Sets or clears `bits` of `w`.
#[inline]
pub fn put(w: &mut u16, bits: u16, on: bool) {
    if on {
        *w |= bits;
    } else {
        *w &= !bits;
    }
}

/// ALM2 bits (+116), placed per DEC-7.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Alm2 {
    pub mha2: u16,
    pub mla2: u16,
}

impl Alm2 {
    pub fn new(s: &ProcessSettings) -> Alm2 {
        if s.alm2_mha2_b1 {
            Alm2 { mha2: 2, mla2: 1 }
        } else {
            Alm2 { mha2: 1, mla2: 2 }
        }
    }
}

/// MODE bits (spec §1.5; LCC/LCM per DEC-5) and the groups the instructions use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mode {
    pub lcc: u16,
    pub lca: u16,
    pub lcm: u16,
}

impl Mode {
    pub const MAN: u16 = 0x0008;
    pub const AUT: u16 = 0x0010;
    pub const CAS: u16 = 0x0020;
    pub const CMB: u16 = 0x0040;
    pub const CAB: u16 = 0x0080;
    pub const CCB: u16 = 0x0100;
    pub const CMV: u16 = 0x0200;
    pub const CSV: u16 = 0x0400;

    pub fn new(s: &ProcessSettings) -> Mode {
        let (lcc, lcm) = if s.mode_lcc_b0 { (1, 4) } else { (4, 1) };
        Mode { lcc, lca: 2, lcm }
    }

    /// Manual group {MAN, CMB, CMV, LCM}.
    pub fn manual(self, mode: u16) -> bool {
        mode & (Self::MAN | Self::CMB | Self::CMV | self.lcm) != 0
    }

    /// Auto group {AUT, CAB, CAS, CCB, CSV, LCA, LCC}.
    pub fn auto(self, mode: u16) -> bool {
        mode & (Self::AUT | Self::CAB | Self::CAS | Self::CCB | Self::CSV | self.lca | self.lcc)
            != 0
    }

    /// Cascade group {CAS, CCB, CSV}: SV from E2.
    pub fn cascade(self, mode: u16) -> bool {
        mode & (Self::CAS | Self::CCB | Self::CSV) != 0
    }

    /// Tracking-eligible: every mode but the cascade group.
    pub fn tracking(self, mode: u16) -> bool {
        (self.manual(mode) || self.auto(mode)) && !self.cascade(mode)
    }

    /// Derivative forced to 0: {MAN, LCM, CMV}.
    pub fn no_derivative(self, mode: u16) -> bool {
        mode & (Self::MAN | Self::CMV | self.lcm) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_match_the_manual_figure() {
        let w = defaults();
        assert_eq!(LoopTag::mode.get(&w), 8);
        assert_eq!(LoopTag::alm.get(&w), 0x4000);
        assert_eq!(LoopTag::i.get(&w), 10.0);
        assert_eq!(LoopTag::filter.get(&w), 0.2);
        assert_eq!(LoopTag::at1_tout1.get(&w), 100.0);
        assert_eq!(LoopTag::sv.get(&w), 0.0);
    }

    #[test]
    fn mode_groups_and_the_lcc_lcm_switch() {
        let s = ProcessSettings::default();
        let m = Mode::new(&s);
        assert!(m.manual(0x8) && !m.auto(0x8) && m.no_derivative(0x8));
        assert!(m.auto(0x10) && m.tracking(0x10) && !m.cascade(0x10));
        assert!(m.cascade(0x20) && m.auto(0x20) && !m.tracking(0x20));
        assert!(m.manual(0x4) && m.auto(0x1), "LCM = b2, LCC = b0");
        let swapped = Mode::new(&ProcessSettings {
            mode_lcc_b0: false,
            ..s
        });
        assert!(swapped.manual(0x1) && swapped.auto(0x4));
        assert!(!m.no_derivative(Mode::CMB), "CMB keeps the derivative");
    }

    #[test]
    fn inhibits_follow_erri_and_dec6() {
        let s = ProcessSettings::default();
        let inh = Inh::new(&s);
        assert!(
            inh.allows(0x4000, alm::PHA),
            "default INH 4000H is TRKF only"
        );
        assert!(!inh.allows(0x8000, alm::PHA));
        assert!(!inh.allows(alm::PHA, alm::PHA));
        let other = Inh::new(&ProcessSettings {
            inh_erri_b15: false,
            ..s
        });
        assert!(!other.allows(0x4000, alm::PHA));
    }

    #[test]
    fn apply_sets_alm_and_bb_unless_inhibited() {
        let inh = Inh::new(&ProcessSettings::default());
        let (mut a, mut b) = (alm::SPA, 0u16);
        assert!(inh.apply(0, &mut a, alm::PHA, &mut b, bb::BB2, true));
        assert_eq!((a, b), (alm::SPA | alm::PHA, bb::BB2));
        assert!(!inh.apply(alm::PHA, &mut a, alm::PHA, &mut b, bb::BB2, true));
        assert_eq!((a, b), (alm::SPA, 0));
        inh.apply(0, &mut a, alm::HHA, &mut b, 0, true);
        assert_eq!((a, b), (alm::SPA | alm::HHA, 0), "no BB bit");
        inh.apply(0x8000, &mut a, alm::HHA, &mut b, 0, true);
        assert_eq!(a, alm::SPA, "ERRI");
    }
}
