//! Rules of the QCPU manual on a project's programs taken together, refused
//! at load with the file and line (docs/plc-toml.md, "[[program]]" rules):
//! timers in interrupt, fixed-scan and standby programs; an edge relay V
//! number used twice; local pointers beyond 4096 points (error 4020).

mod common;
use common::project::load_files;

const TWO: &str = "[[program]]\nfile = \"main.il\"\n[[program]]\nfile = \"fast.il\"\n";

fn with_fast(ty: &str) -> String {
    let interval = if ty == "fixed-scan" {
        "interval = \"10ms\"\n"
    } else {
        ""
    };
    format!(
        "[devices]\nST = 16\n[[program]]\nfile = \"main.il\"\n[[program]]\nfile = \"fast.il\"\n\
         type = \"{ty}\"\n{interval}"
    )
}

const TIMER_RULE: &str = "timers must not be used in interrupt, fixed-scan or standby programs, \
     where they cannot measure time (QCPU manual, timers); use a timer in a scan program, or \
     count the program's runs";

#[test]
fn a_timer_in_a_fixed_scan_or_standby_program_is_refused() {
    let fast = "LD SM400\nOUT T0 K10\nLD SM400\nOUTH ST1 K5\nEND\n";
    for (ty, place) in [
        ("fixed-scan", "a fixed-scan program"),
        ("standby", "a standby program"),
    ] {
        assert_eq!(
            load_files(&with_fast(ty), &[("fast.il", fast)]).unwrap_err(),
            [
                format!("fast.il:2:1: a timer coil (OUT T/OUT ST) in {place}: {TIMER_RULE}"),
                format!("fast.il:4:1: a timer coil (OUT T/OUT ST) in {place}: {TIMER_RULE}"),
            ],
            "{ty}"
        );
    }
    // In initial, scan and low-speed programs they keep time.
    for ty in ["initial", "scan"] {
        load_files(&with_fast(ty), &[("fast.il", fast)]).unwrap();
    }
}

#[test]
fn a_timer_in_an_interrupt_program_is_refused_and_allowed_before_fend() {
    let main = "LD SM400\nOUT T1 K10\nFEND\nI28\nLD SM400\nOUT T0 K10\nIRET\nEND\n";
    assert_eq!(
        load_files(TWO, &[("main.il", main)]).unwrap_err(),
        [format!(
            "main.il:6:1: a timer coil (OUT T/OUT ST) in interrupt program I28: {TIMER_RULE}"
        )]
    );
    // Contacts of a timer and counters are fine in an interrupt program.
    let main = "LD SM400\nOUT T1 K10\nFEND\nI28\nLD T1\nOUT C0 K10\nIRET\nEND\n";
    load_files(TWO, &[("main.il", main)]).unwrap();
}

#[test]
fn an_edge_relay_number_is_used_once_in_all_programs() {
    let main = "LD X0\nEGP V0\nOUT Y0\nLD X1\nEGF V1\nOUT Y1\nEND\n";
    let fast = "LD X2\nEGP V1\nOUT Y2\nEND\n";
    assert_eq!(
        load_files(TWO, &[("main.il", main), ("fast.il", fast)]).unwrap_err(),
        [
            "fast.il:2:1: this edge relay V is already used at main.il:5: an edge relay number \
          may be used once in all programs (QCPU manual, edge relay V)"
        ]
    );
    // Twice in one file too.
    let main = "LD X0\nEGP V3\nOUT Y0\nLD X1\nEGP V3\nOUT Y1\nEND\n";
    assert_eq!(
        load_files(TWO, &[("main.il", main)]).unwrap_err(),
        [
            "main.il:5:1: this edge relay V is already used at main.il:2: an edge relay number \
          may be used once in all programs (QCPU manual, edge relay V)"
        ]
    );
    // A local V is each file's own.
    let local = format!("{TWO}[devices]\nlocal = [\"V0-V15\"]\n");
    load_files(
        &local,
        &[
            ("main.il", "LD X0\nEGP V1\nOUT Y0\nEND\n"),
            ("fast.il", fast),
        ],
    )
    .unwrap();
}

#[test]
fn local_pointers_beyond_4096_points_are_error_4020() {
    let main = "LD X0\nCJ P3000\nP3000\nLD X1\nOUT Y1\nEND\n";
    let fast = "LD X0\nCJ P1095\nP1095\nEND\n";
    // 3001 + 1096 = 4097 points.
    assert_eq!(
        load_files(TWO, &[("main.il", main), ("fast.il", fast)]).unwrap_err(),
        [
            "fast.il:3:1: local pointers take 4097 points in all programs (main.il P0-P3000, \
          fast.il P0-P1095), more than 4096 points (error 4020, CAN'T SET(P)): each program \
          takes P0 up to its highest local pointer (P1095 here), so number each program's \
          pointers from P0"
        ]
    );
    // 4096 exactly fit.
    let fast = "LD X0\nCJ P1094\nP1094\nEND\n";
    load_files(TWO, &[("main.il", main), ("fast.il", fast)]).unwrap();
}

#[test]
fn local_pointers_must_end_before_the_first_common_pointer() {
    let toml = format!("[cpu]\ncommon_pointer = \"P2048\"\n{TWO}");
    let main = "LD X0\nCJ P2000\nP2000\nLD X1\nOUT Y1\nEND\n";
    let fast = "LD X0\nCJ P47\nP47\nEND\n";
    assert_eq!(
        load_files(&toml, &[("main.il", main), ("fast.il", fast)]).unwrap_err(),
        [
            "fast.il:3:1: local pointers take 2049 points in all programs (main.il P0-P2000, \
          fast.il P0-P47), more than the 2048 points before the first common pointer P2048 \
          (error 4020, CAN'T SET(P)): each program takes P0 up to its highest local pointer \
          (P47 here), so number each program's pointers from P0"
        ]
    );
    let fast = "LD X0\nCJ P46\nP46\nEND\n";
    load_files(&toml, &[("main.il", main), ("fast.il", fast)]).unwrap();
}

const STEP_RELAY_RULE: &str = "the step relay S is a device of SFC programs only; a sequence \
     program that uses it stops the CPU with an SFC error (QCPU manual §10.2.9), and softplc \
     loads no SFC program: use M or L instead";

#[test]
fn the_step_relay_s_in_a_sequence_program_is_refused() {
    // 004 §10.2.9 (L6380-6382): S used as an internal relay in a sequence
    // program is an SFC error that stops the CPU. Plain, digit-specified and
    // index-modified operands; SB, SM, SD and SW are other devices.
    let main = "LD SM400\nOUT S0\nMOV K4S16 D0\nLD S2Z1\nOUT SB0\nLD SM0\nMOV SD0 SW0\nEND\n";
    assert_eq!(
        load_files(TWO, &[("main.il", main)]).unwrap_err(),
        [
            format!("main.il:2:1: `S0`: {STEP_RELAY_RULE}"),
            format!("main.il:3:1: `K4S16`: {STEP_RELAY_RULE}"),
            format!("main.il:4:1: `S2Z1`: {STEP_RELAY_RULE}"),
        ]
    );
    // The same rule for one file on its own (`softplc run`/`check`).
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("main.il");
    std::fs::write(&path, main).unwrap();
    let fallback = softplc_core::profile::find("Q06HCPU").unwrap();
    let d = softplc_core::program::load_single_or(&path, None, fallback).unwrap_err();
    assert_eq!(d.0.len(), 3);
    assert!(
        d.0[0].message.contains("step relay S"),
        "{}",
        d.0[0].message
    );
}

#[test]
fn sfc_programs_are_not_accepted() {
    // An SFC program's devices (block BL, transition TR) are no devices of
    // a sequence program: such a file does not load.
    let main = "LD SM400\nLD BL1\\S0\nOUT Y0\nEND\n";
    let e = load_files(TWO, &[("main.il", main)]).unwrap_err();
    assert!(e[0].starts_with("main.il:2:"), "{e:?}");
}
