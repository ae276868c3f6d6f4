//! Binary-coded decimal, one definition for every user: MELSEC's BCD/BIN,
//! DBCD/DBIN, BKBCD/BKBIN (PM §6.3), the BCD arithmetic (PM §6.2.5-§6.2.8)
//! and the BCD forms of the float instructions, the APLC's BCD/BIN/DBCD/DBIN
//! (002 §6.5), and the clock registers (SD210-SD213, the error time SD1-SD3)
//! write and read their digits through [`pack`] and [`unpack`].

/// `v` as BCD: one decimal digit per nibble, the units in the low nibble
/// (as many digits as `v` has; a caller that keeps 4 or 8 checks the range).
#[inline]
pub fn pack(mut v: u64) -> u64 {
    let mut r = 0;
    let mut shift = 0;
    while v > 0 {
        r |= (v % 10) << shift;
        v /= 10;
        shift += 4;
    }
    r
}

/// The value of the BCD digits in `v`; `None` when a nibble is not a decimal
/// digit (A-F).
#[inline]
pub fn unpack(v: u64) -> Option<u64> {
    let mut r = 0;
    let mut place = 1;
    let mut rest = v;
    while rest > 0 {
        let digit = rest & 0xF;
        if digit > 9 {
            return None;
        }
        r += digit * place;
        place *= 10;
        rest >>= 4;
    }
    Some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packs_and_unpacks_every_width() {
        assert_eq!(pack(0), 0);
        assert_eq!(pack(3333), 0x3333);
        assert_eq!(pack(9999), 0x9999);
        assert_eq!(pack(99_999_999), 0x9999_9999);
        assert_eq!(pack(9_999_999_999_999_999), 0x9999_9999_9999_9999);
        assert_eq!(unpack(0x5555), Some(5555));
        assert_eq!(unpack(0x9999_9999), Some(99_999_999));
        assert_eq!(unpack(0x5A55), None);
        assert_eq!(unpack(0xF000_0000), None);
        for v in [0, 1, 9, 10, 59, 99, 1234, 9999, 12_345_678] {
            assert_eq!(unpack(pack(v)), Some(v));
        }
    }
}
