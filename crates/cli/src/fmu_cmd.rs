//! `softplc fmu` (contract §8): a program, project or multi-CPU system as
//! an FMI 3.0 co-simulation FMU (docs/fmu-export.md).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::Args;
use softplc_fmu::export::{self, Export};

use crate::run::parse_duration;
use crate::stdout::outln;

/// The variable naming the FMU library when `--fmu-library` is not given.
const LIBRARY_ENV: &str = "SOFTPLC_FMU_LIBRARY";
/// The file cargo builds from crates/fmu.
const LIBRARY_FILE: &str = "libsoftplc_fmu.so";

#[derive(Args, Debug)]
pub struct FmuArgs {
    /// Program file (.il, .csv, .apl), project directory (or its plc.toml),
    /// or multi-CPU system directory (or its system.toml).
    pub program: PathBuf,
    /// The .fmu file to write.
    #[arg(short = 'o', value_name = "FILE.fmu")]
    pub file: PathBuf,
    /// A device the master writes, named as --set names it (repeatable):
    /// X0, D40:i32, D10:f32, CPU2/M0.
    #[arg(long = "input", value_name = "DEV[:TYPE]")]
    pub inputs: Vec<String>,
    /// A device the master reads, named as --show names it (repeatable).
    #[arg(long = "output", value_name = "DEV[:TYPE]")]
    pub outputs: Vec<String>,
    /// The scan time the FMU starts with (its scan_time parameter, which
    /// the master may change before initialization).
    #[arg(long, default_value = "10ms", value_name = "DUR", value_parser = parse_duration)]
    pub scan_time: Duration,
    /// CPU model of a single program file (as `run --model`).
    #[arg(long, value_name = "MODEL")]
    pub model: Option<String>,
    /// The FMU's shared library (default: $SOFTPLC_FMU_LIBRARY, else
    /// libsoftplc_fmu.so next to the softplc executable).
    #[arg(long, value_name = "PATH")]
    pub fmu_library: Option<PathBuf>,
}

/// Where the FMU library is: `--fmu-library`, else $SOFTPLC_FMU_LIBRARY,
/// else next to the running executable or in `deps/` below it (where cargo
/// builds it), the newer of the two.
fn find_library(given: Option<&Path>) -> Result<PathBuf, String> {
    let check = |p: PathBuf, how: &str| {
        if p.is_file() {
            Ok(p)
        } else {
            Err(format!("{how} {}: no such file", p.display()))
        }
    };
    if let Some(p) = given {
        return check(p.to_path_buf(), "--fmu-library");
    }
    if let Some(p) = std::env::var_os(LIBRARY_ENV).filter(|p| !p.is_empty()) {
        return check(PathBuf::from(p), LIBRARY_ENV);
    }
    let exe = std::env::current_exe().ok();
    let dir = exe.as_deref().and_then(Path::parent);
    // Cargo writes the library to deps/ whenever it builds softplc, and
    // next to softplc only for `-p softplc-fmu`: the newer one is current.
    let newest = dir
        .into_iter()
        .flat_map(|d| [d.join(LIBRARY_FILE), d.join("deps").join(LIBRARY_FILE)])
        .filter_map(|p| {
            let modified = std::fs::metadata(&p).ok()?.modified().ok()?;
            p.is_file().then_some((modified, p))
        })
        .max_by_key(|(modified, _)| *modified);
    if let Some((_, p)) = newest {
        return Ok(p);
    }
    Err(format!(
        "the FMU library {LIBRARY_FILE} is not next to this executable{}: build it with \
         `cargo build -p softplc-fmu` (add --release for a release build of softplc), or \
         give its path with --fmu-library PATH or {LIBRARY_ENV}",
        dir.map_or(String::new(), |d| format!(" ({})", d.display()))
    ))
}

pub fn run(args: FmuArgs) -> ExitCode {
    if args.inputs.is_empty() && args.outputs.is_empty() {
        eprintln!("softplc: give the FMU's variables with --input DEV and --output DEV");
        return ExitCode::from(2);
    }
    let library = match find_library(args.fmu_library.as_deref()) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("softplc: {e}");
            return ExitCode::from(2);
        }
    };
    let e = Export {
        program: args.program.clone(),
        output: args.file.clone(),
        inputs: args.inputs,
        outputs: args.outputs,
        scan_us: softplc_fmu::plc::micros(args.scan_time),
        model: args.model,
        library,
    };
    match export::export(&e) {
        Ok(w) => {
            outln!(
                "{}: FMI 3.0 co-simulation FMU `{}`, {} variables and scan_time, token {}",
                args.file.display(),
                w.model_identifier,
                w.variables,
                w.token
            );
            ExitCode::SUCCESS
        }
        Err(why) => {
            for line in why.lines() {
                eprintln!("{}", crate::run::sanitize(line));
            }
            ExitCode::from(1)
        }
    }
}
