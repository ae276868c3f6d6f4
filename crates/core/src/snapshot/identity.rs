//! The identity of what a state file belongs to: a SHA-256 over every CPU's
//! model, device points, local-device ranges, rack and compiled programs.
//! A program edited (another instruction, operand or line), another model or
//! other device points give another identity, and the file is refused.

use std::fmt::Write as _;

use sha2::{Digest, Sha256};

use crate::engine::Cpu;

/// Feeds formatted text into the hash without building it: only the
/// addresses Rust's `Debug` prints for function pointers (`0x…`), which
/// change from one process to the next, are left out.
struct Feed {
    hash: Sha256,
    /// Inside a `0x…` address.
    hex: bool,
    /// The previous character was a `0` that may start one.
    zero: bool,
}

impl Feed {
    fn new() -> Feed {
        Feed {
            hash: Sha256::new(),
            hex: false,
            zero: false,
        }
    }

    fn finish(mut self) -> [u8; 32] {
        if self.zero {
            self.hash.update(b"0");
        }
        self.hash.finalize().into()
    }
}

impl std::fmt::Write for Feed {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        if !self.hex && !self.zero && !s.contains("0x") && !s.ends_with('0') {
            self.hash.update(s.as_bytes());
            return Ok(());
        }
        for c in s.chars() {
            if self.hex {
                if c.is_ascii_hexdigit() {
                    continue;
                }
                self.hex = false;
            }
            if self.zero && c == 'x' {
                self.zero = false;
                self.hex = true;
                continue;
            }
            if self.zero {
                self.hash.update(b"0");
            }
            self.zero = c == '0';
            if !self.zero {
                let mut b = [0; 4];
                self.hash.update(c.encode_utf8(&mut b).as_bytes());
            }
        }
        Ok(())
    }
}

/// The identity of `cpus` (CPU 1 first).
pub(crate) fn of<'a>(cpus: impl Iterator<Item = &'a Cpu>) -> [u8; 32] {
    let mut f = Feed::new();
    // Writing into the hash cannot fail.
    let _ = write!(f, "softplc state identity 1;");
    for cpu in cpus {
        let cfg = cpu.config();
        let _ = write!(
            f,
            "cpu {};{:?};{:?};",
            cfg.profile.model, cfg.devices, cfg.local_devices
        );
        for s in &cfg.rack.slots {
            let _ = write!(
                f,
                "slot {} {:?} {} {} {:?} {} {:?} {:?} {:?} {};",
                s.index,
                s.kind,
                s.points,
                s.start,
                s.module.map(|m| m.name),
                s.buffer_words,
                s.interrupts,
                s.refresh,
                s.switches,
                s.control_cpu
            );
        }
        for i in 0..cpu.program_count() {
            let p = cpu.program_at(i);
            let name = std::path::Path::new(&p.file)
                .file_name()
                .map_or_else(|| p.file.clone(), |n| n.to_string_lossy().into_owned());
            let _ = write!(
                f,
                "program {name} {} {} {} {} {} {};",
                p.edge_slots,
                p.state_words,
                p.shared_words,
                p.bit_len,
                p.word_len,
                p.ops.len()
            );
            for op in &p.ops {
                let _ = write!(f, "{op:?};");
            }
            for x in &p.ext {
                let _ = write!(f, "{x:?};");
            }
            let _ = write!(f, "{:?}{:?}", p.op_step, p.op_line);
        }
    }
    f.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fed(parts: &[&str]) -> [u8; 32] {
        let mut f = Feed::new();
        for p in parts {
            let _ = f.write_str(p);
        }
        f.finish()
    }

    #[test]
    fn addresses_are_left_out_and_everything_else_counts() {
        let plain: [u8; 32] = Sha256::digest(b"f: , n: 10, k: 0").into();
        assert_eq!(fed(&["f: 0x55d4a1b2, n: 10, k: 0"]), plain);
        assert_eq!(fed(&["f: 0", "x7ff", "e, n: 1", "0, k: 0"]), plain);
        assert_ne!(fed(&["f: , n: 11, k: 0"]), plain);
    }
}
