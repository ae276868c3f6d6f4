//! Writing program files during RUN (004 §4.8; contract §7) for the doors
//! of `serve`: `PUT /api/v1/program` and `serve --watch`.
//!
//! The new text compiles off the engine thread; at the next END the
//! project's rules are checked against the other files and the CPU swaps the
//! program ([`softplc_core::engine::Cpu::replace_program`]), so the answer's
//! scan is the last one of the old program. A write through the API then
//! rewrites the file on disk atomically, so that a restart runs what runs
//! now; the watcher skips a file whose text it has seen last (the
//! API's own rewrite, an editor's touch).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use softplc_core::engine::Written;
use softplc_core::online::{Refused, SourceFile, Sources};

use crate::{Busy, EngineHandle, ServeState};

/// The served program files and the text each last had: written during
/// RUN, or refused by the compiler (the watcher does not try it again).
#[derive(Debug)]
pub struct Online {
    pub sources: Sources,
    seen: Mutex<HashMap<PathBuf, String>>,
    /// One API write at a time, so that the file on disk ends with the
    /// text the CPU runs.
    writing: tokio::sync::Mutex<()>,
}

/// Why a write failed.
#[derive(Debug)]
pub enum WriteError {
    /// Refused: nothing changed.
    Refused(Refused),
    /// The engine did not take the request.
    Busy,
    /// The CPU runs the new program, but the file on disk could not be
    /// rewritten.
    NotSaved(Written, String),
}

impl From<Refused> for WriteError {
    fn from(r: Refused) -> Self {
        WriteError::Refused(r)
    }
}

impl From<Busy> for WriteError {
    fn from(_: Busy) -> Self {
        WriteError::Busy
    }
}

impl Online {
    pub fn new(sources: Sources) -> Online {
        Online {
            sources,
            seen: Mutex::new(HashMap::new()),
            writing: tokio::sync::Mutex::new(()),
        }
    }

    /// Remembers the files' texts as they are now (before watching).
    fn remember_disk(&self) {
        let mut seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        for f in self.sources.files() {
            if let Ok(t) = std::fs::read_to_string(&f.path) {
                seen.insert(f.path.clone(), t);
            }
        }
    }

    fn saw(&self, f: &SourceFile, text: &str) {
        let mut seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        seen.insert(f.path.clone(), text.to_string());
    }

    fn has_seen(&self, f: &SourceFile, text: &str) -> bool {
        let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        seen.get(&f.path).is_some_and(|t| t == text)
    }
}

/// The END job of a write: the rules over all files, then the swap.
fn swap(
    s: &mut ServeState,
    online: &Online,
    f: &SourceFile,
    program: softplc_core::program::Program,
) -> Result<Written, Refused> {
    let cpu = s.cpu_mut_at(f.cpu);
    online.sources.check(f, &program, cpu)?;
    cpu.replace_program(f.slot, program).map_err(Refused::Cpu)
}

/// `PUT /api/v1/program`: replaces program file `name` by `text` at the
/// next END and rewrites the file on disk.
pub async fn write(
    engine: &EngineHandle,
    online: Arc<Online>,
    name: &str,
    text: String,
) -> Result<Written, WriteError> {
    let at = online.sources.find(name)?;
    let _one = online.writing.lock().await;
    let (o, t) = (online.clone(), text.clone());
    let program =
        tokio::task::spawn_blocking(move || o.sources.compile(&o.sources.files()[at], &t))
            .await
            .map_err(|_| WriteError::Busy)??;
    let o = online.clone();
    let written = engine
        .at_end(move |s| swap(s, &o, &o.sources.files()[at], program))
        .await??;
    let f = &online.sources.files()[at];
    online.saw(f, &text);
    let path = f.path.clone();
    tokio::task::spawn_blocking(move || softplc_core::online::write_file(&path, text.as_bytes()))
        .await
        .map_err(|_| WriteError::Busy)?
        .map_err(|e| WriteError::NotSaved(written.clone(), e))?;
    Ok(written)
}

/// How long the watcher waits for a file to settle (editors write in
/// several steps).
pub const DEBOUNCE: Duration = Duration::from_millis(200);

/// What `serve --watch` runs: the file watcher (dropping it stops the
/// watch) and the END hook that swaps the programs it compiled
/// ([`ServeState::add_hook`]).
pub struct Watch {
    pub watcher: Watcher,
    pub hook: crate::Hook,
}

/// The file watcher of `serve --watch`: dropping it stops the watch.
pub type Watcher =
    notify_debouncer_mini::Debouncer<notify_debouncer_mini::notify::RecommendedWatcher>;

/// `serve --watch`: a thread that compiles each program file whenever it is
/// rewritten or replaced on disk, and an END hook that writes it during RUN;
/// a changed `plc.toml` (or `system.toml`, the `manifests`) is reported as
/// needing a restart. Reports go to stderr.
pub fn watch(online: Arc<Online>, manifests: Vec<PathBuf>) -> Result<Watch, String> {
    use notify_debouncer_mini::notify::RecursiveMode;
    online.remember_disk();
    let (tx, rx) = std::sync::mpsc::channel();
    let mut watcher =
        notify_debouncer_mini::new_debouncer(DEBOUNCE, tx).map_err(|e| format!("--watch: {e}"))?;
    // The directories: an editor that saves by renaming a new file over
    // the old one replaces the file a watch on it would follow.
    let mut dirs: Vec<PathBuf> = online
        .sources
        .files()
        .iter()
        .map(|f| f.path.clone())
        .chain(manifests.iter().cloned())
        .map(|p| dir_of(&p))
        .collect();
    dirs.sort();
    dirs.dedup();
    for d in &dirs {
        watcher
            .watcher()
            .watch(d, RecursiveMode::NonRecursive)
            .map_err(|e| format!("--watch {}: {e}", d.display()))?;
    }
    let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let manifests: Vec<PathBuf> = manifests.iter().map(|m| canon(m)).collect();
    // Compiled programs for the END hook: (file, text, program).
    let (ptx, prx) = std::sync::mpsc::channel::<(usize, String, softplc_core::program::Program)>();
    let o = online.clone();
    std::thread::Builder::new()
        .name("softplc-watch".into())
        .spawn(move || {
            for events in rx {
                let Ok(events) = events else { continue };
                let mut paths: Vec<PathBuf> = events.into_iter().map(|e| e.path).collect();
                paths.sort();
                paths.dedup();
                for p in paths {
                    if manifests.contains(&canon(&p)) {
                        eprintln!(
                            "softplc: --watch: {} changed; its settings take effect when serve is restarted",
                            p.display()
                        );
                        continue;
                    }
                    let Some(at) = o.sources.at_path(&p) else {
                        continue;
                    };
                    if let Some((text, program)) = rewritten(&o, &o.sources.files()[at]) {
                        if ptx.send((at, text, program)).is_err() {
                            return;
                        }
                    }
                }
            }
        })
        .map_err(|e| format!("--watch: {e}"))?;
    let hook: crate::Hook = Box::new(move |s: &mut ServeState| {
        while let Ok((at, text, program)) = prx.try_recv() {
            let f = &online.sources.files()[at];
            let r = swap(s, &online, f, program);
            if r.is_ok() {
                online.saw(f, &text);
            }
            report(f, r);
        }
    });
    Ok(Watch { watcher, hook })
}

fn dir_of(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A program file changed on disk: its text and program when it is not
/// the text seen last and compiles (a refusal is reported here).
fn rewritten(online: &Online, f: &SourceFile) -> Option<(String, softplc_core::program::Program)> {
    let bytes = softplc_core::program::read_limited(
        &f.path,
        softplc_core::program::MAX_IL_BYTES,
        "a program file",
    )
    // Removed or half-renamed: the next event brings the new file.
    .ok()?;
    let text = String::from_utf8_lossy(&bytes).into_owned();
    if online.has_seen(f, &text) {
        return None;
    }
    match online.sources.compile(f, &text) {
        Ok(p) => Some((text, p)),
        Err(e) => {
            report(f, Err(e));
            // Not again until the text changes.
            online.saw(f, &text);
            None
        }
    }
}

fn report(f: &SourceFile, r: Result<Written, Refused>) {
    match r {
        Ok(w) => eprintln!("softplc: --watch: {}", summary(&f.name, &w)),
        Err(e) => eprintln!(
            "softplc: --watch: {} not written, the running program is unchanged:\n{e}",
            f.name
        ),
    }
}

/// One line on a write: the file, the scan, what was kept.
pub fn summary(name: &str, w: &Written) -> String {
    format!(
        "{name} written during RUN after scan {}: {} instructions kept, {} added, {} removed ({} steps written, {} in all)",
        w.scan, w.kept, w.added, w.removed, w.steps_written, w.steps
    )
}
