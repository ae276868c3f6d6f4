//! State files (contract §7): a CPU's or a multi-CPU system's whole state
//! at an END, to continue exactly where it was saved (`run --save-state`,
//! `--load-state`, `GET`/`PUT /api/v1/snapshot`).
//!
//! The file: a 56-byte header — magic `SPLCSTAT`, format version (u16),
//! number of CPUs (u16), the identity of the programs and parameters
//! ([`identity`], 32 bytes), the body's length (u64) and the CRC-32 (u32)
//! of the header before it and the body,
//! all little-endian — then the body: the CPU models (u16 length, text) and
//! the state sections each CPU walks (`softplc_engine::Cpu::snapshot`), a
//! system's in `CPU1`…`CPU4` sections and its own `SYST`.
//!
//! A load checks everything before it changes anything: the header, the
//! checksum, the models, the identity, then the whole body against the CPU
//! (sizes, values); only then is it read into place. A refused file leaves
//! the CPU as it was.

mod identity;

use thiserror::Error;

use crate::engine::{Cpu, Snap, StateError};
use crate::system::{Cpus, System};

/// The first bytes of a state file.
pub const MAGIC: [u8; 8] = *b"SPLCSTAT";
/// The format version this build writes and reads.
pub const VERSION: u16 = 1;
/// Bytes before the body.
pub const HEADER_LEN: usize = 56;

/// Why a state file is refused.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum SnapshotError {
    #[error("not a softplc state file (it does not start with SPLCSTAT)")]
    NotAStateFile,
    #[error("state file format version {found}; this softplc reads version {VERSION}")]
    Version { found: u16 },
    #[error("the state file is damaged: {0}")]
    Damaged(String),
    #[error("the state file holds {found} CPU(s); this is {expected}")]
    CpuCount { found: u16, expected: usize },
    #[error("the state file was saved on a {found}; this CPU is a {expected}")]
    Model { found: String, expected: String },
    #[error(
        "the state file was saved from other programs or parameters (another or an edited \
         program, other device points, local devices or modules): load it into the project \
         it was saved from"
    )]
    Identity,
    #[error("the state file does not fit this CPU: {0}")]
    State(#[from] StateError),
}

/// What a state file is of: one CPU or a system.
enum Target<'a> {
    One(&'a mut Cpu),
    System(&'a mut System),
}

impl Target<'_> {
    fn cpus(&self) -> Vec<&Cpu> {
        match self {
            Target::One(c) => vec![&**c],
            Target::System(s) => (0..s.len()).map(|i| s.cpu(i)).collect(),
        }
    }

    fn models(&self) -> String {
        let models: Vec<&str> = self.cpus().iter().map(|c| c.profile().model).collect();
        models.join(",")
    }

    fn walk(&mut self, s: &mut Snap) {
        match self {
            Target::One(c) => c.snapshot(s),
            Target::System(sys) => sys.snapshot(s),
        }
    }

    fn save(&mut self) -> Vec<u8> {
        let cpus = self.cpus();
        let identity = identity::of(cpus.iter().copied());
        let count = cpus.len() as u16;
        let models = self.models();
        let mut out = Vec::with_capacity(HEADER_LEN + 1024);
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&count.to_le_bytes());
        out.extend_from_slice(&identity);
        out.extend_from_slice(&[0; 12]);
        out.extend_from_slice(&(models.len() as u16).to_le_bytes());
        out.extend_from_slice(models.as_bytes());
        let mut s = Snap::save(out);
        self.walk(&mut s);
        // Saving reads nothing and cannot fail.
        let mut out = s.finish().unwrap_or_default();
        let body_len = (out.len() - HEADER_LEN) as u64;
        out[44..52].copy_from_slice(&body_len.to_le_bytes());
        let crc = checksum(&out);
        out[52..56].copy_from_slice(&crc.to_le_bytes());
        out
    }

    fn load(&mut self, file: &[u8]) -> Result<(), SnapshotError> {
        let state = check_header(file, self.cpus().len())?;
        let (models, rest) = state.split_at_checked(2).ok_or_else(short)?;
        let n = u16::from_le_bytes([models[0], models[1]]) as usize;
        let (found, body) = rest.split_at_checked(n).ok_or_else(short)?;
        let found = String::from_utf8_lossy(found);
        let expected = self.models();
        if found != expected {
            return Err(SnapshotError::Model {
                found: found.into_owned(),
                expected,
            });
        }
        if file[12..44] != identity::of(self.cpus().into_iter()) {
            return Err(SnapshotError::Identity);
        }
        let mut check = Snap::check(body);
        self.walk(&mut check);
        check.finish()?;
        let mut load = Snap::load(body);
        self.walk(&mut load);
        load.finish()?;
        Ok(())
    }
}

/// The CRC-32 of the header before the checksum and the body.
fn checksum(file: &[u8]) -> u32 {
    let mut h = crc32fast::Hasher::new();
    h.update(&file[..52]);
    h.update(&file[HEADER_LEN..]);
    h.finalize()
}

fn short() -> SnapshotError {
    SnapshotError::Damaged("it is shorter than its header says".into())
}

/// The body of `file` after its header is checked: magic, version, CPU
/// count, length and checksum.
fn check_header(file: &[u8], cpus: usize) -> Result<&[u8], SnapshotError> {
    if file.len() < MAGIC.len() || file[..MAGIC.len()] != MAGIC {
        return Err(SnapshotError::NotAStateFile);
    }
    let Some(header) = file.get(..HEADER_LEN) else {
        return Err(short());
    };
    let u16_at = |i: usize| u16::from_le_bytes([header[i], header[i + 1]]);
    let mut len = [0; 8];
    len.copy_from_slice(&header[44..52]);
    let len = u64::from_le_bytes(len);
    let body = &file[HEADER_LEN..];
    if body.len() as u64 != len {
        return Err(SnapshotError::Damaged(format!(
            "its header says {len} bytes follow it, {} do",
            body.len()
        )));
    }
    let crc = u32::from_le_bytes([header[52], header[53], header[54], header[55]]);
    let sum = checksum(file);
    if sum != crc {
        return Err(SnapshotError::Damaged(format!(
            "its checksum is {crc:08x}, its contents sum to {sum:08x}"
        )));
    }
    let version = u16_at(8);
    if version != VERSION {
        return Err(SnapshotError::Version { found: version });
    }
    let count = u16_at(10);
    if count as usize != cpus {
        return Err(SnapshotError::CpuCount {
            found: count,
            expected: cpus,
        });
    }
    Ok(body)
}

/// Sets the body length and the checksum of `file` to what its bytes are:
/// for tests and fuzzing that reach the checks behind the checksum with
/// changed bytes. A file shorter than a header is left as it is.
pub fn reseal(file: &mut [u8]) {
    if file.len() < HEADER_LEN {
        return;
    }
    let len = (file.len() - HEADER_LEN) as u64;
    file[44..52].copy_from_slice(&len.to_le_bytes());
    let crc = checksum(file);
    file[52..56].copy_from_slice(&crc.to_le_bytes());
}

/// The state file of `cpu` now (call between scans).
pub fn save(cpu: &mut Cpu) -> Vec<u8> {
    Target::One(cpu).save()
}

/// Restores `cpu` from a state file of [`save`]; on an error nothing
/// changed.
pub fn load(cpu: &mut Cpu, file: &[u8]) -> Result<(), SnapshotError> {
    Target::One(cpu).load(file)
}

impl Cpus {
    /// The state file of the CPU or system now (every CPU's state and the
    /// system's), between scans.
    pub fn save_state(&mut self) -> Vec<u8> {
        self.target().save()
    }

    /// Restores the CPU or system from a state file of
    /// [`Cpus::save_state`]; on an error nothing changed.
    pub fn load_state(&mut self, file: &[u8]) -> Result<(), SnapshotError> {
        self.target().load(file)
    }

    fn target(&mut self) -> Target<'_> {
        match self {
            Cpus::One(c) => Target::One(c),
            Cpus::System(s) => Target::System(s),
        }
    }
}

impl System {
    /// The state file of every CPU and the system ([`Cpus::save_state`]).
    pub fn save_state(&mut self) -> Vec<u8> {
        Target::System(self).save()
    }

    /// Restores every CPU and the system ([`Cpus::load_state`]).
    pub fn load_state(&mut self, file: &[u8]) -> Result<(), SnapshotError> {
        Target::System(self).load(file)
    }
}
