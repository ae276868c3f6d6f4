//! Mapping saved regions onto a new layout, keyed by device rather than by
//! byte offset: when the latch ranges or the file-register size change, the
//! values of devices that are retained both before and after survive, and a
//! warning names the devices whose saved values were dropped.
//!
//! Region names that carry device numbers (what `Cpu::retained_layout` makes):
//! - `latch:<KIND><first>-<last>` (e.g. `latch:D1000-1999`, `latch:TN0-99`):
//!   points `first..=last` of device `KIND`, `len / points` bytes per point;
//! - `file-register`: ZR0 upwards, two bytes per point; a resize keeps the
//!   common prefix.
//!
//! Any other name matches only itself with the same size (as before).

use super::format::ImageRegion;
use super::Region;

/// The recovered contents of each layout region.
pub(crate) struct Mapped {
    /// What `Store::open` returns: `None` for nothing saved (or lost).
    pub out: Vec<Option<Vec<u8>>>,
    pub shadow: Vec<Vec<u8>>,
    pub committed: Vec<bool>,
    /// Some region was filled from differently named or sized saved regions.
    pub remapped: bool,
}

/// A device-keyed region: kind, first and last point, bytes per point.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Key {
    kind: String,
    first: u64,
    last: u64,
    unit: usize,
}

fn key(name: &str, len: usize) -> Option<Key> {
    if name == "file-register" {
        return (len >= 2).then(|| Key {
            kind: "ZR".into(),
            first: 0,
            last: (len / 2) as u64 - 1,
            unit: 2,
        });
    }
    let rest = name.strip_prefix("latch:")?;
    let digit = rest.find(|c: char| c.is_ascii_digit())?;
    let (kind, range) = rest.split_at(digit);
    let (a, b) = range.split_once('-')?;
    let (first, last): (u64, u64) = (a.parse().ok()?, b.parse().ok()?);
    let points = usize::try_from(last.checked_sub(first)? + 1).ok()?;
    if kind.is_empty() || len == 0 || !len.is_multiple_of(points) {
        return None;
    }
    Some(Key {
        kind: kind.into(),
        first,
        last,
        unit: len / points,
    })
}

/// Devices numbered in hexadecimal (for the warnings).
fn hex(kind: &str) -> bool {
    matches!(kind, "X" | "Y" | "B" | "W" | "SB" | "SW" | "DX" | "DY")
}

fn device(kind: &str, n: u64) -> String {
    if hex(kind) {
        format!("{kind}{n:X}")
    } else {
        format!("{kind}{n}")
    }
}

/// Merges intervals and returns the parts of `first..=last` they do not cover.
fn uncovered(first: u64, last: u64, mut done: Vec<(u64, u64)>) -> Vec<(u64, u64)> {
    done.sort_unstable();
    let mut gaps = Vec::new();
    let mut next = first;
    for (a, b) in done {
        if a > next {
            gaps.push((next, a - 1));
        }
        next = next.max(b.saturating_add(1));
        if next > last {
            return gaps;
        }
    }
    if next <= last {
        gaps.push((next, last));
    }
    gaps
}

/// A saved region, its device key, the device intervals carried over, and
/// whether a layout region took it as it is.
type Source = (ImageRegion, Option<Key>, Vec<(u64, u64)>, bool);

/// Maps `saved` (the recovered image's regions) onto `layout`.
pub(crate) fn map(
    layout: &[Region],
    saved: Vec<ImageRegion>,
    warnings: &mut Vec<String>,
) -> Mapped {
    // Usable saved data: committed and intact.
    let mut saved: Vec<Source> = saved
        .into_iter()
        .filter(|r| r.committed && r.intact)
        .map(|r| {
            let k = key(&r.name, r.data.len());
            (r, k, Vec::new(), false)
        })
        .collect();
    let mut m = Mapped {
        out: Vec::with_capacity(layout.len()),
        shadow: Vec::with_capacity(layout.len()),
        committed: Vec::with_capacity(layout.len()),
        remapped: false,
    };
    for l in layout {
        // The same region: taken as it is.
        if let Some(s) = saved
            .iter_mut()
            .find(|s| s.0.name == l.name && s.0.data.len() == l.len)
        {
            s.3 = true;
            if let Some(k) = &s.1 {
                s.2.push((k.first, k.last));
            }
            m.out.push(Some(s.0.data.clone()));
            m.shadow.push(s.0.data.clone());
            m.committed.push(true);
            continue;
        }
        let mut data = vec![0u8; l.len];
        let mut found = false;
        if let Some(lk) = key(&l.name, l.len) {
            for (s, sk, done, _) in saved.iter_mut() {
                let Some(sk) = sk else { continue };
                if sk.kind != lk.kind || sk.unit != lk.unit {
                    continue;
                }
                let (a, b) = (sk.first.max(lk.first), sk.last.min(lk.last));
                if a > b {
                    continue;
                }
                let u = lk.unit as u64;
                let from = ((a - sk.first) * u) as usize..((b - sk.first + 1) * u) as usize;
                let to = ((a - lk.first) * u) as usize;
                data[to..to + from.len()].copy_from_slice(&s.data[from]);
                done.push((a, b));
                found = true;
            }
        } else if let Some(s) = saved.iter().find(|s| s.0.name == l.name) {
            warnings.push(format!(
                "region {:?}: size changed from {} to {} bytes; its saved contents were \
                 discarded and it starts zeroed",
                l.name,
                s.0.data.len(),
                l.len
            ));
        }
        if found {
            m.remapped = true;
            m.out.push(Some(data.clone()));
            m.shadow.push(data);
            m.committed.push(true);
        } else {
            m.out.push(None);
            m.shadow.push(data);
            m.committed.push(false);
        }
    }
    for (s, k, done, exact) in saved {
        match k {
            Some(k) if !exact => {
                let gaps = uncovered(k.first, k.last, done);
                let what = if s.name == "file-register" {
                    "file registers (fewer file registers now)"
                } else {
                    "latched devices (no longer in a latch range)"
                };
                for (a, b) in gaps {
                    warnings.push(format!(
                        "{what}: saved values of {}-{} were dropped",
                        device(&k.kind, a),
                        device(&k.kind, b)
                    ));
                }
            }
            Some(_) => {}
            None if !exact && !layout.iter().any(|l| l.name == s.name) => {
                warnings.push(format!(
                    "region {:?} ({} bytes) is no longer in the layout; its saved contents were \
                     discarded",
                    s.name,
                    s.data.len()
                ));
            }
            None => {}
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn saved(name: &str, data: Vec<u8>) -> ImageRegion {
        ImageRegion {
            name: name.into(),
            committed: true,
            data,
            intact: true,
        }
    }

    fn words(first: u16, n: usize) -> Vec<u8> {
        (0..n)
            .flat_map(|i| (first + i as u16).to_le_bytes())
            .collect()
    }

    #[test]
    fn widened_latch_range_keeps_the_old_devices() {
        // D1000-D1999 (values 1000..1999) widened to D1000-D2099.
        let old = vec![saved("latch:D1000-1999", words(1000, 1000))];
        let mut w = Vec::new();
        let m = map(&[Region::new("latch:D1000-2099", 2200)], old, &mut w);
        let d = m.out[0].as_ref().unwrap();
        assert_eq!(&d[..2], &1000u16.to_le_bytes());
        assert_eq!(&d[1998..2000], &1999u16.to_le_bytes());
        assert_eq!(&d[2000..], &[0u8; 200][..]);
        assert!(w.is_empty(), "{w:?}");
    }

    #[test]
    fn narrowed_and_moved_ranges_drop_only_what_left() {
        let old = vec![saved("latch:D1000-1999", words(1000, 1000))];
        let mut w = Vec::new();
        let m = map(
            &[
                Region::new("latch:D1500-1599", 200),
                Region::new("latch:D1900-2100", 402),
            ],
            old,
            &mut w,
        );
        assert_eq!(&m.out[0].as_ref().unwrap()[..2], &1500u16.to_le_bytes());
        let b = m.out[1].as_ref().unwrap();
        assert_eq!(&b[198..200], &1999u16.to_le_bytes());
        assert_eq!(&b[200..202], &[0, 0]);
        assert_eq!(
            w,
            [
                "latched devices (no longer in a latch range): saved values of D1000-D1499 were dropped",
                "latched devices (no longer in a latch range): saved values of D1600-D1899 were dropped"
            ]
        );
    }

    #[test]
    fn file_register_resize_keeps_the_common_prefix() {
        let old = vec![saved("file-register", words(0, 100))];
        let mut w = Vec::new();
        let m = map(&[Region::new("file-register", 300)], old.clone(), &mut w);
        let d = m.out[0].as_ref().unwrap();
        assert_eq!(&d[..200], &words(0, 100)[..]);
        assert!(w.is_empty());
        let m = map(&[Region::new("file-register", 100)], old, &mut w);
        assert_eq!(m.out[0].as_ref().unwrap(), &words(0, 50));
        assert_eq!(
            w,
            ["file registers (fewer file registers now): saved values of ZR50-ZR99 were dropped"]
        );
    }

    #[test]
    fn bit_and_word_units_and_kinds_do_not_mix() {
        let old = vec![
            saved("latch:M0-9", vec![1; 10]),
            saved("latch:B10-1F", vec![1; 16]), // not a decimal range: name only
        ];
        let mut w = Vec::new();
        let m = map(
            &[Region::new("latch:L0-9", 10), Region::new("latch:M0-4", 5)],
            old,
            &mut w,
        );
        assert_eq!(m.out[0], None);
        assert_eq!(m.out[1], Some(vec![1; 5]));
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].contains("M5-M9"), "{w:?}");
    }
}
