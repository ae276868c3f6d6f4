//! Forced ON/OFF of X and Y (`Cpu::force`, `release`, `forced`; contract §3.1,
//! docs/forcing.md): forced inputs before the program, forced outputs after
//! it, forced values win over program and external writes, a write made while
//! forced takes effect at release, RESET and power-on release everything.

use softplc_core::access::{DeviceSpec, Value};
use softplc_core::device::{DeviceConfig, DeviceKind};
use softplc_core::engine::{Cpu, VirtualClock};

fn cpu(src: &str) -> Cpu {
    let p = softplc_core::program::compile_il("t.il", src, &DeviceConfig::default()).unwrap();
    Cpu::new(
        p,
        softplc_core::profile::default_config(),
        Box::new(VirtualClock::new()),
    )
}

fn bit(cpu: &Cpu, d: &str) -> bool {
    cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap() == Value::Bool(true)
}

fn write(cpu: &mut Cpu, d: &str, v: bool) {
    cpu.write_value(&DeviceSpec::parse(d).unwrap(), &Value::Bool(v))
        .unwrap();
}

#[test]
fn forced_input_is_seen_by_the_program_and_wins_over_the_input_image() {
    let mut c = cpu("LD X0\nOUT Y0\nEND\n");
    c.force(DeviceKind::X, 0, true).unwrap();
    c.scan();
    assert!(bit(&c, "Y0"), "the program sees forced X0 ON");
    // An external write while forced is kept for the release.
    c.set_input(0, false);
    write(&mut c, "X0", false);
    assert!(bit(&c, "X0"), "the forced value wins over a write");
    c.scan();
    assert!(bit(&c, "Y0"));
    assert_eq!(
        c.forced().collect::<Vec<_>>(),
        vec![(DeviceKind::X, 0, true)]
    );
    // Release: the input image (OFF) takes over at once and at the next scan.
    assert!(c.release(DeviceKind::X, 0));
    assert!(!bit(&c, "X0"));
    c.scan();
    assert!(!bit(&c, "Y0"));
    assert!(!c.release(DeviceKind::X, 0), "nothing left to release");
}

#[test]
fn write_to_a_forced_input_takes_effect_at_release() {
    let mut c = cpu("LD X1\nOUT Y1\nEND\n");
    c.force(DeviceKind::X, 1, false).unwrap();
    write(&mut c, "X1", true);
    c.scan();
    assert!(!bit(&c, "Y1"));
    c.release(DeviceKind::X, 1);
    assert!(bit(&c, "X1"), "the write made while forced");
    c.scan();
    assert!(bit(&c, "Y1"));
}

#[test]
fn forced_output_wins_over_the_program_and_returns_to_it_at_release() {
    let mut c = cpu("LD X0\nOUT Y0\nLD Y0\nOUT M0\nEND\n");
    c.force(DeviceKind::Y, 0, true).unwrap();
    c.scan();
    // The program wrote Y0 OFF, then M0 from Y0 (OFF): the output is forced
    // after the program.
    assert!(!bit(&c, "M0"));
    assert!(bit(&c, "Y0"));
    assert!(c.output(0));
    // The external output stays forced even in STOP.
    c.set_stop();
    assert!(c.output(0));
    c.set_run().unwrap();
    c.scan();
    c.release(DeviceKind::Y, 0);
    assert!(!bit(&c, "Y0"), "the program's last result");
    assert!(!c.output(0));
}

#[test]
fn write_to_a_forced_output_takes_effect_at_release() {
    let mut c = cpu("END\n");
    c.force(DeviceKind::Y, 2, false).unwrap();
    write(&mut c, "Y2", true);
    assert!(!bit(&c, "Y2"));
    c.scan();
    assert!(!bit(&c, "Y2"));
    c.release(DeviceKind::Y, 2);
    assert!(bit(&c, "Y2"));
}

#[test]
fn word_and_span_writes_keep_forces() {
    let mut c = cpu("END\n");
    c.force(DeviceKind::Y, 0, true).unwrap();
    // K4Y0 written to 0 through a digit name, then a span write.
    c.write_value(&DeviceSpec::parse("K4Y0").unwrap(), &Value::Int(0))
        .unwrap();
    assert!(bit(&c, "Y0"));
    let s = c
        .span(DeviceKind::Y, 0, 16, softplc_core::access::RBlock::First)
        .unwrap();
    c.write_span_bits(&s, &[false; 16]).unwrap();
    assert!(bit(&c, "Y0"));
    c.release(DeviceKind::Y, 0);
    assert!(!bit(&c, "Y0"));
}

#[test]
fn only_x_and_y_within_their_points_can_be_forced() {
    let mut c = cpu("END\n");
    assert!(c.force(DeviceKind::M, 0, true).is_err());
    assert!(c.force(DeviceKind::X, 0x2000, true).is_err());
    assert_eq!(c.forced().count(), 0);
}

#[test]
fn reset_releases_every_force() {
    let mut c = cpu("END\n");
    c.force(DeviceKind::X, 3, true).unwrap();
    c.force(DeviceKind::Y, 3, true).unwrap();
    c.set_stop();
    c.reset().unwrap();
    assert_eq!(c.forced().count(), 0);
    assert!(!bit(&c, "X3"));
    assert!(!bit(&c, "Y3"));
}

#[test]
fn release_all_releases_everything() {
    let mut c = cpu("END\n");
    c.force(DeviceKind::X, 3, true).unwrap();
    c.force(DeviceKind::Y, 4, true).unwrap();
    c.release_all();
    assert_eq!(c.forced().count(), 0);
    assert!(!bit(&c, "X3") && !bit(&c, "Y4"));
}

#[test]
fn the_program_computes_from_the_output_under_the_force() {
    // Self-holding: X0 starts Y0, which holds itself; Y0 forced OFF does not
    // break the program's own circuit, and M0 sees the program's Y0.
    let mut c = cpu("LD X0\nOR Y0\nOUT Y0\nLD Y0\nOUT M0\nEND\n");
    c.set_input(0, true);
    c.scan();
    c.set_input(0, false);
    c.force(DeviceKind::Y, 0, false).unwrap();
    c.scan();
    assert!(!bit(&c, "Y0") && !c.output(0), "forced OFF outside");
    assert!(bit(&c, "M0"), "the circuit still holds");
    c.release(DeviceKind::Y, 0);
    assert!(bit(&c, "Y0"));
}

#[test]
fn a_qcpu_registers_32_forces_and_refuses_the_33rd() {
    // 004 §7.9.3 (f): 32 devices in all can be registered for forced ON/OFF.
    let mut c = cpu("END\n");
    assert_eq!(c.max_forces(), 32);
    for n in 0..16 {
        c.force(DeviceKind::X, n, true).unwrap();
        c.force(DeviceKind::Y, n, false).unwrap();
    }
    // Changing a registered force takes no new registration.
    c.force(DeviceKind::X, 0, false).unwrap();
    assert_eq!(
        c.force(DeviceKind::X, 0x20, true).unwrap_err(),
        "at most 32 devices can be forced on a Q06HCPU (release one first)"
    );
    assert_eq!(c.forced().count(), 32);
    assert!(!bit(&c, "X20"));
    c.release(DeviceKind::Y, 15);
    c.force(DeviceKind::X, 0x20, true).unwrap();
    assert!(bit(&c, "X20"));
}

#[test]
fn each_model_has_its_own_force_limit() {
    for p in softplc_core::profile::all() {
        let want = if softplc_core::profile::is_aplc(p) {
            128 // 128 bit devices (APLC-TCP manual, performance specifications)
        } else {
            32
        };
        assert_eq!(p.max_forces, want, "{}", p.model);
    }
}
