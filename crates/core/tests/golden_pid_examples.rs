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
//! This file: the manual's chapter 8/9 examples, execution without allocation
//! and the CPU-wide loop registration across program files.

mod common;
use common::pid::{dev, set, write_data, Fam, Loop, BASE, MODE, PV, SV};
use common::{assert_running, Plc};
use softplc_core::device::DeviceKind;

// ------------------------------------------------------------ chapter 8/9 examples

/// Runs a shipped example (examples/pid/) with 100 ms scans and X0 ON.
fn example(src: &str) -> Plc {
    let mut p = Plc::new(src);
    p.scan_time_us(100_000);
    p.set("X0", "1");
    p
}

/// Asserts |PV − SV| ≤ 2 counts (0.1 % of the 0..2000 range).
fn assert_settled(p: &Plc, sv: &str, pv: &str) {
    let (s, v) = (p.int(sv), p.int(pv));
    assert!((s - v).abs() <= 2, "{pv} = {v}, {sv} = {s}");
}

/// 001 §8.2.2 and §9.2.2: 2 loops in auto, SV 600 / 1000; the simulated
/// plants settle within ±2 counts in 120 s (1200 scans of 100 ms).
#[test]
fn examples_auto_two_loops_settle() {
    for (src, loop2) in [
        (
            include_str!("../../../examples/pid/ex822_spid_auto.il"),
            633,
        ),
        (include_str!("../../../examples/pid/ex922_pid_auto.il"), 628),
    ] {
        let mut p = example(src);
        p.scans(1200);
        assert_running(&p);
        assert_eq!((p.int("D610"), p.int(&dev(loop2))), (600, 1000));
        assert_settled(&p, "D610", "D611");
        assert_settled(&p, &dev(loop2), &dev(loop2 + 1));
        // Loop 1's plant gain is 0.8: MV ≈ 600 / 0.8 = 750.
        assert!((p.int("D612") - 750).abs() <= 3, "MV {}", p.int("D612"));
        // X1 stops PID control: the D/A output goes to 0.
        p.set("X1", "1").scan();
        assert_eq!(p.int("D820"), 0);
    }
}

/// 001 §8.2.3 and §9.2.3: auto/manual switching with SM794/SM774 OFF and the
/// 10-step SV restore. Auto for 60 s (PV → 600); manual from scan 601 with the
/// manual MV switch at 900 (BCD): SV tracks PV (→ 720 = 0.8·900); back to auto
/// at scan 1201: MV continues from 900 (bumpless), the SV walks 720 → 600 in
/// 10 steps of (720 − 600)/10 = 12, and PV settles at 600 again.
#[test]
fn examples_manual_auto_switching() {
    for src in [
        include_str!("../../../examples/pid/ex823_spid_manual_auto.il"),
        include_str!("../../../examples/pid/ex923_pid_manual_auto.il"),
    ] {
        let mut p = example(src);
        p.set("K4X20", "H900");
        p.scans(600);
        assert_settled(&p, "D610", "D611");
        p.set("X6", "1").scans(4);
        // Auto → manual copied MV into MV_MAN; then the switch X4 loads 900.
        assert!((p.int("D614") - 750).abs() <= 3);
        p.set("X4", "1").scan();
        p.set("X4", "0").scans(595);
        assert_eq!(p.int("D614"), 900);
        assert_eq!(p.int("D611"), 720);
        assert_eq!(p.int("D610"), 720, "SV tracks PV in manual");
        p.set("X6", "0").scan();
        assert_eq!(p.int("D612"), 900, "bumpless: MV starts from MV_MAN");
        let mut svs = vec![p.int("D610")];
        for _ in 0..150 {
            p.scan();
            if p.int("D610") != *svs.last().unwrap() {
                svs.push(p.int("D610"));
            }
        }
        assert_eq!(
            svs,
            [720, 708, 696, 684, 672, 660, 648, 636, 624, 612, 600],
            "10 steps"
        );
        p.scans(700);
        assert_running(&p);
        assert_settled(&p, "D610", "D611");
    }
}

// ------------------------------------------------------------ no allocation

/// Counts heap allocations made by the current thread while `COUNTING` is set.
mod alloc_count {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    thread_local! {
        pub static COUNTING: Cell<bool> = const { Cell::new(false) };
        pub static COUNT: Cell<usize> = const { Cell::new(0) };
    }

    pub struct Counting;

    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, l: Layout) -> *mut u8 {
            let _ = COUNTING.try_with(|c| {
                if c.get() {
                    COUNT.with(|n| n.set(n.get() + 1));
                }
            });
            unsafe { System.alloc(l) }
        }
        unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
            unsafe { System.dealloc(p, l) }
        }
    }
}

#[global_allocator]
static ALLOC: alloc_count::Counting = alloc_count::Counting;

/// PIDINIT, PIDCONT (32 loops, every loop computed each scan, manual/auto
/// transfers), PIDSTOP, PIDRUN and PIDPRMW execute without allocating.
#[test]
fn exec_does_not_allocate() {
    // The counter works: one Vec allocation is seen.
    alloc_count::COUNT.with(|n| n.set(0));
    alloc_count::COUNTING.with(|c| c.set(true));
    drop(std::hint::black_box(Vec::<u8>::with_capacity(8)));
    alloc_count::COUNTING.with(|c| c.set(false));
    assert_eq!(alloc_count::COUNT.with(|n| n.get()), 1);
    for fam in [Fam::C, Fam::S] {
        let pre = fam.prefix();
        let src = format!(
            "LD SM400\n{pre}PIDINIT D2000\n{pre}PIDCONT D600\n{pre}PIDSTOP K3\n\
             {pre}PIDRUN K3\n{pre}PIDPRMW K2 D2002\nEND\n"
        );
        let mut p = Plc::new(&src);
        p.scan_time_us(10_000);
        let l = Loop {
            ts: 1,
            ti: 100,
            td: 100,
            kd: 800,
            alpha: 20,
            ..BASE
        };
        write_data(&mut p, fam, 2000, 32, &[l; 32]);
        for i in 0..32 {
            set(&mut p, fam, i, SV, 600);
            set(&mut p, fam, i, PV, 500 + i as i64);
            set(&mut p, fam, i, MODE, 1);
        }
        p.scans(3);
        assert_running(&p);
        alloc_count::COUNT.with(|n| n.set(0));
        alloc_count::COUNTING.with(|c| c.set(true));
        for s in 0..20 {
            // Mode changes in place (no allocation in the harness either).
            let mode = p.cpu.memory().get_word(DeviceKind::D, 615).unwrap();
            if s % 5 == 0 {
                p.cpu.set_word(DeviceKind::D, 615, mode ^ 1).unwrap();
            }
            p.scan();
        }
        alloc_count::COUNTING.with(|c| c.set(false));
        assert_running(&p);
        assert_eq!(alloc_count::COUNT.with(|n| n.get()), 0, "{fam:?}");
    }
}

/// PIDINIT in an initial program registers the loops that PIDCONT uses in a
/// scan program of another file: the registration is CPU-wide (001 §8.1.1
/// "registered in the CPU module").
#[test]
fn pidinit_and_pidcont_in_different_program_files() {
    use softplc_core::engine::{Cpu, ExecType, LoadedProgram, VirtualClock};
    use softplc_core::program::compile_il;
    let cfg = softplc_core::profile::default_config();
    let init = "LD SM400\nS.PIDINIT D100\nEND\n";
    let main = "LD SM400\nS.PIDCONT D300\nEND\n";
    let progs = [
        ("init.il", init, ExecType::Initial),
        ("main.il", main, ExecType::Scan),
    ]
    .iter()
    .map(|(n, s, e)| LoadedProgram {
        program: compile_il(n, s, &cfg.devices).unwrap(),
        exec: *e,
        interval: None,
        sim_time: None,
        local_devices: true,
    })
    .collect();
    let clock = VirtualClock::new();
    let mut cpu = Cpu::with_programs(progs, cfg, Box::new(clock.clone())).unwrap();
    softplc_core::tier::apply_env(&mut cpu);
    // Control data: 1 loop, 1 per scan, reverse action (heating: EV = SV − PV), Ts 1 (10 ms), KP 100 (1.00),
    // TI 10 (1 s), TD 0, α 0, MVLL 0, MVHL 2000, ΔMV/ΔPV alarm limits 0 (off).
    let spec = |d: &str| softplc_core::access::DeviceSpec::parse(d).unwrap();
    for (d, v) in [
        ("D100", 1),
        ("D101", 1),
        ("D102", 1),
        ("D103", 1),
        ("D104", 100),
        ("D105", 10),
        ("D108", 0),
        ("D109", 2000),
    ] {
        cpu.write_device(&spec(d), &v.to_string()).unwrap();
    }
    // I/O data: SV 1000, PV 0, auto.
    for (d, v) in [("D310", 1000), ("D311", 0), ("D315", 1)] {
        cpu.write_device(&spec(d), &v.to_string()).unwrap();
    }
    for _ in 0..20 {
        clock.advance_us(10_000);
        cpu.scan();
    }
    // Without the registration PIDCONT would stop the CPU with 4103.
    assert!(cpu.error().is_none(), "{:?}", cpu.error());
    assert_eq!(cpu.state(), softplc_core::engine::CpuState::Run);
    // The loop runs: MV (m+2) has moved up from 0 towards SV − PV.
    match cpu.read_device(&spec("D312")).unwrap() {
        softplc_core::access::Value::Int(mv) => assert!(mv > 0, "MV {mv}"),
        v => panic!("{v:?}"),
    }
}
