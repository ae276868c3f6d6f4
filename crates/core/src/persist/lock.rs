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
    match try_flock(&file) {
        Ok(true) => {}
        Ok(false) => {
            let mut text = String::new();
            let _ = file.read_to_string(&mut text);
            let pid = text
                .trim()
                .parse::<u32>()
                .ok()
                .filter(|&p| p != std::process::id());
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
