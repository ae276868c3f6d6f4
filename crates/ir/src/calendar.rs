//! The CPU's calendar clock (004 §7.6, qcpu.md §4.4): year 1980-2079, leap years
//! automatic, day of week 0 = Sunday. It runs on the engine's clock, so in virtual
//! time it advances exactly with the scans.

/// Date and time as the clock instructions see it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DateTime {
    pub year: i32,
    pub month: u32,
    pub day: u32,
    pub hour: u32,
    pub minute: u32,
    pub second: u32,
}

/// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's algorithm).
pub fn days_from_civil(y: i32, m: u32, d: u32) -> i64 {
    let y = if m <= 2 { y - 1 } else { y } as i64;
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m as i64 + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// Inverse of [`days_from_civil`].
pub fn civil_from_days(z: i64) -> (i32, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = (yoe + era * 400 + (m <= 2) as i64) as i32;
    (y, m, d)
}

pub fn days_in_month(y: i32, m: u32) -> u32 {
    match m {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if (y % 4 == 0 && y % 100 != 0) || y % 400 == 0 => 29,
        2 => 28,
        _ => 0,
    }
}

impl DateTime {
    /// Parses `YYYY-MM-DDTHH:MM:SS` (or a space instead of `T`), fixed width; the
    /// fields are not range-checked (see [`DateTime::is_valid`]).
    pub fn parse(s: &str) -> Option<DateTime> {
        let b = s.as_bytes();
        if b.len() != 19
            || b[4] != b'-'
            || b[7] != b'-'
            || !matches!(b[10], b'T' | b't' | b' ')
            || b[13] != b':'
            || b[16] != b':'
        {
            return None;
        }
        let num = |r: std::ops::Range<usize>| -> Option<u32> {
            let t = &s[r];
            t.bytes()
                .all(|c| c.is_ascii_digit())
                .then(|| t.parse().ok())
                .flatten()
        };
        Some(DateTime {
            year: num(0..4)? as i32,
            month: num(5..7)?,
            day: num(8..10)?,
            hour: num(11..13)?,
            minute: num(14..16)?,
            second: num(17..19)?,
        })
    }

    /// Seconds since 1970-01-01 00:00:00.
    pub fn to_unix(&self) -> i64 {
        days_from_civil(self.year, self.month, self.day) * 86_400
            + (self.hour * 3600 + self.minute * 60 + self.second) as i64
    }

    pub fn from_unix(s: i64) -> DateTime {
        let (year, month, day) = civil_from_days(s.div_euclid(86_400));
        let r = s.rem_euclid(86_400) as u32;
        DateTime {
            year,
            month,
            day,
            hour: r / 3600,
            minute: r / 60 % 60,
            second: r % 60,
        }
    }

    /// Day of week, 0 = Sunday.
    pub fn weekday(&self) -> u32 {
        (days_from_civil(self.year, self.month, self.day) + 4).rem_euclid(7) as u32
    }

    /// True when every field is in the clock's range (1980-2079 and a real date).
    pub fn is_valid(&self) -> bool {
        (1980..=2079).contains(&self.year)
            && (1..=12).contains(&self.month)
            && (1..=days_in_month(self.year, self.month)).contains(&self.day)
            && self.hour < 24
            && self.minute < 60
            && self.second < 60
    }
}

/// The calendar clock: a date-time pinned to an engine-clock reading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlcClock {
    /// Calendar time (µs since 1970) at engine time `at_us`.
    base_us: i64,
    at_us: u64,
}

impl PlcClock {
    pub fn new(start: DateTime, engine_now_us: u64) -> Self {
        PlcClock {
            base_us: start.to_unix() * 1_000_000,
            at_us: engine_now_us,
        }
    }

    /// Calendar time at engine time `now_us`, µs since 1970.
    pub fn unix_us(&self, now_us: u64) -> i64 {
        self.base_us + (now_us as i64 - self.at_us as i64)
    }

    pub fn now(&self, now_us: u64) -> DateTime {
        DateTime::from_unix(self.unix_us(now_us).div_euclid(1_000_000))
    }

    /// The calendar clock in a state file; values whose arithmetic could
    /// overflow (beyond ±73,000 years) are refused.
    pub fn snapshot(&mut self, s: &mut crate::snapshot::Snap) {
        const LIMIT: u64 = 1 << 61;
        let base = s.value(self.base_us as u64) as i64;
        if base.unsigned_abs() > LIMIT {
            s.fail(crate::snapshot::StateError::Invalid {
                what: "calendar clock",
                value: base as u64,
            });
        }
        let mut at = self.at_us;
        s.at_most(&mut at, LIMIT);
        if s.loading() {
            (self.base_us, self.at_us) = (base, at);
        }
    }

    /// Sets the clock (DATEWR, SM210); the sub-second part restarts at 0.
    pub fn set(&mut self, t: DateTime, now_us: u64) {
        *self = PlcClock::new(t, now_us);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manual_example_weekday() {
        // 004 L3652-3661: Tue 10 Aug 1999 11:35:24 → day of week 2.
        let t = DateTime {
            year: 1999,
            month: 8,
            day: 10,
            hour: 11,
            minute: 35,
            second: 24,
        };
        assert_eq!(t.weekday(), 2);
        assert_eq!(DateTime::from_unix(t.to_unix()), t);
        // 2000-01-01 was a Saturday; 2000 is a leap year.
        let y2k = DateTime {
            year: 2000,
            month: 1,
            day: 1,
            hour: 0,
            minute: 0,
            second: 0,
        };
        assert_eq!(y2k.to_unix(), 946_684_800);
        assert_eq!(y2k.weekday(), 6);
        assert_eq!(days_in_month(2000, 2), 29);
        assert_eq!(days_in_month(2100, 2), 28);
        assert!(!DateTime { month: 13, ..y2k }.is_valid());
        assert!(!DateTime {
            day: 30,
            month: 2,
            ..y2k
        }
        .is_valid());
    }

    #[test]
    fn advances_with_engine_time() {
        let y2k = DateTime {
            year: 2000,
            month: 1,
            day: 1,
            hour: 0,
            minute: 0,
            second: 0,
        };
        let c = PlcClock::new(y2k, 5_000_000);
        let t = c.now(5_000_000 + 86_400_000_000 + 3_723_000_000);
        assert_eq!(
            (t.year, t.month, t.day, t.hour, t.minute, t.second),
            (2000, 1, 2, 1, 2, 3)
        );
    }
}
