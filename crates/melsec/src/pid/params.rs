//! PID control data of one loop: decoding and range checks (001 §5.1, Tables
//! 5.1/5.2, layouts §5.1(3)(a)/(b); notes `pid-instructions.md` §2.5, §3.1).

use super::Family;

/// Words of one loop's PID control data (001 §5.1(3): S. family 14, plain family 10).
pub(crate) const MAX_LOOP_WORDS: usize = 14;

softplc_ir::layout! {
    /// One loop's PID control data (001 §5.1 Table 5.2, layouts §5.1(3)(a)
    /// and (b)): the S. family's 14 words; the plain family's are the first
    /// 10 (no KD). Each doc starts with the label a faceplate shows.
    pub struct LoopData[14] {
        /// action (0 fwd, 1 rev): operation select, 0 forward, 1 reverse (001 §4.2.2).
        select: i16 @ 0,
        /// Ts ×10 ms: sampling period, 1..6000.
        ts: i16 @ 1,
        /// Kp ×0.01: proportional gain, 1..10000.
        kp: i16 @ 2,
        /// TI ×100 ms: integral time, 1..32767, above 30000 ∞.
        ti: i16 @ 3,
        /// TD ×10 ms: derivative time, 0..30000.
        td: i16 @ 4,
        /// α %: input filter coefficient, 0..100.
        alpha: i16 @ 5,
        /// MVLL: MV lower limit.
        mvll: i16 @ 6,
        /// MVHL: MV upper limit.
        mvhl: i16 @ 7,
        /// ΔMVL: MV change-rate alarm limit.
        dmvl: i16 @ 8,
        /// ΔPVL: PV change-rate alarm limit.
        dpvl: i16 @ 9,
        /// KD ×0.01: derivative gain, 0..32767, above 30000 ∞ (S. family only).
        kd: i16 @ 11,
    }
}

/// The plain family's fields of [`LoopData`]: all but KD.
pub(crate) const PLAIN_FIELDS: usize = 10;

/// One loop's registered PID control data, 001 §5.1 Table 5.2 (words m+0 …
/// m+13 of §5.1(3)(a), m+0 … m+9 of §5.1(3)(b)).
///
/// Values are the raw words as registered. The "limited" conversions of
/// MVLL/MVHL/ΔMVL/ΔPVL are applied at operation time, never written back
/// (\[DECISION\] pid-instructions.md §3.1 notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct LoopParams {
    /// Operation select: false = forward (0), true = reverse (1) (001 §4.2.2).
    pub reverse: bool,
    /// Sampling period Ts, 1..6000 × 10 ms.
    pub ts: u16,
    /// Proportional gain Kp, 1..10000 × 0.01.
    pub kp: u16,
    /// Integral time TI, 1..32767 × 100 ms; above 30000 it is ∞.
    pub ti: u16,
    /// Derivative time TD, 0..30000 × 10 ms.
    pub td: u16,
    /// Filter coefficient α, 0..100 %.
    pub alpha: u16,
    /// MV lower / upper limit (MVLL, MVHL).
    pub mvll: i16,
    pub mvhl: i16,
    /// MV / PV change-rate limits (ΔMVL, ΔPVL).
    pub dmvl: i16,
    pub dpvl: i16,
    /// Derivative gain KD, 0..32767 × 0.01; above 30000 it is ∞ (S. family only).
    pub kd: u16,
}

impl LoopParams {
    /// Decodes and range-checks one loop's words (`w.len()` is the family's
    /// per-loop size). `None` is error 4100 for that loop (001 §5.1 Table 5.2
    /// "出现错误, 不执行相应环路的 PID 运算"; §8.1.1/§9.1.1 errors):
    /// select ∉ {0,1}, Ts ∉ 1..6000, Kp ∉ 1..10000, TI ∉ 1..32767,
    /// TD ∉ 0..30000, α ∉ 0..100, MVHL < MVLL (raw words), and for the S. family
    /// KD ∉ 0..32767 or a reserved word (+10, +12, +13) ≠ 0 (001 §5.1(3)(a) 要点).
    ///
    /// MVHL < MVLL is checked on the raw words: the limited-mode conversion to
    /// −50..2050 is monotonic, so it can never turn a valid pair into an invalid one.
    pub(crate) fn decode(fam: Family, w: &[u16]) -> Option<LoopParams> {
        type L = LoopData;
        let p = LoopParams {
            reverse: match L::select.get(w) {
                0 => false,
                1 => true,
                _ => return None,
            },
            ts: range(L::ts.get(w), 1, 6000)?,
            kp: range(L::kp.get(w), 1, 10000)?,
            ti: range(L::ti.get(w), 1, 32767)?,
            td: range(L::td.get(w), 0, 30000)?,
            alpha: range(L::alpha.get(w), 0, 100)?,
            mvll: L::mvll.get(w),
            mvhl: L::mvhl.get(w),
            dmvl: L::dmvl.get(w),
            dpvl: L::dpvl.get(w),
            kd: match fam {
                // The reserved words +10, +12, +13 are 0.
                Family::Incomplete => {
                    if w[10] != 0 || w[12] != 0 || w[13] != 0 {
                        return None;
                    }
                    range(L::kd.get(w), 0, 32767)?
                }
                Family::Complete => 0,
            },
        };
        (p.mvhl >= p.mvll).then_some(p)
    }
}

/// `v` as u16 when `lo <= v <= hi` (the "用户指定范围" column of 001 §5.1 Table 5.2).
fn range(v: i16, lo: i16, hi: i16) -> Option<u16> {
    (lo..=hi).contains(&v).then_some(v as u16)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(kd: u16) -> [u16; 14] {
        [1, 100, 100, 100, 0, 0, 0, 2000, 100, 100, 0, kd, 0, 0]
    }

    #[test]
    fn ranges() {
        assert!(LoopParams::decode(Family::Incomplete, &words(800)).is_some());
        assert!(LoopParams::decode(Family::Complete, &words(800)[..10]).is_some());
        for (k, bad) in [
            (0, 2u16),
            (1, 0),
            (1, 6001),
            (2, 0),
            (2, 10001),
            (3, 0),
            (3, 0x8000),
            (4, 30001),
            (5, 101),
            (10, 1),
            (11, 0xFFFF),
            (12, 1),
            (13, 1),
        ] {
            let mut w = words(800);
            w[k] = bad;
            assert!(
                LoopParams::decode(Family::Incomplete, &w).is_none(),
                "word {k} = {bad}"
            );
        }
        // MVHL < MVLL; equal is allowed (001 §4.3.2).
        let mut w = words(0);
        w[6] = 10;
        w[7] = 9;
        assert!(LoopParams::decode(Family::Complete, &w[..10]).is_none());
        w[7] = 10;
        assert!(LoopParams::decode(Family::Complete, &w[..10]).is_some());
    }
}
