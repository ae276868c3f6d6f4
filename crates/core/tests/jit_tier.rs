//! The native-code tier (issue #17) keeps the interpreter's MELSEC behaviour:
//! native regions really run (the CPU reports native ops), and faults with
//! their step numbers, 4101 index range checks, the watchdog on backward
//! jumps, edge memories, master control and the stacks are the same on both
//! tiers. Every program here runs on both and the values are worked out by
//! hand.

mod common;

use std::time::Duration;

use common::{assert_stopped, Plc};
use softplc_core::engine::{CpuConfig, CpuState};
use softplc_core::tier::{apply, Exec, Jit};

/// `src` on the interpreter and on the JIT (which must compile some of it),
/// with native code for every op that can have it, however short the run
/// (`Jit::with_min_run(1)`), so these short programs cross between native
/// code and the interpreter as often as they can.
fn both(src: &str, cfg: CpuConfig) -> [Plc; 2] {
    let mut interp = Plc::with_config(src, cfg.clone());
    apply(&mut interp.cpu, Exec::Interp).unwrap();
    let mut jit = Plc::with_config(src, cfg);
    let stats = jit.cpu.use_tier(&Jit::with_min_run(1)).unwrap().clone();
    assert_eq!(stats.tier, "jit");
    assert!(stats.native_ops > 0, "{stats:?}");
    [interp, jit]
}

fn each(src: &str, f: impl Fn(&mut Plc)) {
    for mut p in both(src, softplc_core::profile::default_config()) {
        f(&mut p);
    }
}

#[test]
fn contacts_blocks_and_mps_on_native_code() {
    // Y0 = (X0 & !X1) | X2;  Y1 = (X0 | X1) & (X2 | X3);  MPS branches: Y2 = X0 & X4, Y3 = X0 & !X4.
    let src = "\
LD X0
ANI X1
OR X2
OUT Y0
LD X0
OR X1
LD X2
OR X3
ANB
OUT Y1
LD X0
MPS
AND X4
OUT Y2
MPP
ANI X4
OUT Y3
END
";
    each(src, |p| {
        // X0=1 X1=0 X2=0 X3=1 X4=0
        common::inputs(p, "10010");
        p.scan();
        assert_eq!(common::outputs(p, 4), "1101");
        common::inputs(p, "01100");
        p.scan();
        assert_eq!(common::outputs(p, 4), "1100");
        common::inputs(p, "10001");
        p.scan();
        assert_eq!(common::outputs(p, 4), "1010");
    });
}

#[test]
fn set_rst_and_mov_runs_follow_the_condition() {
    let src = "\
LD X0
SET M0
LD X1
RST M0
LD X0
MOV K7 D0
MOV D0 D1
DMOV K100000 D2
LD= D1 K7
OUT Y0
LDD> D2 K99999
OUT Y1
END
";
    each(src, |p| {
        p.scan();
        assert!(!p.bit("M0"));
        assert_eq!(p.int("D1"), 0);
        assert!(!p.bit("Y0"));
        p.set("X0", "1").scan();
        assert!(p.bit("M0"));
        assert_eq!((p.int("D0"), p.int("D1"), p.int("D2:i32")), (7, 7, 100000));
        assert!(p.bit("Y0") && p.bit("Y1"));
        // SET holds with its condition OFF; RST clears.
        p.set("X0", "0").set("X1", "1").scan();
        assert!(!p.bit("M0"));
        p.set("X1", "0").scan();
        assert!(!p.bit("M0"));
    });
}

#[test]
fn index_out_of_range_is_4101_at_the_faulting_step() {
    // With Z0 = 20000, D0Z0 is D20000, past the 12288 D points: 4101 at the
    // second MOV (op 3, line 4), whose LD before it ran natively.
    let src = "\
LD SM400
MOV K20000 Z0
LD SM400
MOV K1 D0Z0
OUT Y0
END
";
    each(src, |p| {
        p.scan();
        assert_stopped(p, 4101);
        let e = p.cpu.error().unwrap();
        assert_eq!(e.step, Some(p.cpu.program().op_step[3]));
        assert_eq!(e.line, Some(4));
    });
}

#[test]
fn watchdog_stops_an_endless_loop_on_both_tiers() {
    let cfg = CpuConfig {
        watchdog: Duration::from_millis(20),
        ..softplc_core::profile::default_config()
    };
    for mut p in both("P0\nLD SM400\nOUT M0\nJMP P0\nEND\n", cfg) {
        p.scan();
        assert_stopped(&p, 5000);
    }
}

#[test]
fn edges_between_native_regions() {
    // LDP and the pulse form run in the interpreter; the coils around them natively.
    let src = "\
LDP X0
OUT Y0
LD X0
INCP D0
LD X0
OUT Y1
END
";
    each(src, |p| {
        p.set("X0", "1").scan();
        assert!(p.bit("Y0") && p.bit("Y1"));
        assert_eq!(p.int("D0"), 1);
        p.scan();
        assert!(!p.bit("Y0") && p.bit("Y1"));
        assert_eq!(p.int("D0"), 1);
        p.set("X0", "0").scan();
        p.set("X0", "1").scan();
        assert_eq!(p.int("D0"), 2);
    });
}

#[test]
fn master_control_nesting_turns_native_coils_off() {
    let src = "\
LD X0
MC N0 M100
LD SM400
OUT Y0
LD X1
MC N1 M101
LD SM400
OUT Y1
MOV K5 D0
MCR N1
LD SM400
OUT Y2
MCR N0
LD SM400
OUT Y3
END
";
    each(src, |p| {
        common::inputs(p, "11");
        p.scan();
        assert_eq!(common::outputs(p, 4), "1111");
        assert_eq!(p.int("D0"), 5);
        p.set("D0", "0");
        common::inputs(p, "10");
        p.scan();
        // N1 OFF: Y1 OFF, MOV not executed.
        assert_eq!(common::outputs(p, 4), "1011");
        assert_eq!(p.int("D0"), 0);
        common::inputs(p, "01");
        p.scan();
        assert_eq!(common::outputs(p, 4), "0001");
        assert_eq!(p.state(), CpuState::Run);
    });
}

#[test]
fn for_next_and_jumps_reenter_native_code() {
    // FOR 4 times: D0 += 1 and Y0 ON; CJ skips OUT Y1 while X0 is ON.
    let src = "\
FOR K4
LD SM400
INC D0
OUT Y0
NEXT
LD X0
CJ P1
LD SM400
OUT Y1
P1
LD SM400
OUT Y2
END
";
    each(src, |p| {
        p.scan();
        assert_eq!(p.int("D0"), 4);
        assert_eq!(common::outputs(p, 3), "111");
        p.set("Y1", "0").set("X0", "1").scan();
        assert_eq!(p.int("D0"), 8);
        assert_eq!(common::outputs(p, 3), "101");
    });
}

#[test]
fn exec_choice_interp_leaves_no_native_code() {
    let rungs = "LD X0\nAND X1\nOR X2\nANI X3\nOUT Y0\nLD X4\nOUT Y1\nOUT Y2\n";
    let mut p = Plc::new(&format!("{rungs}END\n"));
    assert_eq!(apply(&mut p.cpu, Exec::Interp).unwrap(), None);
    assert!(p.cpu.tier_stats().is_none());
    let s = apply(&mut p.cpu, Exec::Jit).unwrap().unwrap();
    // Eight contacts and coils native; END interpreted.
    assert_eq!((s.ops, s.native_ops), (9, 8));
    assert_eq!(p.cpu.tier_stats(), Some(&s));
    // Two native ops between interpreted ones do not pay for the call
    // between them: the interpreter runs them.
    let mut p = Plc::new("LD X0\nOUT Y0\nLDP X1\nOUT Y1\nEND\n");
    let s = apply(&mut p.cpu, Exec::Jit).unwrap().unwrap();
    assert_eq!((s.ops, s.native_ops), (5, 0));
}

#[test]
fn master_control_off_hands_the_rest_to_the_interpreter_until_mcr() {
    // Long native runs (the shipped minimum run) before, inside and after an
    // MC: while N0 is OFF the interpreter runs everything up to MCR (native
    // code runs only while no MC forces conditions OFF), then native code
    // takes over again after MCR.
    let run = |coils: &[&str]| -> String {
        coils
            .iter()
            .map(|c| format!("LD X1\nAND SM400\nOR M50\nANI M51\nOUT {c}\n"))
            .collect()
    };
    let src = format!(
        "{}LD X0\nMC N0 M100\n{}MCR N0\n{}END\n",
        run(&["M0", "M1"]),
        run(&["Y0", "Y1"]),
        run(&["Y2", "Y3"])
    );
    let mut interp = Plc::new(&src);
    apply(&mut interp.cpu, Exec::Interp).unwrap();
    let mut jit = Plc::new(&src);
    let stats = jit.cpu.use_tier(&Jit::default()).unwrap().clone();
    // Runs of 11 (with MC's LD X0), 10 and 10; MC, MCR and END are
    // interpreted.
    assert_eq!((stats.native_ops, stats.ops), (31, 34), "{stats:?}");
    for p in [&mut interp, &mut jit] {
        p.set("Y0", "1").set("X1", "1").scan();
        // N0 OFF: Y0/Y1 OFF (were ON), M and Y2/Y3 follow X1.
        assert_eq!(common::outputs(p, 4), "0011");
        assert!(p.bit("M0") && p.bit("M1") && !p.bit("M100"));
        p.set("X0", "1").scan();
        assert_eq!(common::outputs(p, 4), "1111");
        p.set("X1", "0").scan();
        assert_eq!(common::outputs(p, 4), "0000");
        assert!(!p.bit("M0") && p.bit("M100"));
    }
}

#[test]
fn the_last_bits_of_memory_on_native_code() {
    // FY is the last bit device: native code reads a bit four bytes wide
    // only where the three bytes after it are still memory.
    let src = "\
LD X0
OR FY0F
ANI FY0D
OUT FY0E
LD FY0E
SET FY0F
LD X1
RST FY0F
LD FY0F
OUT Y0
END
";
    each(src, |p| {
        p.set("X0", "1").scan();
        assert!(p.bit("FY0E") && p.bit("FY0F") && p.bit("Y0"));
        p.set("X0", "0").set("X1", "1").scan();
        // FY0E from FY0F (still ON); FY0F SET, then RST; Y0 from FY0F.
        assert!(p.bit("FY0E") && !p.bit("FY0F") && !p.bit("Y0"));
        p.set("X1", "0").scan();
        assert!(!p.bit("FY0E") && !p.bit("FY0F") && !p.bit("Y0"));
    });
}
