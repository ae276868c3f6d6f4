//! Error information (004 §7.20, App. 2): SM0/SM1 and SD0-SD26, and the
//! error reset of SM50/SD50.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::ErrorCode;
use softplc_ir::system::{ErrorReport, Severity};

use super::codes::{self, Common, Individual};
use super::devices::{bcd, sd, sd_get, sm, sm_get};

/// SM0/SM1 ON, SD0 the code, SD1-SD3 the time of detection in BCD, SM56 for
/// operation errors; SD4 the information categories (low byte common, high
/// byte individual, App. 2 L10153-10180) of the error's
/// [`codes::information`], with SD5-SD15 and SD16-SD26 in their layouts
/// (L10182-10316). A category whose data the report lacks is stored as 0
/// (none). SM5 / SM16 are ON when common / individual information is
/// present (App. 1 L9529-9531).
pub(crate) fn report(mem: &mut DeviceMemory, r: &ErrorReport<'_>) {
    sm(mem, 0, true);
    sm(mem, 1, true);
    let at = &r.at;
    let y = at.year as u32 % 100;
    sd(mem, 1, bcd(y) << 8 | bcd(at.month));
    sd(mem, 2, bcd(at.day) << 8 | bcd(at.hour));
    sd(mem, 3, bcd(at.minute) << 8 | bcd(at.second));
    if codes::severity(r.code) == Severity::Operation {
        sm(mem, 56, true);
    }
    sd(mem, 0, r.code.0);
    if r.code == codes::BATTERY {
        // Battery low, latched and current (App. 1 L9535-9536).
        sm(mem, 51, true);
        sm(mem, 52, true);
    }
    for n in 5..=26 {
        sd(mem, n, 0);
    }
    let (common, individual) = codes::information(r.code);
    let common = match common {
        Common::Module => r.module.map(|m| {
            sd(mem, 5, m.slot.map_or(NO_SLOT, |s| s as u16));
            sd(mem, 6, m.io as u16);
            Common::Module
        }),
        Common::File => {
            // Drive 0 (program memory) holds the parameter file.
            sd(mem, 5, 0);
            file_name(mem, 6, "PARAM", *b".QPA");
            Some(Common::File)
        }
        Common::Time => r.time.map(|t| {
            time(mem, 5, t.set_us);
            Common::Time
        }),
        Common::Program => program_location(mem, 5, r).then_some(Common::Program),
        Common::None => None,
    };
    let individual = match individual {
        Individual::Time => r.time.map(|t| {
            time(mem, 16, t.measured_us);
            Individual::Time
        }),
        Individual::Program => program_location(mem, 16, r).then_some(Individual::Program),
        Individual::Annunciator => r.detail.map(|n| {
            sd(mem, 16, n as u16);
            Individual::Annunciator
        }),
        Individual::None => None,
    };
    let common = common.map_or(0, |c| c as u16);
    let individual = individual.map_or(0, |i| i as u16);
    sd(mem, 4, individual << 8 | common);
    sm(mem, 5, common != 0);
    sm(mem, 16, individual != 0);
}

/// SD5 of a module error whose I/O number no slot of the rack holds.
pub const NO_SLOT: u16 = 0xFFFF;

/// A time in the "time" layout from register `reg`: µs part (0-999), then
/// ms part (0-65535) (L10230-10240, L10290-10300).
fn time(mem: &mut DeviceMemory, reg: i64, us: u64) {
    sd(mem, reg, (us % 1000) as u16);
    sd(mem, reg + 1, (us / 1000).min(u16::MAX as u64) as u16);
}

/// The "program error location" layout from register `reg` (SD5 or SD16):
/// file name (8 ASCII characters, low byte first), "." and the extension,
/// the SFC pattern, block and step (0: softplc has no SFC), the sequence
/// step number low/high word. False when the report has no step.
fn program_location(mem: &mut DeviceMemory, reg: i64, r: &ErrorReport<'_>) -> bool {
    let Some(step) = r.step else {
        return false;
    };
    let stem = std::path::Path::new(r.file.unwrap_or(""))
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("");
    file_name(mem, reg, stem, *b".QPG");
    sd(mem, reg + 9, step as u16);
    sd(mem, reg + 10, (step >> 16) as u16);
    true
}

/// A file name from register `reg`: 8 ASCII characters (upper case, space
/// padded, low byte first) in four words, then "." and the 3-character
/// extension in two.
fn file_name(mem: &mut DeviceMemory, reg: i64, stem: &str, ext: [u8; 4]) {
    let mut name = [b' '; 8];
    let upper = stem
        .bytes()
        .filter(u8::is_ascii)
        .map(|b| b.to_ascii_uppercase());
    for (d, s) in name.iter_mut().zip(upper) {
        *d = s;
    }
    for (i, pair) in name.chunks(2).enumerate() {
        sd(mem, reg + i as i64, u16::from_le_bytes([pair[0], pair[1]]));
    }
    sd(mem, reg + 4, u16::from_le_bytes([ext[0], ext[1]]));
    sd(mem, reg + 5, u16::from_le_bytes([ext[2], ext[3]]));
}

/// SM50 ON asks to clear the continuation error whose code is in SD50; the
/// lower two digits are ignored (004 L5028-5055).
pub(crate) fn reset_request(mem: &DeviceMemory, current: Option<ErrorCode>) -> Option<bool> {
    sm_get(mem, 50).then(|| current.is_some_and(|c| sd_get(mem, 50) / 100 == c.0 / 100))
}

/// Clears SM0/SM1/SM5/SM16/SM56 and SD0-SD26; a BATTERY ERROR cleared
/// turns SM52 (battery low now) OFF, SM51 stays latched (App. 1 L9535-9536).
pub(crate) fn clear(mem: &mut DeviceMemory) {
    if sd_get(mem, 0) == codes::BATTERY.0 {
        sm(mem, 52, false);
    }
    sm(mem, 0, false);
    sm(mem, 1, false);
    sm(mem, 5, false);
    sm(mem, 16, false);
    sm(mem, 56, false);
    for n in 0..=26 {
        sd(mem, n, 0);
    }
}
