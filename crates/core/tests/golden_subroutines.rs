//! Subroutine calls with arguments (004 §10.3.1 function devices FX/FY/FD,
//! L6722-6778), FCALL's non-execution processing and ECALL/EFCALL into
//! another file's local pointer (004 §10.9.1, L7262-7341; L1171-1200).
//! Argument n (from 0) is FXn/FYn for a bit device and FDn (4 words) for a
//! word device or a constant. Expected values are worked out by hand in the
//! comments. Run with `SOFTPLC_EXEC=jit` too.

mod common;

use common::{diagnostics, Plc};
use softplc_core::access::{DeviceSpec, Value};
use softplc_core::engine::ExecType;

#[test]
fn bit_and_word_arguments_in_and_out() {
    // S1 = X0 → FX0, S2 = Y10 → FY1, S3 = D0 → FD2, S4 = K-2 → FD3.
    let mut p = Plc::new(
        "\
LD SM400
CALL P0 X0 Y10 D0 K-2
FEND
P0
LD FX0
OUT FY1
LD SM400
MOV FD2 D100
+ FD2 FD3 FD2
RET
END
",
    );
    p.set("D0", "10").scan();
    // D100 = D0 at the call (10); FD2 = 10 + (-2) = 8 written back to D0;
    // Y10 = X0 = OFF.
    assert_eq!(p.int("D100"), 10);
    assert_eq!(p.int("D0"), 8);
    assert!(!p.bit("Y10"));
    p.set("X0", "1").scan();
    assert_eq!(p.int("D100"), 8);
    assert_eq!(p.int("D0"), 6);
    assert!(p.bit("Y10"));
}

#[test]
fn fd_holds_32_and_64_bit_values_in_4_words() {
    // 004 §10.3.1 (2)(c): one FD point is 4 words; a 32-bit instruction uses
    // 2, the 64-bit product of D* uses 4.
    let mut p = Plc::new(
        "\
LD SM400
DMOV K100000 D20
CALL P0 D10
CALL P1 D20
FEND
P0
LD SM400
D+ FD0 K100000 FD0
RET
P1
LD SM400
D* FD0 K100000 FD0
RET
END
",
    );
    p.scan();
    // D10:D11 = 100000 = 0x0001_86A0.
    assert_eq!(p.int("D10"), 0x86A0 - 0x10000);
    assert_eq!(p.int("D11"), 1);
    // 100000 × 100000 = 10^10 = 0x0000_0002_540B_E400 in D20-D23.
    assert_eq!(p.int("D20"), 0xE400 - 0x10000);
    assert_eq!(p.int("D21"), 0x540B);
    assert_eq!(p.int("D22"), 2);
    assert_eq!(p.int("D23"), 0);
}

#[test]
fn nested_calls_have_their_own_function_devices() {
    // Outer: S1 = D0 → FD0, S2 = M0 → FY1. Inner: S1 = the outer FD0, S2 = the
    // outer FY1. The inner INC FD0 and SET FY1 come back into the outer's FD0
    // and FY1, and from there to D0 and M0 at the outer RET.
    let mut p = Plc::new(
        "\
LD SM400
CALL P0 D0 M0
FEND
P0
LD SM400
MOV FD0 D9
CALL P1 FD0 FY1
MOV FD0 D10
RET
P1
LD SM400
INC FD0
SET FY1
RET
END
",
    );
    p.set("D0", "5").scan();
    assert_eq!((p.int("D9"), p.int("D10"), p.int("D0")), (5, 6, 6));
    assert!(p.bit("M0"));
    p.scan();
    assert_eq!((p.int("D9"), p.int("D10"), p.int("D0")), (6, 7, 7));
}

#[test]
fn fcall_off_runs_the_subroutine_with_conditions_off() {
    // FCALL with its condition OFF: OUT FY0 is processed as OFF (Y0 turns
    // OFF); INC does not run. CALL with its condition OFF leaves Y1 as it was.
    let mut p = Plc::new(
        "\
LD X0
FCALL P0 Y0
LD X0
CALL P0 Y1
FEND
P0
LD SM400
OUT FY0
INC D0
RET
END
",
    );
    p.set("X0", "1").scan();
    assert!(p.bit("Y0") && p.bit("Y1"));
    assert_eq!(p.int("D0"), 2);
    p.set("X0", "0").scan();
    assert!(!p.bit("Y0"));
    assert!(p.bit("Y1"));
    assert_eq!(p.int("D0"), 2);
}

#[test]
fn pulse_forms_call_on_the_rising_edge() {
    let mut p = Plc::new(
        "\
LD X0
CALLP P0 D0
FCALLP P0 D1
FEND
P0
LD SM400
INC FD0
RET
END
",
    );
    p.set("X0", "1").scans(3);
    // One call each on the rising edge.
    assert_eq!((p.int("D0"), p.int("D1")), (1, 1));
    // FCALLP with its condition OFF: the non-execution pass (INC does not run).
    p.set("X0", "0").scans(2);
    assert_eq!((p.int("D0"), p.int("D1")), (1, 1));
}

fn linked(progs: &[(&str, &str, ExecType)]) -> Result<softplc_core::engine::Cpu, String> {
    use softplc_core::engine::{LoadedProgram, VirtualClock};
    use softplc_core::program::{compile::compile_with, il::parse_il};
    let cfg = softplc_core::profile::default_config();
    let loaded = progs
        .iter()
        .map(|(name, src, exec)| {
            let s = parse_il(name, src).unwrap();
            let program = compile_with(&s, &cfg.devices, None).map_err(|d| d.to_string())?;
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

fn get(cpu: &softplc_core::engine::Cpu, d: &str) -> Value {
    cpu.read_device(&DeviceSpec::parse(d).unwrap()).unwrap()
}

#[test]
fn ecall_reaches_another_files_local_pointer() {
    // main's own P0 and sub's local P0 are different subroutines (004
    // §10.9.1 (1)(b)); ECALL "SUB" P0 reaches sub's. EFCALL with its condition
    // OFF runs sub's P0 with conditions OFF (OUT FY2 processed as OFF).
    let main = "\
LD SM400
ECALL \"SUB\" P0 D0 X0 Y0
CALL P0
LD X1
EFCALL \"SUB\" P0 D1 X0 Y1
FEND
P0
LD SM400
INC D10
RET
END
";
    let sub = "FEND\nP0\nLD FX1\nOUT FY2\nLD SM400\n+ K10 FD0\nRET\nEND\n";
    let mut cpu = linked(&[
        ("main.il", main, ExecType::Scan),
        ("sub.il", sub, ExecType::Standby),
    ])
    .unwrap();
    cpu.set_input(0, true);
    cpu.set_input(1, true);
    cpu.scan();
    assert_eq!(get(&cpu, "D0"), Value::Int(10));
    assert_eq!(get(&cpu, "D1"), Value::Int(10));
    assert_eq!(get(&cpu, "D10"), Value::Int(1));
    assert_eq!(get(&cpu, "Y0"), Value::Bool(true));
    assert_eq!(get(&cpu, "Y1"), Value::Bool(true));
    cpu.set_input(1, false);
    cpu.scan();
    assert_eq!(get(&cpu, "D0"), Value::Int(20));
    assert_eq!(get(&cpu, "D1"), Value::Int(10));
    assert_eq!(get(&cpu, "Y1"), Value::Bool(false));
    // An unknown file or pointer is a load error.
    let e = linked(&[("main.il", main, ExecType::Scan)]).err().unwrap();
    assert!(e.contains("no program named SUB runs on this CPU"), "{e}");
    let e = linked(&[
        ("main.il", main, ExecType::Scan),
        ("sub.il", "FEND\nP1\nRET\nEND\n", ExecType::Standby),
    ])
    .err()
    .unwrap();
    assert!(e.contains("program SUB has no local pointer P0"), "{e}");
}

#[test]
fn argument_load_errors() {
    let d = diagnostics("LD X0\nCALL P0 D0 D1 D2 D3 D4 D5\nFEND\nP0\nRET\nEND\n");
    assert!(!d.is_empty());
    let d = diagnostics("LD X0\nCALL P0 K4M0\nFEND\nP0\nRET\nEND\n");
    assert!(
        d[0].contains("digit-specified argument is not supported"),
        "{d:?}"
    );
    let d = diagnostics("LD X0\nMOV FD0Z0 D0\nEND\n");
    assert!(d[0].contains("cannot be index-modified"), "{d:?}");
    let d = diagnostics("LD X0\nECALL P0 D0\nEND\n");
    assert!(d[0].contains("needs a program name"), "{d:?}");
    let d = diagnostics("LD X0\nXCALL P0\nEND\n");
    assert!(
        d[0].contains("not an instruction of the High Performance model"),
        "{d:?}"
    );
    let d = diagnostics("LD X0\nPLOAD \"A\"\nEND\n");
    assert!(d[0].contains("softplc has no drives"), "{d:?}");
}

#[test]
fn fcall_off_resets_timers_and_leaves_set_alone() {
    // The non-execution processing is that of an OFF master control: OUT T
    // resets the timer, SET is not executed (M0 keeps ON).
    let mut p = Plc::new(
        "\
LD X0
FCALL P0
FEND
P0
LD SM400
OUT T0 K100
SET M0
RET
END
",
    );
    // 30 scans of 10 ms: T0 (100 ms) counts.
    p.set("X0", "1").scans(30);
    assert!(p.int("TN0") > 0);
    assert!(p.bit("M0"));
    p.set("X0", "0").scan();
    assert_eq!(p.int("TN0"), 0);
    assert!(p.bit("M0"));
}
