//! MELSEC-Q device memory (004 §10, Table 10.1).
//!
//! All bit devices live in one flat `bits` array and all word devices in one flat
//! `words` array. Each device kind owns a contiguous range in its array, so the
//! compiler turns `M100` or `D0` into a single pre-resolved index and the scan loop
//! touches memory with one indexed load, never a lookup.

pub mod address;
mod kind;
mod table;

pub use address::{
    parse_operand, parse_operand_in, Constant, DeviceName, Operand, OperandError, Reach,
};
pub use kind::{DeviceKind, Numbering};

pub use table::{DeviceDef, DeviceTable, MELSEC_Q};

use crate::fault::Fault;
use std::sync::atomic::{AtomicBool, Ordering};

/// Words past the last device where a program's access to file registers
/// outside the registered range goes (004 §10.7.5 (1)): reads give 0,
/// writes are dropped when END clears it. Enough for any block a 16-bit
/// count names.
pub const FILE_REGISTER_VOID: u32 = 65536;

/// Number of points per device kind: the "device setting" of the PLC parameters.
///
/// Defaults are the Q06HCPU defaults of 004 Table 3.1 (L1026-1059).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceConfig {
    points: [u32; DeviceKind::COUNT],
    /// The rack's intelligent function modules' buffer memories, then the
    /// CPU shared memories of a multi-CPU system, in `G`.
    units: Vec<UnitWindow>,
    /// The modules as [`Self::set_units`] gave them.
    modules: Vec<(u32, u32)>,
    /// This CPU's place in a multi-CPU system.
    multi_cpu: Option<MultiCpu>,
}

/// A CPU's place in a multi-CPU system (004 ch. 13-19): its number, the
/// CPUs installed, and the modules other CPUs control.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MultiCpu {
    /// This CPU's number, 1-4.
    pub own: u32,
    /// CPUs installed, 2-4.
    pub cpus: u32,
    /// Unit numbers of the modules another CPU controls.
    pub foreign: Vec<u32>,
    /// Words of this CPU's auto-refresh area (its send words over all
    /// refresh settings): its shared memory's user area is
    /// 800H + `refresh_words` to FFFH, where S.TO writes (004 L9053,
    /// L9104-9110).
    pub refresh_words: u32,
}

/// Words of each CPU's shared memory (004 L9049-9111).
pub const SHARED_MEMORY_WORDS: u32 = 4096;
/// The unit number of CPU 1's shared memory: `U3E0\G…` (CPU n: 3E0 + n - 1).
pub const CPU1_UNIT: u32 = 0x3E0;

/// The first address of the auto-refresh area in each CPU's shared memory
/// (004 L9053): below it the own-operation (0-1FFH) and system
/// (200-7FFH) areas.
pub const REFRESH_AREA: u32 = 0x800;

/// Why buffer memory cannot be reached ([`DeviceMap::buffer`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferError {
    /// No intelligent function module has the unit number.
    NoModule,
    /// Past the module's buffer memory, whose last address is `last`.
    Past { last: u32 },
}

/// Where one intelligent function module's buffer memory lives in `G`:
/// `U<unit>\G<addr>` is G`first + addr` for `addr < words` (004 ch. 8).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnitWindow {
    /// The module's start I/O number without its last hex digit (`U2` for X/Y20).
    pub unit: u32,
    /// Its word 0 in `G`.
    pub first: u32,
    pub words: u32,
    /// What it is to this CPU.
    pub owner: UnitOwner,
}

/// What a unit's memory is to the CPU that reaches it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitOwner {
    /// An intelligent function module this CPU controls.
    Module,
    /// A module another CPU of the system controls: its buffer memory is
    /// read, never written (2116, 004 L9199-9205).
    OtherCpusModule,
    /// This CPU's own shared memory: written by S.TO and the auto refresh;
    /// a program's `U\G` or FROM on it is 2114 (004 L8985-8998).
    OwnCpu,
    /// Another CPU's shared memory: read by FROM and `U\G`, never written
    /// (2115).
    OtherCpu,
}

/// Which way a program moves data through a unit's memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitAccess {
    /// A source: FROM, a `U\G` operand read.
    Read,
    /// A destination: TO, a `U\G` operand written.
    Write,
}

impl UnitOwner {
    /// The fault a program's `access` to this memory makes, `None` when it
    /// may: its own CPU shared memory neither way (2114), another CPU's
    /// shared memory or a module another CPU controls read only (2115,
    /// 2116; 004 L8985-8998, L9199-9205). Names and protocols from outside
    /// monitor every unit and ask nothing.
    pub fn refuses(self, access: UnitAccess) -> Option<Fault> {
        match (self, access) {
            (UnitOwner::OwnCpu, _) => Some(Fault::OwnSharedMemory),
            (UnitOwner::OtherCpu, UnitAccess::Write) => Some(Fault::OtherSharedMemory),
            (UnitOwner::OtherCpusModule, UnitAccess::Write) => Some(Fault::NotControlled),
            (UnitOwner::Module, _)
            | (UnitOwner::OtherCpu | UnitOwner::OtherCpusModule, UnitAccess::Read) => None,
        }
    }
}

impl UnitWindow {
    /// The G number of `words` words from address `addr`.
    #[inline]
    pub fn span(&self, addr: u32, words: u32) -> Result<u32, BufferError> {
        if addr as u64 + words as u64 > self.words as u64 {
            return Err(BufferError::Past {
                last: self.words.saturating_sub(1),
            });
        }
        Ok(self.first + addr)
    }
}

impl Default for DeviceConfig {
    fn default() -> Self {
        Self::q06h()
    }
}

impl DeviceConfig {
    /// Q06HCPU profile, 004 Table 3.1.
    ///
    /// Decisions: ST has 0 points by default, as in the manual (assign points to use
    /// retentive timers). File registers default to a 1 MB SRAM card (ZR0-517119,
    /// L1040-1041) so that R0-32767 (block 0) and large ZR addresses exist; the
    /// built-in standard RAM alone would give 32K points.
    pub fn q06h() -> Self {
        use DeviceKind::*;
        let mut c = DeviceConfig {
            points: [0; DeviceKind::COUNT],
            units: Vec::new(),
            modules: Vec::new(),
            multi_cpu: None,
        };
        let t = 2048;
        let st = 0;
        let cn = 1024;
        for (k, n) in [
            (X, 8192),
            (Y, 8192),
            (M, 8192),
            (L, 8192),
            (F, 2048),
            (V, 2048),
            (B, 8192),
            (SB, 2048),
            (S, 8192),
            (SM, 2048),
            (TS, t),
            (TC, t),
            (STS, st),
            (STC, st),
            (CS, cn),
            (CC, cn),
            (FX, 16),
            (FY, 16),
            (D, 12288),
            (W, 8192),
            (SW, 2048),
            (SD, 2048),
            (Z, 16),
            (TN, t),
            (STN, st),
            (CN, cn),
            (FD, 5),
            (R, 32768),
            (ZR, 517_120),
        ] {
            c.points[k as usize] = n;
        }
        c
    }

    pub fn points(&self, kind: DeviceKind) -> u32 {
        self.points[kind as usize]
    }

    /// Places the buffer memories of the rack's intelligent function
    /// modules, `(unit, words)` each, one after another in `G`.
    pub fn set_units(&mut self, modules: &[(u32, u32)]) {
        self.modules = modules.to_vec();
        self.place_units();
    }

    /// Makes this the configuration of CPU `multi.own` of a multi-CPU
    /// system: every installed CPU's shared memory follows the modules'
    /// buffer memories in `G` (`U3E0\G…` to `U3E3\G…`).
    pub fn set_multi_cpu(&mut self, multi: MultiCpu) {
        self.multi_cpu = Some(multi);
        self.place_units();
    }

    /// This CPU's place in a multi-CPU system, `None` for a single CPU.
    pub fn multi_cpu(&self) -> Option<&MultiCpu> {
        self.multi_cpu.as_ref()
    }

    fn place_units(&mut self) {
        let mut first = 0;
        let mut units = Vec::new();
        let mut place = |unit, words, owner| {
            units.push(UnitWindow {
                unit,
                first,
                words,
                owner,
            });
            first += words;
        };
        let multi = self.multi_cpu.as_ref();
        for &(unit, words) in &self.modules {
            let foreign = multi.is_some_and(|m| m.foreign.contains(&unit));
            let owner = if foreign {
                UnitOwner::OtherCpusModule
            } else {
                UnitOwner::Module
            };
            place(unit, words, owner);
        }
        if let Some(m) = multi {
            for n in 1..=m.cpus {
                let owner = if n == m.own {
                    UnitOwner::OwnCpu
                } else {
                    UnitOwner::OtherCpu
                };
                place(CPU1_UNIT + n - 1, SHARED_MEMORY_WORDS, owner);
            }
        }
        self.units = units;
        self.points[DeviceKind::G as usize] = first;
    }

    /// The modules' buffer memories (see [`Self::set_units`]).
    pub fn units(&self) -> &[UnitWindow] {
        &self.units
    }

    /// Sets the points of a device. Timers, retentive timers and counters keep their
    /// contact, coil and current value sizes together.
    pub fn set_points(&mut self, kind: DeviceKind, n: u32) {
        match kind.timer_parts() {
            Some(parts) => {
                for k in parts {
                    self.points[*k as usize] = n;
                }
            }
            None => self.points[kind as usize] = n,
        }
        if kind == DeviceKind::ZR {
            self.points[DeviceKind::R as usize] = n.min(32768);
        }
    }
}

/// Where each device kind lives in the flat bit or word array.
#[derive(Clone, Debug)]
pub struct DeviceMap {
    base: [u32; DeviceKind::COUNT],
    points: [u32; DeviceKind::COUNT],
    bit_len: u32,
    word_len: u32,
    /// Flat word index of the word selecting the file-register block that R
    /// addresses (the dialect's: MELSEC's SD648), `u32::MAX` for none (R is
    /// block 0).
    r_block: u32,
    /// The modules' buffer memories and CPU shared memories in `G`.
    units: Box<[UnitWindow]>,
    /// Flat index of the first of the [`FILE_REGISTER_VOID`] words.
    void: u32,
    /// This CPU's number in a multi-CPU system, 0 for a single CPU.
    own_cpu: u32,
    /// The first address of the user area of its own shared memory.
    user_area: u32,
}

impl DeviceMap {
    pub fn new(cfg: &DeviceConfig) -> Self {
        let mut base = [0; DeviceKind::COUNT];
        let mut points = [0; DeviceKind::COUNT];
        let (mut nb, mut nw) = (0u32, 0u32);
        for k in DeviceKind::ALL {
            let n = cfg.points(k);
            points[k as usize] = n;
            if k == DeviceKind::R {
                continue; // R is a window onto ZR (block 0); placed below.
            }
            if k.is_bit() {
                base[k as usize] = nb;
                nb += n;
            } else {
                base[k as usize] = nw;
                nw += n * k.words_per_point();
            }
        }
        // R is a window onto ZR: its base is block 0. Program operands on R are
        // `Indexed` and add the selected block (`r_block`) when they run.
        base[DeviceKind::R as usize] = base[DeviceKind::ZR as usize];
        let void = nw;
        DeviceMap {
            base,
            points,
            bit_len: nb,
            word_len: nw + FILE_REGISTER_VOID,
            r_block: u32::MAX,
            units: cfg.units.clone().into_boxed_slice(),
            void,
            own_cpu: cfg.multi_cpu.as_ref().map_or(0, |m| m.own),
            user_area: REFRESH_AREA + cfg.multi_cpu.as_ref().map_or(0, |m| m.refresh_words),
        }
    }

    /// This CPU's number (1-4) in a multi-CPU system, `None` for a single CPU.
    #[inline]
    pub fn own_cpu(&self) -> Option<u32> {
        (self.own_cpu != 0).then_some(self.own_cpu)
    }

    /// The first address of the user area of this CPU's shared memory,
    /// right after its auto-refresh area (004 L9053): where S.TO may write.
    #[inline]
    pub fn shared_user_area(&self) -> u32 {
        self.user_area
    }

    /// The buffer memory of the module whose unit number (start I/O number
    /// without its last hex digit) is `unit`, `None` for a slot with no
    /// intelligent function module.
    #[inline]
    pub fn unit(&self, unit: u32) -> Option<UnitWindow> {
        self.units.iter().find(|w| w.unit == unit).copied()
    }

    /// Every module's buffer memory, in slot order.
    pub fn units(&self) -> &[UnitWindow] {
        &self.units
    }

    /// The G number of `words` words from address `addr` of unit `unit`'s
    /// buffer memory: the one check every access makes (instructions,
    /// names, protocols).
    #[inline]
    pub fn buffer(&self, unit: u32, addr: u32, words: u32) -> Result<u32, BufferError> {
        let w = self.unit(unit).ok_or(BufferError::NoModule)?;
        w.span(addr, words)
    }

    /// [`Self::buffer`] as a program reaches it (FROM, TO): no module is
    /// [`Fault::NoModule`], what the unit's owner refuses its fault
    /// ([`UnitOwner::refuses`]), past its memory [`Fault::Range`].
    #[inline]
    pub fn program_buffer(
        &self,
        unit: u32,
        addr: u32,
        words: u32,
        access: UnitAccess,
    ) -> Result<u32, Fault> {
        let w = self.unit(unit).ok_or(Fault::NoModule)?;
        if let Some(f) = w.owner.refuses(access) {
            return Err(f);
        }
        w.span(addr, words).map_err(|_| Fault::Range)
    }

    /// Sets the word selecting the file-register block R addresses (flat
    /// word index; the CPU sets its system's), `None` for block 0 always.
    pub fn set_r_block(&mut self, word: Option<u32>) {
        self.r_block = word.filter(|w| *w < self.word_len).unwrap_or(u32::MAX);
    }

    /// The word selecting the file-register block, if any.
    pub fn r_block(&self) -> Option<u32> {
        (self.r_block != u32::MAX).then_some(self.r_block)
    }

    #[inline]
    pub fn base(&self, kind: DeviceKind) -> u32 {
        self.base[kind as usize]
    }

    #[inline]
    pub fn points(&self, kind: DeviceKind) -> u32 {
        self.points[kind as usize]
    }

    /// Flat index of device `kind` number `n`, or `None` when out of range.
    #[inline]
    pub fn index(&self, kind: DeviceKind, n: u32) -> Option<u32> {
        (n < self.points(kind)).then(|| self.word_at(kind, n))
    }

    /// Flat index of the first word (or the bit) of point `n` of `kind`,
    /// unchecked: FD points are 4 words apart.
    #[inline]
    pub fn word_at(&self, kind: DeviceKind, n: u32) -> u32 {
        self.base(kind) + n * kind.words_per_point()
    }

    pub fn bit_len(&self) -> u32 {
        self.bit_len
    }

    pub fn word_len(&self) -> u32 {
        self.word_len
    }
}

/// The CPU's device memory.
#[derive(Clone, Debug)]
pub struct DeviceMemory {
    pub map: DeviceMap,
    pub bits: Box<[bool]>,
    pub words: Box<[u16]>,
    /// A program reached file registers outside the registered range since
    /// the last [`DeviceMemory::take_file_register_miss`].
    file_register_miss: Miss,
}

/// A flag the read path sets through `&self` (only when an access misses,
/// so in-range accesses pay nothing).
#[derive(Debug, Default)]
struct Miss(AtomicBool);

impl Clone for Miss {
    fn clone(&self) -> Self {
        Miss(AtomicBool::new(self.0.load(Ordering::Relaxed)))
    }
}

/// A device access outside the configured points (MELSEC error 4101 at run time).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{kind}{number} is outside the configured range ({points} points)")]
pub struct OutOfRange {
    pub kind: DeviceKind,
    pub number: i64,
    pub points: u32,
}

impl DeviceMemory {
    pub fn new(cfg: &DeviceConfig) -> Self {
        let map = DeviceMap::new(cfg);
        DeviceMemory {
            bits: vec![false; map.bit_len() as usize].into_boxed_slice(),
            words: vec![0; map.word_len() as usize].into_boxed_slice(),
            map,
            file_register_miss: Miss::default(),
        }
    }

    /// Where `words` words of file registers wholly outside the registered
    /// range are read and written: no error, reads 0, writes ignored (004
    /// §10.7.5 (1), L7180-7194; the manual's "undefined" standard RAM reads
    /// as 0 too). Records the miss for the system (MELSEC's SM672). A span
    /// longer than the void is [`Fault::Range`].
    #[cold]
    pub fn outside_file_registers(&self, words: u32) -> Result<usize, Fault> {
        if words > FILE_REGISTER_VOID {
            return Err(Fault::Range);
        }
        self.file_register_miss.0.store(true, Ordering::Relaxed);
        Ok(self.map.void as usize)
    }

    /// Whether a program reached file registers outside the registered range
    /// since the last call (END processing asks); clears the record and the
    /// void, so what was written there is dropped.
    pub fn take_file_register_miss(&mut self) -> bool {
        let missed = self.file_register_miss.0.swap(false, Ordering::Relaxed);
        if missed {
            let void = self.map.void as usize;
            self.words[void..void + FILE_REGISTER_VOID as usize].fill(0);
        }
        missed
    }

    fn locate(&self, kind: DeviceKind, n: i64) -> Result<usize, OutOfRange> {
        let points = self.map.points(kind);
        if n < 0 || n >= points as i64 {
            return Err(OutOfRange {
                kind,
                number: n,
                points,
            });
        }
        Ok(self.map.word_at(kind, n as u32) as usize)
    }

    /// Reads one bit device (`kind` must be a bit kind).
    pub fn get_bit(&self, kind: DeviceKind, n: i64) -> Result<bool, OutOfRange> {
        debug_assert!(kind.is_bit());
        Ok(self.bits[self.locate(kind, n)?])
    }

    pub fn set_bit(&mut self, kind: DeviceKind, n: i64, v: bool) -> Result<(), OutOfRange> {
        debug_assert!(kind.is_bit());
        let i = self.locate(kind, n)?;
        self.bits[i] = v;
        Ok(())
    }

    /// Reads one word device (`kind` must be a word kind).
    pub fn get_word(&self, kind: DeviceKind, n: i64) -> Result<u16, OutOfRange> {
        debug_assert!(!kind.is_bit());
        Ok(self.words[self.locate(kind, n)?])
    }

    pub fn set_word(&mut self, kind: DeviceKind, n: i64, v: u16) -> Result<(), OutOfRange> {
        debug_assert!(!kind.is_bit());
        let i = self.locate(kind, n)?;
        self.words[i] = v;
        Ok(())
    }

    /// Reads `n` consecutive bits starting at flat bit index `start` as an integer,
    /// least significant first (digit specification `KnM0` uses 4·n bits).
    #[inline]
    pub fn pack_bits(&self, start: usize, n: usize) -> u32 {
        let mut v = 0u32;
        for (i, b) in self.bits[start..start + n].iter().enumerate() {
            v |= (*b as u32) << i;
        }
        v
    }

    #[inline]
    pub fn unpack_bits(&mut self, start: usize, n: usize, v: u32) {
        for (i, b) in self.bits[start..start + n].iter_mut().enumerate() {
            *b = (v >> i) & 1 != 0;
        }
    }

    /// Clears every device (power-on without latch; latch ranges arrive with the
    /// CPU-functions issue).
    pub fn clear(&mut self) {
        self.bits.fill(false);
        self.words.fill(0);
    }
}
