//! State files over random programs and inputs on both tiers (contract
//! §7): N+M scans equal N scans, a save, a load into a new CPU and M scans,
//! bit for bit — device memory and the hidden state (the two CPUs' state
//! files equal). And no bytes make a load panic or change a CPU it refuses.
//!
//! Cases: `PROPTEST_CASES` (default 64 for `cargo test`).

mod random_programs;

use proptest::prelude::*;
use proptest::test_runner::TestRunner;
use random_programs::{body, render};
use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::{Cpu, VirtualClock};
use softplc_core::program::compile_il;
use softplc_core::snapshot;
use softplc_core::tier::{apply, Exec, Jit};

#[derive(Clone, Copy, Debug)]
enum Tier {
    Interp,
    Jit,
}

fn cpu(src: &str, tier: Tier) -> Option<(Cpu, VirtualClock)> {
    let mut cfg = softplc_core::profile::default_config();
    // No file registers: the programs do not use them.
    cfg.devices.set_points(DeviceKind::ZR, 0);
    let prog = compile_il("p.il", src, &cfg.devices).ok()?;
    let clock = VirtualClock::new();
    let mut cpu = Cpu::new(prog, cfg, Box::new(clock.clone()));
    match tier {
        Tier::Interp => apply(&mut cpu, Exec::Interp).map(|_| ()).unwrap(),
        Tier::Jit => cpu.use_tier(&Jit::with_min_run(1)).map(|_| ()).unwrap(),
    }
    Some((cpu, clock))
}

/// X0-X7 from `inputs[k]` before scan k+1, scans `from..to`.
fn scans(cpu: &mut Cpu, clock: &VirtualClock, inputs: &[u8], from: usize, to: usize) {
    let x: Vec<DeviceSpec> = (0..8)
        .map(|k| DeviceSpec::parse(&format!("X{k}")).unwrap())
        .collect();
    for bits in &inputs[from..to] {
        for (k, spec) in x.iter().enumerate() {
            let on = if bits >> k & 1 != 0 { "1" } else { "0" };
            cpu.write_device(spec, on).unwrap();
        }
        clock.advance_us(10_000);
        cpu.scan();
    }
}

fn case(parts: &[String], inputs: &[u8], cut: usize, tier: Tier) -> Result<(), TestCaseError> {
    let src = render(parts);
    let Some((mut whole, ca)) = cpu(&src, tier) else {
        return Ok(());
    };
    scans(&mut whole, &ca, inputs, 0, inputs.len());
    let (mut first, cb) = cpu(&src, tier).unwrap();
    scans(&mut first, &cb, inputs, 0, cut);
    let file = snapshot::save(&mut first);
    let (mut second, cc) = cpu(&src, tier).unwrap();
    snapshot::load(&mut second, &file).map_err(|e| TestCaseError::fail(e.to_string()))?;
    scans(&mut second, &cc, inputs, cut, inputs.len());
    let ctx = || format!("{tier:?}, cut after scan {cut} of {}:\n{src}", inputs.len());
    prop_assert_eq!(whole.state(), second.state(), "{}", ctx());
    prop_assert_eq!(whole.error(), second.error(), "{}", ctx());
    prop_assert!(
        whole.memory().bits == second.memory().bits,
        "bits {}",
        ctx()
    );
    prop_assert!(
        whole.memory().words == second.memory().words,
        "words {}",
        ctx()
    );
    prop_assert!(
        snapshot::save(&mut whole) == snapshot::save(&mut second),
        "hidden state {}",
        ctx()
    );
    Ok(())
}

fn big_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e));
}

fn config(default: u32) -> ProptestConfig {
    ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|c| c.parse().ok())
            .unwrap_or(default),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

#[test]
fn n_plus_m_scans_equal_n_save_load_m_on_both_tiers() {
    big_stack(|| {
        let strategy = (
            body(2),
            prop::collection::vec(any::<u8>(), 2..8),
            any::<prop::sample::Index>(),
        );
        TestRunner::new(config(64))
            .run(&strategy, |(parts, inputs, cut)| {
                let cut = cut.index(inputs.len() + 1);
                case(&parts, &inputs, cut, Tier::Interp)?;
                case(&parts, &inputs, cut, Tier::Jit)
            })
            .unwrap();
    });
}

/// Any damage to a state file is refused — by the checksum, or, with the
/// checksum made to fit, by the checks of every section (or it loads as a
/// state of valid values) — never a panic, and a refused file leaves the
/// CPU as it was.
#[test]
fn damaged_files_never_panic_nor_change_the_cpu() {
    let src = "LD X0\nOUT T0 K10\nLDP X1\nINC D0\nLD X0\nOUT C0 K3\nEND\n";
    let (mut a, clock) = cpu(src, Tier::Interp).unwrap();
    scans(&mut a, &clock, &[1, 3, 0, 2], 0, 4);
    let file = snapshot::save(&mut a);
    let (b, _) = cpu(src, Tier::Interp).unwrap();
    let b = std::cell::RefCell::new(b);
    let before = snapshot::save(&mut b.borrow_mut());
    let strategy = (
        prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..4),
        any::<prop::sample::Index>(),
        any::<bool>(),
        any::<bool>(),
    );
    TestRunner::new(config(256))
        .run(&strategy, |(flips, cut, truncate, reseal)| {
            let mut bad = file.clone();
            for (at, x) in &flips {
                bad[at.index(file.len())] ^= x | 1;
            }
            if truncate {
                bad.truncate(cut.index(file.len()));
            }
            // With a checksum that fits, the checks behind it see the damage.
            if reseal {
                snapshot::reseal(&mut bad);
            }
            let b = &mut *b.borrow_mut();
            if snapshot::load(b, &bad).is_err() {
                prop_assert!(snapshot::save(b) == before);
            } else {
                // Only a file the checksum still accepts: back to the start.
                snapshot::load(b, &before).unwrap();
            }
            Ok(())
        })
        .unwrap();
    // Bytes that only look like a header.
    let mut fake = snapshot::MAGIC.to_vec();
    fake.resize(snapshot::HEADER_LEN, 0xFF);
    assert!(snapshot::load(&mut b.borrow_mut(), &fake).is_err());
}

/// Random bytes after a header of this CPU, their length and checksum made
/// to fit (as the fuzz target does): refused — under 512 bytes cannot hold
/// the CPU's device memory — never a panic, the CPU unchanged.
#[test]
fn random_bodies_never_panic() {
    let (mut cpu, _) = cpu("LD X0\nOUT T0 K10\nEND\n", Tier::Interp).unwrap();
    let before = snapshot::save(&mut cpu);
    let header = before[..snapshot::HEADER_LEN].to_vec();
    let cpu = std::cell::RefCell::new(cpu);
    TestRunner::new(config(256))
        .run(&prop::collection::vec(any::<u8>(), 0..512), |body| {
            let mut file = [&header[..], &body[..]].concat();
            snapshot::reseal(&mut file);
            let cpu = &mut *cpu.borrow_mut();
            prop_assert!(snapshot::load(cpu, &file).is_err());
            prop_assert!(snapshot::save(cpu) == before);
            Ok(())
        })
        .unwrap();
}

/// An edited file whose checksum was made to fit and which still loads
/// (its times, counts and flags edited within what the checks accept): the
/// scans that follow do not panic. Bytes are changed in the clock section
/// at the start of the body and in the scalar state after device memory.
#[test]
fn scans_after_an_edited_file_do_not_panic() {
    let src = "LD X0\nOUT T0 K10\nLDP X1\nINC D0\nLD X0\nOUT C0 K3\nEND\n";
    let (mut a, clock) = cpu(src, Tier::Interp).unwrap();
    scans(&mut a, &clock, &[1, 3, 0], 0, 3);
    let file = snapshot::save(&mut a);
    let n = file.len();
    // The models' text, then the TIME section's tag and length.
    let time = snapshot::HEADER_LEN + 2 + "Q06HCPU".len() + 12;
    let strategy = (
        prop::collection::vec(
            (any::<bool>(), any::<prop::sample::Index>(), any::<u8>()),
            1..3,
        ),
        prop::collection::vec(any::<u8>(), 3),
    );
    TestRunner::new(config(64))
        .run(&strategy, |(flips, inputs)| {
            let mut bad = file.clone();
            for (head, at, x) in &flips {
                let i = if *head {
                    time + at.index(28)
                } else {
                    n - 1 - at.index(3000)
                };
                bad[i] ^= x | 1;
            }
            snapshot::reseal(&mut bad);
            let (mut c, clock) = cpu(src, Tier::Interp).unwrap();
            if snapshot::load(&mut c, &bad).is_ok() {
                scans(&mut c, &clock, &inputs, 0, 3);
            }
            Ok(())
        })
        .unwrap();
}
