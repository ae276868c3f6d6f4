//! Annunciators (004 §10.2.4): OUT/SET/RST of F, LEDR and ANR. Turning an
//! annunciator ON through OUT or SET appends it to the list SD64-SD79 (SD62
//! the first, SD63 the count, SM62 ON) and logs error 9000 with its number
//! (SD4 = 0600H, SD16); RST removes it; OUT turning it OFF does no list
//! processing. The definitions are in `ladder.rs` (OUT/SET/RST, LEDR, ANS,
//! ANR); these are their instructions.

use softplc_ir::device::{DeviceKind, DeviceMap, DeviceMemory};
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};

/// The annunciator list in the system devices: flat indices of SD0 and SM62.
#[derive(Clone, Copy, Debug)]
pub(crate) struct List {
    sd: usize,
    sm62: usize,
}

impl List {
    /// The list of a CPU with device map `map` (`None` without SD79 or SM62).
    pub(crate) fn of(map: &DeviceMap) -> Option<List> {
        map.index(DeviceKind::SD, 79)?;
        Some(List {
            sd: map.base(DeviceKind::SD) as usize,
            sm62: map.index(DeviceKind::SM, 62)? as usize,
        })
    }

    fn sd(&self, mem: &DeviceMemory, n: usize) -> u16 {
        mem.words[self.sd + n]
    }

    fn set_sd(&self, mem: &mut DeviceMemory, n: usize, v: u16) {
        mem.words[self.sd + n] = v;
    }

    /// Appends annunciator `n` (16 entries at most).
    fn add(&self, mem: &mut DeviceMemory, n: u16) {
        let count = self.sd(mem, 63).min(16);
        if count < 16 {
            self.set_sd(mem, 64 + count as usize, n);
            self.set_sd(mem, 63, count + 1);
        }
        let first = self.sd(mem, 64);
        self.set_sd(mem, 62, first);
        mem.bits[self.sm62] = true;
    }

    /// Removes annunciator `n`, shifting the later ones up.
    fn remove(&self, mem: &mut DeviceMemory, n: u16) {
        let count = self.sd(mem, 63).min(16) as usize;
        let Some(pos) = (0..count).find(|k| self.sd(mem, 64 + k) == n) else {
            return;
        };
        for k in pos..count - 1 {
            let next = self.sd(mem, 65 + k);
            self.set_sd(mem, 64 + k, next);
        }
        self.set_sd(mem, 64 + count - 1, 0);
        self.set_sd(mem, 63, (count - 1) as u16);
        let first = if count > 1 { self.sd(mem, 64) } else { 0 };
        self.set_sd(mem, 62, first);
        mem.bits[self.sm62] = count > 1;
    }
}

/// OUT, SET or RST of annunciator F`n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Coil {
    Out,
    Set,
    Rst,
}

/// 004 §10.2.4 OUT/SET/RST F`n`. OUT runs at every execution (OFF turns F
/// OFF without list processing); SET and RST while the condition is ON.
#[derive(Debug)]
pub(crate) struct Annunciator {
    pub coil: Coil,
    pub n: u16,
    /// Flat bit index of F`n`.
    pub f: usize,
    pub list: Option<List>,
}

impl Annunciator {
    fn turn_on(&self, cx: &mut ExecCtx<'_>) {
        if let Some(l) = self.list {
            l.add(cx.mem, self.n);
        }
        cx.cpu.report(Fault::Annunciator, self.n as u32);
    }
}

impl Instr for Annunciator {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let was = cx.mem.bits[self.f];
        match self.coil {
            Coil::Out | Coil::Set => {
                cx.mem.bits[self.f] = true;
                if !was {
                    self.turn_on(cx);
                }
            }
            Coil::Rst => {
                cx.mem.bits[self.f] = false;
                if let Some(l) = self.list {
                    l.remove(cx.mem, self.n);
                }
            }
        }
        Ok(())
    }

    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        if self.coil == Coil::Out {
            cx.mem.bits[self.f] = false;
        }
        Ok(())
    }
}

/// 004 §10.2.4 LEDR (and ANR): turns OFF the annunciator shown first (SD62)
/// and removes it from the list; but when a continuation error outranks
/// the annunciators in the LED display priority (SD207-SD209), LEDR clears
/// that error instead and the annunciator stays (L6294-6297).
#[derive(Debug)]
pub(crate) struct Ledr {
    /// LEDR: a continuation error that outranks the annunciators first;
    /// ANR: annunciators only.
    pub errors_first: bool,
    /// Flat bit index of F0 and the F points.
    pub f: usize,
    pub points: usize,
    pub list: Option<List>,
}

impl Instr for Ledr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let Some(l) = self.list else { return Ok(()) };
        if self.errors_first && crate::system::panel::ledr_clears_error(cx.mem) {
            cx.cpu.clear_error();
            return Ok(());
        }
        let first = l.sd(cx.mem, 64);
        if l.sd(cx.mem, 63) > 0 {
            if (first as usize) < self.points {
                cx.mem.bits[self.f + first as usize] = false;
            }
            l.remove(cx.mem, first);
        }
        Ok(())
    }
}
