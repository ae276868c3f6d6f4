//! Golden tests for program control (CJ/SCJ/JMP/GOEND, CALL/RET, FOR/NEXT/BREAK,
//! pulse forms), run-time errors and STOP. Expected values are worked out by
//! hand in the comments. Step numbers follow
//! each definition's step rule (`softplc_lang::isa::Steps`): contacts and coils 1 step,
//! PLS/PLF/FF/MC 2, OUT T/C 4, any other instruction 1 + its operand count
//! (CJ P1 = 2, FOR K2 = 2, MOV K1 D0 = 3, `/ D0 K0 D10` = 4).

mod common;
use std::time::Duration;

use common::{assert_stopped, Plc};
use softplc_core::engine::{CpuConfig, CpuState, ErrorCode, ErrorMode};

/// The step and source line of the latest error.
fn error_at(p: &Plc) -> (Option<u32>, Option<u32>) {
    let e = p.cpu.error().expect("an error");
    (e.step, e.line)
}

// ---------------------------------------------------------------- jumps

#[test]
fn cj_skips_rungs_coils_keep_state() {
    let mut p = Plc::new(
        "\
LD X0
CJ P1
LD X1
OUT Y0
P1
LD X1
OUT Y1
END
",
    );
    // No jump: Y0 = Y1 = X1.
    p.set("X1", "1").scan();
    assert!(p.bit("Y0") && p.bit("Y1"));
    // Jump: OUT Y0 is not executed, so Y0 keeps ON although X1 is OFF.
    p.set("X0", "1").set("X1", "0").scan();
    assert!(p.bit("Y0"));
    assert!(!p.bit("Y1"));
    // No jump again: Y0 follows X1 (OFF).
    p.set("X0", "0").scan();
    assert!(!p.bit("Y0"));
}

#[test]
fn cj_over_a_running_timer_stops_its_update() {
    let mut p = Plc::new(
        "\
LD X0
CJ P1
LD X1
OUTH T0 K100
P1
END
",
    );
    // 10 ms base, 10 ms scans: 0, 1, 2.
    p.set("X1", "1").scans(3);
    assert_eq!(p.int("TN0"), 2);
    // OUT T0 skipped by CJ: not updated (004 L6500-6502).
    p.set("X0", "1").scans(4);
    assert_eq!(p.int("TN0"), 2);
    // Executed again with the coil still ON: adds the last scan time (10 ms).
    p.set("X0", "0").scan();
    assert_eq!(p.int("TN0"), 3);
}

#[test]
fn jmp_is_unconditional() {
    let mut p = Plc::new(
        "\
JMP P1
LD SM400
OUT Y0
P1
LD SM400
OUT Y1
END
",
    );
    p.scans(2);
    assert!(!p.bit("Y0"));
    assert!(p.bit("Y1"));
}

#[test]
fn scj_jumps_from_the_next_scan() {
    let mut p = Plc::new(
        "\
LD X0
SCJ P1
LD SM400
INC D0
P1
LD SM400
INC D1
END
",
    );
    p.scan();
    assert_eq!((p.int("D0"), p.int("D1")), (1, 1));
    // X0 turns ON: no jump in that scan (D0 = 2), jumps from the next (D0 stays).
    p.set("X0", "1").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (2, 2));
    p.scans(2);
    assert_eq!((p.int("D0"), p.int("D1")), (2, 4));
    // X0 OFF: no jump.
    p.set("X0", "0").scan();
    assert_eq!(p.int("D0"), 3);
    // ON again: again one scan without the jump first.
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 4);
    p.scan();
    assert_eq!(p.int("D0"), 4);
}

#[test]
fn goend_skips_to_end() {
    let mut p = Plc::new(
        "\
LD X0
GOEND
LD SM400
INC D0
END
",
    );
    p.scans(3);
    assert_eq!(p.int("D0"), 3);
    p.set("X0", "1").scans(2);
    assert_eq!(p.int("D0"), 3);
    assert_eq!(p.state(), CpuState::Run);
    p.set("X0", "0").scan();
    assert_eq!(p.int("D0"), 4);
}

// ---------------------------------------------------------------- subroutines

#[test]
fn call_ret_and_callp() {
    let mut p = Plc::new(
        "\
LD X0
CALL P10
LD X1
CALLP P11
FEND
P10
LD SM400
INC D0
RET
P11
LD SM400
INC D1
RET
END
",
    );
    // The subroutines after FEND run only when called.
    p.scans(2);
    assert_eq!((p.int("D0"), p.int("D1")), (0, 0));
    // CALL every scan while X0 is ON: 3 scans → 3.
    p.set("X0", "1").scans(3);
    assert_eq!(p.int("D0"), 3);
    p.set("X0", "0").scan();
    assert_eq!(p.int("D0"), 3);
    // CALLP once per rising edge of X1: 3 scans ON → 1; OFF, ON → 2.
    p.set("X1", "1").scans(3);
    assert_eq!(p.int("D1"), 1);
    p.set("X1", "0").scan();
    p.set("X1", "1").scans(2);
    assert_eq!(p.int("D1"), 2);
    assert_eq!(p.state(), CpuState::Run);
}

#[test]
fn nested_call_two_levels() {
    let mut p = Plc::new(
        "\
LD SM400
CALL P10
LD SM400
MOV D2 D3
FEND
P10
LD SM400
MOV K1 D0
LD SM400
CALL P20
LD SM400
MOV D1 D2
RET
P20
LD SM400
MOV K7 D1
RET
END
",
    );
    // main → P10 (D0 = 1) → P20 (D1 = 7) → back into P10 after its CALL
    // (D2 = D1 = 7) → back into main after its CALL (D3 = D2 = 7), in one scan.
    p.scan();
    assert_eq!(
        [p.int("D0"), p.int("D1"), p.int("D2"), p.int("D3")],
        [1, 7, 7, 7]
    );
    assert_eq!(p.state(), CpuState::Run);
}

// ---------------------------------------------------------------- FOR/NEXT

#[test]
fn for_next_counts() {
    let mut p = Plc::new(
        "\
FOR K10
LD SM400
INC D0
NEXT
FOR K0
LD SM400
INC D1
NEXT
FOR K-5
LD SM400
INC D2
NEXT
FOR K3
FOR K4
LD SM400
INC D3
NEXT
LD SM400
INC D4
NEXT
FOR D10
LD SM400
INC D5
NEXT
END
",
    );
    p.set("D10", "6");
    // Per scan: 10; K0 and K-5 run once; 3 × 4 = 12 inner and 3 outer; D10 = 6.
    p.scan();
    assert_eq!(
        [
            p.int("D0"),
            p.int("D1"),
            p.int("D2"),
            p.int("D3"),
            p.int("D4"),
            p.int("D5")
        ],
        [10, 1, 1, 12, 3, 6]
    );
    p.scan();
    assert_eq!(
        [
            p.int("D0"),
            p.int("D1"),
            p.int("D2"),
            p.int("D3"),
            p.int("D4"),
            p.int("D5")
        ],
        [20, 2, 2, 24, 6, 12]
    );
    assert_eq!(p.state(), CpuState::Run);
}

#[test]
fn break_ends_the_loop() {
    let mut p = Plc::new(
        "\
LD SM400
MOV K0 D0
FOR K10
LD SM400
INC D0
LD= D0 K4
BREAK D1 P1
NEXT
LD SM400
MOV K99 D2
P1
LD SM400
INC D3
END
",
    );
    // Passes 1-3 complete (NEXT three times); in pass 4 D0 = 4 and BREAK stores
    // the repetitions left, the interrupted pass included: 10 - 3 = 7, then
    // jumps to P1, skipping MOV K99 D2. The loop is closed: no FOR error at END.
    p.scan();
    assert_eq!(p.int("D0"), 4);
    assert_eq!(p.int("D1"), 7);
    assert_eq!(p.int("D2"), 0);
    assert_eq!(p.int("D3"), 1);
    assert_eq!(p.state(), CpuState::Run);
    p.scan();
    assert_eq!(p.int("D3"), 2);
    assert_eq!(p.state(), CpuState::Run);
}

// ---------------------------------------------------------------- pulse forms

#[test]
fn pulse_instructions_once_per_rising_edge() {
    let mut p = Plc::new(
        "\
LD X0
INCP D0
LD X0
MOVP D0 D1
END
",
    );
    // X0 ON for 3 scans: INCP once → D0 = 1, MOVP once → D1 = 1.
    p.set("X0", "1").scans(3);
    assert_eq!((p.int("D0"), p.int("D1")), (1, 1));
    // X0 still ON: neither runs, so D1 does not follow D0.
    p.set("D0", "9").scan();
    assert_eq!((p.int("D0"), p.int("D1")), (9, 1));
    // OFF, then ON: both run once more: D0 = 10, D1 = 10.
    p.set("X0", "0").scan();
    p.set("X0", "1").scans(2);
    assert_eq!((p.int("D0"), p.int("D1")), (10, 10));
}

// ---------------------------------------------------------------- errors

#[test]
fn next_without_for_at_run_time() {
    let mut p = Plc::new(
        "\
LD SM400
CJ P1
FOR K2
P1
NEXT
END
",
    );
    // CJ jumps over FOR to NEXT: NEXT without FOR, 4201.
    // Steps: LD 0, CJ 1-2, FOR 3-4, NEXT 5 (line 5).
    p.scan();
    assert_stopped(&p, 4201);
    assert_eq!(error_at(&p), (Some(5), Some(5)));
}

#[test]
fn call_nesting_sixteen_ok_seventeen_fails() {
    let prog = |limit: u32| {
        format!(
            "\
LD SM400
MOV K0 D0
LD SM400
CALL P0
FEND
P0
LD SM400
INC D0
LD< D0 K{limit}
CALL P0
RET
END
"
        )
    };
    // The subroutine at depth n has D0 = n and calls itself while D0 < limit.
    // limit 16: the deepest level is 16 (allowed), D0 = 16.
    let mut p = Plc::new(&prog(16));
    p.scan();
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("D0"), 16);
    // limit 17: at depth 16 (D0 = 16 < 17) the 17th CALL fails with 4213.
    // Steps: LD 0, MOV 1-3, LD 4, CALL 5-6, FEND 7, LD 8, INC 9-10,
    // LD< 11-13, CALL 14 (line 10).
    let mut p = Plc::new(&prog(17));
    p.scan();
    assert_stopped(&p, 4213);
    assert_eq!(p.int("D0"), 16);
    assert_eq!(error_at(&p), (Some(14), Some(10)));
}

#[test]
fn ret_in_main_program() {
    let mut p = Plc::new(
        "\
LD X0
OUT Y0
RET
END
",
    );
    // RET executed in the main routine: 4212 at step 2 (LD 0, OUT 1, RET 2).
    p.set("X0", "1").scan();
    assert_stopped(&p, 4212);
    assert!(p.bit("Y0"), "OUT Y0 ran before the error");
    assert_eq!(error_at(&p), (Some(2), Some(3)));
}

#[test]
fn subroutine_without_ret() {
    let mut p = Plc::new(
        "\
LD SM400
CALL P0
FEND
P0
LD SM400
INC D0
END
",
    );
    // The subroutine runs (D0 = 1) into END without RET: 4211.
    p.scan();
    assert_stopped(&p, 4211);
    assert_eq!(p.int("D0"), 1);
}

#[test]
fn for_without_next_at_run_time() {
    let mut p = Plc::new(
        "\
FOR K3
LD SM400
INC D0
LD SM400
CJ P1
NEXT
P1
END
",
    );
    // CJ leaves the loop in its first pass (D0 = 1); END is reached with the
    // FOR still open: 4200.
    p.scan();
    assert_stopped(&p, 4200);
    assert_eq!(p.int("D0"), 1);
}

#[test]
fn break_without_for() {
    let mut p = Plc::new(
        "\
LD SM400
BREAK D0 P1
P1
END
",
    );
    // BREAK outside any FOR: 4203 at step 1 (line 2).
    p.scan();
    assert_stopped(&p, 4203);
    assert_eq!(error_at(&p), (Some(1), Some(2)));
}

#[test]
fn index_out_of_range_word() {
    let mut p = Plc::new(
        "\
LD SM400
MOV K5 Z0
LD SM400
MOV K1 D12287Z0
LD SM400
OUT Y1
END
",
    );
    // D12287 is the last D (12288 points); with Z0 = 5 it is D12292: 4101.
    // Steps: LD 0, MOV 1-3, LD 4, MOV 5 (line 4). The CPU stops at the point of
    // detection, so OUT Y1 does not run. SD14 holds the step (App. 2).
    p.scan();
    assert_stopped(&p, 4101);
    assert_eq!(error_at(&p), (Some(5), Some(4)));
    assert_eq!(p.int("SD14"), 5);
    assert!(!p.bit("Y1"));
    // STOP: further scans do nothing.
    p.scans(3);
    assert!(!p.bit("Y1"));
    assert_eq!(p.state(), CpuState::Stop);
}

#[test]
fn index_out_of_range_bit() {
    let mut p = Plc::new(
        "\
LD SM400
MOV K-1 Z0
LD SM400
OUT Y0Z0
END
",
    );
    // Y0Z0 with Z0 = -1 is Y(-1), below the first Y: 4101.
    // Steps: LD 0, MOV 1-3, LD 4, OUT Y0Z0 5 (line 4).
    p.scan();
    assert_stopped(&p, 4101);
    assert_eq!(error_at(&p), (Some(5), Some(4)));
}

#[test]
fn division_by_zero_stops() {
    let mut p = Plc::new(
        "\
LD SM400
/ D0 K0 D10
LD SM400
MOV K7 D20
END
",
    );
    // Division by 0: OPERATION ERROR 4100 at step 1 (line 2); default mode stop,
    // so MOV K7 D20 does not run.
    p.scan();
    assert_stopped(&p, 4100);
    assert_eq!(error_at(&p), (Some(1), Some(2)));
    assert_eq!(p.int("D20"), 0);
}

#[test]
fn division_by_zero_continue_mode() {
    let cfg = CpuConfig {
        operation_error: ErrorMode::Continue,
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config(
        "\
LD SM400
/ D0 K0 D10
LD SM400
MOV K7 D20
END
",
        cfg,
    );
    p.set("D10", "123");
    // Continue: the failing instruction is skipped (D10 unchanged), the next
    // runs (D20 = 7), the CPU stays in RUN; SD0 = 4100, SM0/SM1 and SM56
    // (operation error) ON.
    p.scan();
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.error(), Some(ErrorCode(4100)));
    assert_eq!(p.int("SD0"), 4100);
    assert!(p.bit("SM0") && p.bit("SM1") && p.bit("SM56"));
    assert_eq!(p.int("D10"), 123);
    assert_eq!(p.int("D20"), 7);
    assert_eq!(error_at(&p), (Some(1), Some(2)));
    // And the next scans keep running.
    p.set("D20", "0").scan();
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("D20"), 7);
}

#[test]
fn watchdog_error_on_endless_loop() {
    let cfg = CpuConfig {
        watchdog: Duration::from_millis(20),
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config(
        "\
P0
JMP P0
END
",
        cfg,
    );
    // The scan never reaches END: WDT ERROR 5000 (004 L4858-4862).
    p.scan();
    assert_stopped(&p, 5000);
}

#[test]
fn stop_instruction() {
    let mut p = Plc::new(
        "\
LD SM400
OUT Y0
LD SM400
INC D0
LD X0
STOP
LD SM400
OUT Y1
END
",
    );
    p.scan();
    assert_eq!(p.state(), CpuState::Run);
    assert!(p.cpu.output(0));
    // STOP: the scan runs to its END (OUT Y1 after STOP still executes), then
    // the CPU is in STOP. The Y0 device keeps its state, the output is OFF.
    p.set("X0", "1").scan();
    assert_eq!(p.state(), CpuState::Stop);
    assert!(p.bit("Y1"));
    assert!(p.bit("Y0"));
    assert!(!p.cpu.output(0));
    assert_eq!(p.int("D0"), 2);
    // In STOP the program no longer runs.
    p.scans(3);
    assert_eq!(p.int("D0"), 2);
}
