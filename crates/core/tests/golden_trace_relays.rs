//! The sampling trace's start and error relays (004 §7.12 (1) (d), (f),
//! L4590-4615; App. 1 SM801, SM826).

mod common;
use common::Plc;
use softplc_core::access::DeviceSpec;
use softplc_core::engine::trace::{Trace, TraceConfig};

fn trace(devices: &[&str]) -> Trace {
    Trace::new(TraceConfig {
        devices: devices
            .iter()
            .map(|d| DeviceSpec::parse(d).unwrap())
            .collect(),
        every_scans: 1,
        interval_us: None,
        capacity: 100,
        trigger: None,
        after_trigger: 1,
    })
    .unwrap()
}

fn scans_held(p: &Plc) -> Vec<u64> {
    p.cpu
        .trace()
        .unwrap()
        .samples()
        .map(|(s, _, _)| s)
        .collect()
}

#[test]
fn sm801_off_aborts_the_trace_and_on_starts_it_again() {
    // A start request turns SM801 ON; SM801 OFF aborts the trace and clears
    // its count, the related relays OFF (SM800 stays ready); ON again starts
    // it anew (§7.12 (1) (d)).
    let mut p = Plc::new("LD X0\nRST SM801\nLD X1\nSET SM801\nLD SM400\nINC D0\nEND\n");
    p.cpu.set_trace(Some(trace(&["D0"])));
    assert!(p.bit("SM801"));
    p.scans(3);
    assert_eq!(scans_held(&p), [1, 2, 3]);
    assert!(p.bit("SM800") && p.bit("SM802"));
    p.set("SM803", "1").scan().set("SM803", "0");
    assert!(p.bit("SM805"));
    // Scan 5: the program turns SM801 OFF.
    p.set("X0", "1").scan().set("X0", "0").scan();
    assert_eq!(scans_held(&p), Vec::<u64>::new());
    assert!(p.bit("SM800"));
    for r in ["SM801", "SM802", "SM803", "SM804", "SM805"] {
        assert!(!p.bit(r), "{r}");
    }
    // Scan 7: SM801 ON again: sampling from that END.
    p.set("X1", "1").scan().set("X1", "0").scan();
    assert_eq!(scans_held(&p), [7, 8]);
    assert!(p.bit("SM802") && !p.bit("SM805"));
}

#[test]
fn sm826_is_the_trace_error() {
    // D20000 is beyond the CPU's 12288 D: its samples cannot be taken, the
    // trace error relay turns ON (§7.12 (1) (f)); the other devices are
    // still sampled.
    let mut p = Plc::new("LD SM400\nINC D0\nEND\n");
    p.cpu.set_trace(Some(trace(&["D0"])));
    p.scan();
    assert!(!p.bit("SM826"));
    p.cpu.set_trace(Some(trace(&["D0", "D20000"])));
    p.scans(2);
    assert!(p.bit("SM826"));
    assert_eq!(scans_held(&p), [2, 3]);
}

#[test]
fn sm1047_is_sm801_for_converted_programs() {
    // M9047 = SM1047 (App. 1 (9) L9835): it shows SM801, and a converted
    // program aborts and restarts the trace through it.
    let mut p = Plc::new("LD X0\nRST SM1047\nLD X1\nSET SM1047\nLD SM400\nINC D0\nEND\n");
    p.cpu.set_trace(Some(trace(&["D0"])));
    p.scans(2);
    assert!(p.bit("SM1047"));
    p.set("X0", "1").scan().set("X0", "0").scan();
    assert!(!p.bit("SM801") && !p.bit("SM1047") && !p.bit("SM802"));
    assert_eq!(scans_held(&p), Vec::<u64>::new());
    p.set("X1", "1").scan().set("X1", "0").scan();
    assert!(p.bit("SM801") && p.bit("SM1047"));
    assert_eq!(scans_held(&p), [5, 6]);
}
