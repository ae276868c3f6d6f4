//! Writing a program file during RUN from outside (004 §4.8; contract §7):
//! which file a request names, how its new text compiles — in the CPU's
//! dialect, with its project's parameters, checked with the project's rules
//! against the other files — and the file rewritten on disk so that a
//! restart runs it. The CPU itself swaps the program between two scans
//! ([`crate::engine::Cpu::replace_program`]); `softplc-serve` drives both
//! for `PUT /api/v1/program` and `serve --watch`.

use std::path::{Component, Path, PathBuf};

use crate::engine::Cpu;
use crate::program::{Diagnostic, Diagnostics, Program};
use crate::project::Project;

/// Why a write is refused; nothing changed.
#[derive(Debug)]
pub enum Refused {
    /// No program file of that name is served.
    UnknownFile(String),
    /// The text does not compile, or breaks a rule of the project: every
    /// diagnostic, `file:line:column: message`.
    Program(Diagnostics),
    /// The CPU refuses the change (a limit of writing during RUN, a CALL
    /// that no longer links …) or the file cannot be written.
    Cpu(String),
}

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refused::UnknownFile(e) | Refused::Cpu(e) => f.write_str(e),
            Refused::Program(d) => d.fmt(f),
        }
    }
}

/// How a served CPU's program files compile.
#[derive(Debug)]
enum Recipe {
    /// A MELSEC project's files.
    Project(Box<Project>),
    /// One MELSEC program file on its own, on the CPU's model.
    Single(&'static crate::profile::Profile),
    /// The APLC-TCP's one user program, from all these files.
    Aplc(Vec<PathBuf>),
}

/// One program file that may be written during RUN.
#[derive(Debug)]
pub struct SourceFile {
    /// The CPU (0-based) and its program slot.
    pub cpu: usize,
    pub slot: usize,
    /// The file on disk.
    pub path: PathBuf,
    /// Its name relative to the served directory (what a request names).
    pub name: String,
    /// The running program's file name (`Program::file`), which the new
    /// program takes.
    pub program: String,
    recipe: usize,
}

/// The program files of what `serve` runs: one file, a project, or a
/// multi-CPU system's projects.
#[derive(Debug, Default)]
pub struct Sources {
    files: Vec<SourceFile>,
    recipes: Vec<Recipe>,
    /// The served directory: a project's or system's, a single file's own.
    base: PathBuf,
    /// The manifests read at load (`plc.toml`, `system.toml`): changing
    /// them needs a restart.
    manifests: Vec<PathBuf>,
}

impl Sources {
    /// The sources of `path` (a program file, project or system directory,
    /// or its manifest) as `cpus` run them.
    pub fn load(path: &Path, cpus: &crate::system::Cpus) -> Result<Sources, String> {
        if let Some(system) = cpus.system() {
            let mut s = Sources {
                base: system.dir().to_path_buf(),
                ..Sources::default()
            };
            s.manifests
                .push(system.dir().join(crate::system::SYSTEM_MANIFEST));
            for i in 0..system.len() {
                s.add_project(i, system.project(i).clone(), system.cpu(i));
            }
            return Ok(s);
        }
        if crate::project::is_project(path) {
            let project = crate::project::load_project(path).map_err(|d| d.to_string())?;
            let mut s = Sources {
                base: project.dir.clone(),
                ..Sources::default()
            };
            s.add_project(0, project, cpus.get(0));
            return Ok(s);
        }
        let cpu = cpus.get(0);
        let recipe = match crate::profile::is_aplc(cpu.profile()) {
            true => Recipe::Aplc(vec![path.to_path_buf()]),
            false => Recipe::Single(cpu.profile()),
        };
        Ok(Sources {
            base: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            files: vec![SourceFile {
                cpu: 0,
                slot: 0,
                path: path.to_path_buf(),
                name: file_name(path),
                program: cpu.program().file.clone(),
                recipe: 0,
            }],
            recipes: vec![recipe],
            manifests: Vec::new(),
        })
    }

    fn add_project(&mut self, i: usize, project: Project, cpu: &Cpu) {
        self.manifests.push(project.manifest.clone());
        let recipe = self.recipes.len();
        let aplc = crate::profile::is_aplc(project.config.profile);
        for (slot, spec) in project.programs.iter().enumerate() {
            // The APLC-TCP's files are one program.
            let slot = if aplc { 0 } else { slot };
            self.files.push(SourceFile {
                cpu: i,
                slot,
                path: spec.file.clone(),
                name: relative(&spec.file, &self.base),
                program: cpu
                    .program_at(slot.min(cpu.program_count() - 1))
                    .file
                    .clone(),
                recipe,
            });
        }
        self.recipes.push(match aplc {
            true => Recipe::Aplc(project.programs.iter().map(|p| p.file.clone()).collect()),
            false => Recipe::Project(Box::new(project)),
        });
    }

    /// Every program file served.
    pub fn files(&self) -> &[SourceFile] {
        &self.files
    }

    /// The manifests the served CPUs were loaded from.
    pub fn manifests(&self) -> &[PathBuf] {
        &self.manifests
    }

    /// The program file `name` names: its path relative to the served
    /// directory (`main.il`, `cpu2/main.il`), or a file name that only one
    /// program file has. Its index in [`Sources::files`].
    pub fn find(&self, name: &str) -> Result<usize, Refused> {
        let wanted = normal(Path::new(name));
        if let Some(i) = self
            .files
            .iter()
            .position(|f| normal(Path::new(&f.name)) == wanted)
        {
            return Ok(i);
        }
        let by_name: Vec<usize> = (0..self.files.len())
            .filter(|&i| file_name(&self.files[i].path) == name)
            .collect();
        let names = |ids: &mut dyn Iterator<Item = usize>| {
            ids.map(|i| self.files[i].name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        match by_name.as_slice() {
            [one] => Ok(*one),
            [] => Err(Refused::UnknownFile(format!(
                "no program file \"{name}\" is served (the program files: {})",
                names(&mut (0..self.files.len()))
            ))),
            _ => Err(Refused::UnknownFile(format!(
                "\"{name}\" names several program files: give its path ({})",
                names(&mut by_name.iter().copied())
            ))),
        }
    }

    /// The file whose path on disk is `path` (for `serve --watch`): its
    /// index in [`Sources::files`].
    pub fn at_path(&self, path: &Path) -> Option<usize> {
        let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
        let wanted = canon(path);
        self.files.iter().position(|f| canon(&f.path) == wanted)
    }

    /// Compiles `text` as the new content of `f`, named as the running
    /// program is, with the same settings the files were loaded with.
    pub fn compile(&self, f: &SourceFile, text: &str) -> Result<Program, Refused> {
        let (bytes, file) = (text.as_bytes(), f.program.as_str());
        let program = match &self.recipes[f.recipe] {
            Recipe::Single(profile) => {
                let dialect = crate::program::dialect_for(
                    profile,
                    crate::program::ProcessSettings::default(),
                );
                let devices = (profile.default_devices)();
                softplc_lang::load_bytes(file, bytes, &devices, &dialect, None)
            }
            Recipe::Project(p) => softplc_lang::load_bytes(
                file,
                bytes,
                &p.config.devices,
                &p.dialect(),
                p.common_pointer,
            ),
            Recipe::Aplc(paths) => {
                let paths: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
                softplc_aplc::files::load_files_with(&paths, Some((&f.path, bytes)))
            }
        };
        program.map_err(Refused::Program)
    }

    /// The project's rules on the CPU's programs with `program` in `f`'s
    /// slot: the model's program memory, and the rules over all files
    /// (timers, edge relays, local pointers, step relays).
    pub fn check(&self, f: &SourceFile, program: &Program, cpu: &Cpu) -> Result<(), Refused> {
        let programs: Vec<&Program> = (0..cpu.program_count())
            .map(|i| {
                if i == f.slot {
                    program
                } else {
                    cpu.program_at(i)
                }
            })
            .collect();
        let files: Vec<(&str, u32)> = programs
            .iter()
            .map(|p| (p.file.as_str(), p.steps))
            .collect();
        crate::project::check_capacity(cpu.profile(), &files)
            .map_err(|d| Refused::Program(Diagnostics(vec![d])))?;
        let broken = match &self.recipes[f.recipe] {
            Recipe::Project(p) => {
                let ruled: Vec<crate::project::Ruled<'_>> = programs
                    .iter()
                    .zip(&p.programs)
                    .map(|(program, spec)| crate::project::Ruled {
                        program,
                        exec: spec.exec,
                        local_devices: spec.local_devices,
                    })
                    .collect();
                crate::project::check_files(&ruled, &p.config, p.common_pointer)
            }
            Recipe::Single(_) => {
                let mut out: Vec<Diagnostic> = Vec::new();
                crate::project::step_relays(program, &mut out);
                out
            }
            Recipe::Aplc(_) => Vec::new(),
        };
        match broken.is_empty() {
            true => Ok(()),
            false => Err(Refused::Program(Diagnostics(broken))),
        }
    }
}

/// `path`'s file name.
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// `path` relative to `base` when it is inside it, with `/` separators.
fn relative(path: &Path, base: &Path) -> String {
    let rel = path.strip_prefix(base).unwrap_or(path);
    normal(rel)
}

/// A path's normal components joined with `/` (`./a//b.il` → `a/b.il`).
fn normal(path: &Path) -> String {
    path.components()
        .filter_map(|c| match c {
            Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
            Component::ParentDir => Some("..".into()),
            _ => None,
        })
        .collect::<Vec<_>>()
        .join("/")
}

/// Writes `bytes` to `path` atomically: a temporary file in the same
/// directory, synced and renamed over it once complete (a crash leaves the
/// old file or the new, never half of one). The file keeps its permissions.
/// Program files written during RUN, state files, test reports.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), String> {
    use std::io::Write;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let fail = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut tmp = tempfile::NamedTempFile::new_in(dir).map_err(fail)?;
    tmp.write_all(bytes).map_err(fail)?;
    tmp.as_file().sync_all().map_err(fail)?;
    if let Ok(meta) = std::fs::metadata(path) {
        let _ = std::fs::set_permissions(tmp.path(), meta.permissions());
    }
    tmp.persist(path).map_err(|e| fail(e.error))?;
    Ok(())
}
