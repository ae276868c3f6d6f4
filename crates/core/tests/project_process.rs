//! Process CPU projects: `[cpu] model = "Q06PHCPU"` selects the process
//! dialect, `[process]` sets the decisions (DEC-n) and is refused elsewhere.

mod common;
use common::project::{errors, ok, scratch};
use softplc_core::engine::VirtualClock;
use softplc_core::project::load_project;

#[test]
fn process_settings_load_and_reach_the_instructions() {
    let p = ok(
        "[cpu]\nmodel = \"Q06PHCPU\"\n[process]\nieng_decreasing = false\n\
                firmware_serial_ge_07032 = false\n[[program]]\nfile = \"main.il\"\n",
    );
    assert_eq!(p.config.profile.model, "Q06PHCPU");
    assert!(!p.process.ieng_decreasing && !p.process.firmware_serial_ge_07032);
    assert!(p.process.mode_lcc_b0);

    // The setting reaches S.IENG: with RH < RL and `ieng_decreasing = false`
    // BW holds.
    let dir = scratch(
        "[cpu]\nmodel = \"Q06PHCPU\"\n[process]\nieng_decreasing = false\n\
         [[program]]\nfile = \"pc.il\"\n",
    );
    std::fs::write(
        dir.join("pc.il"),
        "LD SM400\nEMOV E0 D10\nEMOV E20 D12\nEMOV E5 D0\nEMOV E-1 D100\n\
         S.IENG D0 D100 D10 SD1506\nEND\n",
    )
    .unwrap();
    let p = load_project(&dir).unwrap();
    let mut cpu = p.build_cpu(Box::new(VirtualClock::new())).unwrap();
    cpu.scan();
    let w = &cpu.memory().words;
    let i = cpu
        .memory()
        .map
        .index(softplc_core::device::DeviceKind::D, 100)
        .unwrap() as usize;
    assert_eq!(f32::from_bits(w[i] as u32 | (w[i + 1] as u32) << 16), -1.0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn process_settings_are_checked() {
    assert_eq!(
        errors("[cpu]\nmodel = \"Q06HCPU\"\n[process]\nieng_decreasing = false\n[[program]]\nfile = \"main.il\"\n"),
        ["3:1: [process] sets the process CPU's decisions, but the model is Q06HCPU \
          (a process CPU is Q02PHCPU, Q06PHCPU, Q12PHCPU, Q25PHCPU, Q12PRHCPU or Q25PRHCPU)"]
    );
    let e = errors(
        "[cpu]\nmodel = \"Q12PHCPU\"\n[process]\nieng_decreasing = 1\nfirmware = true\n[[program]]\nfile = \"main.il\"\n",
    );
    assert_eq!(e.len(), 2, "{e:?}");
    assert!(
        e[0].starts_with("4:19: ieng_decreasing must be true or false, not an integer"),
        "{e:?}"
    );
    assert!(
        e[1].starts_with("5:1: unknown key \"firmware\" in [process]"),
        "{e:?}"
    );
}
