//! Golden tests of the PID control instructions (seed 001; notes
//! `shared/spec/pid-instructions.md`). Every expected value is worked out by
//! hand in the comment next to it from the formulas of 001 §3.1.2/§3.2.2 under
//! the notes' §2.6 [DECISION] policy (f64, MV clamped before stored, round half
//! away from zero for the shown words, first processing seeded with EVn−1 = 0).
//!
//! Unless a test says otherwise: PID control data at D500, I/O data at D600,
//! scans of 1 s with Ts = 1 s (ts = 100), so every scan is one sample; the
//! first scan is the first processing (it uses the configured Ts).
//!
//! This file: loop state in the work words, operation errors, load-time checks
//! and STOP → RUN.

mod common;
use common::pid::{
    continue_on_error, dev, get, plc, plc_src, run_pv, set, write_data, Fam, Loop, BASE, MODE, MV,
    PV, SV,
};
use common::{assert_running, assert_stopped, Plc};
use softplc_core::engine::{CpuState, ErrorCode};

// ------------------------------------------------------------ state in the work words

/// Clearing a loop's I/O data (MV and the work words) restarts it: the next
/// execution is a first processing (001 §5.2(4)(b) 4)).
#[test]
fn clearing_the_area_restarts_the_loop() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        for off in MV..fam.io() {
            if off != MODE {
                set(&mut p, fam, 0, off, 0);
            }
        }
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120], "{fam:?}");
    }
}

/// The running state is only in the devices: a new CPU (power cycle) with the
/// I/O area copied (latched) continues the loop after PIDINIT, instead of a
/// first processing (which would give 110).
#[test]
fn latched_area_survives_power_cycle() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        let mut q = plc(fam, 1, &[l], 600, 1000);
        for w in 600..600 + 10 + fam.io() {
            let v = p.int(&dev(w));
            q.set(&dev(w), &v.to_string());
        }
        // Scan 1 after power-on: scan time 0 → not due; scan 2: 1 s → sample.
        assert_eq!(run_pv(&mut q, fam, &[500, 500]), [120, 130], "{fam:?}");
    }
}

/// Both families in one program are independent: the S. family's registration
/// does not satisfy PIDCONT (4103), and each uses its own data.
#[test]
fn families_are_independent() {
    let src = "LD SM400\nSP.PIDINIT D500\nS.PIDCONT D600\nPIDCONT D700\nEND\n";
    let mut p = Plc::new(src);
    write_data(&mut p, Fam::S, 500, 1, &[BASE]);
    p.scan();
    assert_stopped(&p, 4103);

    let src = "LD SM400\nSP.PIDINIT D500\nPIDINITP D550\nS.PIDCONT D600\nPIDCONT D700\nEND\n";
    let mut p = Plc::new(src);
    p.scan_time_us(1_000_000);
    write_data(&mut p, Fam::S, 500, 1, &[Loop { ti: 100, ..BASE }]);
    write_data(&mut p, Fam::C, 550, 1, &[Loop { kp: 200, ..BASE }]);
    for (sv, pv, mode) in [(610, 611, 615), (710, 711, 715)] {
        p.set(&dev(sv), "600")
            .set(&dev(pv), "500")
            .set(&dev(mode), "1");
    }
    p.scans(2);
    assert_running(&p);
    // S.: PI, 110 then 120. Plain: P only with Kp 2: 200 then 200.
    assert_eq!((p.int("D612"), p.int("D712")), (120, 200));
}

/// Pulse forms run once per rising edge; time is only counted on executions
/// (notes §4: allowed, not useful). SP.PIDCONT on X0: the first processing at
/// the first edge (MV 110); the second edge adds one scan (1 s) → sample.
#[test]
fn pulse_forms() {
    for (fam, src) in [
        (
            Fam::S,
            "LD SM400\nSP.PIDINIT D500\nLD X0\nSP.PIDCONT D600\nEND\n",
        ),
        (
            Fam::C,
            "LD SM400\nPIDINITP D500\nLD X0\nPIDCONTP D600\nEND\n",
        ),
    ] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc_src(src, fam, 1, &[l], 600, 1000);
        set(&mut p, fam, 0, PV, 500);
        p.set("X0", "1").scans(3);
        assert_eq!(get(&p, fam, 0, MV), 110);
        p.set("X0", "0").scans(2);
        p.set("X0", "1").scans(2);
        assert_eq!(get(&p, fam, 0, MV), 120);
        assert_running(&p);
    }
}

// ------------------------------------------------------------ errors (001 §8.1, §9.1; notes §6)

/// 4103: PIDCONT (and S.PIDCONT) before any PIDINIT of the family.
#[test]
fn error_4103_pidcont_before_pidinit() {
    for src in [
        "LD SM400\nPIDCONT D600\nPIDINIT D500\nEND\n",
        "LD SM400\nS.PIDCONT D600\nEND\n",
    ] {
        let mut p = Plc::new(src);
        write_data(&mut p, Fam::C, 500, 1, &[BASE]);
        p.scan();
        assert_stopped(&p, 4103);
    }
}

/// 4103: PIDSTOP/PIDRUN before PIDINIT and PIDCONT have both executed;
/// PIDPRMW (both families, [DECISION] notes §4) before PIDINIT.
#[test]
fn error_4103_order_of_stop_run_prmw() {
    for (fam, body) in [
        (Fam::C, "PIDINIT D500\nPIDSTOP K1\nPIDCONT D600"),
        (Fam::C, "PIDINIT D500\nPIDRUN K1\nPIDCONT D600"),
        (Fam::S, "S.PIDINIT D500\nS.PIDSTOP K1\nS.PIDCONT D600"),
        (Fam::S, "S.PIDINIT D500\nS.PIDRUN K1\nS.PIDCONT D600"),
        (Fam::C, "PIDPRMW K1 D500\nPIDINIT D500\nPIDCONT D600"),
        (Fam::S, "S.PIDPRMW K1 D502\nS.PIDINIT D500\nS.PIDCONT D600"),
    ] {
        let mut p = Plc::new(&format!("LD SM400\n{body}\nEND\n"));
        write_data(&mut p, fam, 500, 1, &[BASE]);
        p.scan();
        assert_stopped(&p, 4103);
    }
    // In the right order, none of them fails.
    let mut p = Plc::new(
        "LD SM400\nPIDINIT D500\nPIDCONT D600\nPIDSTOP K1\nPIDRUN K1\nPIDPRMW K1 D502\nEND\n",
    );
    write_data(&mut p, Fam::C, 500, 1, &[BASE]);
    p.scans(2);
    assert_running(&p);
}

/// 4100 at PIDINIT for the common data: n < k, n = 0, n = 33 (no loop runs:
/// PIDCONT then reports 4100 too, and writes nothing).
#[test]
fn error_4100_common_data() {
    for (n, k) in [(1, 2), (0, 0), (33, 1), (2, 0)] {
        let mut p = plc_src(&Fam::C.program(), Fam::C, 1, &[BASE, BASE], 600, 1000);
        p.set("D500", &n.to_string()).set("D501", &k.to_string());
        p.scan();
        assert_stopped(&p, 4100);
        let mut p = Plc::with_config(
            "LD SM400\nPIDINITP D500\nLD SM400\nPIDCONT D600\nEND\n",
            continue_on_error(),
        );
        write_data(&mut p, Fam::C, 500, 1, &[BASE, BASE]);
        p.set("D500", &n.to_string()).set("D501", &k.to_string());
        set(&mut p, Fam::C, 0, PV, 500);
        set(&mut p, Fam::C, 0, MODE, 1);
        p.scans(2);
        assert_eq!(p.state(), CpuState::Run);
        assert_eq!(p.error(), Some(ErrorCode(4100)));
        assert_eq!(get(&p, Fam::C, 0, MV), 0, "no loop runs ({n}, {k})");
    }
}

/// 4100 for one loop's data (out of range, MVHL < MVLL, S. reserved words,
/// S. KD < 0): that loop is skipped, the other loop runs (operation error
/// "continue"); PIDCONT reports 4100 again on every execution.
#[test]
fn error_4100_one_loop_skipped() {
    #[allow(clippy::type_complexity)]
    let bad_loops: [(Fam, Loop, Option<(u32, i16)>); 9] = [
        (Fam::C, Loop { ts: 0, ..BASE }, None),
        (Fam::C, Loop { kp: 10001, ..BASE }, None),
        (Fam::C, Loop { ti: 0, ..BASE }, None),
        (Fam::C, Loop { td: 30001, ..BASE }, None),
        (Fam::C, Loop { alpha: 101, ..BASE }, None),
        (Fam::C, Loop { select: 2, ..BASE }, None),
        (
            Fam::S,
            Loop {
                mvll: 10,
                mvhl: 9,
                ..BASE
            },
            None,
        ),
        (Fam::S, Loop { kd: -1, ..BASE }, None),
        // Reserved word +12 of loop 1 (D514).
        (Fam::S, BASE, Some((514, 7))),
    ];
    for (fam, bad, poke) in bad_loops {
        let mut p = Plc::with_config(&fam.program(), continue_on_error());
        p.scan_time_us(1_000_000);
        write_data(&mut p, fam, 500, 2, &[bad, BASE]);
        if let Some((d, v)) = poke {
            p.set(&dev(d), &v.to_string());
        }
        for i in 0..2 {
            set(&mut p, fam, i, SV, 600);
            set(&mut p, fam, i, PV, 500);
            set(&mut p, fam, i, MODE, 1);
        }
        p.scan();
        assert_eq!(p.error(), Some(ErrorCode(4100)), "{fam:?} {bad:?}");
        assert_eq!(p.state(), CpuState::Run);
        assert_eq!(get(&p, fam, 0, MV), 0, "loop 1 skipped");
        assert_eq!(get(&p, fam, 1, MV), 100, "loop 2 runs");
        p.set("SD0", "0").set("SM0", "0").scan();
        assert_eq!(p.int("SD0"), 4100, "reported again by PIDCONT");
        // With the default "stop" setting the CPU stops at PIDINIT.
        let mut p = plc(fam, 2, &[bad, BASE], 600, 1000);
        if let Some((d, v)) = poke {
            p.set(&dev(d), &v.to_string());
        }
        p.scan();
        assert_stopped(&p, 4100);
    }
}

/// 4100: MAN/AUTO ∉ {0, 1} skips that loop, the other one runs.
#[test]
fn error_4100_man_auto_word() {
    let fam = Fam::S;
    let mut p = Plc::with_config(&fam.program(), continue_on_error());
    p.scan_time_us(1_000_000);
    write_data(&mut p, fam, 500, 2, &[BASE, BASE]);
    for i in 0..2 {
        set(&mut p, fam, i, SV, 600);
        set(&mut p, fam, i, PV, 500);
        set(&mut p, fam, i, MODE, 1);
    }
    set(&mut p, fam, 0, MODE, 2);
    p.scan();
    assert_eq!(p.error(), Some(ErrorCode(4100)));
    assert_eq!((get(&p, fam, 0, MV), get(&p, fam, 1, MV)), (0, 100));
    let mut p = plc(fam, 1, &[BASE], 600, 1000);
    set(&mut p, fam, 0, MODE, -1);
    p.scan();
    assert_stopped(&p, 4100);
}

/// 4100: PIDSTOP/PIDRUN/PIDPRMW loop number 0, 33, or above the loops used;
/// PIDPRMW data out of range.
#[test]
fn error_4100_loop_numbers_and_prmw_data() {
    for (body, code) in [
        ("PIDSTOP K0", 4100),
        ("PIDSTOP K2", 4100),
        ("PIDRUN K33", 4100),
        ("PIDRUN D0", 4100),
        ("PIDPRMW K2 D502", 4100),
        ("PIDPRMW K-1 D502", 4100),
        ("PIDPRMW K1 D900", 4100),
        ("PIDSTOP K1", 0),
    ] {
        let mut p = Plc::new(&format!(
            "LD SM400\nPIDINIT D500\nPIDCONT D600\n{body}\nEND\n"
        ));
        write_data(&mut p, Fam::C, 500, 1, &[BASE]);
        p.scan();
        if code == 0 {
            assert_running(&p);
        } else {
            assert_stopped(&p, code);
        }
    }
}

/// 4101: an area past the last D (D0-D12287): S.PIDINIT at D12280 with n = 1
/// needs 16 words; PIDCONT at D12270 with n = 1 needs 28; PIDPRMW at D12280
/// needs 10; S.PIDPRMW at D12275 needs 14.
#[test]
fn error_4101_areas_past_the_device_end() {
    let mut p = Plc::new("LD SM400\nS.PIDINIT D12280\nEND\n");
    p.set("D12280", "1").set("D12281", "1");
    p.scan();
    assert_stopped(&p, 4101);

    let mut p = Plc::new("LD SM400\nPIDINIT D500\nPIDCONT D12270\nEND\n");
    write_data(&mut p, Fam::C, 500, 1, &[BASE]);
    p.scan();
    assert_stopped(&p, 4101);

    for src in [
        "LD SM400\nPIDINIT D500\nPIDPRMW K1 D12280\nEND\n",
        "LD SM400\nS.PIDINIT D500\nS.PIDPRMW K1 D12275\nEND\n",
    ] {
        let mut p = Plc::new(src);
        write_data(&mut p, Fam::C, 500, 1, &[BASE]);
        write_data(&mut p, Fam::S, 500, 1, &[BASE]);
        p.scan();
        assert_stopped(&p, 4101);
    }
    // Index modification counts: D12200Z0 with Z0 = 80 → D12280.
    let mut p = Plc::new("LD SM400\nPIDINIT D12200Z0\nEND\n");
    p.set("Z0", "80").set("D12280", "1").set("D12281", "1");
    p.scan();
    assert_stopped(&p, 4101);
}

// ------------------------------------------------------------ load-time checks

#[test]
fn pid57_rejected_at_load() {
    for src in [
        "LD X2\nPID57 H0C K1 D0\nEND\n",
        "LD X2\nPID57P H0C K1 D0\nEND\n",
    ] {
        let d = common::diagnostics(src);
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(d[0].contains("needs an AD57"), "{d:?}");
        assert!(d[0].starts_with("2:"), "{d:?}");
    }
}

#[test]
fn operand_checks_at_load() {
    for (src, what) in [
        ("LD SM400\nPIDINIT K100\nEND\n", "word device"),
        ("LD SM400\nS.PIDCONT M0\nEND\n", "word device"),
        ("LD SM400\nPIDCONT D0 D1\nEND\n", "operand"),
        ("LD SM400\nS.PIDPRMW K1\nEND\n", "operand"),
        ("LD SM400\nPIDPRMW K1 K2\nEND\n", "word device"),
        ("LD SM400\nS.PIDINITP D0\nEND\n", "SP.PIDINIT"),
        ("LD SM400\nS.PIDSTOPP K1\nEND\n", "SP.PIDSTOP"),
    ] {
        let d = common::diagnostics(src);
        assert!(d.iter().any(|m| m.contains(what)), "{src}: {d:?}");
    }
    // Accepted operand kinds: word devices (D, W, R, ZR, index-modified) and,
    // for the loop number, K/H constants, words and digit-specified bits.
    let src = "LD SM400\nPIDINIT W100\nPIDINITP R0\nSP.PIDINIT ZR10\nS.PIDINIT D0Z1\n\
               PIDCONT D600\nPIDCONTP W200\nS.PIDCONT R100\nSP.PIDCONT ZR1000\n\
               PIDSTOP K1\nPIDSTOPP H1\nPIDRUN D0\nPIDRUNP K1M0\n\
               S.PIDSTOP K1\nSP.PIDSTOP D1\nS.PIDRUN K4X0\nSP.PIDRUN H2\n\
               PIDPRMW K1 D100\nPIDPRMWP D0 R0\nS.PIDPRMW K1 W0\nSP.PIDPRMW D2 ZR0\nEND\n";
    let prog = softplc_core::program::compile_il(
        "t.il",
        src,
        &softplc_core::profile::default_config().devices,
    );
    assert!(prog.is_ok(), "{:?}", prog.err().map(|d| d.to_string()));
}

// ------------------------------------------------------------ STOP → RUN

/// STOP→RUN clears the registration (the program's hidden state) but not the
/// I/O data: SP.PIDINIT runs again on the first scan after RUN and the loop
/// continues from its work words (no first processing, which would give 110).
#[test]
fn stop_run_keeps_the_loop_state() {
    for fam in [Fam::C, Fam::S] {
        let l = Loop { ti: 100, ..BASE };
        let mut p = plc(fam, 1, &[l], 600, 1000);
        assert_eq!(run_pv(&mut p, fam, &[500, 500]), [110, 120]);
        p.cpu.set_stop();
        p.scans(3);
        p.cpu.set_run().unwrap();
        // The first scan after RUN adds the scan time the engine measured last
        // (0 or 1 s, an engine detail), so it is 120 (not due) or 130; a first
        // processing would give 110.
        let mv = run_pv(&mut p, fam, &[500, 500, 500]);
        assert!(mv[0] == 120 || mv[0] == 130, "{fam:?} {mv:?}");
        assert_eq!([mv[1] - mv[0], mv[2] - mv[1]], [10, 10], "{fam:?} {mv:?}");
    }
}
