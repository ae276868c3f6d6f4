//! Writing a program during RUN (004 §4.8; contract §7): device memory and
//! the hidden state of unchanged instructions are kept, new falling-edge
//! instructions whose condition is OFF act once, limits and links are
//! checked. Every case runs on the interpreter and on the JIT.

mod common;

use common::project::{error, ok, with_main};
use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::{Cpu, ExecType, LoadedProgram, OnlineLimits, VirtualClock};
use softplc_core::program::{compile_il, Program};
use softplc_core::tier::Jit;

/// Scans of 10 ms of virtual time.
struct Rig {
    cpu: Cpu,
    clock: VirtualClock,
}

impl Rig {
    fn scans(&mut self, n: u32) {
        for _ in 0..n {
            self.clock.advance_us(10_000);
            self.cpu.scan();
        }
    }
    fn int(&self, d: &str) -> i64 {
        match self
            .cpu
            .read_device(&DeviceSpec::parse(d).unwrap())
            .unwrap()
        {
            Value::Int(v) => v,
            v => panic!("{d}: {v:?}"),
        }
    }
    fn bit(&self, d: &str) -> bool {
        self.cpu
            .read_device(&DeviceSpec::parse(d).unwrap())
            .unwrap()
            == Value::Bool(true)
    }
    fn write(&mut self, slot: usize, src: &str) -> Result<softplc_core::engine::Written, String> {
        let file = self.cpu.program_at(slot).file.clone();
        let p = program(&file, src);
        self.cpu.replace_program(slot, p)
    }
}

fn program(file: &str, src: &str) -> Program {
    let cfg = softplc_core::profile::default_config();
    compile_il(file, src, &cfg.devices).unwrap_or_else(|d| panic!("{d}"))
}

/// Both tiers: the interpreter, and the JIT compiling every run it can.
const TIERS: [bool; 2] = [false, true];

fn rig(files: &[(&str, &str, ExecType)], limits: OnlineLimits, jit: bool) -> Rig {
    let mut cfg = softplc_core::profile::default_config();
    cfg.online = limits;
    let loaded = files
        .iter()
        .map(|(f, src, exec)| LoadedProgram {
            program: program(f, src),
            exec: *exec,
            interval: None,
            sim_time: None,
            local_devices: true,
        })
        .collect();
    let clock = VirtualClock::new();
    let mut cpu = Cpu::with_programs(loaded, cfg, Box::new(clock.clone())).unwrap();
    if jit {
        cpu.use_tier(&Jit::with_min_run(1)).unwrap();
    }
    Rig { cpu, clock }
}

const V1: &str = "\
LD X0
OUT T0 K10
LD X3
OUT C0 K5
LDP X4
INC D4
LD X5
INCP D5
LD X8
TIMCHK D10 K100 M10
LD X1
OUT Y0
END
";

/// V1 with three rungs added before the others (a TIMCHK that takes the
/// first state words, an LDF and a PLF whose conditions are OFF) and the
/// last rung changed.
const V2: &str = "\
LD X9
TIMCHK D20 K100 M20
LDF X6
INC D6
LD X7
PLF M7
LD X0
OUT T0 K10
LD X3
OUT C0 K5
LDP X4
INC D4
LD X5
INCP D5
LD X8
TIMCHK D10 K100 M10
LD X2
OUT Y1
END
";

#[test]
fn unchanged_instructions_keep_their_state_and_new_falling_edges_act_once() {
    for jit in TIERS {
        let mut r = rig(
            &[("main.il", V1, ExecType::Scan)],
            OnlineLimits::default(),
            jit,
        );
        for x in [0, 1, 3, 4, 5, 8] {
            r.cpu.set_input(x, true);
        }
        // 30 scans of 10 ms: the timer and TIMCHK add nothing at the scan
        // that starts them, then 10 ms a scan: 290 ms = 2 units of 100 ms.
        r.scans(30);
        assert_eq!(
            (r.int("TN0"), r.int("CN0"), r.int("D10")),
            (2, 1, 2),
            "jit {jit}"
        );
        assert_eq!((r.int("D4"), r.int("D5")), (1, 1));
        assert!(r.bit("Y0"));

        let w = r.write(0, V2).unwrap();
        assert_eq!((w.kept, w.added, w.removed), (11, 8, 2));
        // TIMCHK 4 + LD 1 + LDF 1 + INC 2 + LD 1 + PLF 2 + LD 1 + OUT 1 steps.
        assert_eq!(w.steps_written, 13);
        assert_eq!(w.falling_edges, 2);
        assert_eq!(w.scan, 30);

        r.scans(1);
        // The timer went on (300 ms), the counter did not count X3 again,
        // LDP and INCP did not see X4/X5 rise again, TIMCHK kept measuring
        // although its state words moved behind the new TIMCHK's.
        assert_eq!(
            (r.int("TN0"), r.int("CN0"), r.int("D10")),
            (3, 1, 3),
            "jit {jit}"
        );
        assert_eq!((r.int("D4"), r.int("D5")), (1, 1));
        // LDF X6 and PLF M7 with their conditions OFF acted once.
        assert_eq!(r.int("D6"), 1);
        assert!(r.bit("M7"));
        // Y0 is no longer driven: device memory keeps it.
        assert!(r.bit("Y0") && !r.bit("Y1"));

        r.scans(1);
        assert_eq!(r.int("D6"), 1);
        assert!(!r.bit("M7"));
        // 1000 ms after the timer started: 100 scans in all.
        r.scans(68);
        assert_eq!(r.int("TN0"), 9);
        assert!(!r.bit("T0"));
        r.scans(1);
        assert_eq!(r.int("TN0"), 10);
        assert!(r.bit("T0"));
        // The new LDF still works on a real falling edge.
        r.cpu.set_input(6, true);
        r.scans(1);
        r.cpu.set_input(6, false);
        r.scans(1);
        assert_eq!(r.int("D6"), 2);
    }
}

#[test]
fn a_counter_keeps_its_count_across_writes() {
    for jit in TIERS {
        let src = "LD X3\nOUT C0 K3\nLD C0\nOUT Y0\nEND\n";
        let mut r = rig(
            &[("main.il", src, ExecType::Scan)],
            OnlineLimits::default(),
            jit,
        );
        for _ in 0..2 {
            r.cpu.set_input(3, true);
            r.scans(1);
            r.cpu.set_input(3, false);
            r.scans(1);
        }
        assert_eq!(r.int("CN0"), 2);
        r.write(0, "LD X3\nOUT C0 K3\nLD C0\nOUT Y1\nEND\n")
            .unwrap();
        r.cpu.set_input(3, true);
        r.scans(1);
        assert_eq!(r.int("CN0"), 3, "jit {jit}");
        assert!(r.bit("Y1"));
    }
}

#[test]
fn the_limits_of_a_write_refuse_it_and_keep_the_old_program() {
    for jit in TIERS {
        let limits = OnlineLimits {
            max_steps: 2,
            reserve_steps: 3,
        };
        let mut r = rig(
            &[("main.il", "LD X0\nOUT Y0\nEND\n", ExecType::Scan)],
            limits,
            jit,
        );
        // LD 1 + INC 2 = 3 steps written: more than 2.
        let e = r
            .write(0, "LD X0\nOUT Y0\nLD X1\nINC D0\nEND\n")
            .unwrap_err();
        assert!(
            e.contains("writes 3 steps; a write during RUN writes at most 2"),
            "{e}"
        );
        // Two writes of 2 steps each fit the limit, but the file loaded with
        // 3 steps (LD, OUT, END) may grow only to 3 + 3 = 6.
        r.write(0, "LD X0\nOUT Y0\nLD X1\nOUT Y1\nEND\n").unwrap();
        let e = r
            .write(0, "LD X0\nOUT Y0\nLD X1\nOUT Y1\nLD X2\nOUT Y2\nEND\n")
            .unwrap_err();
        assert!(
            e.contains("7 steps do not fit the file's 6 (3 steps loaded and a reserve of 3"),
            "{e}"
        );
        r.cpu.set_input(1, true);
        r.scans(1);
        assert!(r.bit("Y1"));
    }
}

#[test]
fn calls_from_other_files_follow_the_pointer_or_refuse_its_removal() {
    for jit in TIERS {
        let main = "LD SM400\nECALL \"SUB\" P0\nEND\n";
        let sub = "FEND\nP0\nLD SM400\nINC D10\nRET\nEND\n";
        let mut r = rig(
            &[
                ("main.il", main, ExecType::Scan),
                ("sub.il", sub, ExecType::Standby),
            ],
            OnlineLimits::default(),
            jit,
        );
        r.scans(2);
        assert_eq!(r.int("D10"), 2);
        // P0 moves two ops further: main's ECALL follows it.
        r.write(
            1,
            "FEND\nLD X0\nOUT Y0\nP0\nLD SM400\n+ K10 D10\nRET\nEND\n",
        )
        .unwrap();
        r.scans(1);
        assert_eq!(r.int("D10"), 12, "jit {jit}");
        // Without P0 main's ECALL would go nowhere: refused.
        let e = r.write(1, "FEND\nP1\nRET\nEND\n").unwrap_err();
        assert!(e.contains("main.il CALLs P0 of sub.il"), "{e}");
        r.scans(1);
        assert_eq!(r.int("D10"), 22);
    }
}

#[test]
fn plc_toml_sets_the_limits_of_writes_during_run() {
    let p = ok(&with_main(""));
    assert_eq!(
        p.config.online,
        OnlineLimits {
            max_steps: 512,
            reserve_steps: 500
        }
    );
    let p = ok(&with_main(
        "[cpu]\nonline_write_steps = 100\nonline_reserve_steps = 0\n",
    ));
    assert_eq!(
        p.config.online,
        OnlineLimits {
            max_steps: 100,
            reserve_steps: 0
        }
    );
    assert_eq!(
        error(&with_main("[cpu]\nonline_write_steps = 513\n")),
        "2:22: online_write_steps must be a number of steps from 1 to 512"
    );
}

#[test]
fn a_kept_falling_edge_acts_once_when_its_condition_is_off_after_the_write() {
    for jit in TIERS {
        let src = "LDF X6\nINC D6\nLDF X7\nINC D7\nLD X0\nOUT Y0\nEND\n";
        let mut r = rig(
            &[("main.il", src, ExecType::Scan)],
            OnlineLimits::default(),
            jit,
        );
        r.cpu.set_input(7, true);
        r.scans(3);
        assert_eq!((r.int("D6"), r.int("D7")), (0, 0));
        // Only the last rung changes; both LDFs are kept and written again.
        r.write(0, "LDF X6\nINC D6\nLDF X7\nINC D7\nLD X1\nOUT Y0\nEND\n")
            .unwrap();
        r.scans(2);
        // X6 OFF: acted once; X7 ON: no falling edge, until X7 goes OFF.
        assert_eq!((r.int("D6"), r.int("D7")), (1, 0), "jit {jit}");
        r.cpu.set_input(7, false);
        r.scans(1);
        assert_eq!((r.int("D6"), r.int("D7")), (1, 1));
    }
}

#[test]
fn an_aplc_program_file_is_written_through_its_sources() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("main.apl");
    std::fs::write(&path, "LD X0\nEU\nINC D0\nLD SM0\nMOV 1 D1\n").unwrap();
    let profile = softplc_core::single::profile_for(&path, None, None).unwrap();
    let clock = VirtualClock::new();
    let cpu =
        softplc_core::single::load(&path, profile, Default::default(), Box::new(clock.clone()))
            .unwrap();
    let mut cpus = softplc_core::system::Cpus::One(cpu);
    let sources = softplc_core::online::Sources::load(&path, &cpus).unwrap();
    let f = &sources.files()[sources.find("main.apl").unwrap()];
    let cpu = cpus.get_mut(0);
    cpu.set_input(0, true);
    for _ in 0..2 {
        clock.advance_us(10_000);
        cpu.scan();
    }
    let d = |cpu: &Cpu, n: &str| cpu.read_device(&DeviceSpec::parse(n).unwrap()).unwrap();
    assert_eq!((d(cpu, "D0"), d(cpu, "D1")), (Value::Int(1), Value::Int(1)));
    let program = sources
        .compile(f, "LD X0\nEU\nINC D0\nLD SM0\nMOV 2 D1\n")
        .unwrap();
    sources.check(f, &program, cpu).unwrap();
    let w = cpu.replace_program(f.slot, program).unwrap();
    assert_eq!((w.kept, w.added, w.removed), (4, 1, 1));
    clock.advance_us(10_000);
    cpu.scan();
    // EU kept its edge memory: X0 still ON counts nothing more.
    assert_eq!((d(cpu, "D0"), d(cpu, "D1")), (Value::Int(1), Value::Int(2)));
    // A text that does not compile: the diagnostics name the file and line.
    let Err(softplc_core::online::Refused::Program(diags)) = sources.compile(f, "LD X0\nFOO D0\n")
    else {
        panic!("FOO compiled");
    };
    let text = diags.to_string();
    assert!(
        text.contains("main.apl:2:1: unknown instruction `FOO`"),
        "{text}"
    );
}

#[test]
fn the_projects_rules_refuse_a_timer_written_into_a_fixed_scan_program() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("plc.toml"),
        "[[program]]\nfile = \"main.il\"\n[[program]]\nfile = \"fast.il\"\ntype = \"fixed-scan\"\ninterval = \"20ms\"\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("main.il"), "LD X0\nOUT Y0\nEND\n").unwrap();
    std::fs::write(dir.path().join("fast.il"), "LD X1\nOUT Y1\nEND\n").unwrap();
    let project = softplc_core::project::load_project(dir.path()).unwrap();
    let cpu = project.build_cpu(Box::new(VirtualClock::new())).unwrap();
    let cpus = softplc_core::system::Cpus::One(cpu);
    let sources = softplc_core::online::Sources::load(dir.path(), &cpus).unwrap();
    let f = &sources.files()[sources.find("fast.il").unwrap()];
    assert_eq!((f.slot, f.name.as_str()), (1, "fast.il"));
    let program = sources.compile(f, "LD X1\nOUT T0 K10\nEND\n").unwrap();
    let Err(softplc_core::online::Refused::Program(d)) = sources.check(f, &program, cpus.get(0))
    else {
        panic!("a timer in a fixed-scan program was accepted");
    };
    let text = d.to_string();
    assert!(
        text.contains("fast.il:2:1: a timer coil (OUT T/OUT ST) in a fixed-scan program"),
        "{text}"
    );
    // The same rung in the scan program passes.
    let f = &sources.files()[sources.find("main.il").unwrap()];
    let program = sources.compile(f, "LD X1\nOUT T0 K10\nEND\n").unwrap();
    sources.check(f, &program, cpus.get(0)).unwrap();
}

#[test]
fn an_interrupt_pointer_another_file_defines_is_refused_and_the_old_program_runs() {
    for jit in TIERS {
        let main = "LD X0\nOUT Y0\nFEND\nI28\nIRET\nEND\n";
        let mut r = rig(
            &[
                ("main.il", main, ExecType::Scan),
                ("sub.il", "LD X2\nOUT Y2\nEND\n", ExecType::Scan),
            ],
            OnlineLimits::default(),
            jit,
        );
        let e = r
            .write(1, "LD X1\nOUT Y1\nFEND\nI28\nIRET\nEND\n")
            .unwrap_err();
        assert!(
            e.contains("interrupt pointer I28 is defined in main.il and in sub.il"),
            "{e}"
        );
        assert_eq!(r.cpu.program_writes(), 0);
        r.cpu.set_input(1, true);
        r.cpu.set_input(2, true);
        r.scans(1);
        assert!(r.bit("Y2") && !r.bit("Y1"), "jit {jit}");
    }
}
