//! The file registers' system devices (004 §10.7; App. 1 SM640, SM672;
//! App. 2 SD640-SD647, L10532-10540). softplc has one file-register file
//! per project, shared by every program (the parameter's "use the following
//! file", 004 §10.7.3 (1) (c)): `[devices] file_register` points named by
//! `[devices] file_register_name`. It is always RAM, which programs write:
//! the standard RAM when it fits there, else memory card A's SRAM. A flash
//! card, which programs cannot write (§10.7.2), is never modelled.

use softplc_ir::device::{DeviceKind, DeviceMemory};

use super::devices::{sd, sm};

/// File-register points the standard RAM of a QnHCPU/QnPHCPU holds (004
/// §10.7.1 (1)); a Universal model's is its profile's
/// ([`crate::profiles::standard_ram`]).
pub const QNH_STANDARD_RAM: u32 = 32768;

/// SD640's drive numbers: memory card A (RAM), standard RAM.
pub const DRIVE_CARD: u16 = 1;
pub const DRIVE_STANDARD_RAM: u16 = 3;

/// The file-register file the CPU reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileRegisterFile {
    /// Points the standard RAM holds: a file of at most this many points
    /// is there (drive 3), a larger one on memory card A (drive 1).
    pub standard_ram: u32,
    /// Its name: 1-8 ASCII letters, digits or `_`, padded with spaces
    /// (extension `QDR`).
    pub name: [u8; 8],
}

/// The name a project gets when it names none.
pub const DEFAULT_NAME: &str = "MAIN";

impl Default for FileRegisterFile {
    fn default() -> Self {
        FileRegisterFile {
            standard_ram: QNH_STANDARD_RAM,
            name: file_name(DEFAULT_NAME).unwrap_or(*b"MAIN    "),
        }
    }
}

/// A file-register file name as SD641-SD644 hold it; `Err` says why not.
pub fn file_name(text: &str) -> Result<[u8; 8], String> {
    let ok = !text.is_empty()
        && text.len() <= 8
        && text.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
    if !ok {
        return Err(format!(
            "file register file name \"{text}\" must be 1-8 letters, digits or _ (QCPU manual §10.7.3)"
        ));
    }
    let mut name = [b' '; 8];
    name[..text.len()].copy_from_slice(text.as_bytes());
    name.make_ascii_uppercase();
    Ok(name)
}

impl FileRegisterFile {
    /// SD640's drive for `points` file registers, 0 for none.
    pub fn drive(&self, points: u32) -> u16 {
        match points {
            0 => 0,
            p if p <= self.standard_ram => DRIVE_STANDARD_RAM,
            _ => DRIVE_CARD,
        }
    }

    /// Power-on: SM640 ON and SD640-SD647 (drive, name `NAME.QDR`, capacity
    /// in K points) when the project has file registers; all 0 when not.
    pub(crate) fn power_on(&self, mem: &mut DeviceMemory) {
        let points = mem.map.points(DeviceKind::ZR);
        sm(mem, 640, points > 0);
        sd(mem, 640, self.drive(points));
        let pair = |lo: u8, hi: u8| u16::from_le_bytes([lo, hi]);
        let n = &self.name;
        let words = [
            pair(n[0], n[1]),
            pair(n[2], n[3]),
            pair(n[4], n[5]),
            pair(n[6], n[7]),
            pair(b'.', b'Q'),
            pair(b'D', b'R'),
        ];
        for (i, w) in words.into_iter().enumerate() {
            sd(mem, 641 + i as i64, if points > 0 { w } else { 0 });
        }
        sd(mem, 647, (points / 1024).min(u16::MAX as u32) as u16);
    }

    /// END: SM672 turns ON when the program reached file registers outside
    /// the registered range on memory card A (App. 1: "set in END
    /// processing", reset by the program; the flag is memory card A's, so
    /// standard RAM sets nothing). The void those accesses used is cleared
    /// either way.
    pub(crate) fn end(&self, mem: &mut DeviceMemory) {
        let missed = mem.take_file_register_miss();
        if missed && self.drive(mem.map.points(DeviceKind::ZR)) == DRIVE_CARD {
            sm(mem, 672, true);
        }
    }
}
