//! Word logic, one definition for every dialect: MELSEC's WAND/WOR/WXOR/WXNR,
//! DAND … and BKAND … (PM §7.1) and the APLC's WAND/WOR/WXOR/WINV and
//! DWAND … (002 §6.6) apply these to raw 16- or 32-bit values.

/// A bitwise operation on two words (the second ignored by [`WordLogic::Not`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WordLogic {
    /// Logical product.
    And,
    /// Logical sum.
    Or,
    /// Exclusive OR.
    Xor,
    /// Exclusive NOR: NOT (a XOR b).
    Xnr,
    /// Complement of the first operand.
    Not,
}

impl WordLogic {
    /// `a op b` on the low bits a caller keeps (16 or 32).
    #[inline]
    pub fn apply(self, a: u32, b: u32) -> u32 {
        match self {
            WordLogic::And => a & b,
            WordLogic::Or => a | b,
            WordLogic::Xor => a ^ b,
            WordLogic::Xnr => !(a ^ b),
            WordLogic::Not => !a,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::WordLogic::*;

    #[test]
    fn truth_tables() {
        let (a, b) = (0b1100, 0b1010);
        assert_eq!(And.apply(a, b), 0b1000);
        assert_eq!(Or.apply(a, b), 0b1110);
        assert_eq!(Xor.apply(a, b), 0b0110);
        assert_eq!(Xnr.apply(a, b) & 0xF, 0b1001);
        assert_eq!(Not.apply(a, b) & 0xF, 0b0011);
    }
}
