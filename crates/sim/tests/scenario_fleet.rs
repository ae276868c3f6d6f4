//! Fleets: several PLCs in one scenario (`[[plc]]`), serial ports linked
//! between them (`[[link]]`) and clients polling a PLC's MC or Modbus TCP
//! door (`[[client]]`); examples/fleet.

use std::path::{Path, PathBuf};

use softplc_sim::scenario::{Outcome, Scenario};

fn fleet_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/fleet")
}

/// A scenario file in a fresh directory; `MASTER`, `TANK` and
/// `SUPERVISOR` stand for the example's programs.
fn write(dir: &Path, text: &str) -> PathBuf {
    let ex = fleet_dir();
    let text = text
        .replace("MASTER", &ex.join("master.apl").display().to_string())
        .replace("TANK", &ex.join("tank.apl").display().to_string())
        .replace(
            "SUPERVISOR",
            &ex.join("supervisor.il").display().to_string(),
        );
    let path = dir.join("fleet.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn run(text: &str) -> Outcome {
    let dir = tempfile::tempdir().unwrap();
    let sc = Scenario::load(&write(dir.path(), text)).unwrap();
    sc.build().unwrap().run(&mut |_| {})
}

fn load_err(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), text);
    match Scenario::load(&path).and_then(|s| s.build()) {
        Ok(_) => panic!("loaded: {text}"),
        Err(e) => e,
    }
}

#[track_caller]
fn assert_all_pass(o: &Outcome) {
    let failed: Vec<_> = o.results.iter().filter(|r| !r.passed).collect();
    assert!(failed.is_empty(), "{}", o.report(true));
}

#[test]
fn the_example_line_passes() {
    let mut sc = Scenario::load(&fleet_dir().join("serial_line.toml")).unwrap();
    sc.plot = None; // do not rewrite the committed SVG
    assert_eq!(sc.plcs.len(), 3);
    assert_eq!(sc.links.len(), 1);
    assert_eq!(sc.clients.len(), 1);
    let o = sc.build().unwrap().run(&mut |_| {});
    assert_all_pass(&o);
    assert_eq!(o.results.len(), 10);
    assert!(fleet_dir().join("serial_line.svg").exists());
}

#[test]
fn a_fleet_runs_the_same_bit_for_bit_twice() {
    let trace = || {
        let mut sc = Scenario::load(&fleet_dir().join("serial_line.toml")).unwrap();
        sc.plot = None;
        sc.trace.interval_us = Some(sc.scan_us); // every step
        let o = sc.build().unwrap().run(&mut |_| {});
        o.trace.unwrap()
    };
    let (a, b) = (trace(), trace());
    assert_eq!(a.len(), 24_000);
    assert_eq!(a.devices, b.devices);
    assert_eq!(a.times_us, b.times_us);
    let bits = |t: &softplc_sim::scenario::TraceData| -> Vec<u64> {
        t.values.iter().map(|v| v.to_bits()).collect()
    };
    assert!(bits(&a) == bits(&b), "the two runs differ");
    // Not a trace of zeros: the level rose and the copies followed it.
    let level = a.column_of("tank/D0").unwrap();
    let top = (0..a.len())
        .map(|i| a.values[i * a.devices.len() + level])
        .fold(0.0, f64::max);
    assert!(top > 1190.0, "{top}");
}

/// Master and tank PLC at 9600 baud 8N1 (parity "none": the APLC's default
/// is even) (10 bits: 1042 µs a character, the
/// RTU silence 3.5 characters = 3647 µs), both scanning every 1 ms, the
/// step 1 ms. The master's first FC 03 request (8 bytes) leaves after its
/// scan 1 END at 1000 µs; its last byte is in at 1000 + 8 · 1042 = 9336.
/// The tank PLC's slave port reads it at its next END, 10 000, and answers
/// after the silence since the last byte: from 9336 + 3647 = 12 983, 7
/// bytes (station, 03, byte count, 2 data bytes, CRC) until 12 983 + 7 ·
/// 1042 = 20 277. The master's END at 21 000 takes the reply: D103/D104
/// hold the register's bytes from step 21 (not 20), and the program makes
/// D302 of them in scan 22.
#[test]
fn a_modbus_reply_lands_at_the_scan_worked_out_from_the_baud_rate() {
    let o = run(r#"
scan_time = "1ms"
duration = "30ms"

[[plc]]
name = "master"
program = "MASTER"
[plc.port1]
protocol = "modbus-master"
baud = 9600
parity = "none"

[[plc]]
name = "tank"
program = "TANK"
[plc.port1]
protocol = "modbus-slave"
baud = 9600
parity = "none"
address = 2

[[link]]
a = "master:port1"
b = "tank:port1"

[[timeline]]
scan = 1
set = { "tank/D0" = 1234 }        # 16#04D2: bytes 4, 210

[[expect]]
device = "master/D104"
at = "20ms"
equals = 0

[[expect]]
device = "master/D104"
at = "21ms"
equals = 210

[[expect]]
device = "master/D103"
at = "21ms"
equals = 4

[[expect]]
device = "master/D302"
at = "21ms"
equals = 0

[[expect]]
device = "master/D302"
at = "22ms"
equals = 1234

[[expect]]
device = "master/SM135"          # done, without error
at = "21ms"
equals = true
"#);
    assert_all_pass(&o);
}

/// At 19200 baud 8N1 the character takes 521 µs (silence 1824 µs): the request
/// is in at 1000 + 8 · 521 = 5168, read at the tank's END 6000, answered
/// from 5168 + 1824 = 6992 until 6992 + 7 · 521 = 10 639, taken at the
/// master's END 11 000.
#[test]
fn at_twice_the_baud_rate_the_reply_lands_ten_scans_earlier() {
    let o = run(r#"
scan_time = "1ms"
duration = "30ms"

[[plc]]
name = "master"
program = "MASTER"
[plc.port1]
protocol = "modbus-master"
baud = 19200
parity = "none"

[[plc]]
name = "tank"
program = "TANK"
[plc.port1]
protocol = "modbus-slave"
baud = 19200
parity = "none"
address = 2

[[link]]
a = "master:port1"
b = "tank:port1"

[[timeline]]
scan = 1
set = { "tank/D0" = 1234 }

[[expect]]
device = "master/D104"
at = "10ms"
equals = 0

[[expect]]
device = "master/D104"
at = "11ms"
equals = 210
"#);
    assert_all_pass(&o);
}

/// An MC client reads the Q supervisor's D100..D101 every 100 ms into the
/// master's D400..D401 and writes the master's D200 into the supervisor's
/// D105, both at the supervisor's END (it scans every 50 ms: polls at the
/// ENDs at 50 ms (the first END at or after 0), 100 ms, 200 ms …). The
/// timeline's writes at 200 ms come before the step that ends at 200 ms,
/// so the poll at that END copies them.
#[test]
fn an_mc_client_copies_words_between_plcs_at_the_polled_plcs_end() {
    let o = run(r#"
scan_time = "10ms"
duration = "1s"

[[plc]]
name = "master"
program = "MASTER"

[[plc]]
name = "supervisor"
program = "SUPERVISOR"
scan_time = "50ms"

[[client]]
name = "hmi"
plc = "supervisor"
protocol = "mc"
every = "100ms"
read = { from = "D100", count = 2, to = "master/D400" }
write = { from = "master/D200", to = "D105" }

[[timeline]]
at = "200ms"
set = { "supervisor/D100" = 700, "supervisor/D101" = 650, "master/D200" = 42 }

[[expect]]                        # not polled between 100 ms and 200 ms
device = "master/D400"
at = "190ms"
equals = 0

[[expect]]                        # the poll at 200 ms copied it
device = "master/D400"
at = "200ms"
equals = 700

[[expect]]
device = "master/D401"
at = "200ms"
equals = 650

[[expect]]
device = "supervisor/D105"
at = "200ms"
equals = 42

[[expect]]                        # not before
device = "supervisor/D105"
at = "190ms"
equals = 0

[[expect]]                        # 700 − 650 = 50: no alarm
device = "supervisor/D110"
at = "250ms"
equals = 50
"#);
    assert_all_pass(&o);
}

#[test]
fn a_client_whose_requests_fail_fails_one_line() {
    let o = run(r#"
scan_time = "10ms"
duration = "1s"

[[plc]]
name = "master"
program = "MASTER"

[[plc]]
name = "tank"
program = "TANK"

[[client]]
name = "scada"
plc = "tank"
protocol = "modbus"
every = "500ms"
read = { from = 7990, count = 20, to = "master/D400" }
"#);
    assert_eq!(o.results.len(), 1, "{}", o.report(false));
    let r = &o.results[0];
    assert!(!r.passed);
    assert_eq!(r.text, "client `scada` polls without error");
    // Polls at the ENDs at 10 ms, 500 ms and 1 s; 7990 + 20 runs past D7999
    // (the APLC map's holding registers 0-7999 are D0-D7999): exception 02.
    assert_eq!(
        r.detail,
        "3 of 3 polls failed, the first at 10 ms: Modbus exception 02"
    );
}

// ------------------------------------------------------------ load errors

const TWO: &str = r#"
scan_time = "10ms"
duration = "1s"

[[plc]]
name = "master"
program = "MASTER"
[plc.port1]
protocol = "modbus-master"
baud = 9600

[[plc]]
name = "tank"
program = "TANK"
[plc.port1]
protocol = "modbus-slave"
baud = 9600
address = 2
"#;

#[test]
fn a_link_to_an_unknown_plc_names_it_with_its_line() {
    let e = load_err(&format!(
        "{TWO}\n[[link]]\na = \"master:port1\"\nb = \"pump:port1\"\n"
    ));
    assert!(
        e.ends_with("fleet.toml: 22:5: [[link]] #1 b: no PLC is named `pump` (PLCs: master, tank)"),
        "{e}"
    );
}

#[test]
fn a_link_to_an_unknown_port_is_an_error() {
    let e = load_err(&format!(
        "{TWO}\n[[link]]\na = \"master:port3\"\nb = \"tank:port1\"\n"
    ));
    assert!(
        e.ends_with("21:5: [[link]] #1 a: `master:port3`: unknown port `port3` (port1 or port2)"),
        "{e}"
    );
}

#[test]
fn a_port_linked_twice_is_an_error() {
    let e = load_err(&format!(
        "{TWO}\n[[link]]\na = \"master:port1\"\nb = \"tank:port1\"\n\n[[link]]\na = \"tank:port1\"\nb = \"master:port2\"\n"
    ));
    assert!(
        e.ends_with(
            "25:5: [[link]] #2 a: `tank:port1` is linked twice (also in [[link]] #1 (line 21))"
        ),
        "{e}"
    );
    let e = load_err(&format!(
        "{TWO}\n[[link]]\na = \"tank:port1\"\nb = \"tank:port1\"\n"
    ));
    assert!(
        e.contains("[[link]] #1 b: `tank:port1` is linked twice (also in its own `a`)"),
        "{e}"
    );
}

#[test]
fn a_link_to_a_plc_without_serial_ports_is_an_error() {
    let e = load_err(&format!(
        "{TWO}\n[[plc]]\nname = \"sup\"\nprogram = \"SUPERVISOR\"\n\n[[link]]\na = \"master:port1\"\nb = \"sup:port1\"\n"
    ));
    assert!(
        e.contains("[[link]] #1 b: `sup:port1`: sup (Q06HCPU) has no serial port PORT1: links join the APLC-TCP's PORT1/PORT2"),
        "{e}"
    );
}

#[test]
fn a_port_without_settings_is_an_error() {
    let e = load_err(&format!(
        "{TWO}\n[[link]]\na = \"master:port2\"\nb = \"tank:port1\"\n"
    ));
    assert!(
        e.ends_with("[[link]] #1 (line 21): `master:port2` has no settings ([port2] in its [[plc]] table, or in its plc.toml)"),
        "{e}"
    );
}

#[test]
fn mismatched_settings_name_both_ends() {
    let text = TWO.replacen(
        "baud = 9600\naddress = 2",
        "baud = 19200\nparity = \"odd\"\naddress = 2",
        1,
    );
    let e = load_err(&format!(
        "{text}\n[[link]]\na = \"master:port1\"\nb = \"tank:port1\"\n"
    ));
    assert!(
        e.ends_with("[[link]] #1 (line 22): the two ends do not agree: `master:port1` has 9600 baud, parity even, 8 data bits, 1 stop bits, `tank:port1` has 19200 baud, parity odd, 8 data bits, 1 stop bits"),
        "{e}"
    );
}

#[test]
fn duplicate_plc_names_are_an_error() {
    let text = TWO.replace("name = \"tank\"", "name = \"master\"");
    let e = load_err(&text);
    assert!(
        e.ends_with("fleet.toml: 13:8: [[plc]] #2 `master`: two PLCs are named `master`"),
        "{e}"
    );
    let e = load_err(&TWO.replace("name = \"tank\"", "name = \"tank 2\""));
    assert!(e.contains("`tank 2` is not a plain name"), "{e}");
}

#[test]
fn device_names_must_name_a_known_plc() {
    let e = load_err(&format!(
        "{TWO}\n[[expect]]\ndevice = \"pump/D0\"\nat = \"1s\"\nequals = 0\n"
    ));
    assert!(
        e.contains(
            "expect #1 (pump/D0): device: `pump/D0`: no PLC is named `pump` (PLCs: master, tank)"
        ),
        "{e}"
    );
    let e = load_err(&format!("{TWO}\n[trace]\ndevices = [\"D0\"]\n"));
    assert!(
        e.contains(
            "trace: `D0`: name the PLC it belongs to, as in `master/D0` (PLCs: master, tank)"
        ),
        "{e}"
    );
    let e = load_err(&format!(
        "{TWO}\n[[timeline]]\nat = 0\nset = {{ \"tank/CPU2/D0\" = 1 }}\n"
    ));
    assert!(
        e.contains("timeline #1: PLC `tank`: `CPU2/D0`: there is no CPU 2"),
        "{e}"
    );
}

#[test]
fn single_plc_keys_do_not_mix_with_plc_tables() {
    let e = load_err(&format!("program = \"TANK\"\n{TWO}"));
    assert!(
        e.ends_with(
            "program: a key of a single-PLC scenario; with [[plc]] tables each PLC gives its own"
        ),
        "{e}"
    );
    let e = load_err(&format!("{TWO}\n[port2]\nprotocol = \"free\"\n"));
    assert!(e.contains("[port2]: a key of a single-PLC scenario"), "{e}");
    let e = load_err(
        "program = \"TANK\"\nscan_time = \"10ms\"\nduration = \"1s\"\n[[link]]\na = \"x:port1\"\nb = \"y:port1\"\n",
    );
    assert!(
        e.ends_with("[[link]] and [[client]] connect the PLCs of [[plc]] tables"),
        "{e}"
    );
}

#[test]
fn peers_and_clients_name_their_plc() {
    let e = load_err(&format!(
        "{TWO}\n[[peer]]\nport = 1\ntype = \"modbus-slave\"\nstation = 3\n"
    ));
    assert!(
        e.contains("peer #1: `plc` is required with [[plc]] tables"),
        "{e}"
    );
    let e = load_err(&format!(
        "{TWO}\n[[link]]\na = \"master:port1\"\nb = \"tank:port1\"\n\n[[peer]]\nplc = \"tank\"\nport = 1\ntype = \"modbus-slave\"\nstation = 3\n"
    ));
    assert!(
        e.contains(
            "peer #1: PORT1 is linked to another PLC ([[link]]): a linked port takes no [[peer]]"
        ),
        "{e}"
    );
    let e = load_err(&format!(
        "{TWO}\n[[client]]\nplc = \"tank\"\nprotocol = \"mc\"\nevery = \"1s\"\nread = {{ from = \"D0\", to = \"master/D0\" }}\n"
    ));
    assert!(
        e.contains("[[client]] #1 `client #1` protocol: tank (APLC-TCP) has no MC protocol door"),
        "{e}"
    );
    let e = load_err(&format!(
        "{TWO}\n[[client]]\nplc = \"tank\"\nprotocol = \"modbus\"\nevery = \"1s\"\nread = {{ from = 0, to = \"line9/D0\" }}\n"
    ));
    assert!(
        e.contains("read.to: `line9/D0`: no PLC is named `line9`"),
        "{e}"
    );
    let e = load_err(&format!(
        "{TWO}\n[[client]]\nname = \"hmi\"\nplc = \"tank\"\nprotocol = \"modbus\"\nevery = \"1s\"\nread = {{ from = 0, to = \"master/V0\" }}\n"
    ));
    assert!(
        e.ends_with(
            "client `hmi`: `master/V0`: a program's local device cannot be written from outside"
        ),
        "{e}"
    );
}

/// A peer on a port of a fleet's PLC: the single-PLC serial peers work
/// the same with `plc = "NAME"`.
#[test]
fn a_peer_on_a_fleet_plcs_port() {
    let o = run(r#"
scan_time = "10ms"
duration = "1s"

[[plc]]
name = "master"
program = "MASTER"
[plc.port1]
protocol = "modbus-master"
baud = 19200

[[plc]]
name = "sup"
program = "SUPERVISOR"

[[peer]]
plc = "master"
port = 1
type = "modbus-slave"
station = 2
holding = { "0" = 321 }

[[expect]]
device = "master/D302"
within = "200ms"
equals = 321
"#);
    assert_all_pass(&o);
}

/// Two free ports linked at 9600 baud 8N1 (1042 µs a character): the
/// sender's XMT of "Hi\r" in scan 1 leaves after its END at 1000 µs, the
/// bytes arrive at 2042, 3084 and 4126 µs, and the receiver's RCV (end
/// character CR) takes each at its first END at or after it: "H" at
/// 3 ms, "i" at 4 ms, the CR and the completion at 5 ms.
#[test]
fn free_ports_talk_over_a_link() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("send.apl"),
        "LD SM1\nMOV 72 D0\nMOV 105 D1\nMOV 13 D2\nXMT 1 D0 3\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("recv.apl"), "LD SM1\nRCV 1 D10 20\n").unwrap();
    let path = dir.path().join("free.toml");
    std::fs::write(
        &path,
        r#"
scan_time = "1ms"
duration = "10ms"

[[plc]]
name = "a"
program = "send.apl"
[plc.port1]
protocol = "free"
baud = 9600
parity = "none"

[[plc]]
name = "b"
program = "recv.apl"
[plc.port1]
protocol = "free"
baud = 9600
parity = "none"
end_char = 13

[[link]]
a = "a:port1"
b = "b:port1"

[[expect]]
device = "b/D10"
at = "2ms"
equals = 0

[[expect]]
device = "b/D10"
at = "3ms"
equals = 72

[[expect]]
device = "b/D11"
at = "4ms"
equals = 105

[[expect]]
device = "b/SM123"         # RX done
at = "4ms"
equals = false

[[expect]]
device = "b/SM123"
at = "5ms"
equals = true

[[expect]]
device = "b/D12"
at = "5ms"
equals = 13

[[expect]]
device = "b/SD127"         # characters received
at = "5ms"
equals = 3

[[expect]]
device = "a/SM122"         # TX done once the last byte has left, 4126 µs
at = "5ms"
equals = true
"#,
    )
    .unwrap();
    let o = Scenario::load(&path)
        .unwrap()
        .build()
        .unwrap()
        .run(&mut |_| {});
    assert_all_pass(&o);
}

/// A multi-CPU system and a process CPU in one fleet: `cell/CPU2/D0` is
/// CPU 2 of the system (`cell/D0` CPU 1), each PLC and CPU scans at its own
/// period, and MC clients poll the system's CPU 1 (the own station) and
/// CPU 2 (`CPU2/D0`: destination 03E1). Both poll after the system's first
/// END at or after each 100 ms: CPU 1's, which comes before CPU 2's at the
/// same time.
#[test]
fn a_system_and_a_process_cpu_in_a_fleet() {
    let dir = tempfile::tempdir().unwrap();
    let sys = dir.path().join("cell");
    let count = "LD SM400\nINC D0\nEND\n";
    for (cpu, ras) in [("cpu1", "[ras]\nconstant_scan = \"20ms\"\n"), ("cpu2", "")] {
        let d = sys.join(cpu);
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("main.il"), count).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!("{ras}[[program]]\nfile = \"main.il\"\n[multi_cpu]\ncpus = 2\n"),
        )
        .unwrap();
    }
    std::fs::write(
        sys.join("system.toml"),
        "[[cpu]]\nproject = \"cpu1\"\n[[cpu]]\nproject = \"cpu2\"\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("p.il"), count).unwrap();
    let path = dir.path().join("mixed.toml");
    std::fs::write(
        &path,
        r#"
scan_time = "10ms"
duration = "1s"

[[plc]]
name = "cell"
project = "cell"

[[plc]]
name = "proc"
program = "p.il"
cpu = "Q06PHCPU"
scan_time = "5ms"

[[client]]
plc = "cell"
protocol = "mc"
every = "100ms"
read = { from = "D0", to = "proc/D100" }

[[client]]                       # CPU 2 of the system (destination 03E1)
plc = "cell"
protocol = "mc"
every = "100ms"
read = { from = "CPU2/D0", to = "proc/D101" }

[[expect]]                       # CPU 1 at its 20 ms constant scan
device = "cell/D0"
at = "1s"
equals = 50

[[expect]]
device = "cell/CPU1/D0"
at = "1s"
equals = 50

[[expect]]                       # CPU 2 at the PLC's scan time, the step
device = "cell/CPU2/D0"
at = "1s"
equals = 100

[[expect]]                       # the Q06PHCPU at its own 5 ms
device = "proc/D0"
at = "1s"
equals = 200

[[expect]]                       # polled after CPU 1's END at 1 s
device = "proc/D100"
at = "1s"
equals = 50

[[expect]]                       # before CPU 2's END at the same time
device = "proc/D101"
at = "1s"
equals = 99

[trace]
devices = ["cell/CPU2/D0", "proc/D0"]
interval = "500ms"
"#,
    )
    .unwrap();
    let sc = Scenario::load(&path).unwrap();
    assert_eq!(sc.plcs[1].profile.model, "Q06PHCPU");
    let o = sc.build().unwrap().run(&mut |_| {});
    assert_all_pass(&o);
    assert_eq!(o.scans, 50, "the header counts the first PLC's CPU 1");
    let t = o.trace.unwrap();
    assert_eq!(t.devices[0].0, "cell/CPU2/D0");
    assert_eq!(t.values, [1.0, 2.0, 50.0, 100.0, 100.0, 200.0]);
}
