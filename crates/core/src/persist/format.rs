//! On-disk formats of the state directory: the base image and the journal frames.
//!
//! All integers are little-endian. Decoders never panic and never trust a length
//! field before checking it against the bytes actually present; they return a
//! short description of what is wrong instead.

/// Magic at the start of `image.bin`, format version 2 (per-region checksums).
pub(crate) const IMAGE_MAGIC: &[u8; 8] = b"SPLCIMG\x02";
/// Format version 1 (one checksum over the whole file), still read.
pub(crate) const IMAGE_MAGIC_V1: &[u8; 8] = b"SPLCIMG\x01";
/// Magic at the start of every journal frame (format version 1).
pub(crate) const FRAME_MAGIC: u32 = u32::from_le_bytes(*b"SPJ1");
/// Frame head: magic u32, body length u32, generation u64, chunk-record count u32.
pub(crate) const FRAME_HEAD: usize = 20;
/// Chunk-record head: region index u32, offset u32, length u32.
pub(crate) const RECORD_HEAD: usize = 12;
/// Frame trailer: CRC32 over everything from the magic to the last data byte.
pub(crate) const FRAME_TAIL: usize = 4;
/// Longest region name accepted in a layout or an image.
pub(crate) const MAX_NAME: usize = 256;

/// One region of a decoded base image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ImageRegion {
    pub name: String,
    /// Whether the region holds committed data (false: it was added to the layout
    /// after the last commit and is all zeros).
    pub committed: bool,
    pub data: Vec<u8>,
    /// False when the region's checksum failed (or the file ends inside it): its
    /// contents are lost and `data` is zeros.
    pub intact: bool,
}

/// A decoded base image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Image {
    /// Generation of the last commit folded into this image (0: none yet).
    pub generation: u64,
    pub regions: Vec<ImageRegion>,
}

/// The image header, up to and not including the region data.
///
/// Version 2 layout: magic (8) | generation u64 | region count u32 |
/// per region: name length u16, name (UTF-8), data length u64, flags u8 (bit 0:
/// committed), CRC32 of the region data u32 | CRC32 u32 of all preceding header
/// bytes | region data, concatenated in table order. A damaged region loses only
/// itself; a damaged header loses the image.
pub(crate) fn image_header<'a>(
    generation: u64,
    regions: impl ExactSizeIterator<Item = (&'a str, usize, bool, u32)>,
) -> Vec<u8> {
    let mut out = Vec::with_capacity(64);
    out.extend_from_slice(IMAGE_MAGIC);
    out.extend_from_slice(&generation.to_le_bytes());
    out.extend_from_slice(&(regions.len() as u32).to_le_bytes());
    for (name, len, committed, crc) in regions {
        out.extend_from_slice(&(name.len() as u16).to_le_bytes());
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(&(len as u64).to_le_bytes());
        out.push(u8::from(committed));
        out.extend_from_slice(&crc.to_le_bytes());
    }
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// A bounds-checked little-endian reader over a byte slice.
struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        match self.pos.checked_add(n) {
            Some(end) if end <= self.buf.len() => {
                let s = &self.buf[self.pos..end];
                self.pos = end;
                Ok(s)
            }
            _ => Err(format!(
                "{what} at offset {} needs {n} bytes, only {} left",
                self.pos,
                self.buf.len() - self.pos.min(self.buf.len())
            )),
        }
    }
    fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.take(1, what)?[0])
    }
    fn u16(&mut self, what: &str) -> Result<u16, String> {
        Ok(u16::from_le_bytes(
            self.take(2, what)?.try_into().unwrap_or([0; 2]),
        ))
    }
    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(
            self.take(4, what)?.try_into().unwrap_or([0; 4]),
        ))
    }
    fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(u64::from_le_bytes(
            self.take(8, what)?.try_into().unwrap_or([0; 8]),
        ))
    }
}

/// Decodes and verifies a base image file. `Err` when the header is unusable
/// (then nothing can be recovered); a region whose own checksum fails comes back
/// with `intact: false`.
pub(crate) fn decode_image(bytes: &[u8]) -> Result<Image, String> {
    if bytes.len() < IMAGE_MAGIC.len() + 8 + 4 + 4 {
        return Err(format!("{} bytes is too short for an image", bytes.len()));
    }
    let v1 = &bytes[..IMAGE_MAGIC.len()] == IMAGE_MAGIC_V1;
    if !v1 && &bytes[..IMAGE_MAGIC.len()] != IMAGE_MAGIC {
        return Err("bad magic (not a softplc image, or another format version)".into());
    }
    let body = if v1 {
        // Version 1: one CRC over the whole file.
        let (body, crc) = bytes.split_at(bytes.len() - 4);
        let stored = u32::from_le_bytes(crc.try_into().unwrap_or([0; 4]));
        let actual = crc32fast::hash(body);
        if stored != actual {
            return Err(format!(
                "checksum mismatch (stored {stored:08x}, computed {actual:08x})"
            ));
        }
        body
    } else {
        bytes
    };
    let mut r = Reader {
        buf: body,
        pos: IMAGE_MAGIC.len(),
    };
    let generation = r.u64("generation")?;
    let count = r.u32("region count")? as usize;
    // Each table entry takes at least 11 bytes: bound the count before allocating.
    if count > body.len() / 11 {
        return Err(format!("region count {count} exceeds the file size"));
    }
    let mut table = Vec::with_capacity(count);
    for i in 0..count {
        let name_len = r.u16("region name length")? as usize;
        if name_len == 0 || name_len > MAX_NAME {
            return Err(format!("region #{i}: bad name length {name_len}"));
        }
        let name = String::from_utf8_lossy(r.take(name_len, "region name")?).into_owned();
        let len = r.u64("region length")?;
        let flags = r.u8("region flags")?;
        let crc = if v1 {
            None
        } else {
            Some(r.u32("region checksum")?)
        };
        table.push((name, len, flags, crc));
    }
    if !v1 {
        let end = r.pos;
        let stored = r.u32("header checksum")?;
        let actual = crc32fast::hash(&body[..end]);
        if stored != actual {
            return Err(format!(
                "header checksum mismatch (stored {stored:08x}, computed {actual:08x})"
            ));
        }
    }
    for (name, _, flags, _) in &table {
        if flags & !1 != 0 {
            return Err(format!("region {name:?}: unknown flags {flags:#04x}"));
        }
    }
    let data_len: u64 = table.iter().map(|t| t.1).sum();
    let left = (body.len() - r.pos) as u64;
    if v1 && data_len != left {
        return Err(format!(
            "region table announces {data_len} data bytes, file holds {left}"
        ));
    }
    if !v1 && data_len > left + (64 << 20) {
        // More than a truncation could explain: refuse to allocate it.
        return Err(format!(
            "region table announces {data_len} data bytes, file holds {left}"
        ));
    }
    let mut regions = Vec::with_capacity(count);
    for (name, len, flags, crc) in table {
        let len = len as usize;
        let (data, intact) = match r.take(len, "region data") {
            Ok(d) => match crc {
                Some(c) if crc32fast::hash(d) != c => (vec![0; len], false),
                _ => (d.to_vec(), true),
            },
            // The file ends inside this region (truncated).
            Err(_) => {
                r.pos = body.len();
                (vec![0; len], false)
            }
        };
        regions.push(ImageRegion {
            name,
            committed: flags & 1 != 0,
            data,
            intact,
        });
    }
    Ok(Image {
        generation,
        regions,
    })
}

/// One chunk record of a decoded frame; `data` indexes the journal buffer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Record {
    pub region: usize,
    pub offset: usize,
    pub data: std::ops::Range<usize>,
}

/// A complete, checksum-verified journal frame (one commit).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Frame {
    pub generation: u64,
    pub records: Vec<Record>,
    /// Offset just past the frame.
    pub end: usize,
}

/// Starts a frame in `out` (cleared first). Finish it with [`push_record`] and
/// [`finish_frame`].
pub(crate) fn begin_frame(out: &mut Vec<u8>, generation: u64) {
    out.clear();
    out.extend_from_slice(&FRAME_MAGIC.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes()); // body length, patched by finish_frame
    out.extend_from_slice(&generation.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes()); // record count, patched by finish_frame
}

/// Appends one chunk record to a frame started by [`begin_frame`].
pub(crate) fn push_record(out: &mut Vec<u8>, region: usize, offset: usize, data: &[u8]) {
    out.extend_from_slice(&(region as u32).to_le_bytes());
    out.extend_from_slice(&(offset as u32).to_le_bytes());
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(data);
}

/// Patches the lengths and appends the CRC32 over the whole frame.
pub(crate) fn finish_frame(out: &mut Vec<u8>, records: usize) {
    let body = (out.len() - 8) as u32;
    out[4..8].copy_from_slice(&body.to_le_bytes());
    out[16..20].copy_from_slice(&(records as u32).to_le_bytes());
    let crc = crc32fast::hash(out);
    out.extend_from_slice(&crc.to_le_bytes());
}

/// Decodes the frame starting at `pos`. `Ok(None)` at the exact end of the buffer;
/// `Err` for a torn or damaged frame. Region indices and bounds are checked by the
/// caller, which knows the layout.
pub(crate) fn decode_frame(buf: &[u8], pos: usize) -> Result<Option<Frame>, String> {
    let rest = buf.get(pos..).unwrap_or(&[]);
    if rest.is_empty() {
        return Ok(None);
    }
    if rest.len() < FRAME_HEAD + FRAME_TAIL {
        return Err(format!("torn frame head ({} bytes)", rest.len()));
    }
    let mut r = Reader { buf: rest, pos: 0 };
    let magic = r.u32("frame magic")?;
    if magic != FRAME_MAGIC {
        return Err(format!("bad frame magic {magic:08x}"));
    }
    let body = r.u32("frame length")? as usize;
    let total = 8usize
        .checked_add(body)
        .and_then(|n| n.checked_add(FRAME_TAIL))
        .unwrap_or(usize::MAX);
    if body < FRAME_HEAD - 8 || total > rest.len() {
        return Err(format!(
            "torn frame (announces {total} bytes, {} present)",
            rest.len()
        ));
    }
    let covered = &rest[..8 + body];
    let stored = u32::from_le_bytes(rest[8 + body..total].try_into().unwrap_or([0; 4]));
    let actual = crc32fast::hash(covered);
    if stored != actual {
        return Err(format!(
            "frame checksum mismatch (stored {stored:08x}, computed {actual:08x})"
        ));
    }
    let mut r = Reader {
        buf: covered,
        pos: 8,
    };
    let generation = r.u64("generation")?;
    let count = r.u32("record count")? as usize;
    if count > body / RECORD_HEAD {
        return Err(format!("record count {count} exceeds the frame size"));
    }
    let mut records = Vec::with_capacity(count);
    for _ in 0..count {
        let region = r.u32("record region")? as usize;
        let offset = r.u32("record offset")? as usize;
        let len = r.u32("record length")? as usize;
        let start = r.pos;
        r.take(len, "record data")?;
        records.push(Record {
            region,
            offset,
            data: pos + start..pos + start + len,
        });
    }
    if r.pos != covered.len() {
        return Err(format!(
            "{} stray bytes after the last record",
            covered.len() - r.pos
        ));
    }
    Ok(Some(Frame {
        generation,
        records,
        end: pos + total,
    }))
}
