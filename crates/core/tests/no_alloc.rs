//! The scan loop allocates nothing (ARCHITECTURE.md: "`exec` never
//! allocates"): a counting global allocator checks a
//! CPU with several program types, interrupts and many instruction families.

use std::sync::atomic::Ordering;
use std::time::Duration;

use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, CpuConfig, ExecType, LoadedProgram, VirtualClock};
use softplc_core::program::compile_il;
use softplc_core::rack::{AutoRefresh, Rack, Slot};
use softplc_core::tier::{apply, Exec, Jit};

mod counting_alloc;

use counting_alloc::{ALLOCS, COUNTING};

const MAIN: &str = "\
LD SM402
EI
LD X0
OR M0
ANI X1
OUT M0
LD M0
OUT T0 K10
OUT C0 K5
LDP X2
INCP D0
LD SM400
MOV D0 D1
+ D1 K3 D2
* D2 K2 D4
E+ E1.5 E2.5 D10
BCD D0 D20
BIN D20 D21
BMOV D0 D30 K4
$MOV \"ABC\" D40
LD$= D40 \"ABC\"
OUT M1
LD> D2 K1
SET M2
FOR K3
LD SM400
INC D50
NEXT
LD SM400
CALL P1
CALL P2 X0 M5 D52 K7
LD X0
FCALL P2 X0 M6 D53 K1
LD SM400
DUTY K1 K1 SM420
LD SM400
MOV U2\\G11 D110
FROM H2 K11 D111 K1
TO H2 K1 D0 K1
LD DX2
OUT DY10
FEND
P1
LD SM400
INC D51
RET
P2
LD FX0
OUT FY1
LD SM400
+ FD2 FD3 FD2
RET
I31
LD SM400
INC D60
IRET
END
";

/// On both tiers (issue #17: the native regions and the interpreter between
/// them), one after the other: the counter is global, so no other test may
/// run in parallel in this binary.
#[test]
fn scans_do_not_allocate_on_either_tier() {
    COUNTING.with(|c| c.set(true));
    scans_do_not_allocate(Exec::Interp);
    scans_do_not_allocate(Exec::Jit);
    local_devices_do_not_allocate(Exec::Interp);
    local_devices_do_not_allocate(Exec::Jit);
}

/// Local devices swap between buffers sized at load: programs with their
/// own, one "not used", a fixed-scan program and an interrupt program with
/// SM777 ON, a CALL into another file with SM776 ON, timers (with their
/// remainders), counters, M, V and D in the ranges.
fn local_devices_do_not_allocate(exec: Exec) {
    use softplc_core::engine::LocalRange;
    use softplc_core::program::{compile::compile_with, il::parse_il};
    let mut cfg = softplc_core::profile::default_config();
    cfg.local_devices = [
        (DeviceKind::M, 0, 99),
        (DeviceKind::V, 0, 9),
        (DeviceKind::TS, 0, 9),
        (DeviceKind::CS, 0, 9),
        (DeviceKind::D, 0, 99),
    ]
    .map(|(kind, start, end)| LocalRange { kind, start, end })
    .to_vec();
    let progs = [
        (
            "a.il",
            "LD SM400\nEI\nSET SM776\nSET SM777\nINC D0\nCALL P100\n\
             LD X0\nOUT T0 K5\nOUT C0 K3\nOUT M0\nLDP M0\nOUT V0\nEND\n",
            ExecType::Scan,
            None,
            true,
        ),
        (
            "b.il",
            "LD SM400\nINC D1\nCALL P100\nEND\n",
            ExecType::Scan,
            None,
            false,
        ),
        (
            "c.il",
            "LD SM400\nINC D0\nLD X0\nOUTH T1 K3\nEND\n",
            ExecType::Scan,
            None,
            true,
        ),
        (
            "fast.il",
            "LD SM400\nINC D2\nEND\n",
            ExecType::FixedScan,
            Some(Duration::from_millis(20)),
            true,
        ),
        (
            "sub.il",
            "FEND\nP100\nLD SM400\nINC D3\nRET\nI31\nLD SM400\nINC D4\nIRET\nEND\n",
            ExecType::Standby,
            None,
            true,
        ),
    ];
    let loaded = progs
        .iter()
        .map(|(n, s, e, i, local)| LoadedProgram {
            program: compile_with(&parse_il(n, s).unwrap(), &cfg.devices, Some(100)).unwrap(),
            exec: *e,
            interval: *i,
            sim_time: None,
            local_devices: *local,
        })
        .collect();
    let clock = VirtualClock::new();
    let mut cpu = Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
    match exec {
        Exec::Jit => {
            cpu.use_tier(&Jit::with_min_run(1)).unwrap();
        }
        _ => {
            apply(&mut cpu, exec).unwrap();
        }
    }
    for _ in 0..3 {
        clock.advance_us(10_000);
        cpu.scan();
    }
    let before = ALLOCS.load(Ordering::Relaxed);
    for k in 0..200 {
        cpu.set_input(0, k % 2 == 0);
        clock.advance_us(10_000);
        cpu.scan();
    }
    let allocs = ALLOCS.load(Ordering::Relaxed) - before;
    assert!(cpu.error().is_none(), "{:?}", cpu.error());
    // c.il ran last: its local devices are in device memory.
    assert_eq!(cpu.local_devices_owner(), Some(2));
    assert_eq!(allocs, 0, "allocations during 200 scans with local devices");
}

fn scans_do_not_allocate(exec: Exec) {
    let mut cfg = CpuConfig {
        low_speed_time: Some(Duration::from_millis(1)),
        ..softplc_core::profile::default_config()
    };
    // A rack: a Q64AD at X/Y20 (auto refresh G11 → D200) and a QI60 at
    // X/Y40, so that buffer memory, FROM/TO, direct I/O, the modules' END
    // and the interrupt module's edges run too.
    let mut ad = Slot::with_module(0, 0x20, &softplc_modules::Q64AD);
    ad.refresh.push(AutoRefresh {
        buffer: 11,
        device: DeviceKind::D,
        number: 200,
        words: 1,
        to_cpu: true,
    });
    cfg.devices.set_units(&[(2, ad.buffer_words)]);
    cfg.rack = std::sync::Arc::new(Rack {
        slots: vec![ad, Slot::with_module(1, 0x40, &softplc_modules::QI60)],
    });
    let progs = [
        ("main.il", MAIN, ExecType::Scan, None),
        (
            "init.il",
            "LD SM400\nMOV K1 D100\nEND\n",
            ExecType::Initial,
            None,
        ),
        (
            "fast.il",
            "LD SM400\nINC D101\nEND\n",
            ExecType::FixedScan,
            Some(Duration::from_millis(20)),
        ),
        (
            "slow.il",
            "LD SM400\nINC D102\nEND\n",
            ExecType::LowSpeed,
            None,
        ),
    ];
    let loaded = progs
        .iter()
        .map(|(n, s, e, i)| LoadedProgram {
            program: compile_il(n, s, &cfg.devices).unwrap(),
            exec: *e,
            interval: *i,
            sim_time: None,
            local_devices: true,
        })
        .collect();
    let clock = VirtualClock::new();
    let mut cpu = Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
    // On the JIT: native code for every op that can have it, so the scans
    // cross between it and the interpreter as often as they can.
    let native = match exec {
        Exec::Jit => Some(cpu.use_tier(&Jit::with_min_run(1)).unwrap().clone()),
        _ => apply(&mut cpu, exec).unwrap(),
    };
    assert_eq!(native.is_some(), exec == Exec::Jit);
    assert!(
        !matches!(&native, Some(s) if s.native_ops == 0),
        "{native:?}"
    );
    // Warm-up: first scans may size internal buffers.
    for _ in 0..3 {
        clock.advance_us(10_000);
        cpu.scan();
    }
    cpu.set_input(0, true);
    let before = ALLOCS.load(Ordering::Relaxed);
    for k in 0..200 {
        cpu.set_input(2, k % 2 == 0);
        cpu.set_input(0x40, k % 3 == 0);
        clock.advance_us(10_000);
        cpu.scan();
    }
    let allocs = ALLOCS.load(Ordering::Relaxed) - before;
    assert!(cpu.error().is_none(), "{:?}", cpu.error());
    assert_eq!(allocs, 0, "allocations during 200 scans");
}
