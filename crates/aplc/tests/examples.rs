//! The programs of examples/aplc/ run with this crate's harness, inputs
//! driven by hand scan by scan, asserting the key values their scenario
//! files (examples/aplc/*.toml) assert, so both say the same. Scan n runs at
//! virtual time n × 10 ms, as in the scenarios (docs/scenarios.md "Timing").

mod common;
use common::Plc;

/// Loads examples/aplc/`name`.
fn example(name: &str) -> Plc {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/aplc/");
    let src = std::fs::read_to_string(format!("{path}{name}")).expect(name);
    common::plc(&src)
}

/// A run counting scans: `to(n)` scans until scan n has run.
struct Run {
    p: Plc,
    n: u32,
}

impl Run {
    fn new(name: &str) -> Run {
        let mut p = example(name);
        p.scan_us = 10_000;
        Run { p, n: 0 }
    }
    fn to(&mut self, n: u32) -> &mut Plc {
        while self.n < n {
            self.n += 1;
            self.p.scan();
        }
        &mut self.p
    }
    /// Runs to scan n - 1, then writes (a timeline entry at scan n), then scan n.
    fn set_at(&mut self, n: u32, dev: &str, v: &str) -> &mut Plc {
        self.to(n - 1);
        self.p.set(dev, v);
        self.to(n)
    }
}

/// subroutine.apl / .toml: D0 = 0 until M0 turns ON at 500 ms (scan 50),
/// then 5 on that scan and every one after it.
#[test]
fn subroutine_example() {
    let mut r = Run::new("subroutine.apl");
    assert_eq!(r.to(49).int("D0"), 0);
    assert_eq!(r.set_at(50, "M0", "1").int("D0"), 5);
    assert_eq!(r.to(100).int("D0"), 5);
}

/// sfc.apl / .toml: the timeline of the scenario (scan n = n × 10 ms):
/// M20 from scan 1; X0 pulse at scan 10; M30 at 400; M31 at 500; X1 at 600;
/// then M21 instead of M20 at 650 and an X0 pulse at 700.
#[test]
fn sfc_example() {
    let mut r = Run::new("sfc.apl");
    let on = |p: &Plc, names: &[&str]| names.iter().all(|n| p.bit(n));
    let p = r.set_at(1, "M20", "1");
    assert!(on(p, &["S0", "Y0"]) && !p.bit("S20"));
    // X0 at scan 10: S20 runs in the same scan; S0's Y0 goes OFF one scan late.
    let p = r.set_at(10, "X0", "1");
    assert!(on(p, &["S20", "Y1", "Y0"]) && !p.bit("S0"));
    assert!(!r.to(11).bit("Y0"));
    r.set_at(20, "X0", "0");
    // T2 = 2 s: 200 scans of 10 ms after scan 10, then M20 selects S27.
    let p = r.to(209);
    assert!(p.bit("S20") && !p.bit("S27"));
    let p = r.to(210);
    assert!(on(p, &["S27", "Y2"]) && !p.bit("S20") && !p.bit("S28"));
    // T12 = 1 s: the selective merge into S29 at scan 310.
    assert!(r.to(309).bit("S27"));
    assert!(on(r.to(310), &["S29", "Y4"]));
    // Parallel branch at 400, merge at 500 (both end), jump to S0 at 600.
    let p = r.set_at(400, "M30", "1");
    assert!(on(p, &["S30", "S31", "Y5", "Y6"]) && !p.bit("S29"));
    r.set_at(450, "M30", "0");
    assert!(on(r.to(499), &["S30", "S31"]));
    let p = r.set_at(500, "M31", "1");
    assert!(on(p, &["S32", "Y7"]) && !p.bit("S30") && !p.bit("S31"));
    let p = r.to(501);
    assert!(!p.bit("Y5") && !p.bit("Y6"), "cleared one scan late");
    r.set_at(550, "M31", "0");
    let p = r.set_at(600, "X1", "1");
    assert!(p.bit("S0") && !p.bit("S32"));
    let p = r.to(601);
    assert!(p.bit("Y0") && !p.bit("Y7"));
    r.set_at(610, "X1", "0");
    // Second cycle through the other branch: T2 2 s, then T13 2 s.
    r.to(649).set("M20", "0").set("M21", "1");
    r.set_at(700, "X0", "1");
    r.set_at(710, "X0", "0");
    let p = r.to(900);
    assert!(on(p, &["S28", "Y3"]) && !p.bit("S27"));
    assert!(r.to(1099).bit("S28"));
    let p = r.to(1100);
    assert!(on(p, &["S29", "Y4"]) && !p.bit("S28"));
    assert!(!r.to(1200).bit("S30"), "M30 is OFF: S29 waits");
}

/// pid_setup.apl, open loop, PV written by hand (Ts = 500 ms: with 10 ms
/// scans PID computes on scans 51, 101, 151, 201; D22, §5.4, α = 0.7,
/// Ts/TI = 0.2, TD/(Ts + αD·TD) = 630/500):
/// - PV 0: PVnf 0, EV 1000, ΔMV = 1000 + 200 = 1200;
/// - PV 400: PVnf = 400 + 0.7·(0 − 400) = 120, EV 880, D = 1.26·(0 − 120 − 0)
///   = −151.2, ΔMV = −120 + 176 − 151.2 = −95.2, MV 1104.8 → 1105;
/// - PV 400: PVnf 204, EV 796, D = 1.26·(240 − 204) = 45.36,
///   ΔMV = −84 + 159.2 + 45.36 = 120.56, MV 1104.8 + 120.56 → 1225;
/// - PV 3000: the input change 2600 > D525 = 2000 sets alarm bit 0 of D529;
///   PVnf 1042.8, EV −42.8, D = 1.26·(408 − 1042.8 − 120) = −951.048,
///   ΔMV = −838.8 − 8.56 − 951.048, MV 1225.36 − 1798.408 → −573 (a change of
///   1798, under the output alarm's 2000).
///
/// FROM/TO record run error 73 and the CPU keeps running (D7).
#[test]
fn pid_setup_by_hand() {
    let mut r = Run::new("pid_setup.apl");
    r.set_at(1, "M0", "1");
    assert_eq!(
        (r.p.int("D500"), r.p.int("D511"), r.p.int("D516")),
        (1000, 7, 63)
    );
    assert_eq!(r.to(50).int("D502"), 0, "Ts not elapsed yet");
    assert_eq!(r.to(51).int("D502"), 1200);
    r.p.set("D501", "400");
    assert_eq!(r.to(100).int("D502"), 1200);
    assert_eq!(r.to(101).int("D502"), 1105);
    assert_eq!(r.to(151).int("D502"), 1225);
    assert_eq!(r.p.int("D529"), 0);
    r.p.set("D501", "3000");
    let p = r.to(201);
    assert_eq!((p.int("D502"), p.int("D529")), (-573, 1));
    assert!(p.running());
    assert_eq!(p.error_code(), Some(73));
}

/// The scenario's plant (pid_setup.toml): `fopdt` with gain 1, τ = 5 s, no
/// dead time, u = D502, y = D501, stepped before each scan as
/// crates/sim/src/model/fopdt.rs does: y ← y + (K·u − y)·(1 − e^(−dt/τ)),
/// written rounded.
struct Lag {
    y: f64,
}

impl Lag {
    fn step(&mut self, p: &mut Plc) {
        let b = -(-0.01f64 / 5.0).exp_m1();
        let u = p.int("D502") as f64;
        self.y += (u - self.y) * b;
        p.set("D501", &(self.y.round() as i64).to_string());
    }
}

/// pid_setup.toml: the closed loop on the lag, M0 ON from the first scan.
/// By hand: MV 1200 on scan 51 (PV still 0); the lag then rises for 50 steps
/// to 1200·(1 − e^(−0.1)) = 114.2 → PV 114 on scan 101, where PVnf = 34.2,
/// EV 965.8, D = 1.26·(−34.2) = −43.09, ΔMV = −34.2 + 193.16 − 43.09 =
/// 115.87 → MV 1316. Then (simulated here and in the scenario): the peak
/// stays under 25 % overshoot, PV is within ±3 % of SV from 30 s on, no
/// change alarm (D529 = 0), and SD20 shows FROM/TO's 73.
#[test]
fn pid_setup_closed_loop() {
    let mut r = Run::new("pid_setup.apl");
    let mut lag = Lag { y: 0.0 };
    let mut peak = 0;
    for n in 1..=6000u32 {
        lag.step(&mut r.p);
        if n == 1 {
            r.p.set("M0", "1");
        }
        let p = r.to(n);
        let (pv, mv) = (p.int("D501"), p.int("D502"));
        match n {
            51 => assert_eq!((pv, mv), (0, 1200)),
            101 => assert_eq!((pv, mv), (114, 1316)),
            _ => {}
        }
        peak = peak.max(pv);
        if n >= 3000 {
            assert!((pv - 1000).abs() <= 30, "scan {n}: PV {pv}");
        }
        assert_eq!(p.int("D529"), 0, "scan {n}");
    }
    assert!(peak > 1100 && peak <= 1250, "peak {peak}");
    assert_eq!(r.p.int("SD20"), 73);
}

/// The plant of batch_mix.toml, stepped before each scan as crates/sim does:
/// a `tank` (area 0.5 m², height 1.5 m, cv 0.05; q_in 0.02 m³/s while Y0 is
/// ON, drain valve 100 % while Y2 is ON; level → D100 in mm) and a `motor`
/// (run = Y1, running → X2 after a 0.5 s feedback delay, i.e. on the 50th
/// 10 ms step with the new run value). The program never fills and drains
/// at once, so the tank takes its two closed forms: filling
/// h ← h + q·dt/A, draining √h ← max(√h − c·dt/(2A), 0).
struct Mixer {
    h: f64,
    run: bool,
    same: u32,
    running: bool,
}

impl Mixer {
    fn new() -> Mixer {
        Mixer {
            h: 0.0,
            run: false,
            same: 0,
            running: false,
        }
    }
    fn step(&mut self, p: &mut Plc) {
        let (a, dt) = (0.5, 0.01);
        let q = if p.bit("Y0") { 0.02 } else { 0.0 };
        let c = 0.05 * if p.bit("Y2") { 100.0 } else { 0.0 } / 100.0;
        self.h = if c <= 0.0 {
            self.h + q * dt / a
        } else {
            assert_eq!(q, 0.0, "the program never fills and drains at once");
            let s = (self.h.sqrt() - c * dt / (2.0 * a)).max(0.0);
            s * s
        }
        .clamp(0.0, 1.5);
        p.set("D100", &((self.h * 1000.0).round() as i64).to_string());
        let run = p.bit("Y1");
        if run != self.run {
            self.run = run;
            self.same = 0;
        }
        self.same += 1;
        if self.same >= 50 {
            self.running = run;
        }
        p.set("X2", if self.running { "1" } else { "0" });
    }
}

/// The timeline of batch_mix.toml as (scan, device, value).
const BATCH_TIMELINE: &[(u32, &str, &str)] = &[
    (100, "X0", "1"),
    (150, "X0", "0"),
    (1000, "X10", "1"),
    (1200, "X10", "0"),
    (5500, "X0", "1"),
    (5550, "X0", "0"),
];

/// The scenario's order per scan: the plant steps, the timeline writes,
/// the CPU scans; checks no scan fills and drains at once.
struct Batch {
    r: Run,
    plant: Mixer,
    max_level: i64,
}

impl Batch {
    fn at(&mut self, n: u32) -> &Plc {
        while self.r.n < n {
            let k = self.r.n + 1;
            self.plant.step(&mut self.r.p);
            for (t, d, v) in BATCH_TIMELINE {
                if *t == k {
                    self.r.p.set(d, v);
                }
            }
            let p = self.r.to(k);
            self.max_level = self.max_level.max(p.int("D100"));
            assert!(!(p.bit("Y0") && p.bit("Y2")), "scan {k}: fill and drain");
        }
        &self.r.p
    }
}

/// batch_mix.apl / .toml, scan n at n × 10 ms. Timeline: X0 pulse at scan
/// 100, the emergency stop X10 (input 8) held from 1000 to 1200, X0 again at
/// 5500. By hand: the inlet adds 0.02·0.01/0.5 m = 0.4 mm a step; 900 steps
/// before the stop give 360 mm, held while X10 is ON; 1000 mm (999.6 rounds
/// up) after 2499 steps, on scan 2799. The mixer starts there, its feedback
/// X2 comes 50 steps later (scan 2849), T0 needs 500 scans of it: drain from
/// scan 3349. Draining lowers √h by 0.05·0.01/(2·0.5) = 0.0005 a step from
/// √1.0 (the fill ran one more step: Y0 goes OFF one scan late): 20 mm, i.e.
/// √h ≤ 0.1432, after 1714 steps, on scan 5063 (D0 = 1).
#[test]
fn batch_mix_example() {
    let mut b = Batch {
        r: Run::new("batch_mix.apl"),
        plant: Mixer::new(),
        max_level: 0,
    };
    assert!(b.at(1).bit("Y3"));
    let p = b.at(100);
    assert!(p.bit("S20") && p.bit("Y0"));
    let p = b.at(1000);
    assert_eq!((p.int("D100"), p.bit("Y0")), (360, false));
    assert_eq!(b.at(1199).int("D100"), 360);
    assert!(b.at(1200).bit("Y0"));
    assert!(b.at(2798).bit("S20"));
    let p = b.at(2799);
    assert!(p.bit("S21") && p.bit("Y1"));
    assert_eq!(b.at(2800).int("D100"), 1000);
    assert!(!b.at(2848).bit("X2"));
    assert!(b.at(2849).bit("X2"));
    assert!(b.at(3348).bit("S21"));
    let p = b.at(3349);
    assert!(p.bit("S22") && p.bit("Y2"));
    assert!(b.at(5062).bit("S22"));
    let p = b.at(5063);
    assert!(p.bit("S0"));
    assert_eq!((p.int("D100"), p.int("D0")), (20, 1));
    // The second batch starts from the 20 mm left and ends on scan 10212.
    assert!(b.at(5500).bit("S20"));
    assert!(b.at(10211).bit("S22"));
    let p = b.at(10212);
    assert!(p.bit("S0"));
    assert_eq!(p.int("D0"), 2);
    b.at(11000);
    assert_eq!(b.r.p.int("D0"), 2);
    assert_eq!(b.max_level, 1000);
}
