//! Maximum, minimum and sorting of tables (PM §7.5.10-12): MAX, MIN, DMAX, DMIN,
//! SORT, DSORT.

use super::{elem, fixed_block, get_flag, read_i16, set_elem, width};
use crate::{Args, ExecCtx, Instr};
use softplc_ir::fault::Fault;
use softplc_ir::instr::LocalSlot;
use softplc_ir::ops::Block;
use softplc_ir::ops::{BitArg, Num, WordArg};

/// PM §7.5.10-11 MAX(P)/MIN(P)/DMAX(P)/DMIN(P) `S D n`: the largest (smallest)
/// of the n signed 16-bit (32-bit) values from S goes to D (D, D+1); the
/// position of its first occurrence counted from 1 at S goes to the next word,
/// the number of occurrences to the one after. n ≤ 0: no processing (decision:
/// as the SER page states for the same kind of count). S or D past the end of
/// its device: 4101.
#[derive(Debug)]
struct MaxMin {
    s: Block,
    d: Block,
    n: WordArg,
    wide: bool,
    max: bool,
}

pub(super) fn maxmin(a: &mut Args<'_, '_>, wide: bool, max: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[3]) {
        return None;
    }
    let s = a.block(0);
    let d = fixed_block(a, 1, width(wide) + 2);
    let n = a.word_src(2, Num::I16);
    Some(Box::new(MaxMin {
        s: s?,
        d: d?,
        n: n?,
        wide,
        max,
    }))
}

impl Instr for MaxMin {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mem = &mut *cx.mem;
        let n = read_i16(mem, &self.n)?;
        if n <= 0 {
            return Ok(());
        }
        let n = n as usize;
        let w = width(self.wide);
        let s = mem.block_start(&self.s, n as u32 * w)?;
        let d = mem.block_start(&self.d, w + 2)?;
        let mut best = elem(mem, s, 0, self.wide);
        let (mut pos, mut count) = (1usize, 1usize);
        for k in 1..n {
            let v = elem(mem, s, k, self.wide);
            if v == best {
                count += 1;
            } else if (v > best) == self.max {
                best = v;
                pos = k + 1;
                count = 1;
            }
        }
        set_elem(mem, d, 0, self.wide, best);
        let at = d + w as usize;
        mem.words[at] = pos as u16;
        mem.words[at + 1] = count as u16;
        Ok(())
    }
}

// ------------------------------------------------------------ SORT / DSORT

/// PM §7.5.12 SORT/DSORT `S1 n S2 D1 D2`: sorts the n signed 16-bit (32-bit)
/// values from S1 in place, ascending with SM703 OFF, descending with SM703 ON,
/// over several executions: each execution makes S2 comparisons of the
/// n(n−1)/2 the sort needs (exchange sort: element i against each later j), so
/// it completes after ⌈n(n−1)/2 ÷ S2⌉ executions. The first execution of a
/// sort turns D1 OFF; the execution that finishes it turns D1 ON, and D1 stays
/// ON (the user resets it). The execution after completion starts a new sort.
///
/// The progress (i, j, n of the running sort) is kept in hidden state words; D2
/// and D2+1, which the manual reserves for the system, are range-checked but
/// not written. An interrupted sort (condition OFF) resumes where it stopped
/// when the condition is ON again, since the CPU keeps its progress in D2.
/// SM703 is read at every execution.
///
/// The manual gives SORT/DSORT no pulse form: SORTP/DSORTP are rejected at
/// load. Errors: n < 0 or S2 ≤ 0: 4100 (decision: the manual gives no range
/// but a sort cannot progress with them); n = 0 or 1: the sort is complete at
/// once (D1 ON). S1 past the end of its device: 4101.
#[derive(Debug)]
struct Sort {
    s1: Block,
    n: WordArg,
    per_exec: WordArg,
    done: BitArg,
    work: Block,
    state: LocalSlot<SortState>,
    wide: bool,
    sm703: Option<u32>,
}

pub(super) fn sort(a: &mut Args<'_, '_>, wide: bool) -> Option<Box<dyn Instr>> {
    if !a.count(&[5]) {
        return None;
    }
    // Sorted in place.
    let s1 = a.block_dest(0);
    let n = a.word_src(1, Num::I16);
    let per_exec = a.word_src(2, Num::I16);
    let done = a.bit_dest(3);
    let work = fixed_block(a, 4, 2);
    let state = a.local();
    Some(Box::new(Sort {
        s1: s1?,
        n: n?,
        per_exec: per_exec?,
        done: done?,
        work: work?,
        state,
        wide,
        sm703: a.flag(softplc_lang::dialect::Flag::SortDescending),
    }))
}

softplc_ir::local_state! {
    /// A SORT in progress: the pass (i, j) it reached and its n.
    struct SortState {
        running: bool,
        i: u32,
        j: u32,
        n: u32,
    }
}

impl Instr for Sort {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let mut st = cx.local(&self.state);
        let mem = &mut *cx.mem;
        let per = read_i16(mem, &self.per_exec)?;
        if per <= 0 {
            return Err(Fault::Operation);
        }
        mem.block_start(&self.work, 2)?;
        let starting = !st.running;
        let n = if starting {
            let n = read_i16(mem, &self.n)?;
            if n < 0 {
                return Err(Fault::Operation);
            }
            n as u32
        } else {
            st.n
        };
        let s = mem.block_start(&self.s1, n * width(self.wide))?;
        // Also checks an index-modified D1 before anything is written.
        mem.read_bit(&self.done)?;
        let (mut i, mut j) = if starting {
            mem.write_bit(&self.done, false)?;
            (0, 1)
        } else {
            (st.i, st.j)
        };
        let descending = get_flag(mem, self.sm703);
        let mut left = per as u32;
        let finished = loop {
            if i + 1 >= n {
                break true;
            }
            if left == 0 {
                break false;
            }
            let (a, b) = (
                elem(mem, s, i as usize, self.wide),
                elem(mem, s, j as usize, self.wide),
            );
            if (a > b && !descending) || (a < b && descending) {
                set_elem(mem, s, i as usize, self.wide, b);
                set_elem(mem, s, j as usize, self.wide, a);
            }
            left -= 1;
            j += 1;
            if j >= n {
                i += 1;
                j = i + 1;
            }
        };
        if finished {
            st.running = false;
            cx.set_local(&self.state, st);
            cx.mem.write_bit(&self.done, true)?;
        } else {
            st = SortState {
                running: true,
                i,
                j,
                n,
            };
            cx.set_local(&self.state, st);
        }
        Ok(())
    }
}
