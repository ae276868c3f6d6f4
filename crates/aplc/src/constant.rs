//! APLC constants (002 table 3-5, L2092-2115; contract §1.1 item 5): bare
//! decimal, `16#`/`8#`/`2#` bit patterns without sign, REAL with a decimal
//! point or an exponent. No `K`/`H`/`E` prefixes.

/// The width an operand gives its constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Width {
    W16,
    W32,
    Real,
}

/// True when `t` has the form of a constant (so it is not a name).
pub fn looks_like_constant(t: &str) -> bool {
    let b = t.as_bytes();
    match b.first() {
        Some(c) if c.is_ascii_digit() => true,
        Some(b'+' | b'-' | b'.') => b.len() > 1,
        _ => false,
    }
}

/// Parses constant `t` (as written) for an operand of `width`; the raw bits
/// (16-bit values in the low half), or the message naming the token.
pub fn parse(t: &str, width: Width) -> Result<u32, String> {
    if let Some((radix, digits)) = based(t) {
        let name = match radix {
            16 => "hexadecimal",
            8 => "octal",
            _ => "binary",
        };
        if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
            return Err(format!("`{t}`: bad digit in a {name} constant"));
        }
        let v = u64::from_str_radix(digits, radix)
            .ok()
            .filter(|v| *v <= u32::MAX as u64);
        let max = match width {
            Width::W16 => 0xFFFF,
            Width::W32 | Width::Real => 0xFFFF_FFFF,
        };
        return match v {
            Some(v) if v <= max => Ok(v as u32),
            _ => Err(format!(
                "constant `{t}` does not fit a {} operand",
                width_name(width)
            )),
        };
    }
    let is_real = t.contains(['.', 'E', 'e']);
    if is_real {
        if width != Width::Real {
            return Err(format!(
                "REAL constant `{t}` where an integer operand is needed"
            ));
        }
        let v: f64 = t
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| format!("`{t}` is not a constant"))?;
        let f = v as f32;
        if f.is_infinite() || (v != 0.0 && f.abs() < f32::MIN_POSITIVE) {
            return Err(format!(
                "REAL constant `{t}` is outside ±1.175494E-38..±3.402823E+38"
            ));
        }
        return Ok(f.to_bits());
    }
    let body = t.strip_prefix('+').unwrap_or(t);
    let v: i64 = body
        .parse()
        .ok()
        .filter(|_| !body.starts_with(['+']))
        .ok_or_else(|| format!("`{t}` is not a constant"))?;
    match width {
        Width::W16 if (-32768..=65535).contains(&v) => Ok(v as u32 & 0xFFFF),
        Width::W32 if (-2147483648..=4294967295).contains(&v) => Ok(v as u32),
        Width::Real => {
            let f = v as f32;
            Ok(f.to_bits())
        }
        Width::W16 => Err(format!(
            "constant `{t}` does not fit a 16-bit operand (-32768..65535)"
        )),
        Width::W32 => Err(format!(
            "constant `{t}` does not fit a 32-bit operand (-2147483648..4294967295)"
        )),
    }
}

fn width_name(w: Width) -> &'static str {
    match w {
        Width::W16 => "16-bit",
        Width::W32 => "32-bit",
        Width::Real => "REAL",
    }
}

fn based(t: &str) -> Option<(u32, &str)> {
    let (r, d) = t.split_once('#')?;
    let radix = match r {
        "16" => 16,
        "8" => 8,
        "2" => 2,
        _ => return None,
    };
    Some((radix, d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_3_5() {
        assert_eq!(parse("123", Width::W16), Ok(123));
        assert_eq!(parse("-8949", Width::W16), Ok((-8949i32 as u32) & 0xFFFF));
        assert_eq!(parse("+100", Width::W16), Ok(100));
        assert_eq!(parse("65326", Width::W16), Ok(65326));
        assert!(parse("65536", Width::W16).is_err());
        assert!(parse("-32769", Width::W16).is_err());
        assert_eq!(parse("4294967295", Width::W32), Ok(u32::MAX));
        assert!(parse("4294967296", Width::W32).is_err());
        assert_eq!(parse("16#1FE9", Width::W16), Ok(0x1FE9));
        assert!(parse("16#1FFFF", Width::W16).is_err());
        assert_eq!(parse("16#FD1EAFE9", Width::W32), Ok(0xFD1E_AFE9));
        assert_eq!(parse("8#7173", Width::W16), Ok(0o7173));
        assert_eq!(parse("8#37777777777", Width::W32), Ok(u32::MAX));
        assert!(parse("8#78", Width::W16).unwrap_err().contains("bad digit"));
        assert!(parse("2#102", Width::W16)
            .unwrap_err()
            .contains("bad digit"));
        assert_eq!(parse("2#10111001", Width::W16), Ok(0b1011_1001));
        assert_eq!(parse("1.5", Width::Real), Ok(1.5f32.to_bits()));
        assert_eq!(parse("3.1415E+3", Width::Real), Ok(3141.5f32.to_bits()));
        assert_eq!(parse("10", Width::Real), Ok(10.0f32.to_bits()));
        assert!(parse("1.5", Width::W16).unwrap_err().contains("REAL"));
        assert!(parse("1E39", Width::Real).is_err());
        assert!(parse("++1", Width::W16).is_err());
    }
}
