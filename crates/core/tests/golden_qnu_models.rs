//! The Universal models (QnUCPU) as profiles: their figures, a project and a
//! GX Works2 export naming one, and the program memory of one.

mod common;
use common::project::{error, ok};
use common::*;

use softplc_core::access::DeviceSpec;
use softplc_core::device::DeviceKind;
use softplc_core::engine::VirtualClock;
use softplc_core::profile::{find, Profile};
use softplc_core::program::load_single;

const UNIVERSAL: [&str; 23] = [
    "Q00UJCPU",
    "Q00UCPU",
    "Q01UCPU",
    "Q02UCPU",
    "Q03UDCPU",
    "Q03UDECPU",
    "Q04UDHCPU",
    "Q04UDEHCPU",
    "Q06UDHCPU",
    "Q06UDEHCPU",
    "Q10UDHCPU",
    "Q10UDEHCPU",
    "Q13UDHCPU",
    "Q13UDEHCPU",
    "Q20UDHCPU",
    "Q20UDEHCPU",
    "Q26UDHCPU",
    "Q26UDEHCPU",
    "Q03UDVCPU",
    "Q04UDVCPU",
    "Q06UDVCPU",
    "Q13UDVCPU",
    "Q26UDVCPU",
];

fn model(name: &str) -> &'static Profile {
    find(name).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_universal_model_is_a_qnu_profile() {
    for m in UNIVERSAL {
        let p = model(m);
        assert_eq!((p.model, p.family), (m, "MELSEC-QnU"));
        assert_eq!(p.capacity.programs, 124, "{m}");
        assert!(p.doors.mc.is_some_and(|c| c != 0), "{m}");
        assert!(p.step_numbers);
    }
    // (model, program memory in K steps, file registers, MC model code)
    for (m, k, zr, mc) in [
        ("Q00UJCPU", 10, 0, 0x0260),
        ("Q02UCPU", 20, 65_536, 0x0263),
        ("Q03UDECPU", 30, 98_304, 0x0268),
        ("Q04UDEHCPU", 40, 131_072, 0x0269),
        ("Q06UDVCPU", 60, 393_216, 0x0368),
        ("Q13UDHCPU", 130, 524_288, 0x026B),
        ("Q26UDEHCPU", 260, 655_360, 0x026C),
    ] {
        let p = model(m);
        assert_eq!(p.capacity.program_steps, k * 1024, "{m}");
        assert_eq!(p.doors.mc, Some(mc), "{m}");
        let d = (p.default_devices)();
        assert_eq!(d.points(DeviceKind::ZR), zr, "{m}");
        assert_eq!(d.points(DeviceKind::R), zr.min(32_768), "{m}");
        // The other device points are the QnHCPU's defaults.
        for k in [
            DeviceKind::M,
            DeviceKind::D,
            DeviceKind::W,
            DeviceKind::TN,
            DeviceKind::Z,
        ] {
            assert_eq!(d.points(k), (model("Q06HCPU").default_devices)().points(k));
        }
    }
    // A CPU of the model gets its devices.
    let cfg = softplc_core::profile::config(model("Q04UDEHCPU"));
    assert_eq!(cfg.devices.points(DeviceKind::ZR), 131_072);
}

#[test]
fn file_registers_follow_the_model() {
    // ZR131071 is the last file register of a Q04UDEHCPU's standard RAM.
    let mut p = Plc::on_model("LD SM400\nMOV K7 ZR131071\nEND\n", "Q04UDEHCPU");
    p.scan();
    assert_eq!(p.int("ZR131071"), 7);
    let e = model_diagnostics("Q04UDEHCPU", "LD SM400\nMOV K7 ZR131072\nEND\n");
    assert_eq!(e.len(), 1, "{e:?}");
    // The Q00UJCPU has no standard RAM: no file registers.
    let e = model_diagnostics("Q00UJCPU", "LD SM400\nMOV K7 R0\nEND\n");
    assert_eq!(e.len(), 1, "{e:?}");
}

#[test]
fn a_q04udehcpu_project_loads_and_runs() {
    let p = ok("[cpu]\nmodel = \"q04udehcpu\"\n\n[[program]]\nfile = \"main.il\"\n");
    assert_eq!(p.config.profile.model, "Q04UDEHCPU");
    assert_eq!(p.config.devices.points(DeviceKind::ZR), 131_072);
    assert_eq!(p.dialect().name, "MELSEC-QnU");
    // [devices] still sets the file registers.
    let p = ok("[cpu]\nmodel = \"Q04UDEHCPU\"\n[devices]\nfile_register = 8192\n\n[[program]]\nfile = \"main.il\"\n");
    assert_eq!(p.config.devices.points(DeviceKind::ZR), 8192);
    // [process] is the process CPU's.
    assert!(
        error("[cpu]\nmodel = \"Q04UDEHCPU\"\n[process]\n\n[[program]]\nfile = \"main.il\"\n")
            .contains("but the model is Q04UDEHCPU"),
    );

    // A program with a pulse NOT contact, run: Y0 = X0 · ¬fall(X1).
    let dir = common::project::scratch(
        "[cpu]\nmodel = \"Q04UDEHCPU\"\n\n[[program]]\nfile = \"main.il\"\n",
    );
    std::fs::write(dir.join("main.il"), "LD X0\nANDFI X1\nOUT Y0\nEND\n").unwrap();
    let project = softplc_core::project::load_project(&dir).unwrap();
    let mut cpu = project
        .build_cpu(Box::new(VirtualClock::new()))
        .unwrap_or_else(|d| panic!("{d}"));
    assert_eq!(cpu.profile().model, "Q04UDEHCPU");
    let dev = |name: &str| DeviceSpec::parse(name).unwrap();
    let mut y0 = Vec::new();
    for (x0, x1) in [("1", "1"), ("1", "0"), ("1", "0")] {
        cpu.write_device(&dev("X0"), x0).unwrap();
        cpu.write_device(&dev("X1"), x1).unwrap();
        cpu.scan();
        y0.push(cpu.read_device(&dev("Y0")).unwrap());
    }
    use softplc_core::access::Value::Bool;
    assert_eq!(y0, [Bool(true), Bool(false), Bool(true)]);
    // The same program on a Q06HCPU is refused.
    std::fs::write(
        dir.join("plc.toml"),
        "[cpu]\nmodel = \"Q06HCPU\"\n\n[[program]]\nfile = \"main.il\"\n",
    )
    .unwrap();
    let Err(d) = softplc_core::project::load_project(&dir)
        .unwrap()
        .build_cpu(Box::new(VirtualClock::new()))
    else {
        panic!("ANDFI loaded on a Q06HCPU");
    };
    assert!(
        d.0[0]
            .message
            .contains("`ANDFI`: a Universal model instruction"),
        "{d}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Scratch files, removed with the directory when the test ends.
struct Scratch(tempfile::TempDir);

impl Scratch {
    fn new() -> Scratch {
        Scratch(tempfile::tempdir().unwrap())
    }

    /// A file `name` with `bytes`.
    fn file(&self, name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let path = self.0.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

/// A GX Works2 export (UTF-16LE, tab-separated) whose PLC Information row
/// names `plc`: `LD X0 / ANDFI X1 / OUT Y0 / END`.
fn export(plc: &str) -> Vec<u8> {
    let text = format!(
        "\"MAIN\"\r\n\"PLC Information:\"\t\"{plc}\"\r\n\
         \"Step No.\"\t\"Line Statement\"\t\"Instruction\"\t\"I/O(Device)\"\t\"Blank\"\t\"PI Statement\"\t\"Note\"\r\n\
         \"0\"\t\"\"\t\"LD\"\t\"X0\"\t\"\"\t\"\"\t\"\"\r\n\
         \"1\"\t\"\"\t\"ANDFI\"\t\"X1\"\t\"\"\t\"\"\t\"\"\r\n\
         \"2\"\t\"\"\t\"OUT\"\t\"Y0\"\t\"\"\t\"\"\t\"\"\r\n\
         \"3\"\t\"\"\t\"END\"\t\"\"\t\"\"\t\"\"\t\"\"\r\n"
    );
    let mut b = vec![0xFF, 0xFE];
    b.extend(text.encode_utf16().flat_map(u16::to_le_bytes));
    b
}

#[test]
fn a_csv_export_runs_on_the_model_it_names() {
    let dir = Scratch::new();
    let path = dir.file("uni.csv", &export("QCPU (Q mode) Q04UDEH"));
    let (profile, program) = load_single(&path, None).unwrap_or_else(|d| panic!("{d}"));
    assert_eq!(profile.model, "Q04UDEHCPU");
    assert_eq!(program.steps, 4);
    // --model takes precedence over the row.
    let (profile, _) = load_single(&path, Some(model("Q26UDVCPU"))).unwrap();
    assert_eq!(profile.model, "Q26UDVCPU");
    let d = load_single(&path, Some(model("Q06HCPU"))).unwrap_err();
    assert_eq!(d.0.len(), 1);
    assert_eq!((d.0[0].line, d.0[0].col), (5, 9));
    assert!(
        d.0[0]
            .message
            .contains("`ANDFI`: a Universal model instruction"),
        "{d}"
    );

    // An export of a QnH names it; ANDFI is then refused.
    let path = dir.file("qnh.csv", &export("QCPU (Q mode) Q06H"));
    let d = load_single(&path, None).unwrap_err();
    assert!(
        d.0[0]
            .message
            .contains("`ANDFI`: a Universal model instruction"),
        "{d}"
    );

    // A model softplc does not run is an error at its place in the row.
    let path = dir.file("fx.csv", &export("FXCPU FX3U/FX3UC"));
    let d = load_single(&path, None).unwrap_err();
    assert_eq!(d.0.len(), 1);
    assert_eq!(
        (d.0[0].line, d.0[0].col, d.0[0].message.as_str()),
        (
            2,
            27,
            "the PLC Information row names the CPU model `FX3U/FX3UC`, which softplc does not \
             run (a MELSEC-Q, QnPH or Universal QnU model); give --model to run the program on one"
        )
    );
    let (profile, _) = load_single(&path, Some(model("Q03UDECPU"))).unwrap();
    assert_eq!(profile.model, "Q03UDECPU");
    // A full model name is accepted too; an .il file names no model.
    let path = dir.file("full.csv", &export("Q13UDEHCPU"));
    assert_eq!(load_single(&path, None).unwrap().0.model, "Q13UDEHCPU");
    let path = dir.file("p.il", b"LD X0\nOUT Y0\nEND\n");
    assert_eq!(load_single(&path, None).unwrap().0.model, "Q06HCPU");
}

/// `.il` text of `steps` steps: LD/OUT pairs, NOPs to make up, END.
fn program_of(steps: u32) -> String {
    let mut s = "LD X0\nOUT Y0\n".repeat(((steps - 1) / 2) as usize);
    if steps.is_multiple_of(2) {
        s.push_str("NOP\n");
    }
    s + "END\n"
}

#[test]
fn program_memory_of_a_q04udehcpu() {
    // 40K = 40,960 steps, of which the file header takes 34: a program of
    // 40,926 steps fits, one of 40,927 does not (it does on a Q06UDEHCPU).
    let q04 = model("Q04UDEHCPU");
    let dir = Scratch::new();
    let fits = dir.file("fits.il", program_of(40_926).as_bytes());
    let (_, program) = load_single(&fits, Some(q04)).unwrap_or_else(|d| panic!("{d}"));
    assert_eq!(program.steps, 40_926);
    let over = dir.file("over.il", program_of(40_927).as_bytes());
    let d = load_single(&over, Some(q04)).unwrap_err();
    assert_eq!(
        d.0[0].message,
        "the programs take 40961 steps (34 file-header steps a file included), more than \
         the Q04UDEHCPU's program memory of 40960 steps"
    );
    assert!(load_single(&over, Some(model("Q06UDEHCPU"))).is_ok());
}
