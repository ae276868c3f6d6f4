//! softplc's private encoding of the I/O data work areas (001 §5.2(4): words
//! +1..+9 "用于PID控制的工作区" and each loop's m+7.. work words, "读取/写入
//! 禁止"). \[DECISION\] pid-instructions.md §3.4: a loop's running state lives in
//! these device words, so clearing the area restarts the loop (001 §5.2(4)(b)
//! 4) "当要从初始状态开始控制时，必须通过顺控程序进行数据清除"), latching it
//! keeps the loop across power cycles, and nothing else is hidden.
//!
//! # Loop work words (16 for S.PIDCONT, 11 for PIDCONT), offsets from m+7
//!
//! | words | content |
//! |---|---|
//! | w0..w3 | u64, low word first: bits 63..11 = MVn−1 as signed fixed point Q16.36 (MV · 2³⁶); bits 10..0 = flags |
//! | w4..w5 | PVfn−1 as i32 Q16.16 (PVf · 2¹⁶), low word first |
//! | w6..w7 | PVfn−2 as i32 Q16.16 |
//! | w8 | SV used at the previous sample (i16), for EVn−1 |
//! | w9 | PVn−1, the previous sample's range-clamped PV (i16), for the PV alarm |
//! | w10 | time accumulated since the last sample, ms (u16, saturating) |
//! | w11..w14 | S. family only: Dn−1 as f64 bits, low word first |
//! | w15 | S. family only: reserved (not written) |
//!
//! Flags: b0 first processing done, b1 previous MAN/AUTO was auto, b2 deferred
//! (due but not computed in the previous scan, 001 §5.1.1 要点(2)), b3 the
//! history's EVn−1 was computed as reverse action.
//!
//! EVn−1 is not stored: it is recomputed as `PVfn−1 − SVn−1` (forward) or
//! `SVn−1 − PVfn−1` (reverse) from the stored words, which is bit-identical to
//! the EVn of the previous sample because PVf is quantised before EV is formed
//! (see [`super::algo`]).
//!
//! MV keeps 36 fraction bits (resolution 1.5·10⁻¹¹) so integral action never
//! stalls (\[DECISION\] pid-instructions.md §2.6 "keep MV … in full precision");
//! PVf keeps 16 (1.5·10⁻⁵), well below one count. An all-zero area reads as
//! "first processing not done".
//!
//! # Common work words +1..+9
//!
//! +1 holds the sub-millisecond remainder (µs) of the measured scan times;
//! +2..+9 are reserved (not written).

use super::Family;

/// Flag bits of w0.
pub(crate) const F_INIT: u16 = 1;
pub(crate) const F_AUTO: u16 = 2;
pub(crate) const F_DEFERRED: u16 = 4;
pub(crate) const F_REVERSE: u16 = 8;
const FLAG_BITS: u32 = 11;
const FLAG_MASK: u64 = (1 << FLAG_BITS) - 1;

/// Fraction bits of the stored MV and PVf.
pub(crate) const MV_FRAC: i32 = 36;
pub(crate) const PVF_FRAC: i32 = 16;

/// Offset of the loop work words inside a loop's I/O block (001 §5.2(4)).
pub(crate) const WORK: usize = super::algo::LoopIo::WORDS;

/// Quantises MV to the stored Q16.36 grid (round half away from zero; the MV
/// state of \[DECISION\] pid-instructions.md §2.6, §3.4).
#[inline]
pub(crate) fn quantize_mv(x: f64) -> f64 {
    let s = (2.0f64).powi(MV_FRAC);
    (x * s).round() / s
}

/// Quantises PVf to the stored Q16.16 grid (round half away from zero; the PVf
/// of 001 §3.1.2/§3.2.2 要点(1), state per \[DECISION\] §2.6, §3.4).
#[inline]
pub(crate) fn quantize_pvf(x: f64) -> f64 {
    let s = (2.0f64).powi(PVF_FRAC);
    (x * s).round() / s
}

/// One loop's decoded work words (001 §5.2(4) m+7.., encoding in the module doc;
/// \[DECISION\] pid-instructions.md §3.4).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LoopState {
    pub flags: u16,
    /// MVn−1 (on the Q16.36 grid).
    pub mv: f64,
    /// PVfn−1, PVfn−2 (on the Q16.16 grid).
    pub pvf1: f64,
    pub pvf2: f64,
    pub sv1: i16,
    pub pv1: i16,
    pub acc_ms: u16,
    /// Dn−1 (S. family; 0 for the plain family).
    pub d1: f64,
}

softplc_ir::layout! {
    /// A loop's work words from m+7 (encoding in the module documentation):
    /// 16 for S.PIDCONT; PIDCONT uses the first 11.
    pub struct LoopWork[16] {
        /// Bits 63..11: MVn−1 as Q16.36 fixed point; bits 10..0: flags.
        head: u64 @ 0,
        /// PVfn−1 as Q16.16.
        pvf1: i32 @ 4,
        /// PVfn−2 as Q16.16.
        pvf2: i32 @ 6,
        /// SV used at the previous sample.
        sv1: i16 @ 8,
        /// PVn−1, the previous sample's range-clamped PV.
        pv1: i16 @ 9,
        /// Time accumulated since the last sample, ms (saturating).
        acc_ms: u16 @ 10,
        /// Dn−1 (S. family only).
        d1: f64 @ 11,
    }
}

impl LoopState {
    pub(crate) fn has(&self, f: u16) -> bool {
        self.flags & f != 0
    }

    pub(crate) fn set(&mut self, f: u16, on: bool) {
        if on {
            self.flags |= f;
        } else {
            self.flags &= !f;
        }
    }

    /// Decodes the work words `w` (the family's 16 or 11 words).
    pub(crate) fn load(fam: Family, w: &[u16]) -> LoopState {
        let head = LoopWork::head.get(w);
        let fixed = (head as i64) >> FLAG_BITS;
        LoopState {
            flags: (head & FLAG_MASK) as u16,
            mv: fixed as f64 / (2.0f64).powi(MV_FRAC),
            pvf1: LoopWork::pvf1.get(w) as f64 / (2.0f64).powi(PVF_FRAC),
            pvf2: LoopWork::pvf2.get(w) as f64 / (2.0f64).powi(PVF_FRAC),
            sv1: LoopWork::sv1.get(w),
            pv1: LoopWork::pv1.get(w),
            acc_ms: LoopWork::acc_ms.get(w),
            d1: match fam {
                Family::Incomplete => LoopWork::d1.get(w),
                Family::Complete => 0.0,
            },
        }
    }

    /// Encodes into the work words `w`. `mv`, `pvf1`, `pvf2` must already be
    /// on their grids and within the int16 range (the algorithm guarantees it).
    pub(crate) fn store(&self, fam: Family, w: &mut [u16]) {
        let fixed = (self.mv * (2.0f64).powi(MV_FRAC)) as i64;
        let head = (fixed << FLAG_BITS) as u64 | self.flags as u64 & FLAG_MASK;
        LoopWork::head.set(w, head);
        LoopWork::pvf1.set(w, (self.pvf1 * (2.0f64).powi(PVF_FRAC)) as i32);
        LoopWork::pvf2.set(w, (self.pvf2 * (2.0f64).powi(PVF_FRAC)) as i32);
        LoopWork::sv1.set(w, self.sv1);
        LoopWork::pv1.set(w, self.pv1);
        LoopWork::acc_ms.set(w, self.acc_ms);
        if fam == Family::Incomplete {
            LoopWork::d1.set(w, self.d1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        for fam in [Family::Incomplete, Family::Complete] {
            let st = LoopState {
                flags: F_INIT | F_REVERSE | F_DEFERRED,
                mv: quantize_mv(-32768.0),
                pvf1: quantize_pvf(32767.0),
                pvf2: quantize_pvf(-1234.56789),
                sv1: -7,
                pv1: 2050,
                acc_ms: 65535,
                d1: if fam == Family::Incomplete {
                    -88.88
                } else {
                    0.0
                },
            };
            let mut w = [0u16; 16];
            st.store(fam, &mut w);
            assert_eq!(LoopState::load(fam, &w), st);
            let st2 = LoopState {
                mv: quantize_mv(1234.000000123),
                ..st
            };
            st2.store(fam, &mut w);
            assert_eq!(LoopState::load(fam, &w), st2);
        }
        // A cleared area is "first processing not done".
        let z = LoopState::load(Family::Complete, &[0; 11]);
        assert!(!z.has(F_INIT));
        assert_eq!(z.mv, 0.0);
    }
}
