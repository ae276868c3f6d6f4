//! APLC-TCP retention through a state directory (decision D5, L983-991):
//! each attach is a power-on; only the words of D6000-D6999 that EROMWR saved
//! come back, over the initial values (EEPROM data outranks the data block,
//! table 2-2 L971-979); every other device starts cleared, then takes its
//! initial value.

use softplc_core::access::DeviceSpec;
use softplc_core::access::Value;
use softplc_core::aplc::{self, Name};
use softplc_core::engine::{Cpu, InitialValue, VirtualClock};
use softplc_core::persist::Battery;

/// SM1 writes D6000 = 1234, D6001 = 99, D6100 = 5 and D0 = 55 on the first
/// scan; M0's rising edge stores D6000-D6001 in the EEPROM.
const SRC: &str = "LD SM1\nMOV 1234 D6000\nMOV 99 D6001\nMOV 5 D6100\nMOV 55 D0\nSET M7\n\
LD M0\nEROMWR D6000 2\n";

/// `[initial]` D6000 = 7, D6001 = 8, D6002 = 9.
fn cpu() -> (Cpu, VirtualClock) {
    let p = aplc::load_bytes("main.apl", SRC.as_bytes()).unwrap();
    let mut cfg = aplc::cpu_config();
    for (d, v) in [("D6000", "7"), ("D6001", "8"), ("D6002", "9")] {
        cfg.initial_values.push(InitialValue {
            device: DeviceSpec::parse(d).unwrap(),
            value: v.into(),
        });
    }
    let clock = VirtualClock::new();
    (Cpu::new(p, cfg, Box::new(clock.clone())), clock)
}

fn get(cpu: &Cpu, d: &str) -> Value {
    let n = Name::parse(d).unwrap();
    n.present(cpu.read_device(&n.spec).unwrap())
}

fn set(cpu: &mut Cpu, d: &str, v: &str) {
    let n = Name::parse(d).unwrap();
    cpu.write_value(&n.spec, &n.value(v).unwrap()).unwrap();
}

#[test]
fn eromwr_area_survives_a_restart_other_devices_do_not() {
    let dir = tempfile::tempdir().unwrap();
    let (mut a, clock) = cpu();
    let mut bat = Battery::attach(dir.path(), &mut a, false).unwrap();
    assert_eq!(get(&a, "D6000"), Value::Int(7), "nothing saved yet");
    clock.advance_us(10_000);
    a.scan();
    set(&mut a, "M0", "1");
    clock.advance_us(10_000);
    a.scan();
    // Changed after the write: the EEPROM keeps 1234, D6002 was never written.
    set(&mut a, "D6000", "-1");
    set(&mut a, "D6002", "-2");
    bat.commit(&a).unwrap();
    drop(bat);

    let (mut b, _) = cpu();
    let _bat = Battery::attach(dir.path(), &mut b, false).unwrap();
    for (d, want) in [
        ("D6000", Value::Int(1234)),
        ("D6001", Value::Int(99)),
        ("D6002", Value::Int(9)),
        ("D6100", Value::Int(0)),
        ("D0", Value::Int(0)),
        ("M7", Value::Bool(false)),
        ("M0", Value::Bool(false)),
    ] {
        assert_eq!(get(&b, d), want, "{d} after the restart");
    }
}

#[test]
fn without_eromwr_nothing_survives() {
    let dir = tempfile::tempdir().unwrap();
    let (mut a, clock) = cpu();
    let mut bat = Battery::attach(dir.path(), &mut a, false).unwrap();
    clock.advance_us(10_000);
    a.scan();
    assert_eq!(get(&a, "D6000"), Value::Int(1234));
    bat.commit(&a).unwrap();
    drop(bat);
    let (mut b, _) = cpu();
    let _bat = Battery::attach(dir.path(), &mut b, false).unwrap();
    assert_eq!(get(&b, "D6000"), Value::Int(7), "the initial value");
    assert_eq!(get(&b, "D0"), Value::Int(0));
}
