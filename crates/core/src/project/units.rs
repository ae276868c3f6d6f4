//! Durations as written in `plc.toml` (`"100ms"`, `"0.5ms"`, `"2s"`, `"500us"`)
//! and the setting ranges of the PLC parameters they are checked against.

use std::time::Duration;

const NS_PER_US: u64 = 1_000;
const NS_PER_MS: u64 = 1_000_000;
const NS_PER_S: u64 = 1_000_000_000;

/// Parses a duration: a decimal number and a unit `ns`, `us` (or `µs`), `ms` or
/// `s`, optionally separated by spaces. The value must be a whole number of
/// nanoseconds; no rounding happens, so `"0.05ms"` is exactly 50 µs.
pub fn parse_duration(s: &str) -> Option<Duration> {
    let s = s.trim();
    let split = s.find(|c: char| !(c.is_ascii_digit() || c == '.'))?;
    let (num, unit) = s.split_at(split);
    let scale = match unit.trim_start() {
        "ns" => 1,
        "us" | "µs" => NS_PER_US,
        "ms" => NS_PER_MS,
        "s" => NS_PER_S,
        _ => return None,
    };
    let (int, frac) = match num.split_once('.') {
        Some((i, f)) => (i, f),
        None => (num, ""),
    };
    if int.is_empty() || frac.contains('.') || (num.contains('.') && frac.is_empty()) {
        return None;
    }
    let int: u64 = int.parse().ok()?;
    let mut ns = int.checked_mul(scale)?;
    // The fraction: digits beyond the unit's nanosecond resolution must be 0.
    let mut place = scale;
    for c in frac.chars() {
        let d = c.to_digit(10)? as u64;
        if !place.is_multiple_of(10) {
            if d != 0 {
                return None;
            }
            continue;
        }
        place /= 10;
        ns = ns.checked_add(d * place)?;
    }
    Some(Duration::from_nanos(ns))
}

/// Shows a duration in ms, the way the manual writes settings (`0.5ms`, `200ms`).
pub(crate) fn show(d: Duration) -> String {
    let ns = d.as_nanos() as u64;
    let ms = ns / NS_PER_MS;
    let rest = ns % NS_PER_MS;
    if rest == 0 {
        return format!("{ms}ms");
    }
    let frac = format!("{rest:06}");
    format!("{ms}.{}ms", frac.trim_end_matches('0'))
}

/// A setting range: `min..=max` in multiples of `step`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Range {
    pub min: Duration,
    pub max: Duration,
    pub step: Duration,
}

impl Range {
    const fn ms(min_us: u64, max_us: u64, step_us: u64) -> Range {
        Range {
            min: Duration::from_micros(min_us),
            max: Duration::from_micros(max_us),
            step: Duration::from_micros(step_us),
        }
    }

    pub fn contains(&self, d: Duration) -> bool {
        d >= self.min && d <= self.max && d.as_nanos().is_multiple_of(self.step.as_nanos())
    }

    /// `0.5ms-2000ms in 0.5 ms steps`; ranges in whole seconds are shown in s.
    pub fn describe(&self) -> String {
        if self.step.subsec_nanos() == 0 {
            return format!(
                "{}s-{}s in {} s steps",
                self.min.as_secs(),
                self.max.as_secs(),
                self.step.as_secs()
            );
        }
        let step = show(self.step);
        format!(
            "{}-{} in {} ms steps",
            show(self.min),
            show(self.max),
            step.trim_end_matches("ms")
        )
    }
}

/// Settable ranges of the time parameters (qcpu.md §2.2, §4.1, §4.11, §4.17, §8.3).
pub(crate) mod ranges {
    use super::Range;

    /// WDT: 10-2000 ms in 10 ms units (004 L4850-4891).
    pub const WATCHDOG: Range = Range::ms(10_000, 2_000_000, 10_000);
    /// Constant scan: 0.5-2000 ms in 0.5 ms units (004 L3441-3503).
    pub const CONSTANT_SCAN: Range = Range::ms(500, 2_000_000, 500);
    /// Low-speed program execution time: 1-2000 ms in 1 ms units (004 L1576-1590).
    pub const LOW_SPEED_TIME: Range = Range::ms(1_000, 2_000_000, 1_000);
    /// Low-speed execution monitor time: 10-2000 ms in 1 ms units (004
    /// §4.2.3 (7) L1724-1737).
    pub const LOW_SPEED_MONITOR: Range = Range::ms(10_000, 2_000_000, 1_000);
    /// Initial execution monitor time: 10-2000 ms in 10 ms units (004 L1446-1503).
    pub const INITIAL_MONITOR: Range = Range::ms(10_000, 2_000_000, 10_000);
    /// Low-speed timer base: 1-1000 ms in 1 ms units (004 L1026-1059).
    pub const TIMER_LOW: Range = Range::ms(1_000, 1_000_000, 1_000);
    /// High-speed timer base: 0.1-100 ms in 0.1 ms units (004 L1026-1059).
    pub const TIMER_HIGH: Range = Range::ms(100, 100_000, 100);
    /// I28-I31 periods: 0.5-1000 ms in 0.5 ms units (004 App. 3, L10866-10905).
    pub const INTERRUPT: Range = Range::ms(500, 1_000_000, 500);
    /// Fixed-scan interval in "ms" units: 0.5-999.5 ms (004 L1358-1368).
    pub const FIXED_SCAN_MS: Range = Range::ms(500, 999_500, 500);
    /// Fixed-scan interval in "s" units: 1-60 s.
    pub const FIXED_SCAN_S: Range = Range::ms(1_000_000, 60_000_000, 1_000_000);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses() {
        let p = |s| parse_duration(s);
        assert_eq!(p("100ms"), Some(Duration::from_millis(100)));
        assert_eq!(p("0.5ms"), Some(Duration::from_micros(500)));
        assert_eq!(p("2s"), Some(Duration::from_secs(2)));
        assert_eq!(p("500us"), Some(Duration::from_micros(500)));
        assert_eq!(p("500µs"), Some(Duration::from_micros(500)));
        assert_eq!(p("1.25 s"), Some(Duration::from_millis(1250)));
        assert_eq!(p("0.05ms"), Some(Duration::from_micros(50)));
        assert_eq!(p("0.1000000ms"), Some(Duration::from_micros(100)));
        assert_eq!(p("1.5ns"), None);
        assert_eq!(p("100"), None);
        assert_eq!(p("ms"), None);
        assert_eq!(p(".5ms"), None);
        assert_eq!(p("5.ms"), None);
        assert_eq!(p("1.2.3ms"), None);
        assert_eq!(p("-5ms"), None);
        assert_eq!(p("5min"), None);
        assert_eq!(p("99999999999999999999s"), None);
    }

    #[test]
    fn shows() {
        assert_eq!(show(Duration::from_micros(500)), "0.5ms");
        assert_eq!(show(Duration::from_millis(200)), "200ms");
        assert_eq!(show(Duration::from_micros(100)), "0.1ms");
        assert_eq!(show(Duration::from_secs(2)), "2000ms");
        assert_eq!(show(Duration::from_micros(999_500)), "999.5ms");
        assert_eq!(
            ranges::CONSTANT_SCAN.describe(),
            "0.5ms-2000ms in 0.5 ms steps"
        );
        assert_eq!(ranges::FIXED_SCAN_S.describe(), "1s-60s in 1 s steps");
        assert_eq!(ranges::TIMER_HIGH.describe(), "0.1ms-100ms in 0.1 ms steps");
    }

    #[test]
    fn ranges_check_steps() {
        let r = ranges::CONSTANT_SCAN;
        assert!(r.contains(Duration::from_micros(500)));
        assert!(r.contains(Duration::from_millis(2000)));
        assert!(!r.contains(Duration::from_micros(750)));
        assert!(!r.contains(Duration::from_millis(2001)));
        assert!(!r.contains(Duration::ZERO));
    }
}
