//! Interrupt routines: timed interrupts (SD66-SD68, SM66-SM68), X0-X7 edge
//! events (SM40-SM47), EI/DI, the 8-deep FIFO and error 67, CIRET, fresh
//! locals (spec aplc.md §3.5, §8.5 #78-79).

mod common;
use common::{errors, plc};

/// §8.5 #78 (L10209-10219): `MOV 1000 SD66`, `SET SM66`, `EI`: INT 26 every
/// 1000 ms, toggling Y0.
#[test]
fn timed_interrupt_every_second() {
    let src = "POU MAIN\nLD SM1\nMOV 1000 SD66\nLD SM1\nSET SM66\nLD SM0\nEI\n\
POU INT_1 EVENT 26\nVAR\n    TG TEMP BOOL\nEND_VAR\nLDI Y0\nOUT #TG\nLD #TG\nOUT Y0\nLD SM0\nINC D0\n";
    let mut p = plc(src);
    p.scans(101);
    assert_eq!(p.int("D0"), 0);
    p.scan();
    assert_eq!(
        p.int("D0"),
        1,
        "enabled in scan 1, seen at 20 ms, first at 1020 ms"
    );
    assert!(p.bit("Y0"));
    p.scans(200);
    assert_eq!(p.int("D0"), 3);
    assert!(p.bit("Y0"));
    // Disabling stops it; enabling again restarts the timing.
    p.set("SM66", "0").scans(150);
    assert_eq!(p.int("D0"), 3);
}

/// X0 rising (event 0) and X1 falling (event 11), each with its enable.
#[test]
fn edge_interrupts() {
    let src = "POU MAIN\nLD SM1\nSET SM40\nSET SM41\nEI\nLD M9\nDI\n\
POU INT_0 EVENT 0\nLD SM0\nINC D1\nPOU INT_5 EVENT 11\nLD SM0\nINC D2\nLD M5\nCIRET\nLD SM0\nINC D3\n";
    let mut p = plc(src);
    p.scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D1"), 1);
    p.scan();
    assert_eq!(p.int("D1"), 1, "one event per edge");
    p.set("X0", "0").set("X1", "1").scan();
    assert_eq!(
        (p.int("D1"), p.int("D2")),
        (1, 0),
        "X0 falling and X1 rising are not bound"
    );
    p.set("X1", "0").scan();
    assert_eq!((p.int("D2"), p.int("D3")), (1, 1));
    p.set("M5", "1").set("X1", "1").scan().set("X1", "0").scan();
    assert_eq!((p.int("D2"), p.int("D3")), (2, 1), "CIRET returned early");
    p.set("M9", "1").scan().set("X0", "1").scan();
    assert_eq!(p.int("D1"), 1, "DI: no new requests");
}

/// §9.1 events 0 and 11 (L10088, L10097): an input turned ON and OFF again
/// between two scans (never ON in X) still gives its rising event, one
/// turned OFF and ON again its falling event.
#[test]
fn edge_interrupts_of_a_pulse_between_scans() {
    let src = "POU MAIN\nLD SM1\nSET SM40\nSET SM41\nEI\n\
POU INT_0 EVENT 0\nLD SM0\nINC D1\nPOU INT_1 EVENT 11\nLD SM0\nINC D2\n";
    let mut p = plc(src);
    p.set("X1", "1").scan();
    p.set("X0", "1").set("X0", "0").scan();
    assert!(!p.bit("X0"));
    assert_eq!((p.int("D1"), p.int("D2")), (1, 0), "X0's rising edge");
    p.set("X1", "0").set("X1", "1").scan();
    assert!(p.bit("X1"));
    assert_eq!((p.int("D1"), p.int("D2")), (1, 1), "X1's falling edge");
    p.scans(2);
    assert_eq!((p.int("D1"), p.int("D2")), (1, 1), "no edge, no event");
}

/// §8.5 #79: eight requests are queued, further ones are lost with error 67.
#[test]
fn queue_overflow_is_error_67() {
    let src = "POU MAIN\nLD SM1\nMOV 1 SD67\nSET SM67\nEI\nPOU INT_2 EVENT 27\nLD SM0\nINC D0\n";
    let mut p = plc(src);
    // Enabled in scan 1, timing from scan 2 (20 ms): scan 3 finds 10 events.
    p.scans(3);
    assert_eq!(p.int("D0"), 8, "10 ms of 1 ms interrupts: 8 run, 2 lost");
    assert_eq!(p.error_code(), Some(67));
    assert!(p.running());
}

#[test]
fn interrupt_diagnostics() {
    let e = errors("POU MAIN\nLD M0\nCIRET\n");
    assert!(
        e.contains("t.apl:3:1: CIRET outside an interrupt routine"),
        "{e}"
    );
    let e = errors("POU MAIN\nLD M0\nOUT Y0\nPOU SBR_0\nLD M0\nOUT Y1\nPOU INT_1 EVENT 26\nLD M0\nCALL SBR_0\n");
    assert!(e.contains("t.apl:9:1: CALL in an interrupt routine"), "{e}");
    let e = errors("POU MAIN\nLD M0\nOUT Y0\nPOU INT_1 EVENT 26\nLD M0\nCFEND\n");
    assert!(e.contains("CFEND outside MAIN"), "{e}");
    let e = errors("POU MAIN\nLD M0\nOUT Y0\nPOU INT_1 EVENT 26\nVAR\n  A IN INT\nEND_VAR\n");
    assert!(
        e.contains("`IN`: MAIN and interrupt routines declare TEMP only"),
        "{e}"
    );
}
