//! One owner per state directory: an OS advisory lock (`flock`) on the file
//! `lock` in the directory, taken when a [`Store`](super::Store) opens it and held
//! until the store is dropped. The kernel releases it when the process dies, so
//! it never goes stale, even after kill -9. The owner writes its PID into the
//! file so a refused second owner can say who holds it.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;

use super::{io_err, PersistError};

/// Name of the lock file inside a state directory.
pub const LOCK_FILE: &str = "lock";

/// The held lock; released on drop (or by the kernel when the process exits).
#[derive(Debug)]
pub struct DirLock {
    _file: File,
}

/// Takes the lock of `dir` (which must exist) without waiting.
pub fn lock(dir: &Path) -> Result<DirLock, PersistError> {
    let path = dir.join(LOCK_FILE);
    let mut file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .map_err(io_err("open", &path))?;
    // A lock our own process just released can still be held for a moment by
    // a child being forked (it shares the open file until its exec closes it,
    // O_CLOEXEC), so when the recorded owner is this process, try again for a
    // short while before refusing.
    let mut held = try_flock(&file);
    for _ in 0..50 {
        if !matches!(held, Ok(false)) || recorded_pid(&mut file) != Some(std::process::id()) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        held = try_flock(&file);
    }
    match held {
        Ok(true) => {}
        Ok(false) => {
            let pid = recorded_pid(&mut file).filter(|&p| p != std::process::id());
            return Err(PersistError::Locked {
                dir: dir.to_path_buf(),
                pid,
            });
        }
        Err(e) => return Err(io_err("lock", &path)(e)),
    }
    // Ours now: record the owner (best effort; the lock itself is what counts).
    let _ = file
        .set_len(0)
        .and_then(|()| file.seek(SeekFrom::Start(0)))
        .and_then(|_| writeln!(file, "{}", std::process::id()));
    Ok(DirLock { _file: file })
}

/// The PID the owner wrote into the lock file, if readable.
fn recorded_pid(file: &mut File) -> Option<u32> {
    let mut text = String::new();
    file.seek(SeekFrom::Start(0)).ok()?;
    file.read_to_string(&mut text).ok()?;
    text.trim().parse().ok()
}

/// `flock(LOCK_EX | LOCK_NB)`: Ok(false) when another open file holds it.
#[cfg(unix)]
fn try_flock(file: &File) -> std::io::Result<bool> {
    use std::os::fd::AsRawFd;
    loop {
        // SAFETY: `flock` only reads the descriptor number, which belongs to
        // `file` and stays open for the duration of the call.
        let r = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
        if r == 0 {
            return Ok(true);
        }
        let e = std::io::Error::last_os_error();
        match e.raw_os_error() {
            Some(libc::EWOULDBLOCK) => return Ok(false),
            Some(libc::EINTR) => continue,
            _ => return Err(e),
        }
    }
}

#[cfg(not(unix))]
fn try_flock(file: &File) -> std::io::Result<bool> {
    match file.try_lock() {
        Ok(()) => Ok(true),
        Err(std::fs::TryLockError::WouldBlock) => Ok(false),
        Err(std::fs::TryLockError::Error(e)) => Err(e),
    }
}
