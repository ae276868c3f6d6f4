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
