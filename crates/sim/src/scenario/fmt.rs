//! Number and time formatting for reports.

/// A number without noise: integers as integers, others with up to 6
/// significant digits.
pub fn fmt_num(v: f64) -> String {
    if v.is_nan() {
        return "NaN".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.into();
    }
    if v.fract() == 0.0 && v.abs() < 1e15 {
        return format!("{}", v as i64);
    }
    let mag = v.abs().log10().floor() as i32;
    let decimals = (5 - mag).clamp(0, 12) as usize;
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// A time in µs as `1.5 s`, `10 min`, `24 h`, `20 ms`.
pub fn fmt_time(us: u64) -> String {
    const S: u64 = 1_000_000;
    if us >= 3600 * S && us.is_multiple_of(3600 * S) {
        format!("{} h", us / (3600 * S))
    } else if us >= 60 * S && us.is_multiple_of(60 * S) {
        format!("{} min", us / (60 * S))
    } else if us >= S || us == 0 {
        format!("{} s", fmt_num(us as f64 / 1e6))
    } else if us.is_multiple_of(1000) {
        format!("{} ms", us / 1000)
    } else {
        format!("{} us", us)
    }
}

/// Seconds with millisecond resolution (history tables, CSV).
pub fn fmt_secs(us: u64) -> String {
    let s = us / 1_000_000;
    let frac = us % 1_000_000;
    if frac.is_multiple_of(1000) {
        format!("{s}.{:03}", frac / 1000)
    } else {
        format!("{s}.{frac:06}")
    }
}

/// How a device's samples are shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Bit,
    Int,
    Float,
}

/// A sample of a device of kind `k`.
pub fn fmt_value(v: f64, k: Kind) -> String {
    match k {
        Kind::Bit if v.is_nan() => "?".into(),
        Kind::Bit => (if v > 0.5 { "true" } else { "false" }).into(),
        Kind::Int => fmt_num(v),
        Kind::Float => {
            if v.is_finite() {
                format!("{}", v as f32)
            } else {
                fmt_num(v)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_times() {
        assert_eq!(fmt_num(600.0), "600");
        assert_eq!(fmt_num(-3.0), "-3");
        assert_eq!(fmt_num(2.5), "2.5");
        assert_eq!(fmt_num(0.1 + 0.2), "0.3");
        assert_eq!(fmt_num(59.999996185302734), "60");
        assert_eq!(fmt_num(1234.5678), "1234.57");
        assert_eq!(fmt_time(1_500_000), "1.5 s");
        assert_eq!(fmt_time(600_000_000), "10 min");
        assert_eq!(fmt_time(86_400_000_000), "24 h");
        assert_eq!(fmt_time(10_000), "10 ms");
        assert_eq!(fmt_time(0), "0 s");
        assert_eq!(fmt_secs(2_950_000), "2.950");
        assert_eq!(fmt_secs(3_000_000), "3.000");
        assert_eq!(fmt_value(1.0, Kind::Bit), "true");
        assert_eq!(fmt_value(1.5, Kind::Float), "1.5");
    }
}
