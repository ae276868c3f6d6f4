//! A dialect's device table: the device names a program may write, the storage
//! kind each names, and how its numbers are written. The operand parser
//! ([`super::parse_operand_in`]) is driven by it.

use super::{DeviceKind, Numbering};

/// One device name of a dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceDef {
    /// The name as written (upper case).
    pub name: &'static str,
    /// The storage kind it names (for timers and counters, the contact).
    pub kind: DeviceKind,
    /// `T`, `ST`, `C`: the contact in a bit operand, the current value in a word
    /// operand.
    pub generic: bool,
    pub numbering: Numbering,
}

/// A dialect's device names, longest first (so that `STN` wins over `ST` and `S`).
#[derive(Debug)]
pub struct DeviceTable {
    pub defs: &'static [DeviceDef],
    /// The dialect reaches the rack's modules: direct I/O `DX`/`DY` and
    /// buffer memory `U<n>\\G<addr>` (MELSEC-Q, 004 §10.2, ch. 8).
    pub modules: bool,
}

impl DeviceTable {
    /// The device named at the start of `t` (upper case) followed by a digit of
    /// its numbering.
    pub fn find(&self, t: &str) -> Option<&'static DeviceDef> {
        self.defs.iter().find(|d| {
            t.starts_with(d.name)
                && t.as_bytes()
                    .get(d.name.len())
                    .is_some_and(|&c| d.numbering.is_digit(c))
        })
    }
}

const fn def(name: &'static str, kind: DeviceKind, generic: bool) -> DeviceDef {
    DeviceDef {
        name,
        kind,
        generic,
        numbering: kind.melsec_numbering(),
    }
}

/// The MELSEC-Q devices (004 Table 10.1): X, Y, B, SB, W, SW, FX, FY in hex.
pub static MELSEC_Q: DeviceTable = DeviceTable {
    modules: true,
    defs: &[
        def("STN", DeviceKind::STN, false),
        def("STS", DeviceKind::STS, false),
        def("STC", DeviceKind::STC, false),
        def("ST", DeviceKind::STS, true),
        def("SM", DeviceKind::SM, false),
        def("SD", DeviceKind::SD, false),
        def("SB", DeviceKind::SB, false),
        def("SW", DeviceKind::SW, false),
        def("TN", DeviceKind::TN, false),
        def("TS", DeviceKind::TS, false),
        def("TC", DeviceKind::TC, false),
        def("CN", DeviceKind::CN, false),
        def("CS", DeviceKind::CS, false),
        def("CC", DeviceKind::CC, false),
        def("ZR", DeviceKind::ZR, false),
        def("FX", DeviceKind::FX, false),
        def("FY", DeviceKind::FY, false),
        def("FD", DeviceKind::FD, false),
        def("X", DeviceKind::X, false),
        def("Y", DeviceKind::Y, false),
        def("M", DeviceKind::M, false),
        def("L", DeviceKind::L, false),
        def("F", DeviceKind::F, false),
        def("V", DeviceKind::V, false),
        def("B", DeviceKind::B, false),
        def("S", DeviceKind::S, false),
        def("T", DeviceKind::TS, true),
        def("C", DeviceKind::CS, true),
        def("D", DeviceKind::D, false),
        def("W", DeviceKind::W, false),
        def("R", DeviceKind::R, false),
        def("Z", DeviceKind::Z, false),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::{parse_operand_in, Operand};

    /// A dialect with octal inputs (as the APLC's X/Y) parses `X10` as input 8
    /// and rejects `X8`.
    #[test]
    fn octal_numbering() {
        static OCTAL: DeviceTable = DeviceTable {
            modules: false,
            defs: &[
                DeviceDef {
                    name: "X",
                    kind: DeviceKind::X,
                    generic: false,
                    numbering: Numbering::Oct,
                },
                def("D", DeviceKind::D, false),
            ],
        };
        match parse_operand_in(&OCTAL, "X17") {
            Ok(Operand::Device { dev, .. }) => {
                assert_eq!((dev.kind, dev.number), (DeviceKind::X, 15))
            }
            other => panic!("{other:?}"),
        }
        assert!(parse_operand_in(&OCTAL, "X8").is_err());
        assert!(parse_operand_in(&OCTAL, "D19").is_ok());
        assert!(parse_operand_in(&OCTAL, "M0").is_err());
        assert_eq!(Numbering::Oct.radix(), 8);
    }
}
