//! `[system_block]` of an APLC-TCP project (the APLC programming manual
//! §2.2.1): the output table in STOP, "keep device values" (off unless
//! chosen, §2.1.6) and the run input SM9/SD9; each error at its value
//! (`line:col`, worked out by hand).

mod common;
use common::project::{error, ok, with_main};
use softplc_core::device::DeviceKind;
use softplc_core::engine::{StopOutputs, VirtualClock};

const APLC: &str = "[cpu]\nmodel = \"APLC-TCP\"\n";

#[test]
fn defaults_reinitialise_and_turn_outputs_off() {
    let p = ok(&with_main(APLC));
    assert!(!p.config.keep_device_values);
    assert_eq!(p.config.stop_outputs, StopOutputs::Off);
    // MELSEC-Q keeps its device memory at STOP→RUN.
    assert!(ok(&with_main("")).config.keep_device_values);
}

#[test]
fn settings_are_read() {
    let p = ok(&with_main(&format!(
        "{APLC}[system_block]\nstop_outputs = [\"Y0\", \"y10\", \"Y0\"]\nkeep_device_values = true\n"
    )));
    assert!(p.config.keep_device_values);
    // Y10 is output 8 (octal).
    assert_eq!(p.config.stop_outputs, StopOutputs::Table(vec![0, 8]));
    let p = ok(&with_main(&format!(
        "{APLC}[system_block]\nstop_outputs = \"hold\"\n"
    )));
    assert_eq!(p.config.stop_outputs, StopOutputs::Hold);
}

/// SD9 counts the inputs from X0: X12 is input 10 (L10998).
#[test]
fn run_input_reaches_sm9_and_sd9() {
    let dir = std::env::temp_dir().join(format!("softplc-sysblock-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("main.apl"), "LD SM0\nOUT M0\n").unwrap();
    std::fs::write(
        dir.join("plc.toml"),
        format!("{APLC}[[program]]\nfile = \"main.apl\"\n[system_block]\nrun_input = \"X12\"\n"),
    )
    .unwrap();
    let proj = softplc_core::project::load_project(&dir).unwrap();
    let cpu = proj.build_cpu(Box::new(VirtualClock::new())).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let mem = cpu.memory();
    // X12 OFF at power-on: the CPU waits in STOP for its rising edge
    // (§2.3.2, L1225-1229).
    assert_eq!(proj.config.run_input, Some(10));
    assert_eq!(cpu.state(), softplc_core::engine::CpuState::Stop);
    assert!(mem.get_bit(DeviceKind::SM, 9).unwrap());
    assert_eq!(mem.get_word(DeviceKind::SD, 9).unwrap(), 10);
    assert_eq!(mem.get_word(DeviceKind::SD, 10).unwrap(), 0x0A06);
}

#[test]
fn errors_point_at_the_value() {
    assert_eq!(
        error(&with_main(&format!(
            "{APLC}[system_block]\nrun_input = \"X20\"\n"
        ))),
        "4:13: run_input must be one of X0-X17 or \"off\""
    );
    assert_eq!(
        error(&with_main(&format!(
            "{APLC}[system_block]\nstop_outputs = [\"M0\"]\n"
        ))),
        "4:17: stop_outputs: \"M0\" is not a Y device"
    );
    assert_eq!(
        error(&with_main(&format!("{APLC}[system_block]\nstop_outputs = \"freeze\"\n"))),
        "4:16: stop_outputs must be \"off\", \"hold\" or an array of the Y outputs ON in STOP (such as [\"Y0\", \"Y5\"])"
    );
    assert_eq!(
        error(&with_main(&format!(
            "{APLC}[system_block]\ninterrupt_priority = \"high\"\n"
        ))),
        "4:1: [system_block] interrupt_priority is not a setting in softplc: interrupt routines run one after another at the start of a scan and take no time, so one can never interrupt another, the only thing a priority level could change; waiting events run first in, first out (APLC programming manual §2.2.1, §9.2)"
    );
    assert_eq!(
        error(&with_main("[system_block]\nkeep_device_values = true\n")),
        "1:2: [system_block] is an APLC-TCP setting (set [cpu] model = \"APLC-TCP\")"
    );
}
