//! `softplc serve --record FILE` (docs/recording.md): what the recording
//! embeds (the program's files, its model and calendar) and its hooks on the
//! served CPU.

use std::path::{Path, PathBuf};

use softplc_core::engine::calendar::DateTime;
use softplc_record::{Header, Recorder, Source, SourceFile};
use softplc_serve::ServeState;

/// The largest program (all its files) a recording embeds.
const MAX_EMBEDDED: u64 = 64 << 20;

/// `--record-max-size`: `1GiB`, `500MiB`, `10MB`, `4096` (bytes).
pub fn parse_size(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let n: f64 = num
        .parse()
        .map_err(|_| format!("`{s}`: expected a size such as 1GiB, 500MiB or 10MB"))?;
    let mult: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1,
        "k" | "kb" => 1_000,
        "kib" => 1 << 10,
        "m" | "mb" => 1_000_000,
        "mib" => 1 << 20,
        "g" | "gb" => 1_000_000_000,
        "gib" => 1 << 30,
        u => {
            return Err(format!(
                "`{s}`: unknown unit `{u}` (B, KB, KiB, MB, MiB, GB, GiB)"
            ))
        }
    };
    let bytes = n * mult as f64;
    if !(bytes.is_finite() && bytes >= 4096.0) {
        return Err(format!("`{s}`: a recording needs at least 4096 bytes"));
    }
    Ok(bytes as u64)
}

/// The header of a recording of `program` (a file or a project directory
/// or its plc.toml), whose CPU runs as `cpu_model`. The paths in `skip`
/// (the recording, the state directory), hidden entries and recordings are
/// left out of the embedded files.
pub fn header(
    program: &Path,
    model: Option<&str>,
    cpu_model: &str,
    calendar: DateTime,
    period_us: u64,
    skip: &[PathBuf],
) -> Result<Header, String> {
    let project = softplc_core::project::is_project(program);
    let files = if project {
        let dir = if program.is_dir() {
            program.to_path_buf()
        } else {
            program.parent().map(PathBuf::from).unwrap_or_default()
        };
        let dir = if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir
        };
        let skip: Vec<PathBuf> = skip.iter().filter_map(|p| p.canonicalize().ok()).collect();
        let mut files = Vec::new();
        let mut total = 0u64;
        collect(&dir, &dir, &skip, &mut files, &mut total)?;
        files.sort_by(|a: &SourceFile, b| a.path.cmp(&b.path));
        files
    } else {
        let bytes = std::fs::read(program).map_err(|e| format!("{}: {e}", program.display()))?;
        let name = program
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "program.il".into());
        vec![SourceFile { path: name, bytes }]
    };
    let name = program
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(Header {
        identity: Header::identity_of(&files, model),
        program: name,
        project,
        model: model.map(str::to_string),
        cpu_model: cpu_model.to_string(),
        files,
        calendar_unix_s: calendar.to_unix(),
        period_us,
    })
}

/// The files under `dir` (relative to `root`), without `skip` and hidden
/// entries.
fn collect(
    root: &Path,
    dir: &Path,
    skip: &[PathBuf],
    out: &mut Vec<SourceFile>,
    total: &mut u64,
) -> Result<(), String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for e in entries {
        let e = e.map_err(|e| format!("{}: {e}", dir.display()))?;
        let path = e.path();
        if e.file_name().to_string_lossy().starts_with('.') {
            continue;
        }
        if path.canonicalize().is_ok_and(|c| skip.contains(&c)) {
            continue;
        }
        let ty = e
            .file_type()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        if ty.is_dir() {
            collect(root, &path, skip, out, total)?;
        } else if ty.is_file() {
            let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            if bytes.starts_with(softplc_record::format::MAGIC) {
                // An earlier recording kept beside the project.
                continue;
            }
            *total += bytes.len() as u64;
            if *total > MAX_EMBEDDED {
                return Err(format!(
                    "the project {} holds more than {} MiB of files; a recording embeds them all",
                    root.display(),
                    MAX_EMBEDDED >> 20
                ));
            }
            let rel = path.strip_prefix(root).unwrap_or(&path);
            let rel: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            out.push(SourceFile {
                path: rel.join("/"),
                bytes,
            });
        }
    }
    Ok(())
}

/// Starts recording `state`'s CPU to `path`: the header and the start frame
/// now, a frame after every END's requests, each change named by its door.
pub fn start(
    rec: &Recorder,
    state: &mut ServeState,
    path: &Path,
    header: &Header,
    max: u64,
) -> Result<(), String> {
    rec.start(path, header, max)?;
    let r = rec.clone();
    state.watch_doors(Box::new(move |door| r.set_source(Source::of_door(door))));
    let r = rec.clone();
    state.add_after_requests(Box::new(move |st: &mut ServeState| {
        r.end(st.cpu(), st.ends())
    }));
    Ok(())
}
