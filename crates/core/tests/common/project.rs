//! Project test helpers shared by the `project_*` tests: scratch projects with
//! a given `plc.toml`, their diagnostics as `line:col: message`, and shorthands.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use softplc_core::device::DeviceKind;
use softplc_core::engine::LatchRange;
use softplc_core::program::Diagnostics;
use softplc_core::project::{load_project, Project};

static NEXT: AtomicUsize = AtomicUsize::new(0);

/// Program files every scratch project has.
const PROGRAM_FILES: &[&str] = &["main.il", "init.il", "fast.il", "sub.il", "low.il"];

/// A fresh directory with `plc.toml` = `toml` and the program files.
pub fn scratch(toml: &str) -> PathBuf {
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("softplc-project-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for f in PROGRAM_FILES {
        std::fs::write(dir.join(f), "LD X0\nOUT Y0\nEND\n").unwrap();
    }
    std::fs::write(dir.join("plc.toml"), toml).unwrap();
    dir
}

/// Loads a scratch project and removes its directory again.
pub fn load(toml: &str) -> Result<Project, Diagnostics> {
    let dir = scratch(toml);
    let r = load_project(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    r
}

/// The project must load.
pub fn ok(toml: &str) -> Project {
    load(toml).unwrap_or_else(|d| panic!("should load:\n{toml}\n{d}"))
}

/// Every diagnostic as `line:col: message` (the file name checked and removed).
pub fn errors(toml: &str) -> Vec<String> {
    let dir = scratch(toml);
    let r = load_project(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    let d = match r {
        Ok(_) => panic!("should fail:\n{toml}"),
        Err(d) => d,
    };
    let file = dir.join("plc.toml").display().to_string();
    d.0.iter()
        .map(|d| {
            assert_eq!(d.file, file, "diagnostic file of {d}");
            format!("{}:{}: {}", d.line, d.col, d.message)
        })
        .collect()
}

/// The single diagnostic of a failing project.
pub fn error(toml: &str) -> String {
    let e = errors(toml);
    assert_eq!(e.len(), 1, "expected one diagnostic, got {e:#?}");
    e.into_iter().next().unwrap()
}

/// A scan program, appended after the lines under test so their line numbers
/// start at 1.
pub const MAIN: &str = "\n[[program]]\nfile = \"main.il\"\n";

pub fn with_main(s: &str) -> String {
    format!("{s}{MAIN}")
}

pub fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

pub fn us(n: u64) -> Duration {
    Duration::from_micros(n)
}

pub fn latch(kind: DeviceKind, start: u32, end: u32, clearable: bool) -> LatchRange {
    LatchRange {
        kind,
        start,
        end,
        clearable,
    }
}

pub fn example_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/project")
}

/// Loads a scratch project whose program files are `files` (name, text) and
/// builds its CPU: the project, or every diagnostic as `file:line:col:
/// message` (the file name without directory).
pub fn load_files(toml: &str, files: &[(&str, &str)]) -> Result<Project, Vec<String>> {
    let dir = scratch(toml);
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let r = load_project(&dir).and_then(|p| {
        p.build_cpu(Box::new(softplc_core::engine::VirtualClock::new()))?;
        Ok(p)
    });
    let _ = std::fs::remove_dir_all(&dir);
    r.map_err(|d| {
        d.0.iter()
            .map(|d| {
                let file = Path::new(&d.file)
                    .file_name()
                    .map_or(String::new(), |f| f.to_string_lossy().into_owned());
                format!("{file}:{}:{}: {}", d.line, d.col, d.message)
            })
            .collect()
    })
}
