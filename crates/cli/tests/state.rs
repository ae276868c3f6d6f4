//! The state directory across project changes and damage (issue 11 items 3
//! and 4): retained data is keyed by device, so changing a latch range or the
//! file-register size keeps what still fits; a damaged state file loses only
//! the damaged region and is reported as BATTERY ERROR 1600.

use std::path::Path;
use std::process::{Command, Output};

fn softplc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_softplc"))
}

fn project(dir: &Path, latch: &str, file_register: u32, extra: &str) {
    std::fs::write(
        dir.join("plc.toml"),
        format!(
            "[[program]]\nfile = \"main.il\"\n\n[devices]\nfile_register = {file_register}\n\n\
             [latch]\nlatch1 = [\"{latch}\"]\n\n{extra}"
        ),
    )
    .unwrap();
}

fn run(dir: &Path, args: &[&str]) -> (serde_json::Value, String) {
    let out: Output = softplc()
        .arg("run")
        .arg(dir)
        .args(["--json"])
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    (serde_json::from_slice(&out.stdout).unwrap(), err)
}

fn write_values(dir: &Path) {
    // One scan writes the values; later runs do nothing (X0 stays OFF).
    std::fs::write(
        dir.join("main.il"),
        "LD X0\nMOV K1234 D1000\nMOV K1999 D1999\nMOV K42 ZR0\nMOV K43 ZR1023\nMOV K44 ZR2047\nEND\n",
    )
    .unwrap();
}

#[test]
fn widening_a_latch_range_and_resizing_file_registers_keep_what_fits() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    write_values(dir);
    project(dir, "D1000-D1999", 2048, "");
    run(dir, &["--set", "X0=1"]);

    std::fs::write(dir.join("main.il"), "LD X0\nOUT Y0\nEND\n").unwrap();
    project(dir, "D1000-D2099", 1024, "");
    let (v, err) = run(
        dir,
        &[
            "--show", "D1000", "--show", "D1999", "--show", "ZR0", "--show", "ZR1023",
        ],
    );
    let d = &v["devices"];
    assert_eq!(d["D1000"], 1234, "{err}");
    assert_eq!(d["D1999"], 1999);
    assert_eq!(d["ZR0"], 42);
    assert_eq!(d["ZR1023"], 43);
    assert!(
        err.contains("ZR1024-ZR2047 were dropped"),
        "says what was dropped: {err}"
    );
    assert!(v["error"].is_null(), "a layout change is not damage");

    // Narrowing drops the rest, with a warning.
    project(dir, "D1500-D1999", 1024, "");
    let (v, err) = run(dir, &["--show", "D1999", "--show", "D1000"]);
    assert_eq!(v["devices"]["D1999"], 1999);
    assert_eq!(v["devices"]["D1000"], 0);
    assert!(err.contains("D1000-D1499 were dropped"), "{err}");
}

fn flip_in_region(image: &Path, region: &str) {
    // Find the region's data by the table order: flip the middle byte of the
    // region named `region` (its data follows the header in table order).
    let mut img = std::fs::read(image).unwrap();
    let count = u32::from_le_bytes(img[16..20].try_into().unwrap()) as usize;
    let mut pos = 20;
    let mut regions = Vec::new();
    for _ in 0..count {
        let n = u16::from_le_bytes(img[pos..pos + 2].try_into().unwrap()) as usize;
        let name = String::from_utf8(img[pos + 2..pos + 2 + n].to_vec()).unwrap();
        pos += 2 + n;
        let len = u64::from_le_bytes(img[pos..pos + 8].try_into().unwrap()) as usize;
        pos += 8 + 1 + 4;
        regions.push((name, len));
    }
    let mut at = pos + 4; // header CRC
    for (name, len) in regions {
        if name == region {
            img[at + len / 2] ^= 0x5A;
            std::fs::write(image, img).unwrap();
            return;
        }
        at += len;
    }
    panic!("no region {region}");
}

#[test]
fn damaged_state_file_is_a_visible_fault() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    write_values(dir);
    project(dir, "D1000-D1999", 2048, "");
    run(dir, &["--set", "X0=1"]);
    let image = dir.join("state").join("image.bin");
    // Force a checkpoint by a layout change and back.
    project(dir, "D1000-D1998", 2048, "");
    run(dir, &[]);
    project(dir, "D1000-D1999", 2048, "");
    run(dir, &[]);
    flip_in_region(&image, "file-register");

    let (v, err) = run(
        dir,
        &[
            "--scans", "3", "--show", "D1000", "--show", "ZR0", "--show", "SD0", "--show", "SM0",
        ],
    );
    assert_eq!(v["devices"]["D1000"], 1234, "intact region kept: {err}");
    assert_eq!(v["devices"]["ZR0"], 0, "damaged region lost");
    assert_eq!(v["devices"]["SD0"], 1600);
    assert_eq!(v["devices"]["SM0"], true);
    assert_eq!(v["error"]["code"], 1600);
    assert_eq!(v["state"], "RUN", "continue is the default");
    assert!(err.contains("BATTERY ERROR 1600"), "{err}");
    // Reported once: the next power-on is clean, and the history keeps it.
    let (v, _) = run(dir, &["--show", "SD0"]);
    assert_eq!(v["devices"]["SD0"], 0);

    // on_damage = "stop": the CPU holds a stop error.
    project(dir, "D1000-D1999", 2048, "[state]\non_damage = \"stop\"\n");
    flip_in_region(&image, "latch:D1000-1999");
    let (v, _) = run(dir, &["--scans", "3", "--show", "ZR0"]);
    assert_eq!(v["state"], "STOP");
    assert_eq!(v["error"]["code"], 1600);
}
