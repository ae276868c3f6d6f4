//! Battery-backed memory: latched devices, file registers, error history and the
//! clock offset, kept in a state directory across process exits and crashes.
//!
//! Each `run`/`serve` process start is a power-on: the engine opens a [`Store`]
//! with a layout of named, fixed-size byte [`Region`]s (`"latch:D"`, `"zr"`,
//! `"history"`, `"clock"` …), gets back what was last committed, and calls
//! [`Store::commit`] at END processing of a scan. A commit is all-or-nothing:
//! after a kill -9 at any instant, [`Store::open`] returns exactly the contents of
//! one complete commit (the last one whose `commit` call returned, or — if the
//! process died inside `commit` — possibly that in-flight one), never a mix of two.
//!
//! # Files in the state directory
//!
//! | file | what |
//! |---|---|
//! | `image.bin` | base image: every region in full, as of generation *G* |
//! | `journal.log` | write-ahead log: one frame per commit after *G*, append-only |
//! | `image.bin.tmp` | a checkpoint in progress; deleted on open |
//! | `*.corrupt` | a damaged image or orphaned journal moved aside on open |
//! | `lock` | the owner's `flock` and PID (see *Single writer*) |
//!
//! **Base image** (`image.bin`): magic `SPLCIMG\x02`, the generation *G* of the
//! last commit it contains, the region table (name, length, committed flag, CRC32
//! of the region's bytes), a CRC32 of the header, then the region bytes. It is
//! only ever replaced whole (by rename). On open each region is verified by its
//! own checksum, so one damaged byte loses only its region (version 1 images,
//! with one CRC over the whole file, are still read). Damaged committed data is
//! listed by [`Store::lost`] (see `recover.rs`).
//!
//! **Journal** (`journal.log`): a sequence of frames, one per commit:
//! `magic "SPJ1" | body length u32 | generation u64 | record count u32 |
//! records (region index u32, offset u32, length u32, bytes) | CRC32`.
//! The CRC covers the whole frame, so the frame *is* the commit record: a frame is
//! either complete and valid or it is ignored as a whole. Each frame is built in
//! memory and appended with a single `write` call.
//!
//! # Why this design
//!
//! * **Cheap commits.** The engine commits up to 100 times a second, usually with a
//!   handful of changed words in a megabyte of file registers. Rewriting the image
//!   each time would cost a megabyte of I/O per scan; appending only the changed
//!   chunks costs a few hundred bytes and one `write` syscall.
//! * **Dirty detection by comparison.** The store keeps a copy (the *shadow*) of
//!   the last committed bytes and compares the caller's regions to it in
//!   [`CHUNK`]-byte chunks (whole 16 KiB blocks first, so unchanged areas are a
//!   single `memcmp`). No cooperation from the interpreter is needed, so no device
//!   write can be forgotten. Adjacent dirty chunks share one record.
//! * **Atomicity from the checksum, not from the file system.** Recovery loads the
//!   image, then replays frames in order while each is complete, has a valid CRC,
//!   stays inside the layout and carries generation *previous + 1*. The first frame
//!   failing any of this ends the replay, and the journal is truncated there (with
//!   a warning), so later appends never sit behind garbage. A frame torn by a kill
//!   in the middle of `write` fails its length or CRC check and is dropped whole.
//! * **Generations tie image and journal together.** Frames with a generation at or
//!   below the image's *G* are already in the image and are skipped. This is what
//!   makes checkpoints crash-safe without a second log.
//!
//! # Checkpoints
//!
//! When the journal grows beyond a threshold (default: the larger of 8 MiB and
//! four times the image size, see [`StoreOptions::checkpoint_threshold`]), the
//! commit that crossed it folds everything into a new image:
//!
//! 1. write `image.bin.tmp` (generation *G* = the commit just made), `fsync` it;
//! 2. `rename` it over `image.bin`, `fsync` the directory;
//! 3. truncate `journal.log` to zero.
//!
//! A crash before 2 leaves the old image and the full journal (the temp file is
//! deleted on open); a crash between 2 and 3 leaves the new image and a journal
//! whose frames are all ≤ *G* and are skipped; after 3 the journal is empty. In no
//! window is there a state that recovers to anything but the last commit. The
//! checkpoint `fsync`s even when per-commit sync is off, because truncating the
//! journal before the new image is on disk could lose everything on power loss.
//! A checkpoint costs one image write and two or three `fsync`s (about 10–50 ms for
//! a 1 MiB image on a virtual disk), so it shows as a longer END processing; with
//! a few words changed per scan (~500 bytes per commit) at 100 commits a second,
//! the default threshold is reached about every three minutes.
//!
//! The image is also rewritten on open when the layout differs from the image's
//! region table (regions added, removed, resized or reordered), so journal frames
//! always refer to the region table of the image they follow. Regions are matched
//! by name, and regions whose names carry device numbers (`latch:D1000-1999`,
//! `file-register`) also point by point across a changed range or size
//! (`remap.rs`): devices retained before and after keep their values, and a
//! warning names what was dropped. Any other region whose size changed starts
//! zeroed, is returned as `None`, and a warning says so.
//!
//! # Durability: `set_sync`
//!
//! A commit that returned has been handed to the kernel with `write`, which is
//! enough to survive the death of the process (kill -9, panic, abort): the page
//! cache belongs to the kernel. It is *not* enough for power loss or a kernel crash,
//! where the last seconds of commits may be lost (never mixed: recovery still
//! stops at the first bad frame, and the generation sequence rejects stale frames
//! a lost truncation could bring back). [`Store::set_sync`]`(true)` adds an `fdatasync`
//! per commit, which makes each commit power-loss safe but costs from tens of
//! microseconds (NVMe) to tens of milliseconds (SD cards, HDDs) per scan. Default:
//! off — a real PLC's battery-backed RAM is likewise not promised against every
//! failure, and a 10 ms scan cannot afford a disk flush each time.
//!
//! # Single writer
//!
//! One process owns a state directory at a time: [`Store::open`] takes an OS
//! advisory lock (`flock`) on the file `lock` and holds it while the store
//! lives ([`lock`] module). The kernel drops it when the process dies, kill -9
//! included, so it never goes stale; a second opener gets
//! [`PersistError::Locked`] naming the directory and the owner's PID. (Two
//! writers would both append generation *n + 1* and recovery would stop at the
//! second as out of sequence.)
//!
//! # Errors
//!
//! Damaged or truncated files never make [`Store::open`] fail or panic: it starts
//! from what is valid and records [`warnings`](Store::warnings). Only I/O errors
//! (with the path) and an invalid layout are returned as [`PersistError`].

mod battery;
pub use battery::{Attach, Battery, OnDamage};
mod format;
// flock(2) on the state directory's owner lock.
#[allow(unsafe_code)]
pub mod lock;
mod recover;
mod remap;

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use format::{begin_frame, finish_frame, image_header, push_record};

/// Granularity of dirty detection: a changed byte writes its whole chunk.
///
/// 64 bytes (32 words): a scan that changes a handful of scattered words writes a
/// few hundred bytes, and the journal grows slowly enough that checkpoints are
/// minutes apart. Bulk changes cost no more, since adjacent dirty chunks are
/// merged into one record (12 bytes of overhead per run, not per chunk).
pub const CHUNK: usize = 64;
/// Unchanged areas are recognised in blocks of this many bytes before the chunk scan.
const BLOCK: usize = 16 << 10;
const _: () = assert!(
    BLOCK / CHUNK * CHUNK == BLOCK,
    "chunks must not straddle blocks"
);
/// Lower bound of the default checkpoint threshold.
const MIN_DEFAULT_THRESHOLD: u64 = 8 << 20;

const IMAGE_FILE: &str = "image.bin";
const IMAGE_TMP: &str = "image.bin.tmp";
const JOURNAL_FILE: &str = "journal.log";

/// A named byte region with a fixed size (e.g. "latch:D" 2000 bytes, "zr" 1 MiB,
/// "history", "clock").
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Region {
    pub name: String,
    pub len: usize,
}

impl Region {
    pub fn new(name: impl Into<String>, len: usize) -> Region {
        Region {
            name: name.into(),
            len,
        }
    }
}

/// What a [`Store::commit`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CommitStats {
    /// Bytes appended to the journal (frame head, record heads, data, CRC); 0 when
    /// nothing changed and no frame was written. Checkpoint writes are not counted.
    pub bytes_written: usize,
    /// Dirty [`CHUNK`]-byte chunks written (adjacent chunks share one record).
    pub chunks: usize,
    /// Generation of the state now committed (unchanged if nothing changed).
    pub generation: u64,
    /// Whether this commit was followed by a checkpoint (new image, empty journal).
    pub checkpointed: bool,
}

/// Tuning for [`Store::open_with`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StoreOptions {
    /// `fdatasync` the journal after every commit (power-loss safety); see the
    /// module documentation for the trade-off. Default false.
    pub sync: bool,
    /// Journal size in bytes above which a commit is followed by a checkpoint.
    /// `None`: the larger of 8 MiB and four times the total region size.
    pub checkpoint_threshold: Option<u64>,
}

#[derive(Debug, thiserror::Error)]
pub enum PersistError {
    #[error("{op} {}: {source}", path.display())]
    Io {
        op: &'static str,
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    /// A file is damaged. `open` recovers from these itself and reports them as
    /// warnings; the variant is what those warnings are made of.
    #[error("{}: corrupt: {what}", path.display())]
    Corrupt { path: PathBuf, what: String },
    /// Another process owns the state directory (holds its lock).
    #[error(
        "state directory {} is in use by another softplc process{}; stop it first or use \
         another state directory",
        dir.display(),
        pid.map(|p| format!(" (PID {p})")).unwrap_or_default()
    )]
    Locked { dir: PathBuf, pid: Option<u32> },
    /// The layout passed to `open`, or the regions passed to `commit`, are invalid.
    #[error("persist layout: {0}")]
    Layout(String),
    /// The commit of `generation` is durable in the journal, but the checkpoint that
    /// followed it failed; it is retried at the next commit.
    #[error(
        "checkpoint after generation {generation} failed (the commit itself is durable): {source}"
    )]
    Checkpoint {
        generation: u64,
        #[source]
        source: Box<PersistError>,
    },
}

fn io_err<'a>(op: &'static str, path: &'a Path) -> impl FnOnce(io::Error) -> PersistError + 'a {
    move |source| PersistError::Io {
        op,
        path: path.to_path_buf(),
        source,
    }
}

/// The persistent store of one state directory. See the module documentation.
pub struct Store {
    dir: PathBuf,
    image_path: PathBuf,
    tmp_path: PathBuf,
    journal_path: PathBuf,
    journal: File,
    /// Length of the valid journal (everything in the file up to here is frames).
    journal_len: u64,
    names: Vec<String>,
    /// Last committed contents, one per layout region.
    shadow: Vec<Vec<u8>>,
    /// Regions that hold committed data (false: new or resized since the last commit).
    committed: Vec<bool>,
    generation: u64,
    sync: bool,
    threshold: u64,
    /// Set when a failed journal write could not be rolled back: the next commit
    /// first checkpoints, which rewrites the journal from scratch.
    needs_checkpoint: bool,
    warnings: Vec<String>,
    frame: Vec<u8>,
    runs: Vec<(usize, usize, usize)>,
    /// Held while the store lives: one owner per directory.
    _lock: lock::DirLock,
    /// Committed data found damaged at open (see [`Store::lost`]).
    lost: Vec<String>,
}

impl std::fmt::Debug for Store {
    // Not derived: the shadow copy can be megabytes.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Store")
            .field("dir", &self.dir)
            .field("generation", &self.generation)
            .field("journal_len", &self.journal_len)
            .field(
                "regions",
                &self
                    .names
                    .iter()
                    .zip(&self.shadow)
                    .map(|(n, d)| (n.as_str(), d.len()))
                    .collect::<Vec<_>>(),
            )
            .field("sync", &self.sync)
            .field("threshold", &self.threshold)
            .finish_non_exhaustive()
    }
}

impl Store {
    /// Opens or creates the store in `dir` (created if missing). Returns the last
    /// committed contents of each region in `layout` order, or None for a region that
    /// was never committed or whose size changed (then it starts zeroed and a warning
    /// is available).
    #[allow(clippy::type_complexity)] // the signature the engine was promised
    pub fn open(
        dir: &Path,
        layout: &[Region],
    ) -> Result<(Store, Vec<Option<Vec<u8>>>), PersistError> {
        Store::open_with(dir, layout, StoreOptions::default())
    }

    /// [`Store::open`] with options.
    #[allow(clippy::type_complexity)] // the signature the engine was promised
    pub fn open_with(
        dir: &Path,
        layout: &[Region],
        options: StoreOptions,
    ) -> Result<(Store, Vec<Option<Vec<u8>>>), PersistError> {
        check_layout(layout)?;
        fs::create_dir_all(dir).map_err(io_err("create directory", dir))?;
        let dir_lock = lock::lock(dir)?;
        let image_path = dir.join(IMAGE_FILE);
        let tmp_path = dir.join(IMAGE_TMP);
        let journal_path = dir.join(JOURNAL_FILE);
        let mut warnings = Vec::new();

        // An unfinished checkpoint: the image it was to replace is still valid.
        match fs::remove_file(&tmp_path) {
            Ok(()) => {}
            Err(e) if e.kind() == io::ErrorKind::NotFound => {}
            Err(e) => return Err(io_err("remove", &tmp_path)(e)),
        }

        let rec = recover::recover(&image_path, &journal_path, &mut warnings)?;

        // Map the recovered regions onto the requested layout, by name and
        // device numbers (remap.rs).
        let same_table = rec.have_image
            && !rec.image_damaged
            && rec.regions.len() == layout.len()
            && rec
                .regions
                .iter()
                .zip(layout)
                .all(|(r, l)| r.name == l.name && r.data.len() == l.len);
        let remap::Mapped {
            out,
            shadow,
            committed,
            ..
        } = remap::map(layout, rec.regions, &mut warnings);
        let lost = rec.lost;

        let journal = OpenOptions::new()
            .append(true)
            .create(true)
            .open(&journal_path)
            .map_err(io_err("open", &journal_path))?;
        let journal_len = journal
            .metadata()
            .map_err(io_err("stat", &journal_path))?
            .len();
        let total: usize = layout.iter().map(|r| r.len).sum();
        let threshold = options
            .checkpoint_threshold
            .unwrap_or_else(|| MIN_DEFAULT_THRESHOLD.max(4 * total as u64));
        let mut store = Store {
            dir: dir.to_path_buf(),
            image_path,
            tmp_path,
            journal_path,
            journal,
            journal_len,
            names: layout.iter().map(|r| r.name.clone()).collect(),
            shadow,
            committed,
            generation: rec.generation,
            sync: options.sync,
            threshold,
            needs_checkpoint: false,
            warnings,
            frame: Vec::new(),
            runs: Vec::new(),
            _lock: dir_lock,
            lost,
        };
        if !same_table {
            // New store, changed layout, or a damaged image: the journal must
            // follow an image with this layout.
            store.checkpoint()?;
        } else if rec.replayed == 0 && store.journal_len > 0 {
            // Only frames already in the image (a checkpoint died before truncating).
            store.truncate_journal()?;
        }
        Ok((store, out))
    }

    /// Atomically commits the current contents of all regions (same order/sizes as
    /// layout). Writes only what differs from the last commit; writes nothing (and
    /// keeps the generation) when nothing differs. After a crash at any instant,
    /// open() returns exactly the contents of one complete commit (the last one that
    /// finished, or the one in flight), never a mix.
    pub fn commit(&mut self, regions: &[&[u8]]) -> Result<CommitStats, PersistError> {
        if regions.len() != self.shadow.len() {
            return Err(PersistError::Layout(format!(
                "commit of {} regions, layout has {}",
                regions.len(),
                self.shadow.len()
            )));
        }
        for ((cur, old), name) in regions.iter().zip(&self.shadow).zip(&self.names) {
            if cur.len() != old.len() {
                return Err(PersistError::Layout(format!(
                    "region {name:?}: commit of {} bytes, layout has {}",
                    cur.len(),
                    old.len()
                )));
            }
        }
        if self.needs_checkpoint {
            self.checkpoint()?;
        }

        self.runs.clear();
        let mut chunks = 0;
        for (i, (cur, old)) in regions.iter().zip(&self.shadow).enumerate() {
            chunks += dirty_runs(cur, old, i, &mut self.runs);
        }
        if self.runs.is_empty() && self.committed.iter().all(|&c| c) {
            return Ok(CommitStats {
                bytes_written: 0,
                chunks: 0,
                generation: self.generation,
                checkpointed: false,
            });
        }

        let generation = self.generation + 1;
        begin_frame(&mut self.frame, generation);
        for &(region, start, end) in &self.runs {
            push_record(&mut self.frame, region, start, &regions[region][start..end]);
        }
        finish_frame(&mut self.frame, self.runs.len());
        self.append_frame()?;

        // Durable: only now does the shadow follow.
        for &(region, start, end) in &self.runs {
            self.shadow[region][start..end].copy_from_slice(&regions[region][start..end]);
        }
        self.committed.iter_mut().for_each(|c| *c = true);
        self.generation = generation;
        let mut stats = CommitStats {
            bytes_written: self.frame.len(),
            chunks,
            generation,
            checkpointed: false,
        };
        if self.journal_len > self.threshold {
            self.checkpoint().map_err(|e| PersistError::Checkpoint {
                generation,
                source: Box::new(e),
            })?;
            stats.checkpointed = true;
        }
        Ok(stats)
    }

    /// Appends `self.frame` to the journal. On failure the journal is cut back to its
    /// previous length, so no torn frame stays in front of later ones.
    fn append_frame(&mut self) -> Result<(), PersistError> {
        let before = self.journal_len;
        let mut result = self
            .journal
            .write_all(&self.frame)
            .map_err(io_err("append to", &self.journal_path));
        if result.is_ok() && self.sync {
            result = self
                .journal
                .sync_data()
                .map_err(io_err("sync", &self.journal_path));
        }
        match result {
            Ok(()) => {
                self.journal_len = before + self.frame.len() as u64;
                Ok(())
            }
            Err(e) => {
                if self.journal.set_len(before).is_err() {
                    self.needs_checkpoint = true;
                }
                Err(e)
            }
        }
    }

    /// Writes a new base image of the last committed state and empties the journal.
    /// Called automatically by [`commit`](Store::commit) past the threshold; the
    /// engine may also call it, e.g. when the CPU goes to STOP or the process exits.
    pub fn checkpoint(&mut self) -> Result<(), PersistError> {
        self.write_image()?;
        fs::rename(&self.tmp_path, &self.image_path).map_err(io_err("rename", &self.tmp_path))?;
        sync_dir(&self.dir)?;
        // From here the image alone holds the state: the journal's frames are ≤ G.
        self.truncate_journal()?;
        self.needs_checkpoint = false;
        Ok(())
    }

    fn write_image(&self) -> Result<(), PersistError> {
        let path = &self.tmp_path;
        let file = File::create(path).map_err(io_err("create", path))?;
        let mut w = BufWriter::with_capacity(64 << 10, file);
        let header = image_header(
            self.generation,
            self.names
                .iter()
                .zip(&self.shadow)
                .zip(&self.committed)
                .map(|((n, d), &c)| (n.as_str(), d.len(), c, crc32fast::hash(d))),
        );
        w.write_all(&header).map_err(io_err("write", path))?;
        for data in &self.shadow {
            w.write_all(data).map_err(io_err("write", path))?;
        }
        let file = w
            .into_inner()
            .map_err(|e| io_err("write", path)(e.into_error()))?;
        file.sync_all().map_err(io_err("sync", path))
    }

    fn truncate_journal(&mut self) -> Result<(), PersistError> {
        self.journal
            .set_len(0)
            .map_err(io_err("truncate", &self.journal_path))?;
        if self.sync {
            self.journal
                .sync_all()
                .map_err(io_err("sync", &self.journal_path))?;
        }
        self.journal_len = 0;
        Ok(())
    }

    /// Warnings from open (discarded regions, torn journal tail, damaged files …).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Committed data that open found damaged and could not recover (a region
    /// whose checksum failed, an unreadable image, journal commits after a bad
    /// frame), one description each; empty when everything committed came back.
    /// A torn last journal frame (a kill inside `commit`) is not a loss.
    pub fn lost(&self) -> &[String] {
        &self.lost
    }

    /// Whether each commit is followed by `fdatasync` (power-loss safety at the cost
    /// of a disk flush per commit). Default false: commits survive process death only.
    pub fn set_sync(&mut self, sync: bool) {
        self.sync = sync;
    }

    /// Journal size in bytes above which a commit is followed by a checkpoint.
    pub fn set_checkpoint_threshold(&mut self, bytes: u64) {
        self.threshold = bytes;
    }

    /// Generation of the last commit (0: never committed).
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Current journal size in bytes.
    pub fn journal_len(&self) -> u64 {
        self.journal_len
    }

    /// The last committed contents of region `index` (zeros if never committed).
    pub fn committed(&self, index: usize) -> &[u8] {
        &self.shadow[index]
    }

    /// The state directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

fn check_layout(layout: &[Region]) -> Result<(), PersistError> {
    for (i, r) in layout.iter().enumerate() {
        if r.name.is_empty() || r.name.len() > format::MAX_NAME {
            return Err(PersistError::Layout(format!(
                "region #{i}: name must be 1 to {} bytes",
                format::MAX_NAME
            )));
        }
        if u32::try_from(r.len).is_err() {
            return Err(PersistError::Layout(format!(
                "region {:?}: {} bytes is more than 4 GiB",
                r.name, r.len
            )));
        }
        if layout[..i].iter().any(|o| o.name == r.name) {
            return Err(PersistError::Layout(format!(
                "region {:?} appears twice",
                r.name
            )));
        }
    }
    Ok(())
}

/// Appends the dirty runs of region `index` as (region, start, end) and returns
/// the number of dirty chunks.
fn dirty_runs(
    cur: &[u8],
    old: &[u8],
    index: usize,
    runs: &mut Vec<(usize, usize, usize)>,
) -> usize {
    let len = cur.len();
    let mut chunks = 0;
    let mut run: Option<usize> = None;
    let mut block = 0;
    while block < len {
        let block_end = (block + BLOCK).min(len);
        if cur[block..block_end] == old[block..block_end] {
            if let Some(start) = run.take() {
                runs.push((index, start, block));
            }
        } else {
            let mut at = block;
            while at < block_end {
                let end = (at + CHUNK).min(block_end);
                if cur[at..end] == old[at..end] {
                    if let Some(start) = run.take() {
                        runs.push((index, start, at));
                    }
                } else {
                    chunks += 1;
                    run.get_or_insert(at);
                }
                at = end;
            }
        }
        block = block_end;
    }
    if let Some(start) = run {
        runs.push((index, start, len));
    }
    chunks
}

#[cfg(unix)]
fn sync_dir(dir: &Path) -> Result<(), PersistError> {
    File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(io_err("sync directory", dir))
}

#[cfg(not(unix))]
fn sync_dir(_dir: &Path) -> Result<(), PersistError> {
    Ok(())
}

#[cfg(test)]
mod tests;
