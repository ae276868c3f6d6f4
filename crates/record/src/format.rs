//! The recording file: a magic line, then frames appended one at a time —
//! each a little-endian `u32` length, the CRC-32 of the payload and the
//! payload (postcard). The first frame is the [`Header`], then one [`End`]
//! per END processing, and a [`Record::Shutdown`] when the server stopped.
//!
//! A frame is written with one `write` after its END, so a server killed
//! with SIGKILL leaves whole frames and at most one torn frame at the end:
//! [`Reader`] stops before it and says so. A frame that is damaged with
//! more data after it is an error naming its byte offset.

use std::io::{Read, Write};
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::event::Event;

/// The first bytes of a recording.
pub const MAGIC: &[u8; 14] = b"softplc-rec 1\n";

/// A frame larger than this is refused as damaged (a program's sources and
/// a 1 MiB battery image fit many times over).
const MAX_FRAME: u32 = 256 << 20;

/// What `softplc replay` needs to build the recorded CPU again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// The program as `serve` was given it: a file name, or the project
    /// directory's name.
    pub program: String,
    /// A project directory (its files under `files`), or one program file.
    pub project: bool,
    /// `--model` of a single program file.
    pub model: Option<String>,
    /// The model the CPU ran as (for reports).
    pub cpu_model: String,
    /// Every source file: the program file, or the project's files by path
    /// relative to its directory.
    pub files: Vec<SourceFile>,
    /// CRC-32 of the files and the model, in hex: the program's identity.
    pub identity: String,
    /// The calendar clock at power-on, seconds since 1970.
    pub calendar_unix_s: i64,
    /// The constant-scan period, µs.
    pub period_us: u64,
}

/// One source file of the recorded program.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SourceFile {
    pub path: String,
    pub bytes: Vec<u8>,
}

/// The changes of one END, or of the start before scan 1.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct End {
    /// A scan ran before these changes (false for the start: the load and
    /// the battery-backed image).
    pub scanned: bool,
    /// The CPU's scan count at this END (executed scans since power-on).
    pub scans: u64,
    /// Every engine-clock reading the CPU took, in order, each the
    /// difference to the one before (the first of the recording to 0).
    pub clock: Vec<u64>,
    /// The changes from outside, in the order they were made, after the scan.
    pub events: Vec<Event>,
}

/// One frame's payload.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Record {
    Header(Header),
    End(End),
    /// The server stopped after the END with this scan count.
    Shutdown {
        scans: u64,
    },
    /// Recording stopped here (`--record-max-size` reached); the server ran on.
    Full {
        scans: u64,
    },
    /// Recording stopped here before a change it cannot follow (a program
    /// written during RUN, a state file loaded); the server ran on.
    Stopped {
        scans: u64,
        why: String,
    },
}

impl Header {
    /// The identity of `files` and `model`.
    pub fn identity_of(files: &[SourceFile], model: Option<&str>) -> String {
        let mut h = crc32fast::Hasher::new();
        for f in files {
            h.update(f.path.as_bytes());
            h.update(&[0]);
            h.update(&(f.bytes.len() as u64).to_le_bytes());
            h.update(&f.bytes);
        }
        h.update(model.unwrap_or("").as_bytes());
        format!("{:08x}", h.finalize())
    }
}

/// A record as one frame: length, CRC, payload.
pub fn frame(r: &Record) -> Vec<u8> {
    let payload = postcard::to_stdvec(r).unwrap_or_default();
    let mut out = Vec::with_capacity(payload.len() + 8);
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

/// Why a recording cannot be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FormatError(pub String);

impl std::fmt::Display for FormatError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FormatError {}

/// Reads a recording frame by frame.
pub struct Reader<R> {
    input: R,
    /// Byte offset of the next frame.
    at: u64,
    /// A torn last frame was found: where it starts.
    torn: Option<u64>,
    name: String,
}

impl Reader<std::io::BufReader<std::fs::File>> {
    /// Opens `path` and checks its magic line.
    pub fn open(path: &Path) -> Result<Self, FormatError> {
        let file = std::fs::File::open(path)
            .map_err(|e| FormatError(format!("{}: {e}", path.display())))?;
        Reader::new(std::io::BufReader::new(file), &path.display().to_string())
    }
}

impl<R: Read> Reader<R> {
    /// Reads from `input` (`name` in messages), checking the magic line.
    pub fn new(mut input: R, name: &str) -> Result<Self, FormatError> {
        let mut magic = [0u8; MAGIC.len()];
        let n =
            read_full(&mut input, &mut magic).map_err(|e| FormatError(format!("{name}: {e}")))?;
        if n < magic.len() || &magic != MAGIC {
            return Err(FormatError(format!(
                "{name}: not a softplc recording (it does not start with `softplc-rec 1`)"
            )));
        }
        Ok(Reader {
            input,
            at: MAGIC.len() as u64,
            torn: None,
            name: name.to_string(),
        })
    }

    /// The next record; `None` at the end or before a torn last frame
    /// ([`Self::torn`]).
    pub fn read_record(&mut self) -> Result<Option<Record>, FormatError> {
        if self.torn.is_some() {
            return Ok(None);
        }
        let at = self.at;
        let io = |e: std::io::Error| FormatError(format!("{}: {e}", self.name));
        let mut head = [0u8; 8];
        let n = read_full(&mut self.input, &mut head).map_err(io)?;
        if n == 0 {
            return Ok(None);
        }
        if n < head.len() {
            self.torn = Some(at);
            return Ok(None);
        }
        let len = u32::from_le_bytes([head[0], head[1], head[2], head[3]]);
        let crc = u32::from_le_bytes([head[4], head[5], head[6], head[7]]);
        let damaged =
            |what: &str| FormatError(format!("{}: damaged frame at byte {at}: {what}", self.name));
        if len > MAX_FRAME {
            return Err(damaged(&format!("a length of {len} bytes")));
        }
        let mut payload = vec![0u8; len as usize];
        let n = read_full(&mut self.input, &mut payload).map_err(io)?;
        if n < payload.len() {
            self.torn = Some(at);
            return Ok(None);
        }
        if crc32fast::hash(&payload) != crc {
            // The last frame may be torn mid-write; one with more after it is damage.
            let mut probe = [0u8; 1];
            if read_full(&mut self.input, &mut probe).map_err(io)? == 0 {
                self.torn = Some(at);
                return Ok(None);
            }
            return Err(damaged("its checksum does not match"));
        }
        self.at += 8 + len as u64;
        postcard::from_bytes(&payload)
            .map(Some)
            .map_err(|e| damaged(&format!("unreadable ({e})")))
    }

    /// Where a torn last frame starts (a server killed while writing it).
    pub fn torn(&self) -> Option<u64> {
        self.torn
    }
}

/// Reads until `buf` is full or the input ends; the bytes read.
fn read_full(input: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match input.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

/// Writes the magic line (a new recording).
pub fn write_magic(out: &mut impl Write) -> std::io::Result<()> {
    out.write_all(MAGIC)
}
