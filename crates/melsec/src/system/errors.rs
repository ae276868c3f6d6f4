//! Error information (004 §7.20, App. 2): SM0/SM1 and SD0-SD26, and the
//! error reset of SM50/SD50.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::ErrorCode;
use softplc_ir::system::{ErrorReport, Severity};

use super::codes::{self, ANNUNCIATOR};
use super::devices::{bcd, sd, sd_get, sm, sm_get};

/// SM0/SM1 ON, SD0 the code, SD1-SD3 the time of detection in BCD, SM56 for
/// operation errors; SD4 the common-information category: 4 (program error
/// location) with SD5-SD10 the program file name (8 + "." + 3 characters,
/// ASCII, low byte first) and SD14/SD15 the step number (low/high word), or
/// 6 (0600H) with the annunciator number in SD16. SM5 / SM16 are ON when
/// common / individual information is present (App. 1 L9529-9531).
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
    if let (ANNUNCIATOR, Some(n)) = (r.code, r.detail) {
        sd(mem, 4, 0x0600);
        sd(mem, 16, n as u16);
        sm(mem, 5, false);
        sm(mem, 16, true);
        return;
    }
    sm(mem, 16, false);
    let Some(step) = r.step else {
        sd(mem, 4, 0);
        sm(mem, 5, false);
        return;
    };
    sd(mem, 4, 4);
    sm(mem, 5, true);
    let stem = std::path::Path::new(r.file.unwrap_or(""))
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("")
        .to_ascii_uppercase();
    let mut name = [b' '; 8];
    for (d, s) in name.iter_mut().zip(stem.bytes().filter(u8::is_ascii)) {
        *d = s;
    }
    let ext = *b".QPG";
    for i in 0..4 {
        sd(
            mem,
            5 + i,
            u16::from_le_bytes([name[2 * i as usize], name[2 * i as usize + 1]]),
        );
    }
    sd(mem, 9, u16::from_le_bytes([ext[0], ext[1]]));
    sd(mem, 10, u16::from_le_bytes([ext[2], ext[3]]));
    sd(mem, 14, step as u16);
    sd(mem, 15, (step >> 16) as u16);
}

/// SM50 ON asks to clear the continuation error whose code is in SD50; the
/// lower two digits are ignored (004 L5028-5055).
pub(crate) fn reset_request(mem: &DeviceMemory, current: Option<ErrorCode>) -> Option<bool> {
    sm_get(mem, 50).then(|| current.is_some_and(|c| sd_get(mem, 50) / 100 == c.0 / 100))
}

/// Clears SM0/SM1/SM5/SM16/SM56 and SD0-SD26.
pub(crate) fn clear(mem: &mut DeviceMemory) {
    sm(mem, 0, false);
    sm(mem, 1, false);
    sm(mem, 5, false);
    sm(mem, 16, false);
    sm(mem, 56, false);
    for n in 0..=26 {
        sd(mem, n, 0);
    }
}
