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
    // MC: while N0 is OFF the interpreter runs the MC and everything up to
    // MCR (native code runs only while no MC forces conditions OFF), then
    // native code takes over again after MCR.
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
    // One run of 33: MC and MCR have native code too (MC ON sets its bit;
    // OFF, the interpreter runs it); END is interpreted.
    assert_eq!((stats.native_ops, stats.ops), (33, 34), "{stats:?}");
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

#[test]
fn timers_counters_and_word_instructions_run_as_native_code() {
    let src = "\
LD X0
OUTH T0 K3
LD T0
OUT C0 K2
LD X1
RST T0
RST C0
LD SM400
INC D0
+ D0 K10 D1
D+ K100000 D6 D6
WAND H0F D1 D3
WOR H100 D3
BSET D4 K3
BRST D4 K0
LD X2
MC N0 M100
LD SM400
OUT Y0
MCR N0
END
";
    let [mut interp, mut jit] = both(src, softplc_core::profile::default_config());
    // Every op but END has native code.
    let stats = jit.cpu.use_tier(&Jit::with_min_run(1)).unwrap().clone();
    assert_eq!(stats.native_ops, stats.ops - 1, "{stats:?}");
    for p in [&mut interp, &mut jit] {
        // 10 ms scans: the high-speed timer (10 ms) counts 1 a scan from
        // the scan after its coil turned ON, and is up at 3.
        p.set("X0", "1");
        let mut counts = vec![];
        for _ in 0..5 {
            p.scan();
            counts.push((p.int("TN0"), p.bit("TS0"), p.int("CN0")));
        }
        assert_eq!(
            counts,
            [
                (0, false, 0),
                (1, false, 0),
                (2, false, 0),
                (3, true, 1),
                (3, true, 1)
            ]
        );
        // INC, then D1 = D0 + 10 (16 bits), D6 += 100,000 (32 bits) each scan.
        assert_eq!(
            (p.int("D0"), p.int("D1"), p.int("D6:i32")),
            (5, 15, 500_000)
        );
        // D3 = (15 AND H0F) OR H100; D4 = bit 3 set, bit 0 cleared.
        assert_eq!((p.int("D3"), p.int("D4")), (0x10F, 8));
        // MC N0 OFF: the coil inside is OFF.
        assert!(!p.bit("Y0") && !p.bit("M100"));
        // RST after the timer and counter in the same scan: both 0 and OFF
        // at END; the timer then counts again from 0.
        p.set("X1", "1").scan();
        assert_eq!((p.int("TN0"), p.bit("TS0"), p.int("CN0")), (0, false, 0));
        p.set("X1", "0").scan();
        assert_eq!((p.int("TN0"), p.bit("TS0")), (1, false));
        // MC N0 ON: the coil follows its condition.
        p.set("X2", "1").scan();
        assert!(p.bit("Y0") && p.bit("M100"));
    }
}

#[test]
fn a_negative_set_value_in_a_word_is_4100_on_native_code() {
    // OUT T0 D0 and OUT C0 D1 with D0 = -1: the timer's step faults
    // (operation error, 4100); the counter never runs.
    let src = "\
LD SM400
MOV K-1 D0
LD X0
OUT T0 D0
OUT C0 D1
END
";
    each(src, |p| {
        p.scan();
        common::assert_running(p);
        p.set("X0", "1").scan();
        assert_stopped(p, 4100);
        assert_eq!(p.cpu.error().unwrap().line, Some(4));
    });
}

#[test]
fn words_held_in_registers_follow_what_conditional_instructions_wrote() {
    // Each word is read (compare) before a conditional instruction writes
    // it and read again after: native code holds it in a register across
    // the condition and must take what the instruction left, ON or OFF.
    let src = "\
LD= D0 K0
OUT M0
LD= D1 K0
OUT M1
LD= D2 K0
OUT M2
LD= D3 K0
OUT M3
LD= TN0 K0
OUT M4
LD X0
MOV K5 D0
+ D1 K7 D1
BSET D2 K1
INC D3
RST T0
LD= D0 K5
OUT Y0
LD= D1 K7
OUT Y1
LD= D2 K2
OUT Y2
LD= D3 K1
OUT Y3
LD= TN0 K0
OUT Y4
LD SM400
MOV D3 D4
MOV D4 D5
MOV D5 D6
LD= D6 K1
OUT Y5
LD X1
OUT T0 K100
END
";
    each(src, |p| {
        // The timer at 1 (100 ms scans), the RST off.
        p.scan_time_us(100_000).set("X1", "1").scans(2);
        assert_eq!(p.int("TN0"), 1);
        p.scan();
        // X0 OFF: nothing written; D0-D3 are 0, TN0 is 2 at the compare.
        assert_eq!(common::outputs(p, 6), "000000");
        p.set("X0", "1").scan();
        // X0 ON: D0 = 5, D1 = 7, D2 = 2, D3 = 1; RST T0 clears TN0 before
        // LD= TN0 K0 (the OUT T0 after it counts again); the chain D3 → D6.
        assert_eq!(common::outputs(p, 6), "111111");
        assert_eq!((p.int("D4"), p.int("D5"), p.int("D6")), (1, 1, 1));
    });
}

#[test]
fn a_program_of_many_chunks_compiled_on_several_threads() {
    // 11,000 dependent MOVs and 200 timers: several chunks of native code
    // (compiled on as many threads as the machine has), run in order.
    let mut src = String::from("LD SM400\nMOV K7 D0\n");
    for i in 0..11_000 {
        src.push_str(&format!("MOV D{i} D{}\n", i + 1));
    }
    for i in 0..200 {
        src.push_str(&format!("LD X1\nOUT T{i} K{}\n", i + 1));
    }
    src.push_str("END\n");
    let [mut interp, mut jit] = both(&src, softplc_core::profile::default_config());
    let stats = jit.cpu.use_tier(&Jit::with_min_run(1)).unwrap().clone();
    assert_eq!(stats.native_ops, stats.ops - 1, "{stats:?}");
    for p in [&mut interp, &mut jit] {
        p.scan();
        assert_eq!((p.int("D5000"), p.int("D11000")), (7, 7));
        // 10 ms scans with X1 ON: the 100 ms timers count from the scan
        // after their coil turned ON, 200 ms after 21 scans: T0 (K1) and
        // T1 (K2) are up, T2 (K3) at 2, T199 at 2.
        p.set("X1", "1").scans(21);
        let t = |p: &Plc, i: u32| (p.int(&format!("TN{i}")), p.bit(&format!("TS{i}")));
        assert_eq!(
            [t(p, 0), t(p, 1), t(p, 2), t(p, 199)],
            [(1, true), (2, true), (2, false), (2, false)]
        );
    }
}
