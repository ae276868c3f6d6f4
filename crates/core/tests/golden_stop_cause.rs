//! SD203, the CPU operating status (004 App. 2 L10333, qcpu.md §8): b0-b3
//! 0 RUN, 1 STOP, 2 PAUSE; b4-b7 the STOP/PAUSE cause, 0 the key switch, 1
//! the remote contact, 2 a remote operation, 3 an instruction in the
//! program, 4 an error; the first cause holds while the CPU stays stopped.
//! SD1015 (D9015) copies it, and so does the multi-CPU own-information
//! area (1FH).

mod common;
use common::Plc;
use softplc_core::engine::CpuState;

const MAIN: &str = "LD SM400\nINC D0\nLD X0\nSTOP\nLD X1\n/ K1 K0 D1\nLD M6\nOUT SM206\nEND\n";

fn plain() -> Plc {
    Plc::project("[[program]]\nfile = \"main.il\"\n", &[("main.il", MAIN)])
}

fn contacts() -> Plc {
    Plc::project(
        "[[program]]\nfile = \"main.il\"\n[ras]\nrun_contact = \"X10\"\npause_contact = \"X11\"\n",
        &[("main.il", MAIN)],
    )
}

#[test]
fn key_switch_stop_is_cause_0_and_run_clears_it() {
    let mut p = plain();
    p.scan();
    assert_eq!(p.int("SD203"), 0x00);
    p.cpu.set_stop();
    assert_eq!(p.int("SD203"), 0x01);
    assert_eq!(p.int("SD1015"), 0x01);
    p.cpu.set_run().unwrap();
    assert_eq!(p.int("SD203"), 0x00);
}

#[test]
fn stop_instruction_is_cause_3() {
    let mut p = plain();
    p.set("X0", "1").scan();
    assert_eq!((p.state(), p.int("SD203")), (CpuState::Stop, 0x31));
    assert_eq!(p.int("SD1015"), 0x31);
}

#[test]
fn stop_error_is_cause_4() {
    // K1 / K0: 4100, a stop error with the default "operation error: stop".
    let mut p = plain();
    p.set("X1", "1").scan();
    assert_eq!((p.state(), p.int("SD0")), (CpuState::Stop, 4100));
    assert_eq!(p.int("SD203"), 0x41);
}

#[test]
fn remote_stop_is_cause_2_and_the_first_cause_holds() {
    let mut p = plain();
    p.scan();
    p.cpu.remote_stop(1, false).unwrap();
    assert_eq!(p.int("SD203"), 0x21);
    // The key switch to STOP as well: still the remote STOP's cause.
    p.cpu.set_stop();
    assert_eq!(p.int("SD203"), 0x21);
}

#[test]
fn run_contact_is_cause_1() {
    let mut p = contacts();
    p.scan();
    p.cpu.set_input(0x10, true);
    p.scan();
    assert_eq!((p.state(), p.int("SD203")), (CpuState::Stop, 0x11));
    p.cpu.set_input(0x10, false);
    p.scan();
    assert_eq!((p.state(), p.int("SD203")), (CpuState::Run, 0x00));
}

#[test]
fn pause_causes() {
    // The PAUSE contact with SM206 (M6): PAUSE one END after SM204 (§7.6.2).
    let mut p = contacts();
    p.set("M6", "1").scan();
    p.cpu.set_input(0x11, true);
    p.scans(2);
    assert_eq!((p.state(), p.int("SD203")), (CpuState::Pause, 0x12));
    // A remote PAUSE.
    let mut p = plain();
    p.scan();
    p.cpu.remote_pause(1, false).unwrap();
    p.scans(2);
    assert_eq!((p.state(), p.int("SD203")), (CpuState::Pause, 0x22));
    p.cpu.remote_run(1, false).unwrap();
    assert_eq!(p.int("SD203"), 0x00);
    // The monitor's PAUSE (a breakpoint) is a remote operation too.
    p.cpu.set_pause().unwrap();
    assert_eq!(p.int("SD203"), 0x22);
}

#[test]
fn another_cpu_reads_the_cause_in_the_own_information_area() {
    // CPU 2 stops on its STOP instruction and goes on running CPU 1 (stop_all
    // is about errors); CPU 1 reads CPU 2's SD203 at 1FH of its area.
    use softplc_core::engine::VirtualClock;
    use softplc_core::names::DevName;
    let dir = tempfile::tempdir().unwrap();
    let params = "[multi_cpu]\ncpus = 2\n";
    let mut manifest = String::new();
    for (i, il) in ["LD SM400\nOUT M0\nEND\n", "LD SM400\nSTOP\nEND\n"]
        .iter()
        .enumerate()
    {
        let d = dir.path().join(format!("cpu{}", i + 1));
        std::fs::create_dir(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!("[[program]]\nfile = \"main.il\"\n{params}"),
        )
        .unwrap();
        std::fs::write(d.join("main.il"), il).unwrap();
        manifest += &format!("[[cpu]]\nproject = \"cpu{}\"\n", i + 1);
    }
    std::fs::write(dir.path().join("system.toml"), manifest).unwrap();
    let clock = VirtualClock::new();
    let c = clock.clone();
    let mut sys = softplc_core::system::System::load(dir.path(), &mut || Box::new(c.clone()))
        .unwrap_or_else(|d| panic!("{d}"));
    sys.schedule(std::time::Duration::from_millis(10), 0);
    sys.run_until(30_000, &clock);
    let cpu1 = sys.cpu(0);
    let n = DevName::parse_for("U3E1\\G31", cpu1).unwrap();
    assert_eq!(
        n.read(cpu1).unwrap(),
        softplc_core::access::Value::Int(0x31)
    );
}
