//! Unpacking an `.fmu` (a ZIP archive, FMI 3.0 §2.5) into a temporary
//! directory, or using an already unpacked FMU directory as it is.

use std::io::Read;
use std::path::{Path, PathBuf};

/// Bytes an archive may unpack to: FMUs with embedded solvers or Python
/// runtimes are tens of MB; this bounds a malicious or broken archive.
const MAX_UNPACKED_BYTES: u64 = 1 << 30;

/// An unpacked FMU: its directory (removed on drop when it was unpacked here).
pub struct Unpacked {
    dir: PathBuf,
    _temp: Option<tempfile::TempDir>,
}

impl Unpacked {
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The text of `modelDescription.xml`.
    pub fn model_description(&self) -> Result<String, String> {
        let p = self.dir.join("modelDescription.xml");
        std::fs::read_to_string(&p).map_err(|e| format!("cannot read {}: {e}", p.display()))
    }
}

/// The text of `modelDescription.xml` of the FMU at `path` (an archive or a
/// directory), without unpacking anything else.
pub fn model_description(path: &Path) -> Result<String, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot open the FMU: {e}"))?;
    if meta.is_dir() {
        return Unpacked {
            dir: path.to_path_buf(),
            _temp: None,
        }
        .model_description();
    }
    let file = std::fs::File::open(path).map_err(|e| format!("cannot open the FMU: {e}"))?;
    let mut zip =
        zip::ZipArchive::new(file).map_err(|e| format!("not an FMU (a ZIP archive): {e}"))?;
    let mut entry = zip
        .by_name("modelDescription.xml")
        .map_err(|e| format!("the archive has no modelDescription.xml: {e}"))?;
    let mut text = String::new();
    (&mut entry)
        .take(MAX_DESCRIPTION_BYTES)
        .read_to_string(&mut text)
        .map_err(|e| format!("modelDescription.xml: {e}"))?;
    Ok(text)
}

/// Bytes of `modelDescription.xml` read from an archive (FMUs with
/// thousands of variables have descriptions of a few MB).
const MAX_DESCRIPTION_BYTES: u64 = 64 << 20;

/// Opens `path`: a directory is used in place; a file is unpacked as a ZIP
/// archive into a fresh temporary directory. Entries that would land outside
/// it (absolute paths, `..`) are errors.
pub fn open(path: &Path) -> Result<Unpacked, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot open the FMU: {e}"))?;
    if meta.is_dir() {
        return Ok(Unpacked {
            dir: path.to_path_buf(),
            _temp: None,
        });
    }
    let file = std::fs::File::open(path).map_err(|e| format!("cannot open the FMU: {e}"))?;
    let mut zip =
        zip::ZipArchive::new(file).map_err(|e| format!("not an FMU (a ZIP archive): {e}"))?;
    let temp = tempfile::Builder::new()
        .prefix("softplc-fmu-")
        .tempdir()
        .map_err(|e| format!("cannot create a directory to unpack the FMU: {e}"))?;
    let mut budget = MAX_UNPACKED_BYTES;
    for i in 0..zip.len() {
        let mut entry = zip
            .by_index(i)
            .map_err(|e| format!("entry #{} of the archive: {e}", i + 1))?;
        let name = entry
            .name()
            .map_or_else(|_| format!("#{}", i + 1), |n| n.into_owned());
        let rel = entry
            .enclosed_name()
            .ok_or_else(|| format!("archive entry `{name}` points outside the FMU"))?;
        let out = temp.path().join(rel);
        if entry.is_dir() {
            std::fs::create_dir_all(&out).map_err(|e| format!("unpacking `{name}`: {e}"))?;
            continue;
        }
        if let Some(parent) = out.parent() {
            std::fs::create_dir_all(parent).map_err(|e| format!("unpacking `{name}`: {e}"))?;
        }
        let mut f = std::fs::File::create(&out).map_err(|e| format!("unpacking `{name}`: {e}"))?;
        let copied = std::io::copy(&mut (&mut entry).take(budget + 1), &mut f)
            .map_err(|e| format!("unpacking `{name}`: {e}"))?;
        if copied > budget {
            return Err(format!(
                "the FMU unpacks to more than {} MiB",
                MAX_UNPACKED_BYTES >> 20
            ));
        }
        budget -= copied;
    }
    Ok(Unpacked {
        dir: temp.path().to_path_buf(),
        _temp: Some(temp),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn archive(entries: &[(&str, &[u8])]) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("m.fmu");
        let mut w = zip::ZipWriter::new(std::fs::File::create(&p).unwrap());
        for (name, data) in entries {
            w.start_file(*name, zip::write::SimpleFileOptions::default())
                .unwrap();
            w.write_all(data).unwrap();
        }
        w.finish().unwrap();
        (dir, p)
    }

    #[test]
    fn unpacks_into_a_temporary_directory_removed_on_drop() {
        let (_d, p) = archive(&[
            ("modelDescription.xml", b"<fmiModelDescription/>"),
            ("binaries/x86_64-linux/m.so", b"\x7fELF"),
        ]);
        assert_eq!(model_description(&p).unwrap(), "<fmiModelDescription/>");
        let u = open(&p).unwrap();
        let dir = u.dir().to_path_buf();
        assert_eq!(u.model_description().unwrap(), "<fmiModelDescription/>");
        assert_eq!(
            std::fs::read(dir.join("binaries/x86_64-linux/m.so")).unwrap(),
            b"\x7fELF"
        );
        drop(u);
        assert!(!dir.exists());
    }

    #[test]
    fn bad_archives_are_errors() {
        let (_d, p) = archive(&[("../evil.txt", b"x")]);
        let err = open(&p).err().unwrap();
        assert!(
            err.contains("`../evil.txt` points outside the FMU"),
            "{err}"
        );
        let t = tempfile::tempdir().unwrap();
        let not_zip = t.path().join("x.fmu");
        std::fs::write(&not_zip, "plain text").unwrap();
        assert!(open(&not_zip)
            .err()
            .unwrap()
            .contains("not an FMU (a ZIP archive)"));
        let err = open(&t.path().join("missing.fmu")).err().unwrap();
        assert!(err.contains("cannot open the FMU"), "{err}");
    }
}
