//! Differential test of the two tiers (issue #17): random well-formed
//! programs — contacts, ANB/ORB blocks, MPS, coils, MOV/arithmetic/compare,
//! forward jumps, FOR/NEXT, master control, pulse forms and index modification
//! that may go out of range — run on the interpreter and on the JIT with the
//! same inputs; after every scan the device memory, the CPU state and the
//! error (code and step) must be equal.
//!
//! Cases: `PROPTEST_CASES` (default 256 for `cargo test`; `.ci/run` runs
//! 10,000).

mod random_programs;

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;
use random_programs::{body, render};
use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_core::tier::{apply, Exec, Jit};
use softplc_jit::plan::MIN_RUN;

/// Scans per program.
const SCANS: usize = 4;

/// How a case's CPU runs: the interpreter, or the JIT with native runs of at
/// least this many ops (1: every op that can be native is, so the most calls
/// between native code and the interpreter; the default: as shipped).
#[derive(Clone, Copy)]
enum Tier {
    Interp,
    Jit(usize),
}

/// The CPU the cases run on: the default, with retentive timers (ST) and
/// without file registers (the programs do not use them, and a CPU is built
/// three times per case).
fn config() -> softplc_core::engine::CpuConfig {
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(DeviceKind::ZR, 0);
    cfg.devices.set_points(DeviceKind::STS, 16);
    cfg
}

fn cpu(src: &str, tier: Tier) -> Option<(Cpu, VirtualClock)> {
    let cfg = config();
    let prog = compile_il("p.il", src, &cfg.devices).ok()?;
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    match tier {
        Tier::Interp => {
            apply(&mut cpu, Exec::Interp).unwrap();
        }
        Tier::Jit(n) => {
            cpu.use_tier(&Jit::with_min_run(n)).unwrap();
        }
    }
    Some((cpu, clock))
}

fn same(a: &Cpu, b: &Cpu, scan: usize, src: &str) -> Result<(), TestCaseError> {
    let ctx = || format!("after scan {scan} of\n{src}");
    prop_assert_eq!(a.state(), b.state(), "{}", ctx());
    prop_assert_eq!(
        a.error().map(|e| (e.code, e.step)),
        b.error().map(|e| (e.code, e.step)),
        "{}",
        ctx()
    );
    let (ma, mb) = (a.memory(), b.memory());
    if ma.bits != mb.bits {
        let i = (0..ma.bits.len()).find(|&i| ma.bits[i] != mb.bits[i]);
        return Err(TestCaseError::fail(format!("bit {i:?} differs {}", ctx())));
    }
    if ma.words != mb.words {
        let i = (0..ma.words.len()).find(|&i| ma.words[i] != mb.words[i]);
        return Err(TestCaseError::fail(format!("word {i:?} differs {}", ctx())));
    }
    Ok(())
}

/// One case: `parts` rendered, scanned `SCANS` times with X0-X7 from `inputs`.
fn case(parts: &[String], inputs: &[u8]) -> Result<(), TestCaseError> {
    let src = render(parts);
    let Some((mut a, ca)) = cpu(&src, Tier::Interp) else {
        // Not every combination is a valid program (e.g. a nesting limit).
        return Ok(());
    };
    let (mut b, cb) = cpu(&src, Tier::Jit(1)).expect("loads on both tiers");
    let (mut c, cc) = cpu(&src, Tier::Jit(MIN_RUN)).expect("loads on both tiers");
    let x: Vec<DeviceSpec> = (0..8)
        .map(|k| DeviceSpec::parse(&format!("X{k}")).unwrap())
        .collect();
    for (scan, bits) in inputs.iter().enumerate() {
        for cpu in [&mut a, &mut b, &mut c] {
            for (k, spec) in x.iter().enumerate() {
                let on = if bits >> k & 1 != 0 { "1" } else { "0" };
                cpu.write_device(spec, on).unwrap();
            }
        }
        for (cpu, clock) in [(&mut a, &ca), (&mut b, &cb), (&mut c, &cc)] {
            // 10-115 ms: 100 ms timers count too.
            clock.advance_us(10_000 + u64::from(bits % 8) * 15_000);
            cpu.scan();
        }
        same(&a, &b, scan + 1, &src)?;
        same(&a, &c, scan + 1, &src)?;
    }
    Ok(())
}

/// Runs `f` on a thread with a large stack: the nested strategies need more
/// than a test thread has in a debug build.
fn big_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e));
}

#[test]
fn both_tiers_leave_the_same_memory_and_faults() {
    big_stack(|| {
        let cases = std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|c| c.parse().ok())
            .unwrap_or(256);
        let config = ProptestConfig {
            cases,
            failure_persistence: None,
            ..ProptestConfig::default()
        };
        let strategy = (body(2), prop::collection::vec(any::<u8>(), SCANS));
        TestRunner::new(config)
            .run(&strategy, |(parts, inputs)| case(&parts, &inputs))
            .unwrap();
    });
}

/// The generator makes programs that load, and native code runs in them:
/// most of them, or the property above would test little.
#[test]
fn most_generated_programs_load_and_run_native_code() {
    big_stack(|| {
        let mut runner = TestRunner::deterministic();
        let strategy = body(2);
        let (mut loaded, mut native, mut ops, mut native_ops) = (0, 0, 0, 0);
        for _ in 0..200 {
            let parts = strategy.new_tree(&mut runner).unwrap().current();
            let src = render(&parts);
            match compile_il("p.il", &src, &config().devices) {
                Ok(_) => loaded += 1,
                Err(d) => {
                    eprintln!("{d}\n{src}");
                    continue;
                }
            }
            let (mut cpu, _) = cpu(&src, Tier::Interp).unwrap();
            let stats = cpu.use_tier(&Jit::with_min_run(1)).unwrap().clone();
            native += usize::from(stats.native_ops > 0);
            ops += stats.ops;
            native_ops += stats.native_ops;
        }
        assert!(loaded >= 180, "{loaded} of 200 loaded");
        assert!(native >= 170, "{native} of {loaded} have native code");
        assert!(
            native_ops * 2 >= ops,
            "{native_ops} of {ops} ops run as native code"
        );
    });
}
