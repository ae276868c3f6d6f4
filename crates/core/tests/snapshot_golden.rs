//! State files (contract §7): N+M scans give exactly what N scans, a save,
//! a load into a freshly built CPU and M scans give — device memory and
//! every hidden state (the two CPUs' state files are equal byte for byte).
//! Each case also asserts device values worked out by hand.

use std::time::Duration;

use softplc_core::access::Value;
use softplc_core::engine::trace::{Trace, TraceConfig};
use softplc_core::engine::VirtualClock;
use softplc_core::engine::{Clock, Cpu, CpuConfig, ErrorMode, ExecType, LoadedProgram};
use softplc_core::names::DevName;
use softplc_core::program::compile_il;
use softplc_core::snapshot::{self, SnapshotError};
use softplc_core::system::System;

/// Scheduled writes: (before scan n, device, value).
type Writes<'a> = &'a [(u64, &'a str, &'a str)];

fn write(cpu: &mut Cpu, dev: &str, value: &str) {
    let n = DevName::parse_for(dev, cpu).unwrap();
    n.write(cpu, value).unwrap();
}

fn read(cpu: &Cpu, dev: &str) -> i64 {
    match DevName::parse_for(dev, cpu).unwrap().read(cpu).unwrap() {
        Value::Int(i) => i,
        Value::Bool(b) => b as i64,
        v => panic!("{dev}: {v:?}"),
    }
}

fn run(
    cpu: &mut Cpu,
    clock: &VirtualClock,
    writes: Writes,
    scans: std::ops::RangeInclusive<u64>,
    us: u64,
) {
    let before = |cpu: &mut Cpu, n: u64| {
        for (_, d, v) in writes.iter().filter(|w| w.0 == n) {
            write(cpu, d, v);
        }
    };
    run_with(cpu, clock, &before, scans, us);
}

/// Scans with what `before` does before each scan n.
fn run_with(
    cpu: &mut Cpu,
    clock: &VirtualClock,
    before: &dyn Fn(&mut Cpu, u64),
    scans: std::ops::RangeInclusive<u64>,
    us: u64,
) {
    for n in scans {
        before(cpu, n);
        clock.advance_us(us);
        cpu.scan();
    }
}

/// Runs `build`'s CPU N+M scans of `us` in one go and N, save, load into a
/// new CPU, M; asserts both end the same; the resumed CPU.
fn resumed(build: &dyn Fn(&VirtualClock) -> Cpu, writes: Writes, n: u64, m: u64, us: u64) -> Cpu {
    let before = |cpu: &mut Cpu, k: u64| {
        for (_, d, v) in writes.iter().filter(|w| w.0 == k) {
            write(cpu, d, v);
        }
    };
    resumed_with(build, &before, n, m, us)
}

/// [`resumed`] with what `before` does before each scan.
fn resumed_with(
    build: &dyn Fn(&VirtualClock) -> Cpu,
    before: &dyn Fn(&mut Cpu, u64),
    n: u64,
    m: u64,
    us: u64,
) -> Cpu {
    let ca = VirtualClock::new();
    let mut whole = build(&ca);
    run_with(&mut whole, &ca, before, 1..=n + m, us);

    let cb = VirtualClock::new();
    let mut first = build(&cb);
    run_with(&mut first, &cb, before, 1..=n, us);
    let file = snapshot::save(&mut first);

    let cc = VirtualClock::new();
    // Built at another time: the file's time replaces it.
    cc.advance_us(777);
    let mut second = build(&cc);
    snapshot::load(&mut second, &file).unwrap();
    assert_eq!(cc.now_us(), n * us, "the clock comes back from the file");
    assert_eq!(second.scans(), first.scans());
    run_with(&mut second, &cc, before, n + 1..=n + m, us);

    assert_eq!(whole.state(), second.state());
    assert_eq!(whole.error(), second.error());
    assert!(
        whole.memory().bits == second.memory().bits,
        "bit memory differs"
    );
    assert!(
        whole.memory().words == second.memory().words,
        "word memory differs"
    );
    let (a, b) = (snapshot::save(&mut whole), snapshot::save(&mut second));
    assert!(
        a == b,
        "hidden state differs ({} and {} bytes)",
        a.len(),
        b.len()
    );
    second
}

fn il(src: &'static str) -> impl Fn(&VirtualClock) -> Cpu {
    il_with(src, softplc_core::profile::default_config)
}

fn il_with(src: &'static str, cfg: fn() -> CpuConfig) -> impl Fn(&VirtualClock) -> Cpu {
    move |clock| {
        let cfg = cfg();
        let prog = compile_il("main.il", src, &cfg.devices).unwrap();
        let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
        softplc_core::tier::apply_env(&mut cpu);
        cpu
    }
}

/// T0 K10 and T1 K100 (100 ms base) count from scan 1 with X0 ON; 10 ms
/// scans. A timer adds the previous scan's time from its second scan on:
/// after 60 scans 590 ms (TN0 = 5, 90 ms in its remainder), after 150
/// scans 1490 ms: T0 is up (TN0 = 10, Y0 ON), TN1 = 14.
#[test]
fn a_timer_mid_count() {
    let src = "LD X0\nOUT T0 K10\nLD X0\nOUT T1 K100\nLD T0\nOUT Y0\nEND\n";
    let cpu = resumed(&il(src), &[(1, "X0", "1")], 60, 90, 10_000);
    assert_eq!(read(&cpu, "TN0"), 10);
    assert_eq!(read(&cpu, "Y0"), 1);
    assert_eq!(read(&cpu, "TN1"), 14);
}

/// C0 counts X1's rising edges: ON at scans 2, 4, 6 (before the cut at 5)
/// and 8, 10: five counts, C0 K5 up. LDP X2 / LDF X2 count rises into D0
/// and falls into D1: X2 ON at scan 5 (the last before the cut), OFF at 7:
/// one rise, one fall — a lost edge memory would count the rise again after
/// the load. PLS M10 on X3 ON at 5: one scan of M10, counted in D2.
#[test]
fn a_counter_and_edges() {
    let src = "LD X1\nOUT C0 K5\nLDP X2\nINC D0\nLDF X2\nINC D1\n\
               LD X3\nPLS M10\nLD M10\nINC D2\nEND\n";
    let writes = [
        (2, "X1", "1"),
        (3, "X1", "0"),
        (4, "X1", "1"),
        (5, "X1", "0"),
        (6, "X1", "1"),
        (7, "X1", "0"),
        (8, "X1", "1"),
        (9, "X1", "0"),
        (10, "X1", "1"),
        (5, "X2", "1"),
        (7, "X2", "0"),
        (5, "X3", "1"),
    ];
    let cpu = resumed(&il(src), &writes, 5, 7, 10_000);
    assert_eq!(read(&cpu, "CN0"), 5);
    assert_eq!(read(&cpu, "C0"), 1);
    assert_eq!((read(&cpu, "D0"), read(&cpu, "D1")), (1, 1));
    assert_eq!(read(&cpu, "D2"), 1);
}

/// CALL into a subroutine with a FOR loop: 3 passes of INC D0 per scan; 12
/// scans are 36. The CALL and FOR stacks are empty at END.
#[test]
fn call_and_for_at_end() {
    let src = "LD SM400\nCALL P0\nFEND\nP0\nFOR K3\nLD SM400\nINC D0\nNEXT\nRET\nEND\n";
    let cpu = resumed(&il(src), &[], 5, 7, 10_000);
    assert_eq!(read(&cpu, "D0"), 36);
}

/// The manual's two-loop PID example (PIDINIT/PIDCONT) mid-run: 300 of 600
/// scans of 100 ms; the setpoints are as set, the rest (MV, the loops' work
/// areas, the plant's state) equals the uninterrupted run.
#[test]
fn a_pid_loop_mid_run() {
    let src = include_str!("../../../examples/pid/ex922_pid_auto.il");
    let build = move |clock: &VirtualClock| {
        let cfg = softplc_core::profile::default_config();
        let prog = compile_il("pid.il", src, &cfg.devices).unwrap();
        let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
        softplc_core::tier::apply_env(&mut cpu);
        cpu
    };
    let cpu = resumed(&build, &[(1, "X0", "1")], 300, 300, 100_000);
    assert_eq!(read(&cpu, "D610"), 600);
}

/// A fixed-scan program every 25 ms and a low-speed program of 15 ms under
/// a 20 ms constant scan; the cut falls between their runs. The fixed-scan
/// program counts D0: 60 scans of 20 ms are 1200 ms, 48 runs.
#[test]
fn fixed_scan_and_low_speed_programs() {
    let build = |clock: &VirtualClock| {
        let cfg = CpuConfig {
            constant_scan: Some(Duration::from_millis(20)),
            ..softplc_core::profile::default_config()
        };
        let progs = [
            (
                "main.il",
                "LD SM400\nINC D2\nEND\n",
                ExecType::Scan,
                None,
                None,
            ),
            (
                "fixed.il",
                "LD SM400\nINC D0\nEND\n",
                ExecType::FixedScan,
                Some(Duration::from_millis(25)),
                None,
            ),
            (
                "low.il",
                "LD SM400\nINC D1\nEND\n",
                ExecType::LowSpeed,
                None,
                Some(Duration::from_millis(15)),
            ),
        ];
        let loaded = progs
            .iter()
            .map(|(name, src, exec, interval, sim)| LoadedProgram {
                program: compile_il(name, src, &cfg.devices).unwrap(),
                exec: *exec,
                interval: *interval,
                sim_time: *sim,
                local_devices: true,
            })
            .collect();
        let mut cpu = Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
        softplc_core::tier::apply_env(&mut cpu);
        cpu
    };
    let cpu = resumed(&build, &[], 27, 33, 20_000);
    assert_eq!(read(&cpu, "D2"), 60);
    assert_eq!(read(&cpu, "D0"), 48);
}

/// I31 (every 10 ms) occurs while EI has not run: the cause is remembered
/// (004 L1236-1238) across the cut and runs when X0 turns EI on at scan 6,
/// then once before each of scans 7-10: D0 = 5.
#[test]
fn an_interrupt_pending() {
    let src = "LD X0\nEI\nFEND\nI31\nLD SM400\nINC D0\nIRET\nEND\n";
    let cpu = resumed(&il(src), &[(6, "X0", "1")], 5, 5, 10_000);
    assert_eq!(read(&cpu, "D0"), 5);
}

/// Division by zero with operation errors set to continue: OPERATION
/// ERROR 4100 each scan X0 is ON (scans 3, 4 and 8): the latest error and
/// three history entries survive the cut.
#[test]
fn error_history() {
    fn cfg() -> CpuConfig {
        CpuConfig {
            operation_error: ErrorMode::Continue,
            ..softplc_core::profile::default_config()
        }
    }
    let src = "LD X0\n/ K10 D100 D0\nLD SM400\nINC D10\nEND\n";
    let writes = [
        (3, "X0", "1"),
        (5, "X0", "0"),
        (8, "X0", "1"),
        (9, "X0", "0"),
    ];
    let cpu = resumed(&il_with(src, cfg), &writes, 4, 6, 10_000);
    assert_eq!(cpu.error().map(|e| e.code.0), Some(4100));
    assert_eq!(cpu.history().count(), 3);
    assert_eq!(read(&cpu, "D10"), 10);
}

/// An APLC-TCP program: TON T5 and CTU C5 counting X1's rises at scans 2,
/// 4 (before the cut at 4) and 6: C5 is up, Y0 ON.
#[test]
fn an_aplc_program() {
    let src = "LD SM0\nTON T5 50\nLD X1\nCTU C5 3\nLD C5\nOUT Y0\n";
    let build = move |clock: &VirtualClock| {
        let p = softplc_core::aplc::load_bytes("main.apl", src.as_bytes()).unwrap();
        let mut cpu = Cpu::new(p, softplc_core::aplc::cpu_config(), Box::new(clock.clone()));
        softplc_core::tier::apply_env(&mut cpu);
        cpu
    };
    let writes = [
        (2, "X1", "1"),
        (3, "X1", "0"),
        (4, "X1", "1"),
        (5, "X1", "0"),
        (6, "X1", "1"),
    ];
    let cpu = resumed(&build, &writes, 4, 26, 10_000);
    assert_eq!(read(&cpu, "CN5"), 3);
    assert_eq!(read(&cpu, "Y0"), 1);
    // T5 (100 ms base) over 30 scans of 10 ms: 300 ms, 3 of its 50.
    assert_eq!(read(&cpu, "TN5"), 3);
}

/// A Q64AD in the middle of a time-averaging period (the golden rack test's
/// case: 50 ms of CH1, 8 mA for the first 250 conversions, 16 mA for the
/// last 375 → 2200), cut after scan 4, with X5 forced ON across the cut:
/// the module's averaging and its physical inputs, the force and the value
/// under it come back.
#[test]
fn a_module_mid_period_and_a_forced_input() {
    let toml = "[[program]]\nfile = \"main.il\"\n\
                [[slot]]\ntype = \"input\"\npoints = 32\n\
                [[slot]]\ntype = \"intelligent\"\nmodule = \"Q64AD\"\n";
    let il = "LD X20\nANI M0\nMOV H0E U2\\G0\nMOV H101 U2\\G9\nMOV K50 U2\\G1\nSET Y29\nSET M0\n\
              LD Y29\nANI X29\nRST Y29\n\
              LD X2E\nMOV U2\\G11 D0\nMOV U2\\G10 D1\n\
              LD X5\nINC D5\nEND\n";
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("plc.toml"), toml).unwrap();
    std::fs::write(dir.path().join("main.il"), il).unwrap();
    let build = |clock: &VirtualClock| {
        let p = softplc_core::project::load_project(dir.path()).unwrap();
        let mut cpu = p.build_cpu(Box::new(clock.clone())).unwrap();
        softplc_core::tier::apply_env(&mut cpu);
        cpu
    };
    let before = |cpu: &mut Cpu, n: u64| {
        let ma = match n {
            1 => 8.0,
            4 => 16.0,
            _ => return,
        };
        cpu.module_mut(1).unwrap().set_channel(1, ma).unwrap();
        if n == 1 {
            cpu.force(softplc_core::device::DeviceKind::X, 5, true)
                .unwrap();
        }
    };
    let cpu = resumed_with(&build, &before, 4, 3, 10_000);
    assert_eq!(read(&cpu, "U2\\G11"), 2200);
    assert_eq!((read(&cpu, "D0"), read(&cpu, "D1")), (2200, 1));
    // X5 forced ON in all 7 scans.
    assert_eq!(read(&cpu, "D5"), 7);
}

/// A sampling trace of D0 every second scan, 4 samples kept, cut after
/// scan 5: its samples
/// and its count come back into a trace of the same settings; a CPU
/// without a trace (or with another) takes the file and passes them over.
#[test]
fn a_sampling_trace() {
    fn traced(clock: &VirtualClock, every: u32) -> Cpu {
        let mut cpu = il("LD SM400\nINC D0\nEND\n")(clock);
        let t = Trace::new(TraceConfig {
            devices: vec![softplc_core::access::DeviceSpec::parse("D0").unwrap()],
            every_scans: every,
            interval_us: None,
            capacity: 4,
            trigger: None,
            after_trigger: 0,
        })
        .unwrap();
        cpu.set_trace(Some(t));
        cpu
    }
    let cpu = resumed(&|c| traced(c, 2), &[], 5, 6, 10_000);
    let samples: Vec<(u64, Value)> = cpu
        .trace()
        .unwrap()
        .samples()
        .map(|(scan, _, v)| (scan, v[0].clone()))
        .collect();
    // Sampled at the ENDs of scans 1, 3, 5 … 11 (D0 = the scan count); the
    // latest 4 kept, scan 5's from before the cut.
    let want: Vec<(u64, Value)> = [5, 7, 9, 11].map(|n| (n, Value::Int(n as i64))).into();
    assert_eq!(samples, want);
    let clock = VirtualClock::new();
    let mut first = traced(&clock, 2);
    run(&mut first, &clock, &[], 1..=5, 10_000);
    let file = snapshot::save(&mut first);
    let mut plain = il("LD SM400\nINC D0\nEND\n")(&VirtualClock::new());
    snapshot::load(&mut plain, &file).unwrap();
    assert_eq!(read(&plain, "D0"), 5);
    let mut other = traced(&VirtualClock::new(), 3);
    snapshot::load(&mut other, &file).unwrap();
    assert_eq!(other.trace().unwrap().samples().count(), 0);
}

// ------------------------------------------------------------ refusals

fn saved(src: &'static str) -> Vec<u8> {
    let clock = VirtualClock::new();
    let mut cpu = il(src)(&clock);
    run(&mut cpu, &clock, &[(1, "X0", "1")], 1..=3, 10_000);
    snapshot::save(&mut cpu)
}

/// Loads `file` into a new CPU of `src`: the error, and that the CPU is as
/// it was.
fn refused(src: &'static str, file: &[u8]) -> SnapshotError {
    let clock = VirtualClock::new();
    let mut cpu = il(src)(&clock);
    run(&mut cpu, &clock, &[(1, "D5", "7")], 1..=1, 10_000);
    let before = snapshot::save(&mut cpu);
    let e = snapshot::load(&mut cpu, file).unwrap_err();
    assert!(
        snapshot::save(&mut cpu) == before,
        "a refused file changed the CPU"
    );
    assert_eq!(clock.now_us(), 10_000);
    e
}

const SRC: &str = "LD X0\nOUT T0 K10\nINC D0\nEND\n";

#[test]
fn another_or_an_edited_program_is_refused() {
    let file = saved(SRC);
    assert_eq!(
        refused("LD X0\nOUT Y0\nEND\n", &file),
        SnapshotError::Identity
    );
    assert_eq!(
        refused("LD X0\nOUT T0 K11\nINC D0\nEND\n", &file),
        SnapshotError::Identity
    );
    // The same program loads.
    let clock = VirtualClock::new();
    let mut cpu = il(SRC)(&clock);
    snapshot::load(&mut cpu, &file).unwrap();
    assert_eq!(read(&cpu, "D0"), 3);
}

#[test]
fn another_model_is_refused() {
    let file = saved(SRC);
    let clock = VirtualClock::new();
    let profile = softplc_core::profile::find("Q25HCPU").unwrap();
    let cfg = softplc_core::profile::config(profile);
    let prog = compile_il("main.il", SRC, &cfg.devices).unwrap();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    assert_eq!(
        snapshot::load(&mut cpu, &file).unwrap_err(),
        SnapshotError::Model {
            found: "Q06HCPU".into(),
            expected: "Q25HCPU".into()
        }
    );
}

#[test]
fn a_flipped_byte_or_a_truncated_file_is_refused() {
    let file = saved(SRC);
    for at in [0, 9, 20, 50, 60, file.len() / 2, file.len() - 1] {
        let mut bad = file.clone();
        bad[at] ^= 0x10;
        let e = refused(SRC, &bad);
        let want = if at == 0 {
            SnapshotError::NotAStateFile
        } else {
            SnapshotError::Damaged(String::new())
        };
        assert_eq!(
            std::mem::discriminant(&e),
            std::mem::discriminant(&want),
            "byte {at}: {e}"
        );
    }
    for len in [0, 7, 8, 55, 56, 100, file.len() - 1] {
        let e = refused(SRC, &file[..len]);
        assert!(
            matches!(e, SnapshotError::NotAStateFile | SnapshotError::Damaged(_)),
            "{len} bytes: {e}"
        );
    }
    assert!(refused(SRC, &[&file[..], &[0]].concat())
        .to_string()
        .contains("damaged"));
}

// ------------------------------------------------------------ a system

/// Two CPUs in one time, CPU 1 scanning every 10 ms and CPU 2 every 20 ms,
/// exchanging D0-D3 by auto refresh; cut at 230 ms, between CPU 2's scans.
#[test]
fn a_multi_cpu_system() {
    let cpu1 = "[multi_cpu]\ncpus = 2\n[[multi_cpu.refresh]]\ndevice = \"D0\"\nwords = [2, 2]\n";
    let cpu2 = "[multi_cpu]\ncpus = 2\n[[multi_cpu.refresh]]\ndevice = \"D0\"\nwords = [2, 2]\n\
                [ras]\nconstant_scan = \"20ms\"\n";
    let il1 = "LD SM400\nINC D0\nEND\n";
    let il2 = "LD SM400\nINC D2\nMOV D0 D10\nEND\n";
    let dir = tempfile::tempdir().unwrap();
    let mut manifest = String::new();
    for (i, (toml, il)) in [(cpu1, il1), (cpu2, il2)].iter().enumerate() {
        let d = dir.path().join(format!("cpu{}", i + 1));
        std::fs::create_dir(&d).unwrap();
        std::fs::write(
            d.join("plc.toml"),
            format!("[[program]]\nfile = \"main.il\"\n{toml}"),
        )
        .unwrap();
        std::fs::write(d.join("main.il"), il).unwrap();
        manifest += &format!("[[cpu]]\nproject = \"cpu{}\"\n", i + 1);
    }
    std::fs::write(dir.path().join("system.toml"), manifest).unwrap();
    let load = |clock: &VirtualClock| {
        let c = clock.clone();
        let mut s = System::load(dir.path(), &mut || Box::new(c.clone())).unwrap();
        s.schedule(Duration::from_millis(10), 0);
        s
    };
    let (ca, cb, cc) = (
        VirtualClock::new(),
        VirtualClock::new(),
        VirtualClock::new(),
    );
    let mut whole = load(&ca);
    whole.run_until(500_000, &ca);
    let mut first = load(&cb);
    first.run_until(230_000, &cb);
    let file = first.save_state();
    let mut second = load(&cc);
    second.load_state(&file).unwrap();
    second.run_until(500_000, &cc);
    for i in 0..2 {
        assert!(
            whole.cpu(i).memory().words == second.cpu(i).memory().words,
            "CPU {}",
            i + 1
        );
        assert!(
            whole.cpu(i).memory().bits == second.cpu(i).memory().bits,
            "CPU {}",
            i + 1
        );
    }
    assert!(whole.save_state() == second.save_state());
    // CPU 1: 10 ms scans over 500 ms; CPU 2: 20 ms.
    assert_eq!(read(second.cpu(0), "D0"), 50);
    assert_eq!(read(second.cpu(1), "D2"), 25);
    // A single CPU's file is not a system's.
    let clock = VirtualClock::new();
    let mut one = il(SRC)(&clock);
    assert_eq!(
        snapshot::load(&mut one, &file).unwrap_err(),
        SnapshotError::CpuCount {
            found: 2,
            expected: 1
        }
    );
}
