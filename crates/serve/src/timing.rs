//! How well the real-time loop keeps its period: the distributions of each
//! scan's start lateness (actual start − its deadline), of CPU 1's period
//! jitter (|start-to-start interval − period|) and of CPU 1's execution
//! time, in HDR histograms sized at start, so recording a scan never
//! allocates. `GET /api/v1/timing` and `serve --timing-report` show them.

use std::time::{Duration, Instant};

use hdrhistogram::Histogram;

/// Largest value kept apart, ns (an hour); anything longer counts as this.
const HIGHEST_NS: u64 = 3_600_000_000_000;
/// Significant digits kept: values within 0.1%.
const DIGITS: u8 = 3;

/// The loop's timing since it started or was last reset.
#[derive(Clone, Debug)]
pub struct Timing {
    lateness: Histogram<u64>,
    period_jitter: Histogram<u64>,
    exec: Histogram<u64>,
    overruns: u64,
    since: Instant,
    /// CPU 1's period and the spin before each deadline, as configured.
    period: Duration,
    spin: Duration,
    /// CPU 1's last scan start, for its period.
    last_start: Option<Instant>,
}

impl Default for Timing {
    fn default() -> Timing {
        let h = || Histogram::new_with_bounds(1, HIGHEST_NS, DIGITS).expect("valid bounds");
        Timing {
            lateness: h(),
            period_jitter: h(),
            exec: h(),
            overruns: 0,
            since: Instant::now(),
            period: Duration::ZERO,
            spin: Duration::ZERO,
            last_start: None,
        }
    }
}

/// One distribution, µs (0.1 µs resolution).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dist {
    pub count: u64,
    pub p50_us: f64,
    pub p99_us: f64,
    pub p999_us: f64,
    pub max_us: f64,
    pub mean_us: f64,
}

/// [`Timing`] read out.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimingReport {
    /// CPU 1's period and the busy-wait before each deadline, µs.
    pub period_us: u64,
    pub spin_us: u64,
    /// Time covered (since the start or the last reset), s.
    pub seconds: f64,
    /// Scan start lateness: every scan the loop started on its deadline.
    pub lateness: Dist,
    /// CPU 1's |start-to-start interval − its period|.
    pub period_jitter: Dist,
    /// CPU 1's execution time (input refresh to END, as SD520).
    pub exec: Dist,
    /// Scans that did not end within their period.
    pub overruns: u64,
}

impl Timing {
    /// The loop's CPU 1 period and spin, reported with the figures.
    pub fn configure(&mut self, period: Duration, spin: Duration) {
        (self.period, self.spin) = (period, spin);
    }

    /// A scan started at `start` against its deadline `due` (a start before
    /// it counts as 0).
    #[inline]
    pub fn started(&mut self, due: Instant, start: Instant) {
        self.lateness
            .saturating_record(start.saturating_duration_since(due).as_nanos() as u64);
    }

    /// CPU 1's scan started at `start`, its period `period`.
    #[inline]
    pub fn first_cpu_started(&mut self, start: Instant, period: Duration) {
        if let Some(last) = self.last_start.replace(start) {
            let interval = start.saturating_duration_since(last);
            let off = interval.abs_diff(period);
            self.period_jitter.saturating_record(off.as_nanos() as u64);
        }
    }

    /// CPU 1's scan executed in `exec`.
    #[inline]
    pub fn executed(&mut self, exec: Duration) {
        self.exec.saturating_record(exec.as_nanos() as u64);
    }

    #[inline]
    pub fn overran(&mut self) {
        self.overruns += 1;
    }

    /// Starts over (the next interval is measured from the next scan).
    pub fn reset(&mut self) {
        self.lateness.reset();
        self.period_jitter.reset();
        self.exec.reset();
        self.overruns = 0;
        self.since = Instant::now();
        self.last_start = None;
    }

    pub fn report(&self) -> TimingReport {
        TimingReport {
            period_us: self.period.as_micros() as u64,
            spin_us: self.spin.as_micros() as u64,
            seconds: self.since.elapsed().as_secs_f64(),
            lateness: dist(&self.lateness),
            period_jitter: dist(&self.period_jitter),
            exec: dist(&self.exec),
            overruns: self.overruns,
        }
    }
}

fn dist(h: &Histogram<u64>) -> Dist {
    if h.is_empty() {
        return Dist::default();
    }
    let us = |ns: u64| (ns as f64 / 100.0).round() / 10.0;
    Dist {
        count: h.len(),
        p50_us: us(h.value_at_quantile(0.5)),
        p99_us: us(h.value_at_quantile(0.99)),
        p999_us: us(h.value_at_quantile(0.999)),
        max_us: us(h.max()),
        mean_us: (h.mean() / 100.0).round() / 10.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_of_a_known_spread() {
        let mut t = Timing::default();
        let due = Instant::now();
        // 1000 scans: 990 on time (1 µs late), 9 at 50 µs, one at 2 ms.
        for i in 0..1000u64 {
            let late = match i {
                0..990 => 1_000,
                990..999 => 50_000,
                _ => 2_000_000,
            };
            t.started(due, due + Duration::from_nanos(late));
        }
        let r = t.report();
        assert_eq!(r.lateness.count, 1000);
        assert_eq!(r.lateness.p50_us, 1.0);
        // The 990th value is still 1 µs; the 999th is 50 µs.
        assert_eq!(r.lateness.p99_us, 1.0);
        assert_eq!(r.lateness.p999_us, 50.0);
        // 2 ms within 0.1%.
        assert!(
            (r.lateness.max_us - 2000.0).abs() <= 2.0,
            "{}",
            r.lateness.max_us
        );
        // (990 × 1 + 9 × 50 + 2000) / 1000 = 3.44 µs
        assert!(
            (r.lateness.mean_us - 3.4).abs() <= 0.1,
            "{}",
            r.lateness.mean_us
        );
        // A start before its deadline is on time.
        t.started(due + Duration::from_micros(5), due);
        assert_eq!(t.report().lateness.count, 1001);
    }

    #[test]
    fn period_jitter_is_the_distance_from_the_period() {
        let mut t = Timing::default();
        let p = Duration::from_millis(1);
        let t0 = Instant::now();
        // Starts at 0, 1.010, 1.990, 3.000 ms: intervals 1010, 980, 1010 µs.
        for us in [0, 1010, 1990, 3000] {
            t.first_cpu_started(t0 + Duration::from_micros(us), p);
        }
        let r = t.report().period_jitter;
        assert_eq!(r.count, 3);
        assert_eq!(r.p50_us, 10.0);
        assert_eq!(r.max_us, 20.0);
        // After a reset the first start has nothing to compare with.
        t.reset();
        t.first_cpu_started(t0 + Duration::from_micros(5000), p);
        assert_eq!(t.report().period_jitter.count, 0);
    }

    #[test]
    fn an_empty_timing_reports_zeros() {
        let mut t = Timing::default();
        t.overran();
        t.executed(Duration::from_micros(120));
        let r = t.report();
        assert_eq!(r.lateness, Dist::default());
        assert_eq!(r.exec.count, 1);
        assert_eq!(r.overruns, 1);
        t.reset();
        assert_eq!(t.report().overruns, 0);
        assert_eq!(t.report().exec.count, 0);
    }
}
