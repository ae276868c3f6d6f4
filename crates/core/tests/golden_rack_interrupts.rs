//! Interrupts of the rack and of errors (004 §4.1.3 L1201-1260, §7.15.1
//! L4997-5022, §10.10 and App. 3 L7342-7413, L10866-10905; interrupt
//! counters L6600-6645): I0-I15 from a QI60's rising inputs, I50-I255 from
//! an intelligent module's causes, the error interrupts I32-I39, their
//! priorities, EI/DI/IMASK, the load check of pointers no slot raises and
//! the interrupt counters. Values worked out by hand in the comments.

mod common;
use std::sync::Arc;

use common::{assert_running, assert_stopped, Plc};
use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::{Cpu, CpuState, VirtualClock};
use softplc_core::program::{compile_il_in, dialect_for, Dialect, ProcessSettings};
use softplc_ir::rack::{Module, ModuleIo, ModuleProfile, Rack, Slot, SlotType};

/// A QI60 in slot 0 (X0-XF raise I0-I15), 16 inputs X10-X1F in slot 1.
const QI60: &str = "[[program]]\nfile = \"main.il\"\n\
    [[slot]]\ntype = \"interrupt\"\nmodule = \"QI60\"\npoints = 16\n\
    [[slot]]\ntype = \"input\"\npoints = 16\n";

fn qi60(program: &str) -> Plc {
    Plc::project(QI60, &[("main.il", program)])
}

/// I0 and I5 each note their turn: D100 counts the interrupts run, I0
/// stores its turn in D0, I5 in D5.
const I0_I5: &str = "FEND\nI0\nLD SM400\nINC D100\nMOV D100 D0\nIRET\n\
    I5\nLD SM400\nINC D100\nMOV D100 D5\nIRET\nEND\n";

/// A rising X0 runs I0 once at the start of the next scan, after the input
/// refresh; a held input does not run it again; the next rising edge does
/// (App. 3: I0 is the QI60's first point).
#[test]
fn qi60_rising_input_runs_i0_once() {
    let mut p = qi60(&format!("EI\n{I0_I5}"));
    p.scan();
    assert_eq!(p.int("D100"), 0);
    // The door's write reaches the QI60 through the input image.
    p.set("X0", "1").scan();
    assert_eq!((p.int("D100"), p.int("D0")), (1, 1));
    p.scans(3);
    assert_eq!(p.int("D100"), 1, "a held input is no new edge");
    p.set("X0", "0").scan();
    assert_eq!(p.int("D100"), 1, "a falling edge raises nothing");
    p.set("X0", "1").scan();
    assert_eq!(p.int("D100"), 2);
    // An input module's X10 is no interrupt input.
    p.set("X10", "1").scan();
    assert_eq!(p.int("D100"), 2);
    assert_eq!(p.cpu.interrupt_counts()[0], 2);
    assert_running(&p);
}

/// Two inputs rising in the same scan run by priority (App. 3: I0 237,
/// I5 242): I0 first although I5's program comes later in the file either
/// way.
#[test]
fn simultaneous_edges_run_by_priority() {
    let swapped = "FEND\nI5\nLD SM400\nINC D100\nMOV D100 D5\nIRET\n\
        I0\nLD SM400\nINC D100\nMOV D100 D0\nIRET\nEND\n";
    for program in [I0_I5, swapped] {
        let mut p = qi60(&format!("EI\n{program}"));
        p.scan();
        p.set("X5", "1").set("X0", "1").scan();
        assert_eq!((p.int("D0"), p.int("D5")), (1, 2), "{program}");
    }
}

/// A QI60 interrupt outranks the fixed-cycle I31 (App. 3: I0 237, I31
/// 253): in the scan at 10 ms, where I31 is due, I0 runs first.
#[test]
fn qi60_before_fixed_cycle() {
    let program = "EI\nFEND\nI0\nLD SM400\nINC D100\nMOV D100 D0\nIRET\n\
        I31\nLD SM400\nINC D100\nMOV D100 D31\nIRET\nEND\n";
    let mut p = qi60(program);
    // Scan 1 (10 ms): I31's first occurrence waits (DI since power-on); EI.
    p.scan();
    // Scan 2 (20 ms): I0, then the waiting I31 and the 20 ms one.
    p.set("X0", "1").scan();
    assert_eq!(p.int("D0"), 1);
    assert_eq!((p.int("D31"), p.int("D100")), (3, 3));
}

/// DI holds a rising edge until EI; several edges while disabled are
/// remembered once (004 L1236-1238).
#[test]
fn di_holds_the_edge_until_ei() {
    let mut p = qi60(&format!("LD M0\nDI\nLDI M0\nEI\n{I0_I5}"));
    p.set("M0", "1").scan();
    p.set("X0", "1").scan();
    p.set("X0", "0").scan();
    p.set("X0", "1").scan();
    assert_eq!(p.int("D100"), 0, "disabled: nothing runs");
    // EI runs in this scan, after the interrupt service.
    p.set("M0", "0").scan();
    assert_eq!(p.int("D100"), 0);
    p.scan();
    assert_eq!(p.int("D100"), 1, "two edges while disabled run once");
    p.scans(2);
    assert_eq!(p.int("D100"), 1);
}

/// IMASK masks one QI60 pointer (I0: bit 0 of the first word); its edge
/// waits until the mask allows it.
#[test]
fn imask_masks_a_qi60_pointer() {
    let program = format!(
        "LD SM400\nFMOV HFFFF D200 K16\nLD M0\nMOV HFFFE D200\nLD SM400\nIMASK D200\nEI\n{I0_I5}"
    );
    let mut p = qi60(&program);
    p.set("M0", "1").scan();
    p.set("X0", "1").set("X5", "1").scan();
    assert_eq!((p.int("D0"), p.int("D5")), (0, 1), "I0 masked, I5 runs");
    p.set("M0", "0").scan();
    p.scan();
    assert_eq!(p.int("D0"), 2, "I0 runs once unmasked");
}

// ------------------------------------------------ an intelligent module's I50

/// A test module: a cause for each bit the program writes into its word 0,
/// raised at END (the word is then cleared), as an intelligent function
/// module raises its interrupt causes.
#[derive(Debug)]
struct Raiser;

impl Module for Raiser {
    fn power_on(&mut self, _io: &mut ModuleIo<'_>) {}
    fn end(&mut self, io: &mut ModuleIo<'_>, _now_us: u64) {
        io.raised = u64::from(io.buffer[0]);
        io.buffer[0] = 0;
    }
}

static RAISER: ModuleProfile = ModuleProfile {
    name: "raiser",
    kind: SlotType::Intelligent,
    points: 16,
    buffer_words: 4,
    pointers: None,
    causes: 2,
    manual: "test module",
    new: |_| Box::new(Raiser),
    switches: None,
};

/// A CPU with the raiser at X/Y0 (unit 0), causes 0 and 1 → I50 and I51,
/// and a QI60 at X10-X1F (I0-I15).
struct Bench {
    cpu: Cpu,
    clock: VirtualClock,
}

impl Bench {
    fn new(src: &str) -> Bench {
        let mut cfg = softplc_core::profile::default_config();
        let slot = Slot {
            interrupts: vec![(0, 50), (1, 51)],
            ..Slot::with_module(0, 0, &RAISER)
        };
        let qi60 = Slot::with_module(1, 16, &softplc_modules::QI60);
        cfg.devices.set_units(&[(0, 4)]);
        cfg.rack = Arc::new(Rack {
            slots: vec![slot, qi60],
        });
        let base = dialect_for(cfg.profile, ProcessSettings::default());
        let dialect = Dialect {
            settings: base.settings.clone().with(cfg.rack.clone()),
            ..base
        };
        let prog = compile_il_in("test.il", src, &cfg.devices, &dialect)
            .unwrap_or_else(|d| panic!("load failed:\n{d}"));
        let clock = VirtualClock::new();
        let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
        softplc_core::tier::apply_env(&mut cpu);
        Bench { cpu, clock }
    }

    fn scan(&mut self) -> &mut Self {
        self.clock.advance_us(10_000);
        self.cpu.scan();
        self
    }

    fn set(&mut self, dev: &str, value: &str) -> &mut Self {
        let spec = DeviceSpec::parse(dev).unwrap();
        self.cpu.write_device(&spec, value).unwrap();
        self
    }

    fn int(&self, dev: &str) -> i64 {
        match self.cpu.read_device(&DeviceSpec::parse(dev).unwrap()) {
            Ok(Value::Int(i)) => i,
            v => panic!("{dev}: {v:?}"),
        }
    }
}

/// The program asks the module for cause 0: the module raises it at END and
/// I50 runs at the start of the next scan (004 L5600-5620 interrupt pointer
/// setting; App. 3 I50-I255).
#[test]
fn module_cause_runs_i50_at_the_next_scan() {
    let src = "EI\nLDP M0\nMOV K1 U0\\G0\nLDP M1\nMOV K3 U0\\G0\nFEND\n\
        I50\nLD SM400\nINC D100\nMOV D100 D50\nIRET\n\
        I51\nLD SM400\nINC D100\nMOV D100 D51\nIRET\nEND\n";
    let mut b = Bench::new(src);
    b.scan();
    b.set("M0", "1").scan();
    assert_eq!(b.int("D100"), 0, "raised at this scan's END");
    b.scan();
    assert_eq!((b.int("D100"), b.int("D50")), (1, 1));
    b.scan();
    assert_eq!(b.int("D100"), 1, "one cause, one run");
    // Both causes at one END: I50 (priority 18) before I51 (19).
    b.set("M1", "1").scan().scan();
    assert_eq!((b.int("D50"), b.int("D51")), (2, 3));
    assert_eq!(b.cpu.state(), CpuState::Run);
}

/// I50 outranks the QI60's I0 (App. 3: I50 18, I0 237): the cause raised
/// at END and the edge seen at the next input refresh run in one service,
/// I50 first.
#[test]
fn module_interrupt_before_qi60() {
    let src = "EI\nLDP M0\nMOV K1 U0\\G0\nFEND\n\
        I0\nLD SM400\nINC D100\nMOV D100 D0\nIRET\n\
        I50\nLD SM400\nINC D100\nMOV D100 D50\nIRET\nEND\n";
    let mut b = Bench::new(src);
    b.scan();
    b.set("M0", "1").scan();
    b.set("X10", "1").scan();
    assert_eq!((b.int("D50"), b.int("D0")), (1, 2));
}

/// A module's pointer loads only when its slot's interrupt pointer setting
/// names it.
#[test]
fn module_pointer_accepted_only_with_its_slot_setting() {
    // A generic module whose cause 0 raises I50: I50 loads, I60 does not.
    let toml = "[[program]]\nfile = \"main.il\"\n\
        [[slot]]\ntype = \"intelligent\"\nmodule = \"generic\"\ninterrupts = { 0 = \"I50\" }\n";
    let ok = Plc::try_project(toml, &[("main.il", "EI\nFEND\nI50\nIRET\nEND\n")]);
    assert!(ok.is_ok(), "{:?}", ok.err());
    let err = Plc::try_project(
        toml,
        &[("main.il", "EI\nFEND\nI50\nIRET\nI60\nIRET\nEND\n")],
    )
    .err()
    .expect("I60 has no slot");
    assert!(
        err.starts_with("5:1: interrupt pointer I60: no slot raises it"),
        "{err}"
    );
    assert!(err.contains("interrupts = { 0 = \"I50\" }"), "{err}");
}

// ------------------------------------------------ load checks

/// I5 needs a QI60; without one the load fails naming the pointer and the
/// file:line:col of its definition. I28-I31 and the error pointers need no
/// rack.
#[test]
fn qi60_pointer_without_a_qi60_is_a_load_error() {
    let toml = "[[program]]\nfile = \"main.il\"\n";
    let program = "EI\nFEND\nI28\nIRET\nI32\nIRET\nI39\nIRET\nI5\nIRET\nEND\n";
    let dir = common::project::scratch(toml);
    std::fs::write(dir.join("main.il"), program).unwrap();
    let built = softplc_core::project::load_project(&dir)
        .and_then(|p| p.build_cpu(Box::new(VirtualClock::new())));
    let _ = std::fs::remove_dir_all(&dir);
    let d = built.err().expect("I5 has no QI60");
    assert_eq!(d.0.len(), 1, "{d}");
    let d = &d.0[0];
    assert!(d.file.ends_with("main.il"), "{}", d.file);
    assert_eq!((d.line, d.col), (9, 1));
    assert!(
        d.message.starts_with(
            "interrupt pointer I5: no slot raises it (an interrupt module (QI60) raises I0-I15"
        ),
        "{}",
        d.message
    );
    // With the QI60 it loads; I16-I27 (sequence-start modules) never do.
    qi60(program);
    let err = Plc::try_project(QI60, &[("main.il", "FEND\nI16\nIRET\nEND\n")]).err();
    assert!(err.is_some_and(|e| e.contains("I16: no slot raises it")));
    // A single program file has no rack.
    let d = common::diagnostics("FEND\nI0\nIRET\nEND\n");
    assert!(
        d[0].starts_with("2:1: interrupt pointer I0: no slot"),
        "{d:?}"
    );
}

// ------------------------------------------------ error interrupts

/// Enables every interrupt pointer (IMASK with all bits, EI), once a scan.
const ENABLE_ALL: &str = "LD SM400\nFMOV HFFFF D300 K16\nIMASK D300\nEI\n";

/// I32: a stop error (4101, an index past D) runs I32, then the CPU stops
/// (004 L10902 *3); without IMASK it stays disabled and the CPU just stops
/// (L5019-5021).
#[test]
fn i32_runs_before_a_stop_error_stops_the_cpu() {
    let body = "LD M0\nMOV K1 D0Z0\nFEND\nI32\nLD SM400\nINC D200\nMOV SD0 D201\nIRET\nEND\n";
    let mut p = Plc::new(&format!("{ENABLE_ALL}{body}"));
    p.scan();
    p.set("Z0", "20000").set("M0", "1").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D200"), 1);
    assert_eq!(p.int("D201"), 4101, "I32 sees the error code");
    // Not enabled by IMASK: no I32.
    let mut p = Plc::new(&format!("EI\n{body}"));
    p.scan();
    p.set("Z0", "20000").set("M0", "1").scan();
    assert_stopped(&p, 4101);
    assert_eq!(p.int("D200"), 0);
}

/// I35: with operation errors set to continue, an operation error (4100,
/// division by 0) runs I35 at the start of the next scan, once per error;
/// with "stop" it is I32's (L5001: only errors set to continue run their
/// class's pointer).
#[test]
fn i35_on_a_continued_operation_error() {
    let program = format!(
        "{ENABLE_ALL}LD M0\n/ D0 K0 D10\nFEND\n\
         I35\nLD SM400\nINC D200\nIRET\nI32\nLD SM400\nINC D232\nIRET\nEND\n"
    );
    let toml = "[[program]]\nfile = \"main.il\"\n[ras]\noperation_error = \"continue\"\n";
    let mut p = Plc::project(toml, &[("main.il", &program)]);
    p.scan();
    p.set("M0", "1").scan();
    assert_eq!(p.state(), CpuState::Run);
    assert_eq!(p.int("SD0"), 4100);
    assert_eq!(p.int("D200"), 0, "runs at the next interrupt service");
    p.set("M0", "0").scan();
    assert_eq!(p.int("D200"), 1);
    p.scan();
    assert_eq!((p.int("D200"), p.int("D232")), (1, 0));
    // Default "stop": I32, not I35.
    let mut p = Plc::project(
        "[[program]]\nfile = \"main.il\"\n",
        &[("main.il", &program)],
    );
    p.scan();
    p.set("M0", "1").scan();
    assert_stopped(&p, 4100);
    assert_eq!((p.int("D200"), p.int("D232")), (0, 1));
}

/// An error while its pointer is disabled runs nothing, not even once
/// enabled (QCPU User's Manual (Function Explanation, Program
/// Fundamentals) §3.1.3: error causes while disabled are discarded).
#[test]
fn an_error_while_disabled_is_not_remembered() {
    let program = "LD M1\nFMOV HFFFF D300 K16\nIMASK D300\nEI\nLD M0\n/ D0 K0 D10\nFEND\n\
         I35\nLD SM400\nINC D200\nIRET\nEND\n";
    let toml = "[[program]]\nfile = \"main.il\"\n[ras]\noperation_error = \"continue\"\n";
    let mut p = Plc::project(toml, &[("main.il", program)]);
    p.set("M0", "1").scan();
    p.set("M0", "0").set("M1", "1").scan().scan();
    assert_eq!(p.int("D200"), 0);
}

/// I38: a scan longer than the constant scan is PRG.TIME OVER (5010), a
/// continuing error detected at END; I38 runs at the start of the next
/// scan. Scans of 10 ms against 5 ms overrun every time.
#[test]
fn i38_on_prg_time_over() {
    let program = format!("{ENABLE_ALL}FEND\nI38\nLD SM400\nINC D200\nIRET\nEND\n");
    let toml = "[[program]]\nfile = \"main.il\"\n[ras]\nconstant_scan = \"5ms\"\n";
    let mut p = Plc::project(toml, &[("main.il", &program)]);
    p.scan();
    assert_eq!(p.int("SD0"), 5010);
    assert_eq!(p.int("D200"), 0);
    p.scans(3);
    assert_eq!(p.int("D200"), 3);
    assert_eq!(p.state(), CpuState::Run);
}

/// I39: an annunciator turning ON (F****, 9000) runs I39 at the next scan.
#[test]
fn i39_on_an_annunciator() {
    let program = format!("{ENABLE_ALL}LD M0\nOUT F5\nFEND\nI39\nLD SM400\nINC D200\nIRET\nEND\n");
    let mut p = Plc::new(&program);
    p.scan();
    p.set("M0", "1").scan();
    assert_eq!(p.int("SD0"), 9000);
    p.scan();
    assert_eq!(p.int("D200"), 1);
}

/// Error interrupts outrank every other (App. 3: I35 3, I0 237): an
/// operation error in I0 runs I35 right after I0, in the same service.
#[test]
fn an_error_in_an_interrupt_program_runs_its_pointer_after_it() {
    let toml = format!("{QI60}[ras]\noperation_error = \"continue\"\n");
    let program = format!(
        "{ENABLE_ALL}FEND\nI0\nLD SM400\n/ D0 K0 D10\nINC D100\nMOV D100 D0\nIRET\n\
         I35\nLD SM400\nINC D100\nMOV D100 D35\nIRET\nEND\n"
    );
    let mut p = Plc::project(&toml, &[("main.il", &program)]);
    p.scan();
    p.set("X0", "1").scan();
    assert_eq!((p.int("D0"), p.int("D35")), (1, 2));
}

// ------------------------------------------------ interrupt counters

/// `counter_start = "C300"`: C300 counts I0, C331 I31 (004 L6600-6645),
/// each interrupt taken with EI, whether or not a program exists.
#[test]
fn interrupt_counters() {
    let toml = format!("{QI60}[interrupts]\ncounter_start = \"C300\"\n");
    // No I0 program; I31 every 10 ms; DI while M0.
    let program = "LD M0\nDI\nLDI M0\nEI\nFEND\nI31\nIRET\nEND\n";
    let mut p = Plc::project(&toml, &[("main.il", program)]);
    p.scan();
    for _ in 0..3 {
        p.set("X0", "1").scan().set("X0", "0").scan();
    }
    assert_eq!(p.int("CN300"), 3);
    // I31 at 10 ms (waited until EI), 20 … 70 ms: 7.
    assert_eq!(p.int("CN331"), 7);
    // DI from 80 ms (I31 at 80 ms still ran): two edges and the I31 of 90,
    // 100 and 110 ms wait, and will count once each.
    p.set("M0", "1").scan();
    p.set("X0", "1")
        .scan()
        .set("X0", "0")
        .scan()
        .set("X0", "1")
        .scan();
    assert_eq!((p.int("CN300"), p.int("CN331")), (3, 8));
    // EI at 120 ms; at 130 ms the waiting causes (I0 once; I31 of 90-120
    // ms once) and the 130 ms I31.
    p.set("M0", "0").scan().scan();
    assert_eq!(p.int("CN300"), 4);
    assert_eq!(p.int("CN331"), 8 + 1 + 1);
}

/// `counter_start` must leave room for 256 counters in C (1024 points by
/// default) and name a counter.
#[test]
fn counter_start_checks() {
    let load = |v: &str| {
        Plc::try_project(
            &format!("[[program]]\nfile = \"main.il\"\n[interrupts]\ncounter_start = \"{v}\"\n"),
            &[("main.il", "LD SM400\nOUT Y0\nEND\n")],
        )
        .err()
    };
    assert!(load("C768").is_none());
    let e = load("C769").expect("past C1023");
    assert!(e.contains("C769-C1024") && e.contains("C1023"), "{e}");
    let e = load("D300").expect("not a counter");
    assert!(e.contains("is not a counter"), "{e}");
}
