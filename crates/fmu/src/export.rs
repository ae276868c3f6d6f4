//! `softplc fmu`: writes a program, project or multi-CPU system as an FMI
//! 3.0 co-simulation FMU (FMI 3.0 §2.5: the archive; §2.4: the model
//! description) around the shared library of this crate.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use quick_xml::escape::escape;

use crate::plc::{self, Causality, Config, FmiType, Plc, CONFIG_FILE, SCAN_TIME};
use crate::slave::{FIRST_DEVICE_VR, SCAN_TIME_VR, TIME_VR};

/// What to export.
pub struct Export {
    /// A program file, a project directory (or its plc.toml), or a
    /// multi-CPU system directory (or its system.toml).
    pub program: PathBuf,
    /// The .fmu written.
    pub output: PathBuf,
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    /// The scan time the FMU starts with (its `scan_time` parameter).
    pub scan_us: u64,
    /// The CPU model of a single program file.
    pub model: Option<String>,
    /// The shared library (`libsoftplc_fmu.so`) put in `binaries/`.
    pub library: PathBuf,
}

/// What was written, for the command's summary.
pub struct Written {
    pub model_identifier: String,
    pub token: String,
    pub variables: usize,
}

/// The binaries folder of this platform (FMI 3.0 §2.5.1.4).
pub fn platform_folder() -> Result<&'static str, String> {
    match (std::env::consts::ARCH, std::env::consts::OS) {
        ("x86_64", "linux") => Ok("x86_64-linux"),
        ("aarch64", "linux") => Ok("aarch64-linux"),
        (a, o) => Err(format!(
            "an FMU for {a}-{o} is not supported (softplc exports Linux FMUs)"
        )),
    }
}

/// The model identifier: the output's file name made a C identifier
/// (FMI 3.0 §2.4.1: it names the binary).
pub fn model_identifier(output: &Path) -> String {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert_str(0, "plc_");
    }
    id
}

/// Writes the FMU. Nothing is left at `output` when it fails.
pub fn export(e: &Export) -> Result<Written, String> {
    let platform = platform_folder()?;
    let library = std::fs::read(&e.library)
        .map_err(|err| format!("cannot read the FMU library {}: {err}", e.library.display()))?;
    let staging =
        tempfile::tempdir().map_err(|err| format!("cannot make a scratch directory: {err}"))?;
    let resources = staging.path().join("resources");
    let program = stage_program(&e.program, &resources)?;
    let config = Config {
        program,
        model: e.model.clone(),
        scan_time_us: e.scan_us.max(1),
        inputs: e.inputs.iter().map(|s| s.trim().to_string()).collect(),
        outputs: e.outputs.iter().map(|s| s.trim().to_string()).collect(),
    };
    std::fs::write(resources.join(CONFIG_FILE), config.to_toml())
        .map_err(|err| format!("cannot write {CONFIG_FILE}: {err}"))?;
    // Loaded from the copy: the FMU holds everything it needs.
    let plc = Plc::load(&resources, &config, config.scan_time_us)?;
    let token = plc::token(&resources)?;
    let id = model_identifier(&e.output);
    let model_name = e
        .program
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| id.clone());
    let xml = model_description(&plc, &model_name, &id, &token);
    write_archive(
        e,
        &xml,
        &format!("binaries/{platform}/{id}.so"),
        &library,
        &resources,
    )?;
    Ok(Written {
        model_identifier: id,
        token,
        variables: plc.vars.len(),
    })
}

/// Copies the program into `resources/` and says where it is there: a
/// file as itself, a project or system directory as `program/` (its files,
/// subdirectories included, without hidden ones and its state directory).
fn stage_program(program: &Path, resources: &Path) -> Result<String, String> {
    let mkdir = |d: &Path| {
        std::fs::create_dir_all(d).map_err(|err| format!("cannot create {}: {err}", d.display()))
    };
    mkdir(resources)?;
    let is_dir_kind =
        softplc_core::project::is_project(program) || softplc_core::system::is_system(program);
    if !is_dir_kind {
        if program.is_dir() {
            return Err(format!(
                "{}: neither a project (plc.toml) nor a multi-CPU system (system.toml)",
                program.display()
            ));
        }
        let name = program
            .file_name()
            .ok_or_else(|| format!("{}: not a file name", program.display()))?;
        std::fs::copy(program, resources.join(name))
            .map_err(|err| format!("cannot read {}: {err}", program.display()))?;
        return Ok(name.to_string_lossy().into_owned());
    }
    let (dir, manifest) = if program.is_dir() {
        (program.to_path_buf(), None)
    } else {
        let dir = program.parent().filter(|p| !p.as_os_str().is_empty());
        (
            dir.map_or_else(|| PathBuf::from("."), Path::to_path_buf),
            program.file_name(),
        )
    };
    let target = resources.join("program");
    let mut files = Vec::new();
    plc::collect(&dir, Path::new(""), &mut files)?;
    for rel in files {
        let skipped = rel.components().any(|c| {
            let s = c.as_os_str().to_string_lossy();
            s.starts_with('.') || s == "state"
        });
        if skipped {
            continue;
        }
        let to = target.join(&rel);
        if let Some(parent) = to.parent() {
            mkdir(parent)?;
        }
        std::fs::copy(dir.join(&rel), &to)
            .map_err(|err| format!("cannot read {}: {err}", dir.join(&rel).display()))?;
    }
    Ok(match manifest {
        Some(m) => format!("program/{}", m.to_string_lossy()),
        None => "program".into(),
    })
}

/// A start value in modelDescription.xml's syntax.
fn start_text(v: &softplc_core::access::Value, ty: FmiType) -> String {
    use softplc_core::access::Value;
    match (v, ty) {
        (Value::Bool(b), _) => b.to_string(),
        (Value::Float(f), _) => format!("{:?}", *f as f32),
        (Value::Int(i), _) => i.to_string(),
        (Value::Str(_), _) => String::new(),
    }
}

/// modelDescription.xml (FMI 3.0 §2.4).
pub fn model_description(plc: &Plc, model_name: &str, id: &str, token: &str) -> String {
    let scan_s = plc.scan_us() as f64 / 1e6;
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    x.push_str(&format!(
        "<fmiModelDescription fmiVersion=\"3.0\" modelName=\"{}\" instantiationToken=\"{}\" \
         description=\"softplc PLC: {} in virtual time\" generationTool=\"softplc {}\" \
         variableNamingConvention=\"flat\">\n",
        escape(model_name),
        escape(token),
        escape(model_name),
        env!("CARGO_PKG_VERSION"),
    ));
    x.push_str(&format!(
        "  <CoSimulation modelIdentifier=\"{id}\" canHandleVariableCommunicationStepSize=\"true\" \
         canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\" \
         canBeInstantiatedOnlyOncePerProcess=\"false\" hasEventMode=\"false\" \
         providesIntermediateUpdate=\"false\" canReturnEarlyAfterIntermediateUpdate=\"false\"/>\n"
    ));
    x.push_str("  <UnitDefinitions>\n    <Unit name=\"s\">\n      <BaseUnit s=\"1\"/>\n    </Unit>\n  </UnitDefinitions>\n");
    x.push_str("  <LogCategories>\n    <Category name=\"logStatusError\" description=\"calls refused and why\"/>\n  </LogCategories>\n");
    // A second, or 100 scans when they are longer.
    let stop = (scan_s * 100.0).max(1.0);
    x.push_str(&format!(
        "  <DefaultExperiment startTime=\"0\" stopTime=\"{stop}\" stepSize=\"{scan_s}\"/>\n"
    ));
    x.push_str("  <ModelVariables>\n");
    x.push_str(&format!(
        "    <Float64 name=\"time\" valueReference=\"{TIME_VR}\" causality=\"independent\" \
         variability=\"continuous\" unit=\"s\" description=\"simulation time\"/>\n"
    ));
    x.push_str(&format!(
        "    <Float64 name=\"{SCAN_TIME}\" valueReference=\"{SCAN_TIME_VR}\" causality=\"parameter\" \
         variability=\"fixed\" start=\"{scan_s}\" unit=\"s\" min=\"1e-6\" \
         description=\"virtual time each scan takes\"/>\n"
    ));
    for (i, v) in plc.vars.iter().enumerate() {
        let vr = i + FIRST_DEVICE_VR as usize;
        let name = escape(&v.name);
        let ty = v.ty.name();
        match v.causality {
            Causality::Input => x.push_str(&format!(
                "    <{ty} name=\"{name}\" valueReference=\"{vr}\" causality=\"input\" \
                 variability=\"discrete\" start=\"{}\"/>\n",
                start_text(v.input_value(), v.ty)
            )),
            Causality::Output => x.push_str(&format!(
                "    <{ty} name=\"{name}\" valueReference=\"{vr}\" causality=\"output\" \
                 variability=\"discrete\"/>\n"
            )),
        }
    }
    x.push_str("  </ModelVariables>\n  <ModelStructure>\n");
    let outputs = plc
        .vars
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output);
    // Inputs act at the next scan: no output depends on one directly.
    for (i, _) in outputs.clone() {
        x.push_str(&format!(
            "    <Output valueReference=\"{}\" dependencies=\"\"/>\n",
            i + FIRST_DEVICE_VR as usize
        ));
    }
    for (i, _) in outputs {
        x.push_str(&format!(
            "    <InitialUnknown valueReference=\"{}\" dependencies=\"\"/>\n",
            i + FIRST_DEVICE_VR as usize
        ));
    }
    x.push_str("  </ModelStructure>\n</fmiModelDescription>\n");
    x
}

/// Zips modelDescription.xml, the binary and `resources/` into a file next
/// to the output, then renames it into place.
fn write_archive(
    e: &Export,
    xml: &str,
    binary: &str,
    library: &[u8],
    resources: &Path,
) -> Result<(), String> {
    use zip::write::SimpleFileOptions;
    let out_dir = e
        .output
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let fail = |err: &dyn std::fmt::Display| format!("cannot write {}: {err}", e.output.display());
    let tmp = tempfile::NamedTempFile::new_in(out_dir).map_err(|err| fail(&err))?;
    let mut zip = zip::ZipWriter::new(tmp.as_file());
    let deflated =
        SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let mut add = |name: &str, bytes: &[u8], opts: SimpleFileOptions| -> Result<(), String> {
        zip.start_file(name, opts).map_err(|err| fail(&err))?;
        zip.write_all(bytes).map_err(|err| fail(&err))
    };
    add("modelDescription.xml", xml.as_bytes(), deflated)?;
    add(binary, library, deflated.unix_permissions(0o755))?;
    let mut files = Vec::new();
    plc::collect(resources, Path::new(""), &mut files)?;
    files.sort();
    for rel in files {
        let bytes = std::fs::read(resources.join(&rel)).map_err(|err| fail(&err))?;
        let name = format!("resources/{}", rel.to_string_lossy().replace('\\', "/"));
        add(&name, &bytes, deflated)?;
    }
    zip.finish().map_err(|err| fail(&err))?;
    // A temporary file is private (0600); the FMU is an ordinary file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644))
            .map_err(|err| fail(&err))?;
    }
    tmp.persist(&e.output).map_err(|err| fail(&err.error))?;
    Ok(())
}
