//! Local devices (004 §10.13.1, L7562-7686): the ranges of M, V, T, ST, C
//! and D each program has its own copy of (`[devices] local`), programs
//! whose local devices are "not used" (L1381, L7611), SM776 at CALL
//! (L7618-7650, App. 1 L9710), SM777 in interrupt and fixed-scan programs
//! (L7652-7680, App. 1 L9711), the clear at power-on, RESET and STOP→RUN
//! (L1952, L7681-7686), never latched (L3552), and the plc.toml errors.
//! Scans take 10 ms; values worked out by hand in the comments.

mod common;

use common::project::errors;
use common::Plc;

/// `plc.toml` with `head` (sections before the programs) and one
/// `[[program]]` per `(file, extra lines)`.
fn toml(head: &str, programs: &[(&str, &str)]) -> String {
    let mut t = head.to_string();
    for (file, extra) in programs {
        t += &format!("\n[[program]]\nfile = \"{file}\"\n{extra}\n");
    }
    t
}

const LOCAL_D: &str = "[devices]\nlocal = [\"D0-D99\"]\n";

/// Each program counts in its own D0 and shows it in a global register.
const A: &str = "LD SM400\nINC D0\nMOV D0 D100\nEND\n";
const B: &str = "LD SM400\nINC D0\nMOV D0 D101\nEND\n";

/// Two scan programs each INC D0 of a local range: each counts its own
/// (L7580-7582), 3 after 3 scans. Outside, D0 is what device memory holds
/// after the last program ran: B's (the monitor without a chosen program,
/// L4152-4157).
#[test]
fn each_program_counts_in_its_own_local_d0() {
    let mut p = Plc::project(
        &toml(LOCAL_D, &[("a.il", ""), ("b.il", "")]),
        &[("a.il", A), ("b.il", B)],
    );
    p.scans(3);
    assert_eq!((p.int("D100"), p.int("D101")), (3, 3));
    assert_eq!(p.int("D0"), 3);
    assert_eq!(p.cpu.local_devices_owner(), Some(1));
    // Without the range the two share D0: A sees 1, 3, 5; B 2, 4, 6.
    let mut p = Plc::project(
        &toml("", &[("a.il", ""), ("b.il", "")]),
        &[("a.il", A), ("b.il", B)],
    );
    p.scans(3);
    assert_eq!((p.int("D100"), p.int("D101")), (5, 6));
    assert_eq!(p.cpu.local_devices_owner(), None);
}

/// A program whose local devices are "not used" swaps nothing: it works on
/// the local devices of the program before it (L1381, L7611), and what it
/// writes there stays in that program's copy.
///
/// A: D103 := its D1, INC D0, D100 := D0. B (not used): D101 := D0,
/// INC D1. C: D0 += 10, D102 := D0.
/// Scan 1: A (its copy: 0, 0) D103 = 0, D0 = 1, D100 = 1; B on A's: D101
/// = 1, A's D1 = 1; C (its copy) D0 = 10, D102 = 10.
/// Scan 2: A (D0 1, D1 1) D103 = 1, D0 = 2, D100 = 2; B D101 = 2, A's D1 =
/// 2; C D0 = 20, D102 = 20.
#[test]
fn a_program_not_using_local_devices_runs_on_the_previous_programs() {
    let a = "LD SM400\nMOV D1 D103\nINC D0\nMOV D0 D100\nEND\n";
    let b = "LD SM400\nMOV D0 D101\nINC D1\nEND\n";
    let c = "LD SM400\n+ K10 D0\nMOV D0 D102\nEND\n";
    let mut p = Plc::project(
        &toml(
            LOCAL_D,
            &[
                ("a.il", ""),
                ("b.il", "local_devices = false"),
                ("c.il", ""),
            ],
        ),
        &[("a.il", a), ("b.il", b), ("c.il", c)],
    );
    p.scan();
    assert_eq!(
        [p.int("D100"), p.int("D101"), p.int("D102"), p.int("D103")],
        [1, 1, 10, 0]
    );
    p.scan();
    assert_eq!(
        [p.int("D100"), p.int("D101"), p.int("D102"), p.int("D103")],
        [2, 2, 20, 1]
    );
    // Device memory holds C's: D0 = 20, D1 = 0.
    assert_eq!((p.int("D0"), p.int("D1")), (20, 0));
}

/// A "not used" program that runs first after STOP→RUN works on the
/// cleared local range no program owns; from the second scan on, on the
/// last program's (C's D0 = 1, then 2).
#[test]
fn a_not_used_program_first_in_the_scan_sees_the_last_programs() {
    let first = "LD SM400\nMOV D0 D101\nEND\n";
    let mut p = Plc::project(
        &toml(LOCAL_D, &[("n.il", "local_devices = false"), ("a.il", "")]),
        &[("n.il", first), ("a.il", A)],
    );
    p.scan();
    assert_eq!((p.int("D101"), p.int("D100")), (0, 1));
    p.scan();
    assert_eq!((p.int("D101"), p.int("D100")), (1, 2));
}

/// Local devices are cleared at STOP→RUN and at power-on/RESET (L1952,
/// L7681-7686), a global device is not at STOP→RUN; a remote latch clear
/// does not clear them (L7686: "not by GX Developer operations").
#[test]
fn cleared_at_stop_to_run_and_reset() {
    let b = "LD SM400\nINC D0\nMOV D0 D101\nINC D200\nEND\n";
    let mut p = Plc::project(
        &toml(LOCAL_D, &[("a.il", ""), ("b.il", "")]),
        &[("a.il", A), ("b.il", b)],
    );
    p.scans(2);
    assert_eq!((p.int("D100"), p.int("D101"), p.int("D200")), (2, 2, 2));
    p.cpu.set_stop();
    p.cpu.latch_clear(true).unwrap();
    assert_eq!(p.int("D0"), 2, "latch clear keeps the local devices");
    // Remote latch clear cleared the globals; count again from 0.
    p.set("D200", "5");
    p.cpu.set_run().unwrap();
    assert_eq!(p.int("D0"), 0);
    p.scan();
    // A's and B's copies start from 0 again; D200 goes on from 5.
    assert_eq!((p.int("D100"), p.int("D101"), p.int("D200")), (1, 1, 6));
    p.scans(2);
    p.cpu.set_stop();
    p.cpu.reset().unwrap();
    assert_eq!((p.int("D0"), p.int("D200")), (0, 0));
    p.scan();
    assert_eq!((p.int("D100"), p.int("D101"), p.int("D200")), (1, 1, 1));
}

/// A timer in a local range times per program, its sub-unit remainder
/// included (004 §10.2.10: the previous scan time is added at each OUT T).
/// Scans of 30 ms, T0 at the 100 ms base with K1: A's coil is ON from scan
/// 1, so +30 ms at scans 2-5: 30, 60, 90, 120 → T0 = 1 (remainder 20)
/// and the contact turns ON at scan 5. B's coil from scan 2: ON at scan 6.
/// With one remainder for both, A's would have reached 100 ms at scan 4.
#[test]
fn a_timer_in_a_local_range_times_per_program() {
    let a = "LD X0\nOUT T0 K1\nLD T0\nOUT M100\nEND\n";
    let b = "LD X1\nOUT T0 K1\nLD T0\nOUT M101\nEND\n";
    let mut p = Plc::project(
        &toml(
            "[devices]\nlocal = [\"T0-T9\"]\n",
            &[("a.il", ""), ("b.il", "")],
        ),
        &[("a.il", a), ("b.il", b)],
    );
    p.scan_time_us(30_000);
    p.set("X0", "1").scan();
    p.set("X1", "1").scans(3);
    assert_eq!((p.bit("M100"), p.bit("M101")), (false, false), "scan 4");
    p.scan();
    assert_eq!((p.bit("M100"), p.bit("M101")), (true, false), "scan 5");
    // Device memory holds B's T0: coil ON, 90 ms in, value 0.
    assert_eq!((p.bit("TC0"), p.int("TN0")), (true, 0));
    p.scan();
    assert_eq!((p.bit("M100"), p.bit("M101")), (true, true), "scan 6");
}

/// An M range and a counter range are local too: each program's C0
/// counts its own rising X0 (the coil is local as well) and its M0 is its
/// own.
#[test]
fn local_relays_and_counters() {
    let a = "LD X0\nOUT C0 K2\nLD C0\nOUT M100\nLD SM400\nSET M0\nEND\n";
    let b = "LD M0\nOUT M101\nLD SM400\nOUT C0 K9\nMOV C0 D101\nEND\n";
    let mut p = Plc::project(
        &toml(
            "[devices]\nlocal = [\"M0-M99\", \"C0-C9\"]\n",
            &[("a.il", ""), ("b.il", "")],
        ),
        &[("a.il", a), ("b.il", b)],
    );
    // B's C0 counts its own coil's single rise (scan 1): 1 thereafter.
    p.set("X0", "1").scan();
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    // A's C0 counted 2 rises: ON. B never sees A's M0.
    assert_eq!((p.bit("M100"), p.bit("M101")), (true, false));
    assert_eq!(p.int("D101"), 1);
}

/// The interrupt module of the rack: a rising X0 runs I0 at the start of
/// the next scan. int.il's I0 adds 10 to D0 and shows it in D110.
const QI60: &str = "[[slot]]\ntype = \"interrupt\"\nmodule = \"QI60\"\npoints = 16\n";
const MAIN_EI: &str = "EI\nLD SM400\nINC D0\nMOV D0 D100\nEND\n";
const INT: &str = "FEND\nI0\nLD SM400\n+ K10 D0\nMOV D0 D110\nIRET\nEND\n";

fn with_interrupt(int_extra: &str) -> Plc {
    let head = format!("{LOCAL_D}{QI60}");
    Plc::project(
        &toml(
            &head,
            &[
                ("main.il", ""),
                ("int.il", &format!("type = \"standby\"\n{int_extra}")),
            ],
        ),
        &[("main.il", MAIN_EI), ("int.il", INT)],
    )
}

/// SM777 OFF: the interrupt program runs on the local devices of the
/// program it interrupted (L7666: "the file executed before"). Scan 1:
/// main D0 = 1. Scan 2: I0 on main's D0: 11, D110 = 11; main: 12.
#[test]
fn sm777_off_interrupt_uses_the_interrupted_programs_locals() {
    let mut p = with_interrupt("");
    p.scan();
    assert_eq!(p.int("D100"), 1);
    p.set("X0", "1").scan();
    assert_eq!((p.int("D110"), p.int("D100")), (11, 12));
}

/// SM777 ON: the interrupt program runs on its own file's local devices,
/// read before it runs and saved after IRET (L7667, L7674); the
/// interrupted program's come back. Scan 2: I0's D0 10, main 2; the next
/// rising X0 (scan 4): I0's 20, main 4.
#[test]
fn sm777_on_interrupt_uses_its_own_files_locals() {
    let mut p = with_interrupt("");
    p.scan();
    p.set("SM777", "1").set("X0", "1").scan();
    assert_eq!((p.int("D110"), p.int("D100")), (10, 2));
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!((p.int("D110"), p.int("D100")), (20, 4));
    // Decision: an interrupt program whose file does not use local
    // devices swaps nothing, even with SM777 ON: on main's, 11 and 12.
    let mut p = with_interrupt("local_devices = false");
    p.scan();
    p.set("SM777", "1").set("X0", "1").scan();
    assert_eq!((p.int("D110"), p.int("D100")), (11, 12));
}

/// A fixed-scan program (interval 10 ms: once before the scan programs of
/// every 10 ms scan) follows SM777 like an interrupt program (L7652).
/// SM777 OFF — scan 1: fast on the cleared range nobody owns, D0 = 10,
/// D120 = 10; main on its own: 1. Scan 2: fast on main's (the program
/// before): 11, main 12.
/// SM777 ON — fast on its own: 10, 20; main 1, 2.
#[test]
fn sm777_and_fixed_scan_programs() {
    let fast = "LD SM400\n+ K10 D0\nMOV D0 D120\nEND\n";
    let main = "LD SM400\nINC D0\nMOV D0 D100\nEND\n";
    let t = toml(
        LOCAL_D,
        &[
            ("main.il", ""),
            ("fast.il", "type = \"fixed-scan\"\ninterval = \"10ms\""),
        ],
    );
    let mut p = Plc::project(&t, &[("main.il", main), ("fast.il", fast)]);
    p.scan();
    assert_eq!((p.int("D120"), p.int("D100")), (10, 1));
    p.scan();
    assert_eq!((p.int("D120"), p.int("D100")), (11, 12));
    let mut p = Plc::project(&t, &[("main.il", main), ("fast.il", fast)]);
    p.set("SM777", "1").scan();
    assert_eq!((p.int("D120"), p.int("D100")), (10, 1));
    p.scan();
    assert_eq!((p.int("D120"), p.int("D100")), (20, 2));
}

/// CALL of a subroutine in another file (a common pointer): with SM776
/// OFF it runs on the caller's local devices, with SM776 ON on its own
/// file's, read at CALL and saved after RET (L7624-7646).
/// main: INC D0, CALL P100, D100 := D0. sub.il's P100: D0 += 10, D130 :=
/// D0.
/// OFF — scan 1: 1 → 11, D130 = D100 = 11; scan 2: 12 → 22.
/// ON — scan 1: main 1, sub 10, D100 = 1; scan 2: main 2, sub 20.
#[test]
fn sm776_call_into_another_file() {
    let main = "LD SM400\nINC D0\nCALL P100\nMOV D0 D100\nEND\n";
    let sub = "FEND\nP100\nLD SM400\n+ K10 D0\nMOV D0 D130\nRET\nEND\n";
    let t = toml(
        &format!("[cpu]\ncommon_pointer = \"P100\"\n{LOCAL_D}"),
        &[("main.il", ""), ("sub.il", "type = \"standby\"")],
    );
    let mut p = Plc::project(&t, &[("main.il", main), ("sub.il", sub)]);
    p.scan();
    assert_eq!((p.int("D130"), p.int("D100")), (11, 11));
    p.scan();
    assert_eq!((p.int("D130"), p.int("D100")), (22, 22));
    let mut p = Plc::project(&t, &[("main.il", main), ("sub.il", sub)]);
    p.set("SM776", "1").scan();
    assert_eq!((p.int("D130"), p.int("D100")), (10, 1));
    p.scan();
    assert_eq!((p.int("D130"), p.int("D100")), (20, 2));
    // SM776 is read at every CALL (L7646): OFF again, the caller's: 3 → 13.
    p.set("SM776", "0").scan();
    assert_eq!((p.int("D130"), p.int("D100")), (13, 13));
}

/// A latch range that overlaps the local range latches only its global
/// part (L3552: a local device is not latched even in a latch range): after
/// RESET D0 (local) is 0, D150 (latched) kept; the battery-backed image
/// has no local device.
#[test]
fn a_local_device_is_never_latched() {
    let a = "LD SM400\nINC D0\nMOV D0 D150\nEND\n";
    let mut p = Plc::project(
        &toml(
            &format!("{LOCAL_D}[latch]\nlatch1 = [\"D0-D199\"]\n"),
            &[("a.il", "")],
        ),
        &[("a.il", a)],
    );
    p.scans(3);
    assert_eq!((p.int("D0"), p.int("D150")), (3, 3));
    p.cpu.set_stop();
    p.cpu.reset().unwrap();
    assert_eq!((p.int("D0"), p.int("D150")), (0, 3));
    let names: Vec<String> = p
        .cpu
        .retained_layout()
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    assert!(names.contains(&"latch:D100-199".to_string()), "{names:?}");
    assert!(
        !names.iter().any(|n| n.starts_with("latch:D0-")),
        "{names:?}"
    );
}

/// Errors at the offending value, as every plc.toml key reports them.
#[test]
fn plc_toml_errors() {
    let prog = "\n[[program]]\nfile = \"main.il\"\n";
    let e = |devices: &str| errors(&format!("[devices]\n{devices}{prog}"));
    assert_eq!(
        e("local = [\"X0-XF\"]\n"),
        ["2:10: X cannot be a local device; local devices are M, V, T, ST, C and D"]
    );
    assert_eq!(
        e("local = [\"L0-L9\"]\n"),
        ["2:10: L cannot be a local device; local devices are M, V, T, ST, C and D"]
    );
    assert_eq!(
        e("local = [\"D0-D99\", \"D200-D299\"]\n"),
        ["2:20: local already has a range for D (\"D0-D99\"); the parameter allows one range per device, the same for every program"]
    );
    assert_eq!(
        e("local = [\"D0-D12288\"]\n"),
        ["2:10: \"D0-D12288\": D12288 is outside the configured points (D has 12288)"]
    );
    // The range is checked against the points the table sets, wherever.
    assert_eq!(
        e("local = [\"D0-D99\"]\nD = 64\n"),
        ["2:10: \"D0-D99\": D99 is outside the configured points (D has 64)"]
    );
    assert_eq!(
        e("local = \"D0-D99\"\n"),
        ["2:9: local must be an array of ranges such as [\"D0-D99\", \"M0-M99\"], not a string"]
    );
    assert_eq!(
        e("local = [\"D9-D0\"]\n"),
        ["2:10: range \"D9-D0\" ends before it starts"]
    );
    assert_eq!(
        errors("[[program]]\nfile = \"main.il\"\nlocal_devices = \"no\"\n"),
        ["3:17: local_devices must be true (the project's local devices, default) or false (not used), not a string"]
    );
    assert_eq!(
        errors(
            "[cpu]\nmodel = \"APLC-TCP\"\n[[program]]\nfile = \"main.il\"\nlocal_devices = false\n"
        ),
        ["5:1: the APLC-TCP has no local devices"]
    );
}

/// Timers, retentive timers and counters are named by contact or current
/// value; ST needs points.
#[test]
fn plc_toml_accepts_every_local_device() {
    let p = common::project::ok(
        "[devices]\nST = 16\nlocal = [\"M0-M9\", \"V0-V9\", \"TN0-TN9\", \"ST0-ST9\", \"C0-C9\", \"D0-D9\"]\n\
         [[program]]\nfile = \"main.il\"\nlocal_devices = false\n",
    );
    assert_eq!(p.config.local_devices.len(), 6);
    assert!(!p.programs[0].local_devices);
}

/// The monitor with a chosen program (L4152-4157, L7562-7686): outside the
/// scan, `with_local_devices_of` shows a program's own copy, a write there
/// lands in that copy, and device memory gets the last program's back.
///
/// A: INC D0, D100 := D0. B: D0 += 10, D101 := D0. After 3 scans A's D0 is
/// 3 and B's 30; device memory holds B's (it ran last). Write 7 into A's
/// D0: the next scan A counts on from it (D100 = 8) and B from 30 (40).
#[test]
fn the_monitor_reads_and_writes_a_chosen_programs_local_devices() {
    const B10: &str = "LD SM400\n+ K10 D0\nMOV D0 D101\nEND\n";
    let mut p = Plc::project(
        &toml(LOCAL_D, &[("a.il", ""), ("b.il", "")]),
        &[("a.il", A), ("b.il", B10)],
    );
    p.scans(3);
    let d0 = softplc_core::access::DeviceSpec::parse("D0").unwrap();
    let read = |c: &mut softplc_core::engine::Cpu| match c.read_device(&d0) {
        Ok(softplc_core::access::Value::Int(i)) => i,
        v => panic!("{v:?}"),
    };
    let a = p.cpu.program_slot("A").unwrap();
    assert_eq!(p.cpu.program_slot("b.il"), Some(1));
    assert_eq!(p.cpu.program_slot("c"), None);
    assert_eq!(p.cpu.with_local_devices_of(a, read), 3);
    assert_eq!(p.cpu.with_local_devices_of(1, read), 30);
    assert_eq!(p.int("D0"), 30);
    assert_eq!(p.cpu.local_devices_owner(), Some(1));
    p.cpu
        .with_local_devices_of(a, |c| c.write_device(&d0, "7"))
        .unwrap();
    assert_eq!(p.int("D0"), 30);
    p.scans(1);
    assert_eq!((p.int("D100"), p.int("D101")), (8, 40));
    // A global device reads the same from every program.
    assert_eq!(
        p.cpu
            .with_local_devices_of(a, |c| c
                .read_device(&softplc_core::access::DeviceSpec::parse("D101").unwrap()))
            .unwrap(),
        softplc_core::access::Value::Int(40)
    );
}
