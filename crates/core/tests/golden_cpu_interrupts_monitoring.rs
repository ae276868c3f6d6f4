//! CPU functions (004 ch. 4 and 7): program execution types, operating states,
//! latch, initial values. Expected values are worked out from the manual's rules
//! in the comments.
//!
//! This file: interrupts, annunciators, the error history, sampling trace,
//! program/interrupt monitor lists and the timing instructions (ANS/ANR, DUTY).

mod common;
use std::time::Duration;

use common::Plc;
use softplc_core::access::DeviceSpec;
use softplc_core::engine::{CpuConfig, CpuState, ExecType};

const INTERRUPTS: &str = "\
LD SM402
EI
LD X0
DI
LDI X0
EI
LD SM400
MOV K7 Z0
FEND
I31
LD SM400
INC D10
MOV K99 Z0
IRET
I28
LD SM400
INC D20
IRET
END
";

#[test]
fn fixed_cycle_interrupts() {
    // I31 every 10 ms, I28 every 100 ms (defaults, 004 L1056). Power-on at 0:
    // the first I31 occurs at 10 ms, before EI has run in scan 1, so it is
    // remembered and runs at the next check together with the 20 ms one.
    let mut p = Plc::new(INTERRUPTS);
    p.scan();
    assert_eq!(p.int("D10"), 0);
    assert!(p.bit("SM715"));
    p.scan();
    assert_eq!(p.int("D10"), 2);
    p.scans(8);
    // 100 ms: I31 ran for 10..=100 ms (10 times), I28 once.
    assert_eq!((p.int("D10"), p.int("D20")), (10, 1));
    // Z0 is saved and restored around the interrupt program.
    assert_eq!(p.int("Z0"), 7);
    // DI: occurrences are remembered once, not counted.
    p.set("X0", "1").scans(5);
    assert_eq!(
        p.int("D10"),
        11,
        "the 110 ms occurrence ran before DI took effect"
    );
    p.set("X0", "0").scan();
    // EI in that scan; the remembered cause runs at the next check with the new one.
    p.scan();
    assert_eq!(p.int("D10"), 13);
}

#[test]
fn imask_disables_one_interrupt() {
    // IMASK D100: bit 15 of the second word (I31) cleared → only I28 runs.
    let src = INTERRUPTS.replacen(
        "LD SM402\nEI\n",
        "LD SM402\nFMOVX\nMOV H7FFF D101\nIMASK D100\nEI\n",
        1,
    );
    let src = src.replace(
        "FMOVX\n",
        &(0..16)
            .map(|k| format!("MOV HFFFF D{}\n", 100 + k))
            .collect::<String>(),
    );
    let mut p = Plc::new(&src);
    p.scans(20);
    assert_eq!((p.int("D10"), p.int("D20")), (0, 2));
    assert_eq!(p.int("SD716:u16"), 0x7FFF);
}

#[test]
fn interrupt_program_without_iret_is_4221() {
    let mut p = Plc::new("LD SM400\nEI\nFEND\nI31\nLD SM400\nINC D0\nEND\n");
    p.scans(3);
    assert_eq!(p.state(), CpuState::Stop);
    assert_eq!(p.int("SD0"), 4221);
}

#[test]
fn annunciators_follow_the_manual_example() {
    // qcpu.md §9 item 9: SET F50, F25, F99; RST F25; SET F15, F70, F65, F38, F110,
    // F151, F210; LEDR.
    let mut src = String::new();
    for (i, f) in [50, 25, 99].iter().enumerate() {
        src += &format!("LD M{i}\nSET F{f}\n");
    }
    src += "LD M3\nRST F25\n";
    for (i, f) in [15, 70, 65, 38, 110, 151, 210].iter().enumerate() {
        src += &format!("LD M{}\nSET F{f}\n", 10 + i);
    }
    src += "LD M20\nLEDR\nEND\n";
    let mut p = Plc::new(&src);
    for m in ["M0", "M1", "M2", "M3"] {
        p.set(m, "1").scan().set(m, "0");
    }
    // After RST F25: SD62=50, SD63=2, list 50, 99.
    assert_eq!(
        (p.int("SD62"), p.int("SD63"), p.int("SD64"), p.int("SD65")),
        (50, 2, 50, 99)
    );
    assert!(p.bit("SM62"));
    // F**** is a continuation error: SD0 = 9000, the CPU runs on.
    assert_eq!(p.int("SD0"), 9000);
    assert_eq!(p.state(), CpuState::Run);
    for k in 10..17 {
        p.set(&format!("M{k}"), "1")
            .scan()
            .set(&format!("M{k}"), "0");
    }
    let list: Vec<i64> = (64..73).map(|n| p.int(&format!("SD{n}"))).collect();
    assert_eq!(list, [50, 99, 15, 70, 65, 38, 110, 151, 210]);
    assert_eq!(p.int("SD63"), 9);
    p.set("M20", "1").scan();
    let list: Vec<i64> = (64..72).map(|n| p.int(&format!("SD{n}"))).collect();
    assert_eq!(list, [99, 15, 70, 65, 38, 110, 151, 210]);
    assert_eq!((p.int("SD62"), p.int("SD63"), p.int("SD72")), (99, 8, 0));
    assert!(!p.bit("F50"));
    // Every annunciator ON was logged: 3 + 7 entries of 9000.
    let h = p.cpu.error_history();
    assert_eq!(h.len(), 10);
    assert!(h.iter().all(|e| e.code.0 == 9000));
    assert_eq!(h[0].detail, Some(50));
    // SM50 with SD50 = 9000 clears the error registers (lower digits ignored).
    p.set("SD50", "9012").set("SM50", "1").scan();
    assert!(!p.bit("SM0"));
    assert_eq!(p.int("SD0"), 0);
}

#[test]
fn error_history_keeps_the_latest_16_with_time() {
    // Continue mode: every scan's division by zero is logged; 20 scans → 16 kept,
    // stamped with the clock (2000-01-01 00:00:00 + scan time).
    let cfg = CpuConfig {
        operation_error: softplc_core::engine::ErrorMode::Continue,
        ..softplc_core::profile::default_config()
    };
    let mut p = Plc::with_config("LD SM400\n/ K1 K0 D0\nEND\n", cfg);
    p.scan_time_us(1_000_000).scans(20);
    let h = p.cpu.error_history();
    assert_eq!(h.len(), 16);
    assert!(h.iter().all(|e| e.code.0 == 4100 && e.detail == Some(1)));
    // The last entry is scan 20, 20 s after 2000-01-01 00:00:00.
    assert_eq!(h[15].time, 946_684_800 + 20);
    assert_eq!(h[0].time, 946_684_800 + 5);
    // SD1-SD3: BCD time stamp 00-01 / 01 00h / 00:20.
    assert_eq!(
        (p.int("SD1:u16"), p.int("SD2:u16"), p.int("SD3:u16")),
        (0x0001, 0x0100, 0x0020)
    );
}

#[test]
fn sampling_trace_ring_buffer_and_trigger() {
    use softplc_core::engine::trace::{Trace, TraceConfig};
    let spec = |s: &str| DeviceSpec::parse(s).unwrap();
    let mut p = Plc::new("LD SM400\nINC D0\nLD X0\nOUT M0\nEND\n");
    let cfg = TraceConfig {
        devices: vec![spec("D0"), spec("M0")],
        every_scans: 2,
        interval_us: None,
        capacity: 3,
        trigger: Some(spec("X0")),
        after_trigger: 1,
    };
    p.cpu.set_trace(Some(Trace::new(cfg).unwrap()));
    // Samples at END of scans 1, 3, 5, 7 (every 2nd); the ring keeps the last 3.
    p.scans(7);
    let rows: Vec<_> = p
        .cpu
        .trace()
        .unwrap()
        .samples()
        .map(|(scan, t, v)| (scan, t, v[0].clone()))
        .collect();
    assert_eq!(
        rows,
        [
            (3, 30_000, softplc_core::access::Value::Int(3)),
            (5, 50_000, softplc_core::access::Value::Int(5)),
            (7, 70_000, softplc_core::access::Value::Int(7)),
        ]
    );
    assert!(p.bit("SM802") && !p.bit("SM805"));
    // Trigger in scan 8 (X0, M0 ON): one more sample (scan 9), then complete.
    p.set("X0", "1").scans(6);
    let t = p.cpu.trace().unwrap();
    assert!(t.is_complete());
    assert!(p.bit("SM805") && p.bit("SM803"));
    let last: Vec<u64> = t.samples().map(|(scan, _, _)| scan).collect();
    assert_eq!(last, [5, 7, 9]);
    assert_eq!(t.to_csv().lines().next(), Some("scan,time_ms,D0,M0"));
    assert_eq!(t.to_csv().lines().nth(3), Some("9,90,9,1"));
}

#[test]
fn trace_limits() {
    use softplc_core::engine::trace::{Trace, TraceConfig};
    let devices = (0..51)
        .map(|n| DeviceSpec::parse(&format!("M{n}")).unwrap())
        .collect();
    let cfg = TraceConfig {
        devices,
        every_scans: 1,
        interval_us: None,
        capacity: 10,
        trigger: None,
        after_trigger: 0,
    };
    assert!(Trace::new(cfg).unwrap_err().contains("at most 50 bit"));
    let cfg = TraceConfig {
        devices: vec![DeviceSpec::parse("D0").unwrap()],
        every_scans: 1,
        interval_us: None,
        capacity: 8193,
        trigger: None,
        after_trigger: 0,
    };
    assert!(Trace::new(cfg).is_err());
}

#[test]
fn trace_fixed_time_and_sm803_trigger() {
    use softplc_core::engine::trace::{Trace, TraceConfig};
    let mut p = Plc::new("LD SM400\nINC D0\nEND\n");
    let cfg = TraceConfig {
        devices: vec![DeviceSpec::parse("D0").unwrap()],
        every_scans: 1,
        interval_us: Some(25_000),
        capacity: 100,
        trigger: None,
        after_trigger: 2,
    };
    p.cpu.set_trace(Some(Trace::new(cfg).unwrap()));
    // 10 ms scans, a sample at the first END 25 ms after the previous one:
    // ENDs at 10, 40, 70 ms (scans 1, 4, 7).
    p.scans(7);
    let scans: Vec<u64> = p
        .cpu
        .trace()
        .unwrap()
        .samples()
        .map(|(s, _, _)| s)
        .collect();
    assert_eq!(scans, [1, 4, 7]);
    // SM803 ON (user trigger) in scan 8: two more samples (10, 13), then complete.
    p.set("SM803", "1").scans(10);
    let t = p.cpu.trace().unwrap();
    assert!(t.is_complete());
    let scans: Vec<u64> = t.samples().map(|(s, _, _)| s).collect();
    assert_eq!(scans, [1, 4, 7, 10, 13]);
}

#[test]
fn program_and_interrupt_monitor_lists() {
    // 004 §7.11: execution counts per program and per interrupt pointer.
    let mut p = Plc::with_programs(
        &[
            (INTERRUPTS, ExecType::Scan, None),
            (
                "LD SM400\nINC D40\nEND\n",
                ExecType::FixedScan,
                Some(Duration::from_millis(50)),
            ),
        ],
        softplc_core::profile::default_config(),
    );
    p.scans(10);
    let m = p.cpu.program_monitor();
    assert_eq!((m[0].count, m[0].exec), (10, ExecType::Scan));
    assert_eq!((m[1].count, m[1].exec), (2, ExecType::FixedScan));
    assert!(m[0].max >= m[0].last);
    // I31 every 10 ms from 10 ms (the first one after EI in scan 2), I28 at 100 ms.
    let i = p.cpu.interrupt_counts();
    assert_eq!((i[31], i[28], i[29]), (10, 1, 0));
}

#[test]
fn ans_sets_the_annunciator_after_its_time_and_anr_resets_it() {
    // ANS T0 K5 F10: F10 when X0 has been ON for 0.5 s (T0, 100 ms base, counting
    // from the execution after the coil turned ON: scan 51 with 10 ms scans).
    let mut p = Plc::new("LD X0\nANS T0 K5 F10\nLD X1\nANRP\nEND\n");
    p.set("X0", "1").scans(50);
    assert!(!p.bit("F10"));
    p.scan();
    assert!(p.bit("F10"));
    assert_eq!((p.int("SD62"), p.int("SD63")), (10, 1));
    p.set("X0", "0").set("X1", "1").scan();
    assert!(!p.bit("F10"));
    assert_eq!((p.int("SD62"), p.int("SD63")), (0, 0));
}

#[test]
fn duty_user_timing_clock() {
    // DUTY K2 K3 SM420: ON for 2 scans, OFF for 3, counted at END from the END of
    // the scan that executed DUTY. M0 copies SM420 as the program sees it.
    let mut p = Plc::new("LD SM400\nDUTY K2 K3 SM420\nLD SM420\nOUT M0\nEND\n");
    let mut seen = Vec::new();
    for _ in 0..11 {
        p.scan();
        seen.push(p.bit("M0") as u8);
    }
    // Scan 1 sees the power-on OFF; END 1 counts 0 (ON), END 2 count 1 (ON),
    // ENDs 3-5 OFF, ENDs 6-7 ON …; scan k sees END k-1.
    assert_eq!(seen, [0, 1, 1, 0, 0, 0, 1, 1, 0, 0, 0]);
    // DUTY into anything but SM420-424/SM430-434 is a load error.
    let d = common::diagnostics("LD SM400\nDUTY K1 K1 M0\nEND\n");
    assert!(d[0].contains("user timing clock"), "{d:?}");
}

#[test]
fn trace_and_tracer_instructions() {
    use softplc_core::engine::trace::{Trace, TraceConfig};
    let mut p = Plc::new("LD X0\nTRACE\nLD X1\nTRACER\nLD SM400\nINC D0\nEND\n");
    let cfg = TraceConfig {
        devices: vec![DeviceSpec::parse("D0").unwrap()],
        every_scans: 1,
        interval_us: None,
        capacity: 100,
        trigger: None,
        after_trigger: 1,
    };
    p.cpu.set_trace(Some(Trace::new(cfg).unwrap()));
    p.scans(2).set("X0", "1").scan().set("X0", "0").scans(3);
    // TRACE in scan 3: one more sample (scan 3's own END counts), then complete.
    let t = p.cpu.trace().unwrap();
    assert!(t.is_complete());
    assert_eq!(
        t.samples().map(|(s, _, _)| s).collect::<Vec<_>>(),
        [1, 2, 3]
    );
    // TRACER: the trace starts again from nothing.
    p.set("X1", "1").scan().set("X1", "0").scan();
    let t = p.cpu.trace().unwrap();
    assert!(!t.is_complete());
    assert_eq!(t.samples().map(|(s, _, _)| s).collect::<Vec<_>>(), [7, 8]);
}

// EI/DI without a contact (PM §6.7; a GX Works2 export opens a rung with DI).

const I31_COUNTS_D0: &str = "FEND\nI31\nLD SM400\nINC D0\nIRET\nEND\n";

#[test]
fn di_may_open_a_rung_and_ei_after_an_output_runs_unconditionally() {
    // EI follows the output of the X0 rung: it does not take X0's condition.
    let mut p = Plc::new(&format!("DI\nLD X0\nOUT Y0\nEI\n{I31_COUNTS_D0}"));
    p.scans(5);
    assert!(!p.bit("Y0"));
    // I31 (10 ms) is due once a scan: the cause of scan 1, held while DI, runs
    // once EI enables it, then one run before each of scans 2-5.
    assert_eq!(p.int("D0"), 5);
}

#[test]
fn ei_after_a_contact_runs_while_the_condition_is_on() {
    let mut p = Plc::new(&format!("LD X0\nEI\n{I31_COUNTS_D0}"));
    p.scans(5);
    assert_eq!(p.int("D0"), 0);
    p.set("X0", "1").scans(5);
    // The cause held pending while disabled runs when EI executes, then one
    // run before each of the next four scans.
    assert_eq!(p.int("D0"), 5);
}

#[test]
fn di_without_a_contact_disables_at_every_scan() {
    let mut p = Plc::new(&format!("LD SM400\nEI\nDI\n{I31_COUNTS_D0}"));
    p.scans(5);
    assert_eq!(p.int("D0"), 0);
}
