//! Programming manual (common instructions) §7.15, clock instructions: DATERD,
//! DATEWR, DATE+, DATE-, SECOND, HOUR (each with its pulse form).
//!
//! The calendar is the engine's [`PlcClock`](softplc_ir::calendar::PlcClock)
//! (004 §7.6, qcpu.md §4.4): year 1980-2079, leap years automatic, day of week
//! 0 = Sunday … 6 = Saturday; it advances with the engine clock, so in virtual
//! time with the scans. Clock data is 7 words (year, month, day, hour, minute,
//! second, day of week), time data 3 words (hour, minute, second), all BIN.
//!
//! The QnH set has no DSECOND/DHOUR: SECOND already writes 32 bits and HOUR reads
//! 32 bits.

use super::{Args, ExecCtx, Instr};
use softplc_ir::calendar::DateTime;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_ir::ops::{Num, WordArg};
use softplc_lang::isa::{Def, Doc};

/// This family's instructions.
pub static DEFS: &[Def] = &[
    Def::app("DATERD", &CLOCK, compile_daterd),
    Def::app("DATEWR", &CLOCK, compile_datewr),
    Def::app("DATE+", &CLOCK, |a| compile_date_arith(a, false)),
    Def::app("DATE-", &CLOCK, |a| compile_date_arith(a, true)),
    Def::app("SECOND", &CLOCK, compile_second),
    Def::app("HOUR", &CLOCK, compile_hour),
];

static CLOCK: Doc = Doc {
    family: "clock",
    cite: "PM §7.15; 004 §7.6",
    notes: "DATEWR invalid → 4100, clock unchanged",
};

const DAY: i32 = 86_400;

/// Reads `N` consecutive words of a block (4101 past the device's end).
fn read_words<const N: usize>(cx: &ExecCtx<'_>, b: &Block) -> Result<[u16; N], Fault> {
    let i = cx.mem.block_start(b, N as u32)?;
    let mut w = [0u16; N];
    w.copy_from_slice(&cx.mem.words[i..i + N]);
    Ok(w)
}

/// Writes consecutive words to a block (4101 past the device's end, nothing written).
fn write_words(cx: &mut ExecCtx<'_>, b: &Block, w: &[u16]) -> Result<(), Fault> {
    let i = cx.mem.block_start(b, w.len() as u32)?;
    cx.mem.words[i..i + w.len()].copy_from_slice(w);
    Ok(())
}

/// Time data (hour 0-23, minute 0-59, second 0-59) as seconds since 00:00:00;
/// anything else is 4100.
fn time_of(w: [u16; 3]) -> Result<i32, Fault> {
    let [h, m, s] = w.map(|v| v as i16 as i32);
    if !(0..24).contains(&h) || !(0..60).contains(&m) || !(0..60).contains(&s) {
        return Err(Fault::Operation);
    }
    Ok(h * 3600 + m * 60 + s)
}

/// Seconds 0-86399 as hour, minute, second.
fn hms(t: i32) -> [u16; 3] {
    [(t / 3600) as u16, (t / 60 % 60) as u16, (t % 60) as u16]
}

/// PM §7.15.1 DATERD(P) `D`: reads the clock into D…D+6 — year (4 digits),
/// month, day, hour, minute, second, day of week (0 = Sunday). The reading is
/// the clock at the start of the scan (the engine's time does not advance during
/// a scan). A block past the end of the device is 4101.
#[derive(Debug)]
struct DateRd {
    d: Block,
}

fn compile_daterd(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    Some(Box::new(DateRd {
        d: a.block_dest(0)?,
    }))
}

impl Instr for DateRd {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let t = cx.clock.now(cx.now_us);
        let w = [
            t.year as u16,
            t.month as u16,
            t.day as u16,
            t.hour as u16,
            t.minute as u16,
            t.second as u16,
            t.weekday() as u16,
        ];
        write_words(cx, &self.d, &w)
    }
}

/// PM §7.15.2 DATEWR(P) `S`: writes S…S+6 (same layout as DATERD) to the clock
/// when the instruction executes; the sub-second part restarts at 0.
///
/// Errors: a field outside its range — year 1980-2079, month 1-12, a day that
/// does not exist in that month (29 February only in leap years), hour 0-23,
/// minute 0-59, second 0-59, day of week 0-6 — is 4100 and leaves the clock
/// unchanged (the manual: the clock cannot take invalid data). Decision: the
/// day of week is range-checked but not compared with the date; as on the CPU
/// after a power cycle, the clock derives it from the date, so DATERD returns
/// the true weekday of the written date.
#[derive(Debug)]
struct DateWr {
    s: Block,
}

fn compile_datewr(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[1]) {
        return None;
    }
    Some(Box::new(DateWr { s: a.block(0)? }))
}

impl Instr for DateWr {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let w: [u16; 7] = read_words(cx, &self.s)?;
        let f = |k: usize| w[k] as i16 as i32;
        if f(1) < 0 || f(2) < 0 || f(3) < 0 || f(4) < 0 || f(5) < 0 || !(0..=6).contains(&f(6)) {
            return Err(Fault::Operation);
        }
        let t = DateTime {
            year: f(0),
            month: f(1) as u32,
            day: f(2) as u32,
            hour: f(3) as u32,
            minute: f(4) as u32,
            second: f(5) as u32,
        };
        if !t.is_valid() {
            return Err(Fault::Operation);
        }
        cx.clock.set(t, cx.now_us);
        Ok(())
    }
}

/// PM §7.15.3 DATE+(P) `S1 S2 D` and §7.15.4 DATE-(P): adds (subtracts) the
/// time data S2 (hour, minute, second) to (from) the time data S1 and stores the
/// time of day in D…D+2, wrapping at 24 hours: 10:20:30 + 20:20:20 = 6:40:50,
/// 10:20:30 − 20:20:20 = 14:00:10. Either input outside hour 0-23, minute 0-59,
/// second 0-59 is 4100 (D unchanged). The inputs are read before D is written,
/// so D may overlap them.
#[derive(Debug)]
struct DateArith {
    sub: bool,
    s1: Block,
    s2: Block,
    d: Block,
}

fn compile_date_arith(a: &mut Args<'_, '_>, sub: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s1 = a.block(0);
    let s2 = a.block(1);
    let d = a.block_dest(2);
    Some(Box::new(DateArith {
        sub,
        s1: s1?,
        s2: s2?,
        d: d?,
    }))
}

impl Instr for DateArith {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let t1 = time_of(read_words(cx, &self.s1)?)?;
        let t2 = time_of(read_words(cx, &self.s2)?)?;
        let t = if self.sub { t1 - t2 } else { t1 + t2 };
        write_words(cx, &self.d, &hms(t.rem_euclid(DAY)))
    }
}

/// PM §7.15.5 SECOND(P) `S D`: time data S…S+2 (hour 0-23, minute 0-59, second
/// 0-59) to seconds, a BIN 32-bit value 0-86399 in D, D+1. A field out of range
/// is 4100.
#[derive(Debug)]
struct Second {
    s: Block,
    d: WordArg,
}

fn compile_second(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.block(0);
    let d = a.word_dest(1, Num::I32, 2);
    Some(Box::new(Second { s: s?, d: d? }))
}

impl Instr for Second {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let t = time_of(read_words(cx, &self.s)?)?;
        cx.mem.write32(&self.d, t as u32)
    }
}

/// PM §7.15.6 HOUR(P) `S D`: seconds (BIN 32 bits in S, S+1, 0-86399) to time
/// data hour, minute, second in D…D+2. A value outside 0-86399 is 4100.
#[derive(Debug)]
struct Hour {
    s: WordArg,
    d: Block,
}

fn compile_hour(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
    if !a.count(&[2]) {
        return None;
    }
    let s = a.word_src(0, Num::I32);
    let d = a.block_dest(1);
    Some(Box::new(Hour { s: s?, d: d? }))
}

impl Instr for Hour {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let t = cx.mem.read32(&self.s)? as i32;
        if !(0..DAY).contains(&t) {
            return Err(Fault::Operation);
        }
        write_words(cx, &self.d, &hms(t))
    }
}
