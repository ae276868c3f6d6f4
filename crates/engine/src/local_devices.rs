//! Local devices (004 §10.13.1): ranges of M, V, T, ST, C and D of which
//! every program file that uses them has its own copy.
//!
//! Device memory holds one owner's values of the ranges at a time. A program
//! that uses local devices swaps the owner's out and its own in when it
//! starts, and leaves them there when it ends (the next program that needs
//! another owner's saves them); a program whose local devices are "not
//! used" swaps nothing, so it runs on the local devices of the program
//! before it (004 §10.13.1 (d) 3)). A subroutine called in another file runs
//! on its file's local devices while the family's "at CALL" relay is ON
//! (MELSEC SM776, (e)), an interrupt or fixed-scan program on its own while
//! the "in interrupts" relay is ON (SM777, (f)); both give the previous
//! owner's values back when they return. Timers carry their sub-unit
//! remainder (`CpuServices::timer_rem`) with them.
//!
//! Every copy is sized when the CPU is built: a swap copies between
//! preallocated buffers and allocates nothing.

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::snapshot::Snap;
use softplc_ir::system::LocalDeviceRelays;

use crate::{LatchRange, LocalRange, Runtime};

/// How a program starts running, which decides whose local devices it uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Entry {
    /// A program switch: an initial, scan or low-speed program.
    Program,
    /// A subroutine of another file reached by CALL.
    Call,
    /// An interrupt or fixed-scan program.
    Interrupt,
}

/// Flat spans `(start, len)` of the local ranges.
#[derive(Debug, Default)]
struct Spans {
    bits: Vec<(usize, usize)>,
    words: Vec<(usize, usize)>,
    /// Timer remainders (`CpuServices::timer_rem`): T, then ST.
    rems: Vec<(usize, usize)>,
}

impl Spans {
    fn len(spans: &[(usize, usize)]) -> usize {
        spans.iter().map(|s| s.1).sum()
    }
}

/// One owner's values of the local ranges, the spans' points one after
/// another.
#[derive(Debug)]
struct Values {
    bits: Box<[bool]>,
    words: Box<[u16]>,
    rems: Box<[u32]>,
}

impl Values {
    fn new(spans: &Spans) -> Values {
        Values {
            bits: vec![false; Spans::len(&spans.bits)].into_boxed_slice(),
            words: vec![0; Spans::len(&spans.words)].into_boxed_slice(),
            rems: vec![0; Spans::len(&spans.rems)].into_boxed_slice(),
        }
    }

    fn clear(&mut self) {
        self.bits.fill(false);
        self.words.fill(0);
        self.rems.fill(0);
    }

    /// Device memory into these values.
    fn save(&mut self, spans: &Spans, mem: &DeviceMemory, rem: &[u32]) {
        gather(&mut self.bits, &spans.bits, &mem.bits);
        gather(&mut self.words, &spans.words, &mem.words);
        gather(&mut self.rems, &spans.rems, rem);
    }

    /// These values into device memory.
    fn load(&self, spans: &Spans, mem: &mut DeviceMemory, rem: &mut [u32]) {
        scatter(&self.bits, &spans.bits, &mut mem.bits);
        scatter(&self.words, &spans.words, &mut mem.words);
        scatter(&self.rems, &spans.rems, rem);
    }
}

fn gather<T: Copy>(to: &mut [T], spans: &[(usize, usize)], from: &[T]) {
    let mut at = 0;
    for &(start, len) in spans {
        to[at..at + len].copy_from_slice(&from[start..start + len]);
        at += len;
    }
}

fn scatter<T: Copy>(from: &[T], spans: &[(usize, usize)], to: &mut [T]) {
    let mut at = 0;
    for &(start, len) in spans {
        to[start..start + len].copy_from_slice(&from[at..at + len]);
        at += len;
    }
}

/// The programs' local devices and whose are in device memory.
#[derive(Debug)]
pub(crate) struct LocalDevices {
    spans: Spans,
    /// Each program file's values (`None`: its local devices are "not
    /// used"), then [`Self::nobody`]'s: what device memory held before any
    /// program's came in (after a clear).
    copies: Box<[Option<Values>]>,
    /// Whose values are in device memory: a program slot or `nobody`.
    owner: usize,
    relays: Option<LocalDeviceRelays>,
}

/// The kinds a local range of `kind` covers: a timer's, retentive timer's
/// or counter's contact, coil and current value together; M, V and D
/// alone; `None` for a device that cannot be local.
fn parts(kind: &DeviceKind) -> Option<&[DeviceKind]> {
    use DeviceKind::*;
    match kind {
        M | V | D => Some(std::slice::from_ref(kind)),
        _ => kind.timer_parts().map(|p| p.as_slice()),
    }
}

impl LocalDevices {
    /// The local devices of a CPU with `mem`'s layout whose programs use
    /// them as `uses` says (in slot order); `None` without ranges. Fails
    /// on a device that cannot be local.
    pub(crate) fn new(
        ranges: &[LocalRange],
        uses: &[bool],
        mem: &DeviceMemory,
        relays: Option<LocalDeviceRelays>,
    ) -> Result<Option<LocalDevices>, String> {
        if ranges.is_empty() {
            return Ok(None);
        }
        let map = &mem.map;
        let mut spans = Spans::default();
        for r in ranges {
            let Some(kinds) = parts(&r.kind) else {
                return Err(format!(
                    "{} cannot be a local device: local devices are M, V, T, ST, C and D",
                    r.kind
                ));
            };
            for &k in kinds {
                let points = map.points(k);
                if r.start > r.end || r.start >= points {
                    continue;
                }
                let len = (r.end.min(points - 1) - r.start + 1) as usize;
                let start = (map.base(k) + r.start) as usize;
                if k.is_bit() {
                    spans.bits.push((start, len));
                } else {
                    spans.words.push((start, len));
                }
            }
            let rem_base = match r.kind.range_kind() {
                DeviceKind::TS => Some(0),
                DeviceKind::STS => Some(map.points(DeviceKind::TS)),
                _ => None,
            };
            let timers = map.points(r.kind.range_kind());
            if let Some(base) = rem_base.filter(|_| r.start <= r.end && r.start < timers) {
                let len = (r.end.min(timers - 1) - r.start + 1) as usize;
                spans.rems.push(((base + r.start) as usize, len));
            }
        }
        let copies: Box<[Option<Values>]> = uses
            .iter()
            .map(|&u| u.then(|| Values::new(&spans)))
            .chain([Some(Values::new(&spans))])
            .collect();
        Ok(Some(LocalDevices {
            owner: copies.len() - 1,
            spans,
            copies,
            relays,
        }))
    }

    /// Whether program `slot` has its own local devices.
    pub(crate) fn used_by(&self, slot: usize) -> bool {
        slot < self.nobody() && matches!(self.copies.get(slot), Some(Some(_)))
    }

    /// Each program's copy and whose are in device memory, in a state file.
    pub(crate) fn snapshot(&mut self, s: &mut Snap) {
        let bound = self.copies.len();
        s.index(&mut self.owner, bound);
        for c in self.copies.iter_mut() {
            if s.same(c.is_some()) {
                if let Some(v) = c {
                    s.bools(&mut v.bits);
                    s.words(&mut v.words);
                    s.u32s(&mut v.rems);
                }
            }
        }
    }

    /// The copy of nobody's values.
    fn nobody(&self) -> usize {
        self.copies.len() - 1
    }

    /// Program `slot` starts as `entry`: swaps its local devices in when it
    /// uses them and `entry` calls for it. The owner to give device memory
    /// back to when it returns, if it took it from one.
    #[cold]
    #[inline(never)]
    fn enter(
        &mut self,
        slot: usize,
        entry: Entry,
        mem: &mut DeviceMemory,
        rem: &mut [u32],
    ) -> Option<usize> {
        if self.owner == slot || !matches!(self.copies.get(slot), Some(Some(_))) {
            return None;
        }
        let relay = match entry {
            Entry::Program => {
                self.switch(slot, mem, rem);
                return None;
            }
            Entry::Call => self.relays.map(|r| r.at_call),
            Entry::Interrupt => self.relays.map(|r| r.in_interrupts),
        };
        let on = relay.is_some_and(|b| mem.bits.get(b as usize) == Some(&true));
        if !on {
            return None;
        }
        let back = self.owner;
        self.switch(slot, mem, rem);
        Some(back)
    }

    /// Saves the owner's values from device memory and loads `to`'s.
    #[cold]
    #[inline(never)]
    fn switch(&mut self, to: usize, mem: &mut DeviceMemory, rem: &mut [u32]) {
        let spans = &self.spans;
        if let Some(Some(v)) = self.copies.get_mut(self.owner) {
            v.save(spans, mem, rem);
        }
        if let Some(Some(v)) = self.copies.get(to) {
            v.load(spans, mem, rem);
            self.owner = to;
        }
    }

    /// Program `slot`'s local devices into device memory for a look from
    /// outside (a monitor with a chosen program): the owner to give device
    /// memory back to afterwards, `None` when it holds `slot`'s already or
    /// `slot` does not use local devices (then it sees device memory as it
    /// is, as when it runs).
    fn show(&mut self, slot: usize, mem: &mut DeviceMemory, rem: &mut [u32]) -> Option<usize> {
        if self.owner == slot || !matches!(self.copies.get(slot), Some(Some(_))) {
            return None;
        }
        let back = self.owner;
        self.switch(slot, mem, rem);
        Some(back)
    }

    /// Power-on, RESET and STOP→RUN: every program's local devices and
    /// their place in device memory cleared (004 §10.13.1 (g)).
    pub(crate) fn clear(&mut self, mem: &mut DeviceMemory, rem: &mut [u32]) {
        for v in self.copies.iter_mut().flatten() {
            v.clear();
        }
        for &(start, len) in &self.spans.bits {
            mem.bits[start..start + len].fill(false);
        }
        for &(start, len) in &self.spans.words {
            mem.words[start..start + len].fill(0);
        }
        for &(start, len) in &self.spans.rems {
            rem[start..start + len].fill(0);
        }
        self.owner = self.nobody();
    }

    /// Flat spans of the local ranges in the bit and the word array.
    pub(crate) fn bit_spans(&self) -> &[(usize, usize)] {
        &self.spans.bits
    }

    pub(crate) fn word_spans(&self) -> &[(usize, usize)] {
        &self.spans.words
    }

    /// The program whose local devices are in device memory, `None` when
    /// no program's are (after a clear).
    pub(crate) fn owner(&self) -> Option<usize> {
        (self.owner != self.nobody()).then_some(self.owner)
    }
}

impl Runtime {
    /// Program `slot` starts as `entry` (see [`LocalDevices`]); what
    /// [`Self::leave_locals`] needs when it returns.
    #[inline]
    pub(crate) fn enter_locals(&mut self, slot: usize, entry: Entry) -> Option<usize> {
        match &mut self.local_devices {
            None => None,
            Some(l) => l.enter(slot, entry, &mut self.mem, &mut self.cpu.timer_rem),
        }
    }

    /// Program `slot`'s local devices into device memory for a look from
    /// outside; what [`Self::leave_locals`] needs to put them back.
    pub(crate) fn show_locals(&mut self, slot: usize) -> Option<usize> {
        match &mut self.local_devices {
            None => None,
            Some(l) => l.show(slot, &mut self.mem, &mut self.cpu.timer_rem),
        }
    }

    /// The program that [`Self::enter_locals`] started returned: the owner
    /// before it gets device memory back.
    #[inline]
    pub(crate) fn leave_locals(&mut self, back: Option<usize>) {
        if let (Some(to), Some(l)) = (back, &mut self.local_devices) {
            l.switch(to, &mut self.mem, &mut self.cpu.timer_rem);
        }
    }
}

/// `latch` without the local devices: a local device is never latched
/// (004 L3552), so the part of a latch range that is local is cut out.
pub(crate) fn without_locals(latch: &[LatchRange], locals: &[LocalRange]) -> Vec<LatchRange> {
    let mut out = Vec::with_capacity(latch.len());
    for r in latch {
        let mut pieces = vec![(r.start, r.end)];
        for l in locals
            .iter()
            .filter(|l| l.kind.range_kind() == r.kind.range_kind())
        {
            pieces = pieces
                .into_iter()
                .flat_map(|(a, b)| {
                    let mut keep = Vec::with_capacity(2);
                    if b < l.start || a > l.end {
                        keep.push((a, b));
                    } else {
                        if a < l.start {
                            keep.push((a, l.start - 1));
                        }
                        if b > l.end {
                            keep.push((l.end + 1, b));
                        }
                    }
                    keep
                })
                .collect();
        }
        out.extend(
            pieces
                .into_iter()
                .map(|(start, end)| LatchRange { start, end, ..*r }),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn latch(kind: DeviceKind, start: u32, end: u32) -> LatchRange {
        LatchRange {
            kind,
            start,
            end,
            clearable: true,
        }
    }

    fn local(kind: DeviceKind, start: u32, end: u32) -> LocalRange {
        LocalRange { kind, start, end }
    }

    #[test]
    fn the_local_part_of_a_latch_range_is_cut_out() {
        use DeviceKind::*;
        let l = [latch(D, 0, 99), latch(TS, 0, 9), latch(W, 0, 9)];
        let got = without_locals(&l, &[local(D, 10, 19), local(TS, 0, 4)]);
        assert_eq!(
            got,
            vec![
                latch(D, 0, 9),
                latch(D, 20, 99),
                latch(TS, 5, 9),
                latch(W, 0, 9)
            ]
        );
        // Wholly local: nothing left; a timer range named by its value.
        assert_eq!(
            without_locals(&[latch(TN, 3, 4)], &[local(TS, 0, 9)]),
            vec![]
        );
    }
}
