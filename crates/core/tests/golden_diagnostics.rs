//! Self-diagnostics (004 §7.15, App. 2 SD4-SD26): the error-information
//! categories each error carries, and the PLC RAS error classes that stop
//! or continue (L4911-4922). Values worked out by hand from App. 2's
//! layouts. Step numbers: contacts 1 step, any other instruction 1 + its
//! operand count.

mod common;
use common::project::errors;
use common::{assert_stopped, Plc};
use softplc_core::engine::{CpuConfig, CpuState};
use std::time::Duration;

/// "MAIN    .QPG" as App. 2 stores a file name: two ASCII characters a
/// word, the first in the low byte (L10182-10230).
const MAIN_QPG: [i64; 6] = [0x414D, 0x4E49, 0x2020, 0x2020, 0x512E, 0x4750];

/// The rack of golden_rack.rs: 32 inputs X0-X1F (slot 0), 16 outputs
/// Y20-Y2F (slot 1), a module at X/Y30 (slot 2), an empty slot 40-4F
/// (slot 3), a generic module at X/Y50 (slot 4).
const RACK: &str = "[[program]]\nfile = \"main.il\"\n\
    [[slot]]\ntype = \"input\"\npoints = 32\n\
    [[slot]]\ntype = \"output\"\npoints = 16\n\
    [[slot]]\ntype = \"intelligent\"\nbuffer_words = 100\n\
    [[slot]]\ntype = \"empty\"\n\
    [[slot]]\ntype = \"intelligent\"\nmodule = \"generic\"\n";

fn words(p: &Plc, first: u32, n: u32) -> Vec<i64> {
    (first..first + n)
        .map(|d| p.int(&format!("SD{d}")))
        .collect()
}

/// PRG.TIME OVER (5010): common information "time (set value)" (SD4 low
/// byte 3), SD5 µs, SD6 ms of the constant scan; individual information
/// "time (measured)" (high byte 3), SD16 µs, SD17 ms of the scan
/// (L10153-10180, L10230-10240, L10290-10300). Constant scan 10 ms, a
/// scan of 12.3 ms: SD5 = 0, SD6 = 10, SD16 = 300, SD17 = 12.
#[test]
fn prg_time_over_carries_the_set_and_measured_times() {
    let cfg = CpuConfig {
        constant_scan: Some(Duration::from_millis(10)),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("LD SM400\nINC D0\nEND\n", cfg);
    p.scans(2);
    p.scan_time_us(12_300).scan();
    assert_eq!(p.int("SD0"), 5010);
    assert_eq!(p.int("SD4"), 0x0303);
    assert_eq!(words(&p, 5, 2), [0, 10]);
    assert_eq!(words(&p, 16, 2), [300, 12]);
    assert!(p.bit("SM5") && p.bit("SM16"));
    // No program location: SD7-SD15 and SD18-SD26 stay 0.
    assert!(words(&p, 7, 9).iter().all(|&w| w == 0));
    assert!(words(&p, 18, 9).iter().all(|&w| w == 0));
}

/// WDT ERROR (5000): the watchdog time set in SD5/SD6 (20 ms: 0 µs, 20 ms)
/// and the time measured in SD16/SD17, at least the time set.
#[test]
fn wdt_error_carries_the_set_and_measured_times() {
    let cfg = CpuConfig {
        watchdog: Duration::from_millis(20),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("P0\nJMP P0\nEND\n", cfg);
    p.scan();
    assert_stopped(&p, 5000);
    assert_eq!(p.int("SD4"), 0x0303);
    assert_eq!(words(&p, 5, 2), [0, 20]);
    assert!(p.int("SD17") >= 20, "measured {} ms", p.int("SD17"));
}

/// An initial program's WDT ERROR carries the initial execution monitor
/// time as the time set (L1446-1503): 30 ms.
#[test]
fn initial_monitor_wdt_carries_the_monitor_time() {
    let toml = "[[program]]\nfile = \"init.il\"\ntype = \"initial\"\n\
                [[program]]\nfile = \"main.il\"\n[ras]\ninitial_monitor = \"30ms\"\n";
    let mut p = Plc::project(
        toml,
        &[("init.il", "P0\nJMP P0\nEND\n"), ("main.il", "END\n")],
    );
    p.scan();
    assert_stopped(&p, 5000);
    assert_eq!(p.int("SD4"), 0x0303);
    assert_eq!(words(&p, 5, 2), [0, 30]);
}

/// SP.UNIT ERROR (2110): common information "module" (low byte 1), SD5 the
/// slot, SD6 the start I/O number; individual information "program error
/// location" (high byte 4): SD16-SD19 the file name, SD20/SD21 ".QPG",
/// SD25/SD26 the step (L10182-10200, L10268-10316). A unit no slot holds
/// (U9, I/O 90H) has no slot number: SD5 = FFFFH.
#[test]
fn sp_unit_error_names_the_slot_and_io_number() {
    for (program, slot, io) in [
        ("LD SM400\nFROM H0 K0 D0 K1\nEND\n", 0, 0x00),
        ("LD SM400\nMOV K1 U2\\G0Z0\nEND\n", 1, 0x20),
        ("LD SM400\nTO H4 K0 K1 K1\nEND\n", 3, 0x40),
        // FFFFH read as a signed word.
        ("LD SM400\nMOV U9\\G0 D0\nEND\n", -1, 0x90),
    ] {
        let mut p = Plc::project(RACK, &[("main.il", program)]);
        p.scan();
        assert_stopped(&p, 2110);
        assert_eq!(p.int("SD4"), 0x0401, "{program}");
        assert_eq!(words(&p, 5, 2), [slot, io], "{program}");
        assert!(words(&p, 7, 9).iter().all(|&w| w == 0), "{program}");
        assert_eq!(words(&p, 16, 6), MAIN_QPG, "{program}");
        // LD SM400 is step 0: the failing instruction is step 1.
        assert_eq!(words(&p, 22, 5), [0, 0, 0, 1, 0], "{program}");
        assert!(p.bit("SM5") && p.bit("SM16"));
    }
}

/// An operation error keeps "program error location" as common information
/// (SD4 = 4): SD5-SD8 the file name, SD9/SD10 ".QPG", SD14/SD15 the step;
/// no individual information (SM16 OFF, SD16-SD26 0).
#[test]
fn operation_error_carries_the_program_location() {
    let mut p = Plc::project(
        "[[program]]\nfile = \"main.il\"\n",
        &[("main.il", "LD SM400\nMOV K1 D0\n/ K1 K0 D1\nEND\n")],
    );
    p.scan();
    assert_eq!(p.int("SD0"), 4100);
    assert_eq!(p.int("SD4"), 4);
    assert_eq!(words(&p, 5, 6), MAIN_QPG);
    // LD 1 step, MOV 3 steps: the division is step 4.
    assert_eq!(words(&p, 11, 5), [0, 0, 0, 4, 0]);
    assert!(words(&p, 16, 11).iter().all(|&w| w == 0));
    assert!(!p.bit("SM16"));
}

/// A later error replaces the information of an earlier one: after the
/// SP.UNIT ERROR's program location in SD16-SD26, PRG.TIME OVER leaves
/// only its own words.
#[test]
fn a_new_error_clears_the_old_information() {
    let toml = format!("{RACK}[ras]\nmodule_error = \"continue\"\nconstant_scan = \"10ms\"\n");
    let mut p = Plc::project(&toml, &[("main.il", "LD X5\nFROM H0 K0 D0 K1\nEND\n")]);
    p.set("X5", "1").scan();
    assert_eq!(p.int("SD4"), 0x0401);
    p.set("X5", "0").scan_time_us(11_000).scan();
    assert_eq!(p.int("SD0"), 5010);
    assert_eq!(words(&p, 16, 11), [0, 11, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
}

/// `[ras] module_error = "continue"`: SP.UNIT ERROR skips the access and
/// the CPU runs on (L4911-4922, "intelligent module program execution
/// error"); the instructions after it run; SM50/SD50 clears it (L5028-5055).
#[test]
fn module_error_may_continue() {
    let toml = format!("{RACK}[ras]\nmodule_error = \"continue\"\n");
    let mut p = Plc::project(
        &toml,
        &[("main.il", "LD SM400\nFROM H0 K0 D0 K1\nINC D1\nEND\n")],
    );
    p.scans(2);
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("SD0"), 2110);
    assert_eq!(p.int("D1"), 2);
    // The default stops.
    let mut p = Plc::project(RACK, &[("main.il", "LD SM400\nFROM H0 K0 D0 K1\nEND\n")]);
    p.scan();
    assert_stopped(&p, 2110);
    // Cleared by SM50 with 2110 in SD50, the condition gone.
    let mut p = Plc::project(&toml, &[("main.il", "LD X5\nFROM H0 K0 D0 K1\nEND\n")]);
    p.set("X5", "1").scan();
    assert_eq!(p.int("SD0"), 2110);
    p.set("X5", "0").set("SD50", "2110").set("SM50", "1").scan();
    assert!(p.cpu.error().is_none());
    assert_eq!((p.int("SD0"), p.int("SD4")), (0, 0));
}

/// `[ras] file_access_error = "continue"`: FILE OPE. ERROR (2410, PSCAN
/// naming no program, L4957) lets the CPU run on; the default stops.
#[test]
fn file_access_error_may_continue() {
    let main = "LD SM400\nPSCAN \"NONE\"\nINC D1\nEND\n";
    let toml = "[[program]]\nfile = \"main.il\"\n[ras]\nfile_access_error = \"continue\"\n";
    let mut p = Plc::project(toml, &[("main.il", main)]);
    p.scans(2);
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("SD0"), 2410);
    assert_eq!(p.int("D1"), 2);
    let mut p = Plc::project("[[program]]\nfile = \"main.il\"\n", &[("main.il", main)]);
    p.scan();
    assert_stopped(&p, 2410);
}

/// The error classes of hardware softplc lacks are refused, naming why
/// (L4911-4922); a misspelt class key is still an unknown key.
#[test]
fn hardware_error_classes_are_refused() {
    for key in [
        "fuse_blown_error",
        "io_verify_error",
        "memory_card_access_error",
        "memory_card_operation_error",
        "external_power_error",
        "extension_instruction_error",
    ] {
        let toml = format!("[[program]]\nfile = \"main.il\"\n[ras]\n{key} = \"continue\"\n");
        let e = errors(&toml);
        assert_eq!(e.len(), 1, "{e:?}");
        assert!(e[0].starts_with(&format!("4:1: [ras] {key}: ")), "{e:?}");
        assert!(
            e[0].contains("never occurs (QCPU manual §7.15 (3))"),
            "{e:?}"
        );
    }
    let e = errors("[[program]]\nfile = \"main.il\"\n[ras]\nmodule_eror = \"stop\"\n");
    assert_eq!(
        e,
        ["4:1: unknown key \"module_eror\" in [ras]; did you mean \"module_error\"?"]
    );
    let e = errors("[[program]]\nfile = \"main.il\"\n[ras]\nmodule_error = \"halt\"\n");
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(e[0].starts_with("4:16:"), "{e:?}");
}

/// A continuing SP.UNIT ERROR runs I34 and a continuing FILE OPE. ERROR
/// I36 at the next interrupt service (004 §7.15.1, L5008-5010), once IMASK
/// enables them (they are disabled at power-on).
#[test]
fn continuing_class_errors_run_their_interrupt_pointers() {
    let enable = "LD SM402\nFMOV HFFFF D300 K16\nIMASK D300\nEI\n";
    let program = format!(
        "{enable}LD X5\nFROM H0 K0 D0 K1\nLD X6\nPSCAN \"NONE\"\nFEND\n\
         I34\nLD SM400\nINC D234\nIRET\nI36\nLD SM400\nINC D236\nIRET\nEND\n"
    );
    let toml =
        format!("{RACK}[ras]\nmodule_error = \"continue\"\nfile_access_error = \"continue\"\n");
    let mut p = Plc::project(&toml, &[("main.il", &program)]);
    p.scan();
    p.set("X5", "1").scan();
    assert_eq!(p.int("SD0"), 2110);
    p.set("X5", "0").scan();
    assert_eq!((p.int("D234"), p.int("D236")), (1, 0));
    p.set("X6", "1").scan();
    assert_eq!(p.int("SD0"), 2410);
    p.set("X6", "0").scan();
    assert_eq!((p.int("D234"), p.int("D236")), (1, 1));
    assert_eq!(p.state(), CpuState::Run);
}
