//! Operand syntax: device names, digit specification, bit-of-word, index
//! modification and constants (004 §10, §2.8; contract §1).
//!
//! This is pure syntax: whether `D99999` exists or `K70000` fits is decided by the
//! compiler, which knows the device points and the operand width.

use super::kind::DeviceKind;
use super::table::{DeviceTable, MELSEC_Q};

/// A named device as written: `X1F`, `D100`, `T5`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceName {
    pub kind: DeviceKind,
    pub number: u32,
    /// Written as plain `T`, `ST` or `C`: the contact in a bit operand, the current
    /// value in a word operand. `kind` then holds the contact kind.
    pub generic: bool,
    /// How the device is reached: device memory, or a module of the rack.
    pub reach: Reach,
}

/// How an operand reaches its device (004 §10.2, ch. 8).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reach {
    /// The CPU's device memory (`X10`, `D0`).
    Memory,
    /// Direct access to the module on the base when the instruction runs:
    /// `DX10` (kind X), `DY10` (kind Y).
    Direct,
    /// Buffer memory of the intelligent function module with this unit
    /// number: `U2\\G11` is kind [`DeviceKind::G`], number 11, unit 2.
    Unit(u32),
}

impl DeviceName {
    /// The kind this name means in a word operand (`T0` → `TN0`).
    pub fn word_kind(&self) -> DeviceKind {
        match (self.generic, self.kind) {
            (true, DeviceKind::TS) => DeviceKind::TN,
            (true, DeviceKind::STS) => DeviceKind::STN,
            (true, DeviceKind::CS) => DeviceKind::CN,
            (_, k) => k,
        }
    }
}

/// A constant operand.
#[derive(Clone, Debug, PartialEq)]
pub enum Constant {
    /// `K123`, `K-50` (decimal) or `H1F` (hex).
    Int { value: i64, hex: bool },
    /// `E1.5`, `E1.234+3`.
    Real(f64),
    /// `"text"`.
    Str(String),
}

/// One operand as written.
#[derive(Clone, Debug, PartialEq)]
pub enum Operand {
    Device {
        dev: DeviceName,
        /// Digit specification `Kn` (n = 1..8) on a bit device.
        digits: Option<u8>,
        /// Bit of a word device, `D0.F`.
        bit: Option<u8>,
        /// Index modification `Zn`.
        index: Option<u8>,
    },
    Const(Constant),
    /// `P0`-`P4095`.
    Pointer(u32),
    /// `I0`-`I255`.
    Interrupt(u32),
    /// `N0`-`N14`.
    Nesting(u32),
}

/// Why a token is not an operand; `offset` is the character offset in the token.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct OperandError {
    pub message: String,
    pub offset: usize,
}

fn err<T>(offset: usize, message: impl Into<String>) -> Result<T, OperandError> {
    Err(OperandError {
        message: message.into(),
        offset,
    })
}

/// Parses one operand token with the MELSEC-Q devices. Letters are
/// case-insensitive.
pub fn parse_operand(token: &str) -> Result<Operand, OperandError> {
    parse_operand_in(&MELSEC_Q, token)
}

/// Parses one operand token in MELSEC syntax (K/H/E constants, `K4M0`, `D0.F`,
/// `D0Z1`) with the device names of `table`.
pub fn parse_operand_in(table: &DeviceTable, token: &str) -> Result<Operand, OperandError> {
    if token.is_empty() {
        return err(0, "empty operand");
    }
    if let Some(rest) = token.strip_prefix('"') {
        return match rest.strip_suffix('"') {
            Some(s) if !s.contains('"') => Ok(Operand::Const(Constant::Str(s.to_string()))),
            _ => err(0, format!("unterminated string constant `{token}`")),
        };
    }
    let up = token.to_ascii_uppercase();
    if !up.is_ascii() {
        return err(0, format!("`{token}` is not an operand"));
    }
    let b = up.as_bytes();
    match b[0] {
        b'K' => parse_k(table, &up),
        b'H' => parse_hex_const(&up),
        b'E' => parse_real(&up).map(|v| Operand::Const(Constant::Real(v))),
        b'P' => parse_decimal(&up, 1).map(Operand::Pointer),
        b'I' => parse_decimal(&up, 1).map(Operand::Interrupt),
        b'N' => parse_decimal(&up, 1).map(Operand::Nesting),
        b'U' if table.modules && up.contains('\\') => parse_unit(&up),
        b'J' | b'U' if up.contains('\\') => err(
            0,
            format!("`{token}`: link direct (J\\) and module (U\\G) devices are not supported"),
        ),
        _ => parse_device(table, &up, 0),
    }
}

fn parse_decimal(s: &str, from: usize) -> Result<u32, OperandError> {
    let digits = &s[from..];
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return err(
            from,
            format!("`{s}`: expected a decimal number after `{}`", &s[..from]),
        );
    }
    digits
        .parse::<u32>()
        .or_else(|_| err(from, format!("`{s}`: number too large")))
}

fn parse_k(table: &DeviceTable, s: &str) -> Result<Operand, OperandError> {
    let rest = &s[1..];
    let b = rest.as_bytes();
    // `K4M0`: one digit, then a device letter.
    if b.len() >= 2 && b[0].is_ascii_digit() && b[1].is_ascii_alphabetic() {
        let n = b[0] - b'0';
        if !(1..=8).contains(&n) {
            return err(1, format!("`{s}`: digit specification must be K1 to K8"));
        }
        let op = parse_device(table, s, 2)?;
        if let Operand::Device {
            dev, bit, digits, ..
        } = &op
        {
            if !dev.kind.is_bit() || bit.is_some() || digits.is_some() {
                return err(2, format!("`{s}`: digit specification needs a bit device"));
            }
        }
        return Ok(match op {
            Operand::Device { dev, index, .. } => Operand::Device {
                dev,
                digits: Some(n),
                bit: None,
                index,
            },
            other => other,
        });
    }
    let (neg, digits) = match rest.as_bytes().first() {
        Some(b'-') => (true, &rest[1..]),
        Some(b'+') => (false, &rest[1..]),
        _ => (false, rest),
    };
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return err(1, format!("`{s}`: expected a decimal constant"));
    }
    let mag: i64 = match digits.parse::<u64>() {
        Ok(v) if v <= i64::MAX as u64 => v as i64,
        _ => return err(1, format!("`{s}`: constant out of range")),
    };
    Ok(Operand::Const(Constant::Int {
        value: if neg { -mag } else { mag },
        hex: false,
    }))
}

fn parse_hex_const(s: &str) -> Result<Operand, OperandError> {
    let digits = &s[1..];
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_hexdigit()) {
        return err(1, format!("`{s}`: expected a hexadecimal constant"));
    }
    if digits.trim_start_matches('0').len() > 8 {
        return err(1, format!("`{s}`: constant out of range"));
    }
    let v = u64::from_str_radix(digits, 16).unwrap_or(0);
    Ok(Operand::Const(Constant::Int {
        value: v as i64,
        hex: true,
    }))
}

/// `E1.5`, `E-0.25`, `E1.234+3` (MELSEC exponent form), `E1.234E-3`.
fn parse_real(s: &str) -> Result<f64, OperandError> {
    let body = &s[1..];
    let b = body.as_bytes();
    let mut i = 0;
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        i += 1;
    }
    let mant_start = i;
    while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
        i += 1;
    }
    let mantissa = &body[..i];
    if i == mant_start || mantissa[mant_start..].matches('.').count() > 1 {
        return err(
            1,
            format!("`{s}`: expected a real constant such as E1.5 or E1.234+3"),
        );
    }
    let mut text = mantissa.to_string();
    if i < b.len() {
        let exp = if b[i] == b'E' {
            &body[i + 1..]
        } else {
            &body[i..]
        };
        let digits = exp.strip_prefix(['+', '-']).unwrap_or(exp);
        // The MELSEC form `1.234+3` needs the sign; `1.2E3` may omit it.
        let signed = digits.len() < exp.len();
        if digits.is_empty()
            || !digits.bytes().all(|c| c.is_ascii_digit())
            || !signed && b[i] != b'E'
        {
            return err(1 + i, format!("`{s}`: bad exponent in real constant"));
        }
        text.push('e');
        text.push_str(exp);
    }
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => err(1, format!("`{s}`: real constant out of range")),
    }
}

/// Parses a device starting at byte `from` of the upper-case token `s`.
fn parse_device(table: &DeviceTable, s: &str, from: usize) -> Result<Operand, OperandError> {
    let t = &s[from..];
    let direct = table.modules
        && (t.starts_with("DX") || t.starts_with("DY"))
        && t.as_bytes().get(2).is_some_and(u8::is_ascii_hexdigit);
    if direct {
        return match parse_device(table, s, from + 1)? {
            Operand::Device {
                dev,
                bit: None,
                index: None,
                digits,
            } => Ok(Operand::Device {
                dev: DeviceName {
                    reach: Reach::Direct,
                    ..dev
                },
                digits,
                bit: None,
                index: None,
            }),
            _ => err(
                from,
                format!("`{s}`: direct access takes no bit number or index modification"),
            ),
        };
    }
    if t.starts_with("DX") || t.starts_with("DY") {
        return err(
            from,
            format!("`{s}`: direct access (DX/DY) is not supported by this CPU; use X/Y"),
        );
    }
    let Some(d) = table.find(t) else {
        return err(from, format!("`{s}` is not a device or constant"));
    };
    let (kind, generic) = (d.kind, d.generic);
    let num_start = from + d.name.len();
    let b = s.as_bytes();
    let mut i = num_start;
    while i < b.len() && d.numbering.is_digit(b[i]) {
        i += 1;
    }
    let number = match u32::from_str_radix(&s[num_start..i], d.numbering.radix()) {
        Ok(n) => n,
        Err(_) => return err(num_start, format!("`{s}`: device number too large")),
    };
    let mut bit = None;
    let mut index = None;
    if i < b.len() && b[i] == b'.' {
        if kind.is_bit() {
            return err(i, format!("`{s}`: a bit number `.n` needs a word device"));
        }
        let rest = &s[i + 1..];
        if rest.len() != 1 || !rest.as_bytes()[0].is_ascii_hexdigit() {
            return err(
                i + 1,
                format!("`{s}`: bit number must be one hex digit 0-F"),
            );
        }
        bit = Some(u8::from_str_radix(rest, 16).unwrap_or(0));
        i = b.len();
    } else if i < b.len() && b[i] == b'Z' {
        let z = parse_decimal(s, i + 1)?;
        if z > 15 {
            return err(
                i,
                format!("`{s}`: index register Z{z} does not exist (Z0-Z15)"),
            );
        }
        index = Some(z as u8);
        i = b.len();
    }
    if i != b.len() {
        return err(i, format!("`{s}`: unexpected `{}`", &s[i..]));
    }
    Ok(Operand::Device {
        dev: DeviceName {
            kind,
            number,
            generic,
            reach: Reach::Memory,
        },
        digits: None,
        bit,
        index,
    })
}

/// `U<n>\\G<addr>`: buffer memory of the module at unit `n` (its start I/O
/// number without the last hex digit, up to 3 hex digits), word `addr`
/// (decimal, 0-65535), with a bit number `.b` or an index `Zn` (004 ch. 8).
fn parse_unit(s: &str) -> Result<Operand, OperandError> {
    let Some((u, g)) = s[1..].split_once('\\') else {
        return err(0, format!("`{s}` is not a device or constant"));
    };
    if u.is_empty() || u.len() > 3 || !u.bytes().all(|c| c.is_ascii_hexdigit()) {
        return err(1, format!("`{s}`: the unit `U<n>` is the module's start I/O number without its last digit, 1-3 hex digits (U2 for X/Y20)"));
    }
    let unit = u32::from_str_radix(u, 16).unwrap_or(0);
    let at = u.len() + 2;
    if !g.starts_with('G') {
        return err(
            at,
            format!("`{s}`: expected `G` and a buffer-memory address after `\\`"),
        );
    }
    let op = parse_device(&UNIT_WORDS, s, at)?;
    let Operand::Device {
        dev, bit, index, ..
    } = op
    else {
        return err(at, format!("`{s}` is not a device or constant"));
    };
    if dev.number > 65535 {
        return err(
            at + 1,
            format!("`{s}`: buffer-memory addresses are G0-G65535"),
        );
    }
    Ok(Operand::Device {
        dev: DeviceName {
            reach: Reach::Unit(unit),
            ..dev
        },
        digits: None,
        bit,
        index,
    })
}

/// The `G` of `U<n>\\G<addr>`: decimal buffer-memory words.
static UNIT_WORDS: DeviceTable = DeviceTable {
    modules: false,
    defs: &[super::DeviceDef {
        name: "G",
        kind: DeviceKind::G,
        generic: false,
        numbering: super::Numbering::Dec,
    }],
};

#[cfg(test)]
mod tests {
    use super::*;

    fn dev(s: &str) -> (DeviceKind, u32, Option<u8>, Option<u8>, Option<u8>) {
        match parse_operand(s).unwrap() {
            Operand::Device {
                dev,
                digits,
                bit,
                index,
            } => (dev.kind, dev.number, digits, bit, index),
            o => panic!("{s}: {o:?}"),
        }
    }

    #[test]
    fn devices() {
        use DeviceKind::*;
        assert_eq!(dev("X1F"), (X, 0x1F, None, None, None));
        assert_eq!(dev("y10"), (Y, 0x10, None, None, None));
        assert_eq!(dev("M100"), (M, 100, None, None, None));
        assert_eq!(dev("SM400"), (SM, 400, None, None, None));
        assert_eq!(dev("SB7FF"), (SB, 0x7FF, None, None, None));
        assert_eq!(dev("SW1A"), (SW, 0x1A, None, None, None));
        assert_eq!(dev("ZR100000"), (ZR, 100000, None, None, None));
        assert_eq!(dev("TN5"), (TN, 5, None, None, None));
        assert_eq!(dev("ST3"), (STS, 3, None, None, None));
        assert_eq!(dev("STN3"), (STN, 3, None, None, None));
        assert_eq!(dev("K4M0"), (M, 0, Some(4), None, None));
        assert_eq!(dev("K2Y10"), (Y, 0x10, Some(2), None, None));
        assert_eq!(dev("K4M0Z2"), (M, 0, Some(4), None, Some(2)));
        assert_eq!(dev("D0.F"), (D, 0, None, Some(15), None));
        assert_eq!(dev("D200Z0"), (D, 200, None, None, Some(0)));
        assert_eq!(dev("B1FZ3"), (B, 0x1F, None, None, Some(3)));
        assert_eq!(dev("FD4"), (FD, 4, None, None, None));
        assert_eq!(dev("FXF"), (FX, 0xF, None, None, None));
        assert_eq!(dev("Z15"), (Z, 15, None, None, None));
        assert_eq!(dev("U2\\G11"), (G, 11, None, None, None));
        assert_eq!(dev("u1f\\g65535"), (G, 65535, None, None, None));
        assert_eq!(dev("U2\\G11Z3"), (G, 11, None, None, Some(3)));
        assert_eq!(dev("U2\\G11.F"), (G, 11, None, Some(15), None));
        assert_eq!(dev("DX1F"), (X, 0x1F, None, None, None));
        assert_eq!(dev("DY10"), (Y, 0x10, None, None, None));
    }

    #[test]
    fn reach() {
        let reach = |s| match parse_operand(s).unwrap() {
            Operand::Device { dev, .. } => dev.reach,
            o => panic!("{s}: {o:?}"),
        };
        assert_eq!(reach("U2\\G11"), Reach::Unit(2));
        assert_eq!(reach("U3E0\\G0"), Reach::Unit(0x3E0));
        assert_eq!(reach("DX0"), Reach::Direct);
        assert_eq!(reach("X0"), Reach::Memory);
        assert_eq!(reach("D0"), Reach::Memory);
    }

    #[test]
    fn constants() {
        let k = |s| parse_operand(s).unwrap();
        assert_eq!(
            k("K123"),
            Operand::Const(Constant::Int {
                value: 123,
                hex: false
            })
        );
        assert_eq!(
            k("K-50"),
            Operand::Const(Constant::Int {
                value: -50,
                hex: false
            })
        );
        assert_eq!(
            k("H1F"),
            Operand::Const(Constant::Int {
                value: 31,
                hex: true
            })
        );
        assert_eq!(
            k("hFFFFFFFF"),
            Operand::Const(Constant::Int {
                value: 0xFFFF_FFFF,
                hex: true
            })
        );
        assert_eq!(k("E1.5"), Operand::Const(Constant::Real(1.5)));
        assert_eq!(k("E1.234+3"), Operand::Const(Constant::Real(1234.0)));
        assert_eq!(k("E-2.5-1"), Operand::Const(Constant::Real(-0.25)));
        assert_eq!(k("E10.2345"), Operand::Const(Constant::Real(10.2345)));
        assert_eq!(k("\"AB C\""), Operand::Const(Constant::Str("AB C".into())));
        assert_eq!(k("P12"), Operand::Pointer(12));
        assert_eq!(k("N3"), Operand::Nesting(3));
    }

    #[test]
    fn rejects() {
        for s in [
            "Q1",
            "K9M0",
            "K4D0",
            "X1G",
            "D0.G",
            "D0Z16",
            "M0.1",
            "H123456789",
            "E1.2.3",
            "\"ab",
            "DX0.1",
            "DYZ",
            "U\\G0",
            "U1234\\G0",
            "U1\\D0",
            "U1\\G65536",
            "J1\\W0",
            "K",
            "E",
            "D",
            "K12A",
        ] {
            assert!(parse_operand(s).is_err(), "{s} should be rejected");
        }
    }
}
