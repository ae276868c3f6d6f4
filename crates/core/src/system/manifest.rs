//! `system.toml`: the CPUs of a multi-CPU system in CPU-number order
//! (contract §6): `[[cpu]] project = "cpu1"`, 2-4 of them.

use std::path::{Path, PathBuf};

use crate::program::{Diagnostic, Diagnostics};

/// The manifest file name of a multi-CPU system.
pub const SYSTEM_MANIFEST: &str = "system.toml";

/// True when `path` is a directory holding `system.toml`, or that file.
pub fn is_system(path: &Path) -> bool {
    if path.is_dir() {
        path.join(SYSTEM_MANIFEST).is_file()
    } else {
        path.file_name().is_some_and(|n| n == SYSTEM_MANIFEST)
    }
}

/// The system directory and its manifest for a directory or manifest path.
pub fn locate(path: &Path) -> (PathBuf, PathBuf) {
    if path.is_dir() {
        (path.to_path_buf(), path.join(SYSTEM_MANIFEST))
    } else {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        (dir, path.to_path_buf())
    }
}

/// The project directories of the CPUs, CPU 1 first.
pub fn read(path: &Path) -> Result<(PathBuf, Vec<PathBuf>), Diagnostics> {
    let (dir, manifest) = locate(path);
    let name = manifest.display().to_string();
    let fail = |line: u32, col: u32, message: String| {
        Diagnostics(vec![Diagnostic {
            file: name.clone(),
            line,
            col,
            message,
        }])
    };
    let bytes = crate::program::read_limited(
        &manifest,
        crate::project::MAX_MANIFEST_BYTES,
        SYSTEM_MANIFEST,
    )
    .map_err(|e| fail(0, 0, e))?;
    let text =
        String::from_utf8(bytes).map_err(|_| fail(0, 0, "the file is not UTF-8 text".into()))?;
    let at = |span: Option<std::ops::Range<usize>>| {
        span.map_or((1, 1), |s| crate::project::line_col(&text, s.start))
    };
    let doc: toml::Spanned<toml::Table> = toml::from_str(&text).map_err(|e| {
        let (l, c) = at(e.span());
        fail(l, c, format!("TOML syntax error: {}", e.message()))
    })?;
    let table = doc.get_ref();
    if let Some(k) = table.keys().find(|k| *k != "cpu") {
        return Err(fail(
            1,
            1,
            format!("unknown key `{k}` (system.toml has [[cpu]] tables only)"),
        ));
    }
    let cpus = match table.get("cpu") {
        Some(toml::Value::Array(a)) => a,
        _ => {
            return Err(fail(
                1,
                1,
                "a multi-CPU system lists its CPUs as [[cpu]] tables with project = \"dir\"".into(),
            ))
        }
    };
    if !(2..=4).contains(&cpus.len()) {
        return Err(fail(
            1,
            1,
            format!("{} CPUs: a multi-CPU system has 2-4", cpus.len()),
        ));
    }
    let mut projects = Vec::new();
    for (i, c) in cpus.iter().enumerate() {
        let project = c
            .as_table()
            .and_then(|t| (t.len() == 1).then(|| t.get("project")).flatten()?.as_str());
        match project {
            Some(p) => projects.push(dir.join(p)),
            None => {
                return Err(fail(
                    1,
                    1,
                    format!(
                        "CPU {}: each [[cpu]] has exactly project = \"a project directory\"",
                        i + 1
                    ),
                ))
            }
        }
    }
    Ok((dir, projects))
}
