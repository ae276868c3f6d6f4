//! Scenario `[port1]`/`[port2]` and `[[peer]]` (docs/scenarios.md "Serial
//! peers"): the run loop calls the communication phase after every scan, the
//! shipped examples pass and are the same byte for byte on every run, and a
//! bad peer is reported when the file is loaded or built.

use std::path::{Path, PathBuf};

use softplc_sim::scenario::Scenario;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/aplc")
        .join(name)
}

fn trace_of(path: &Path, devices: &[&str]) -> String {
    let mut sc = Scenario::load(path).unwrap();
    sc.plot = None;
    sc.trace.devices = devices.iter().map(|d| d.to_string()).collect();
    sc.trace.interval_us = Some(sc.scan_us);
    let o = sc.build().unwrap().run(&mut |_| {});
    assert_eq!(o.failed(), 0, "{}", o.report(false));
    format!("{:?}", o.trace.expect("trace").values)
}

#[test]
fn serial_examples_pass_and_repeat_exactly() {
    let poll = example("modbus_poll.toml");
    let devs = ["D100", "D104", "D106", "D204", "SM124", "SM135", "D50"];
    assert_eq!(trace_of(&poll, &devs), trace_of(&poll, &devs));
    let bar = example("barcode.toml");
    let devs = ["D10", "D100", "SD127", "SM121"];
    assert_eq!(trace_of(&bar, &devs), trace_of(&bar, &devs));
}

/// The programs the Python tests run against pymodbus and pyserial over ptys
/// (tests/python/test_aplc_ports.py) pass as scenarios in virtual time.
#[test]
fn the_pty_test_programs_pass_as_scenarios() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/aplc_ports");
    for name in ["master.toml", "free.toml"] {
        let o = Scenario::load(&dir.join(name))
            .unwrap()
            .build()
            .unwrap()
            .run(&mut |_| {});
        assert_eq!(o.failed(), 0, "{}", o.report(false));
        assert!(o.passed() >= 4, "{name}");
    }
}

fn parse_err(text: &str) -> String {
    let head = "program = \"p.apl\"\nscan_time = \"10ms\"\nduration = \"1s\"\n";
    match Scenario::parse(&format!("{head}{text}"), Path::new("s.toml")) {
        Ok(_) => panic!("parsed:\n{text}"),
        Err(e) => e,
    }
}

#[test]
fn bad_ports_and_peers_are_load_errors() {
    let e = parse_err("[port1]\nprotocol = \"free\"\nbaud = 300\n");
    assert!(e.contains("[port1] baud: baud 300"), "{e}");
    let e = parse_err("[[peer]]\nport = 3\ntype = \"script\"\n");
    assert!(
        e.contains("peer #1: `port` is 1 (PORT1) or 2 (PORT2)"),
        "{e}"
    );
    let e = parse_err("[[peer]]\nport = 1\ntype = \"modbus-slave\"\nstation = 0\n");
    assert!(e.contains("`station` is 1-247"), "{e}");
    let e = parse_err("[[peer]]\nport = 1\ntype = \"script\"\n[[peer.step]]\nexpect = [1, 300]\n");
    assert!(e.contains("bytes are integers 0-255"), "{e}");
    let e = parse_err("[[peer]]\nport = 1\ntype = \"modem\"\n");
    assert!(
        e.contains("`type` is \"modbus-slave\" or \"script\""),
        "{e}"
    );
    // MELSEC programs have no APLC ports.
    let e = Scenario::parse(
        "program = \"p.il\"\nscan_time = \"10ms\"\nduration = \"1s\"\n[[peer]]\nport = 1\ntype = \"script\"\n",
        Path::new("s.toml"),
    )
    .unwrap_err();
    assert!(e.contains("serial peers need an APLC-TCP program"), "{e}");
}

#[test]
fn a_peer_needs_its_port_and_a_follow_its_model() {
    let dir = example("");
    let write = |name: &str, text: &str| {
        let p =
            std::env::temp_dir().join(format!("softplc-sim-ports-{}-{name}", std::process::id()));
        std::fs::write(&p, text).unwrap();
        p
    };
    let prog = dir.join("barcode.apl").display().to_string();
    let sc = write(
        "a.toml",
        &format!("program = \"{prog}\"\nscan_time = \"10ms\"\nduration = \"1s\"\n[[peer]]\nport = 2\ntype = \"script\"\n[[peer.step]]\nat = 0.1\nsend = \"x\"\n"),
    );
    let e = Scenario::load(&sc).unwrap().build().err().unwrap();
    assert!(e.contains("peer #1: PORT2 has no settings"), "{e}");
    let sc = write(
        "b.toml",
        &format!("program = \"{prog}\"\nscan_time = \"10ms\"\nduration = \"1s\"\n[port1]\nprotocol = \"modbus-master\"\n[[peer]]\nport = 1\ntype = \"modbus-slave\"\nstation = 1\nfollow = [{{ register = 0, model = \"pump\", output = \"y\" }}]\n"),
    );
    let e = Scenario::load(&sc).unwrap().build().err().unwrap();
    assert!(e.contains("no model named `pump`"), "{e}");
}
