//! CPU functions (004 ch. 4 and 7): program execution types, operating states,
//! latch, initial values. Expected values are worked out from the manual's rules
//! in the comments.
//!
//! This file: several program files (common pointers) and programs compiled
//! for other device points.

use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::ExecType;

fn linked(
    progs: &[(&str, &str, ExecType)],
    common: u32,
) -> Result<softplc_core::engine::Cpu, String> {
    use softplc_core::engine::{LoadedProgram, VirtualClock};
    use softplc_core::program::{compile::compile_with, il::parse_il};
    let cfg = softplc_core::profile::default_config();
    let loaded = progs
        .iter()
        .map(|(name, src, exec)| {
            let s = parse_il(name, src).unwrap();
            let program =
                compile_with(&s, &cfg.devices, Some(common)).map_err(|d| d.to_string())?;
            Ok(LoadedProgram {
                program,
                exec: *exec,
                interval: None,
                sim_time: None,
                local_devices: true,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let mut cpu =
        softplc_core::engine::Cpu::with_programs(loaded, cfg, Box::new(VirtualClock::new()))?;
    softplc_core::tier::apply_env(&mut cpu);
    Ok(cpu)
}

#[test]
fn common_pointer_calls_cross_files() {
    // P100 and up are common: main.il calls sub.il's P100, which calls back into
    // its own local P5 and returns; edge memory of the callee is its own.
    let main = "LD SM400\nCALL P100\nLD X0\nCALLP P100\nEND\n";
    let sub = "FEND\nP100\nLD SM400\nINC D0\nCALL P5\nRET\nP5\nLD SM400\nINC D1\nRET\nEND\n";
    let mut cpu = linked(
        &[
            ("main.il", main, ExecType::Scan),
            ("sub.il", sub, ExecType::Standby),
        ],
        100,
    )
    .unwrap();
    cpu.scan();
    cpu.scan();
    let get = |cpu: &softplc_core::engine::Cpu, d: &str| {
        cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap()
    };
    assert_eq!(get(&cpu, "D0"), softplc_core::access::Value::Int(2));
    assert_eq!(get(&cpu, "D1"), softplc_core::access::Value::Int(2));
    cpu.set_input(0, true);
    cpu.scan();
    cpu.scan();
    // CALLP adds one call on the rising edge only.
    assert_eq!(get(&cpu, "D0"), softplc_core::access::Value::Int(5));
    // Undefined common pointer, duplicate common pointer, jump into another file.
    let e = linked(&[("main.il", main, ExecType::Scan)], 100)
        .err()
        .unwrap();
    assert!(
        e.contains("no program defines the common pointer P100"),
        "{e}"
    );
    let e = linked(
        &[
            ("a.il", sub, ExecType::Scan),
            ("b.il", sub, ExecType::Standby),
        ],
        100,
    )
    .err()
    .unwrap();
    assert!(
        e.contains("P100 is defined in a.il and in b.il (error 4021)"),
        "{e}"
    );
    let e = linked(&[("a.il", "LD X0\nCJ P200\nEND\n", ExecType::Scan)], 100)
        .err()
        .unwrap();
    assert!(e.contains("jumps cannot leave their file"), "{e}");
}

#[test]
fn programs_must_match_the_cpus_device_points() {
    use softplc_core::engine::{Cpu, LoadedProgram, VirtualClock};
    use softplc_core::program::compile_il;
    // Compiled for the default points; the CPU has 16 retentive timers more.
    let prog = compile_il(
        "a.il",
        "LD X0\nOUT Y0\nEND\n",
        &softplc_core::profile::default_config().devices,
    )
    .unwrap();
    let mut cfg = softplc_core::profile::default_config();
    cfg.devices.set_points(DeviceKind::STS, 16);
    let loaded = vec![LoadedProgram {
        program: prog,
        exec: ExecType::Scan,
        interval: None,
        sim_time: None,
        local_devices: true,
    }];
    let e = Cpu::with_programs(loaded, cfg, Box::new(VirtualClock::new()))
        .err()
        .unwrap();
    assert!(e.contains("other device points"), "{e}");
}
