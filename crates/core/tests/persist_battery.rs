//! The CPU's battery-backed memory through a state directory: each attach is a
//! power-on (004 §4.3 data clear table).

use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::{Cpu, CpuConfig, ErrorMode, VirtualClock};
use softplc_core::persist::Battery;
use softplc_core::program::compile_il;

fn cpu() -> (Cpu, VirtualClock) {
    let cfg = CpuConfig {
        operation_error: ErrorMode::Continue,
        ..softplc_core::profile::default_config()
    };
    let src = "LD SM402\nSET L7\nSET M7\nMOV K1234 R100\nMOV K55 D0\nLD X0\n/ K1 K0 D1\nEND\n";
    let p = compile_il("main.il", src, &cfg.devices).unwrap();
    let clock = VirtualClock::new();
    (Cpu::new(p, cfg, Box::new(clock.clone())), clock)
}

fn get(cpu: &Cpu, d: &str) -> Value {
    cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap()
}

#[test]
fn latched_devices_file_registers_history_and_clock_survive() {
    let dir = tempfile::tempdir().unwrap();
    let (mut a, clock) = cpu();
    let mut bat = Battery::attach(dir.path(), &mut a, true).unwrap();
    a.set_input(0, true);
    clock.advance_us(10_000);
    a.scan();
    assert_eq!(a.error_history().len(), 1);
    // 2024-01-01 00:00:00 = 1704067200 s.
    a.set_calendar_unix_us(1_704_067_200_000_000);
    bat.commit(&a).unwrap();
    drop(bat);
    // Power-on: L (latch 1 by default) and R come back, M and D are cleared, the
    // error history is kept, the clock continues from 2024-01-01.
    let (mut b, _) = cpu();
    let bat_b = Battery::attach(dir.path(), &mut b, true).unwrap();
    assert_eq!(get(&b, "L7"), Value::Bool(true));
    assert_eq!(get(&b, "M7"), Value::Bool(false));
    assert_eq!(get(&b, "R100"), Value::Int(1234));
    assert_eq!(get(&b, "D0"), Value::Int(0));
    let h = b.error_history();
    assert_eq!((h.len(), h[0].code.0), (1, 4100));
    let t = b.calendar_unix_us() / 1_000_000;
    // The offset is kept rounded to whole seconds (±0.5 s).
    assert!((1_704_067_199..1_704_067_206).contains(&t), "clock {t}");
    // Without restore_clock (softplc run) the configured start is kept. (One
    // owner per state directory: the previous one is released first.)
    drop(bat_b);
    let (mut c, _) = cpu();
    let _bat = Battery::attach(dir.path(), &mut c, false).unwrap();
    assert_eq!(c.calendar_unix_us() / 1_000_000, 946_684_800);
}
