//! `run --save-state FILE` / `--load-state FILE` (contract §7): the state
//! file of a CPU or system written after the last scan, read before scan 1
//! instead of the power-on. Errors name the file.

use std::path::Path;

use softplc_core::snapshot::SnapshotError;

/// Reads `path` and restores it with `load`; the error names the file.
pub(crate) fn load(
    path: &Path,
    load: impl FnOnce(&[u8]) -> Result<(), SnapshotError>,
) -> Result<(), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("--load-state {}: {e}", path.display()))?;
    load(&bytes).map_err(|e| format!("--load-state {}: {e}", path.display()))
}

/// Writes `bytes` to `path` whole (`online::write_file`), so an
/// interrupted save leaves the old file.
pub(crate) fn save(path: &Path, bytes: &[u8]) -> Result<(), String> {
    softplc_core::online::write_file(path, bytes).map_err(|e| format!("--save-state {e}"))
}
