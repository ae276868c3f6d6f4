//! The battery-backed memory image: latch ranges, file registers and the
//! error history as named byte regions (004 §4.3 data clear table), and the
//! host's abort and battery-error hooks.

use super::*;

/// Bytes per error-history entry in the retained image: code u16, detail u32
/// (`u32::MAX` = none), time i64, all little-endian.
const HISTORY_ENTRY: usize = 14;

impl Cpu {
    /// The battery-backed memory of this CPU as named byte regions: each latch
    /// range (bit devices one byte per point, words little-endian), the file
    /// registers and the error history (004 §4.3 data clear table).
    pub fn retained_layout(&self) -> Vec<(String, usize)> {
        let mut v: Vec<(String, usize)> = self
            .retained_spans()
            .into_iter()
            .map(|(name, bit, _, len)| (name, if bit { len } else { 2 * len }))
            .collect();
        v.push(("history".into(), 2 + crate::HISTORY_LEN * HISTORY_ENTRY));
        v
    }

    /// Fills `bufs` (sized as [`Self::retained_layout`]) with the current values.
    pub fn save_retained(&self, bufs: &mut [Vec<u8>]) {
        let mem = &self.rt.mem;
        let spans = self.retained_spans();
        for ((_, bit, start, len), buf) in spans.iter().zip(bufs.iter_mut()) {
            if *bit {
                for (b, v) in buf.iter_mut().zip(&mem.bits[*start..start + len]) {
                    *b = *v as u8;
                }
            } else {
                for (b, w) in buf.chunks_exact_mut(2).zip(&mem.words[*start..start + len]) {
                    b.copy_from_slice(&w.to_le_bytes());
                }
            }
        }
        if let Some(h) = bufs.get_mut(spans.len()) {
            h.fill(0);
            h[..2].copy_from_slice(&(self.rt.history.len() as u16).to_le_bytes());
            for (k, e) in self.rt.history.iter().enumerate() {
                let o = 2 + k * HISTORY_ENTRY;
                h[o..o + 2].copy_from_slice(&e.code.0.to_le_bytes());
                h[o + 2..o + 6].copy_from_slice(&e.detail.unwrap_or(u32::MAX).to_le_bytes());
                h[o + 6..o + 14].copy_from_slice(&e.time.to_le_bytes());
            }
        }
    }

    /// Restores battery-backed memory read at power-on (`None`: that region was
    /// never saved or its size changed). Device initial values are written again
    /// afterwards because they override latched data (004 L7738-7740).
    pub fn restore_retained(&mut self, data: &[Option<Vec<u8>>]) {
        self.rt.x_touched();
        let spans = self.retained_spans();
        let mem = &mut self.rt.mem;
        for ((_, bit, start, len), d) in spans.iter().zip(data) {
            let Some(d) = d else { continue };
            if *bit {
                for (v, b) in mem.bits[*start..start + len].iter_mut().zip(d) {
                    *v = *b != 0;
                }
            } else {
                for (w, b) in mem.words[*start..start + len]
                    .iter_mut()
                    .zip(d.chunks_exact(2))
                {
                    *w = u16::from_le_bytes([b[0], b[1]]);
                }
            }
        }
        if let Some(Some(h)) = data.get(spans.len()) {
            self.rt.history.clear();
            let n = u16::from_le_bytes([h[0], h[1]]) as usize;
            for k in 0..n.min(crate::HISTORY_LEN) {
                let o = 2 + k * HISTORY_ENTRY;
                let detail = u32::from_le_bytes(h[o + 2..o + 6].try_into().unwrap_or([0xFF; 4]));
                self.rt.history.push_back(crate::HistoryEntry {
                    code: ErrorCode(u16::from_le_bytes([h[o], h[o + 1]])),
                    detail: (detail != u32::MAX).then_some(detail),
                    time: i64::from_le_bytes(h[o + 6..o + 14].try_into().unwrap_or([0; 8])),
                });
            }
        }
        self.write_initial_values();
        self.note(DoorEvent::Retained { data });
    }

    /// A flag that stops the CPU when set, even in the middle of a scan stuck
    /// in an endless loop (checked where the watchdog is, on backward jumps):
    /// the scan ends, the CPU goes to STOP without an error. For Ctrl-C,
    /// SIGTERM and wall-clock limits.
    pub fn abort_handle(&self) -> std::sync::Arc<std::sync::atomic::AtomicBool> {
        self.rt.abort.clone()
    }

    /// Whether the abort flag is set.
    pub fn aborted(&self) -> bool {
        self.rt.abort.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Reports battery-backed data lost at power-on: the family's battery
    /// error (MELSEC's BATTERY ERROR) in the system devices and the error
    /// history; with `stop` the CPU holds it as a stop error (RESET clears it).
    pub fn report_battery_error(&mut self, stop: bool) {
        self.rt.record(
            crate::Fault::Battery,
            None,
            None,
            None,
            None,
            Default::default(),
        );
        if stop {
            self.stop_error = true;
            self.enter_stop(softplc_ir::system::Cause::Error);
        }
        self.note(DoorEvent::BatteryError { stop });
    }

    /// (region name, is bit array, flat start, points) of every retained span.
    pub(super) fn retained_spans(&self) -> Vec<(String, bool, usize, usize)> {
        let mem = &self.rt.mem;
        let mut v = Vec::new();
        for r in &self.cfg.latch {
            for (kind, bit, start, len) in latch_kind_spans(mem, r) {
                let name = format!(
                    "latch:{}{}-{}",
                    kind.name(),
                    r.start,
                    r.start as usize + len - 1
                );
                v.push((name, bit, start, len));
            }
        }
        let zr = mem.map.base(DeviceKind::ZR) as usize;
        v.push((
            "file-register".into(),
            false,
            zr,
            mem.map.points(DeviceKind::ZR) as usize,
        ));
        v
    }
}

/// Flat spans of a latch range: (is bit array, start, length). Timers and
/// counters latch contact, coil and current value together.
pub(super) fn latch_spans(mem: &DeviceMemory, r: &crate::LatchRange) -> Vec<(bool, usize, usize)> {
    latch_kind_spans(mem, r)
        .into_iter()
        .map(|(_, bit, start, len)| (bit, start, len))
        .collect()
}

fn latch_kind_spans(
    mem: &DeviceMemory,
    r: &crate::LatchRange,
) -> Vec<(DeviceKind, bool, usize, usize)> {
    let kinds: &[DeviceKind] = r
        .kind
        .timer_parts()
        .map_or(std::slice::from_ref(&r.kind), |p| p.as_slice());
    kinds
        .iter()
        .filter_map(|k| {
            let points = mem.map.points(*k);
            if r.start >= points {
                return None;
            }
            let end = r.end.min(points - 1);
            let start = (mem.map.base(*k) + r.start) as usize;
            Some((*k, k.is_bit(), start, (end - r.start + 1) as usize))
        })
        .collect()
}
