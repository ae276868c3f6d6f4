//! Recovery at open: load the base image (each region checked by its own CRC),
//! replay the journal, truncate a bad journal tail, and say what was lost.
//!
//! A journal tail torn by a kill (a frame shorter than its header announces) is
//! the expected result of dying inside `commit` and is only a warning: that
//! commit had not returned. Anything else — a region whose checksum fails, an
//! unreadable image header, a complete frame with a bad checksum or out of
//! sequence — is damage to committed data and is listed in [`Recovered::lost`],
//! which the CPU reports as a self-diagnostic error.

use std::fs::{self, OpenOptions};
use std::io;
use std::path::{Path, PathBuf};

use super::format::{self, decode_frame, decode_image};
use super::{io_err, PersistError};

/// The state recovered from the image and the journal, in the image's region table.
pub(crate) struct Recovered {
    pub generation: u64,
    pub regions: Vec<format::ImageRegion>,
    /// The image exists, is valid, and the journal was replayed against it.
    pub have_image: bool,
    /// Frames applied from the journal.
    pub replayed: usize,
    /// Committed data that could not be recovered, one description each.
    pub lost: Vec<String>,
    /// A region of the image failed its checksum: the image must be rewritten.
    pub image_damaged: bool,
}

/// Moves a damaged file aside as `<name>.corrupt` (replacing an older one).
fn move_aside(path: &Path) -> Result<PathBuf, PersistError> {
    let to = corrupt_name(path);
    fs::rename(path, &to).map_err(io_err("rename", path))?;
    Ok(to)
}

fn corrupt_name(path: &Path) -> PathBuf {
    let mut to = path.as_os_str().to_owned();
    to.push(".corrupt");
    PathBuf::from(to)
}

fn warn(warnings: &mut Vec<String>, e: PersistError) {
    warnings.push(e.to_string());
}

/// Loads the image, replays the journal, truncates a bad journal tail.
pub(crate) fn recover(
    image_path: &Path,
    journal_path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Recovered, PersistError> {
    let mut lost = Vec::new();
    let image = match fs::read(image_path) {
        Ok(bytes) => match decode_image(&bytes) {
            Ok(image) => Some(image),
            Err(what) => {
                warn(
                    warnings,
                    PersistError::Corrupt {
                        path: image_path.to_path_buf(),
                        what: format!("{what}; starting from empty memory"),
                    },
                );
                let to = move_aside(image_path)?;
                warnings.push(format!("damaged image kept as {}", to.display()));
                lost.push(format!(
                    "all retained memory ({} unreadable: {what})",
                    image_path.display()
                ));
                None
            }
        },
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(io_err("read", image_path)(e)),
    };
    let journal = match fs::read(journal_path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == io::ErrorKind::NotFound => Vec::new(),
        Err(e) => return Err(io_err("read", journal_path)(e)),
    };
    let Some(image) = image else {
        if !journal.is_empty() {
            let to = move_aside(journal_path)?;
            warnings.push(format!(
                "{}: journal without a valid image ({} bytes) cannot be replayed; kept as {}",
                journal_path.display(),
                journal.len(),
                to.display()
            ));
            if lost.is_empty() {
                lost.push(format!(
                    "all retained memory ({} is missing)",
                    image_path.display()
                ));
            }
        }
        return Ok(Recovered {
            generation: 0,
            regions: Vec::new(),
            have_image: false,
            replayed: 0,
            lost,
            image_damaged: false,
        });
    };

    let base = image.generation;
    let mut generation = base;
    let mut regions = image.regions;
    let mut replayed = 0;
    let mut pos = 0;
    let problem = loop {
        let frame = match decode_frame(&journal, pos) {
            Ok(None) => break None,
            Ok(Some(frame)) => frame,
            Err(what) => break Some(what),
        };
        if replayed == 0 && frame.generation <= base {
            // Already folded into the image by a checkpoint that did not get to
            // truncate the journal (possibly written for an older layout).
        } else if frame.generation == generation + 1 {
            if let Some(bad) = frame.records.iter().find(|r| {
                r.region >= regions.len()
                    || match r.offset.checked_add(r.data.len()) {
                        Some(end) => end > regions[r.region].data.len(),
                        None => true,
                    }
            }) {
                break Some(format!(
                    "generation {}: record for region #{} at {}+{} is outside the layout",
                    frame.generation,
                    bad.region,
                    bad.offset,
                    bad.data.len()
                ));
            }
            for r in &frame.records {
                let region = &mut regions[r.region];
                // A region lost in the image stays zeroed: a few replayed chunks
                // over zeros would be a mix of states.
                if region.intact {
                    region.data[r.offset..r.offset + r.data.len()]
                        .copy_from_slice(&journal[r.data.clone()]);
                }
            }
            regions.iter_mut().for_each(|r| r.committed = true);
            generation += 1;
            replayed += 1;
        } else {
            break Some(format!(
                "generation {} follows generation {generation}",
                frame.generation
            ));
        }
        pos = frame.end;
    };
    // Regions whose checksum failed (or that the file cut short), now that the
    // journal has said whether they held committed data.
    let bad: Vec<&str> = regions
        .iter()
        .filter(|r| !r.intact && r.committed)
        .map(|r| r.name.as_str())
        .collect();
    let image_damaged = !bad.is_empty();
    if image_damaged {
        // Keep the damaged file for inspection; the open rewrites it.
        let to = corrupt_name(image_path);
        fs::copy(image_path, &to).map_err(io_err("copy", image_path))?;
        for name in &bad {
            warn(
                warnings,
                PersistError::Corrupt {
                    path: image_path.to_path_buf(),
                    what: format!(
                        "region {name:?}: checksum mismatch or cut short; it starts zeroed"
                    ),
                },
            );
            lost.push(format!("region {name:?} (damaged in the image)"));
        }
        warnings.push(format!("damaged image kept as {}", to.display()));
    }
    if let Some(what) = problem {
        // A torn last frame is what a kill inside `commit` leaves; anything else
        // lost commits that had returned.
        if !what.starts_with("torn frame") {
            lost.push(format!(
                "journal commits after generation {generation} ({what})"
            ));
        }
        warn(
            warnings,
            PersistError::Corrupt {
                path: journal_path.to_path_buf(),
                what: format!(
                    "{what}; discarded {} bytes from offset {pos} (state is generation {generation})",
                    journal.len() - pos
                ),
            },
        );
        let file = OpenOptions::new()
            .write(true)
            .open(journal_path)
            .map_err(io_err("open", journal_path))?;
        file.set_len(pos as u64)
            .map_err(io_err("truncate", journal_path))?;
    }
    Ok(Recovered {
        generation,
        regions,
        have_image: true,
        replayed,
        lost,
        image_damaged,
    })
}
