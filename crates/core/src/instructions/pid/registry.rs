//! The CPU-internal PID registration of one family: what S.PIDINIT/PIDINIT
//! registers (001 §8.1.1/§9.1.1 "登录到 CPU 模块"), the loops stopped by
//! PIDSTOP (001 §8.1.3/§9.1.4) and whether PIDCONT has run (the 4103 rule of
//! PIDSTOP/PIDRUN). Notes `pid-instructions.md` §3.4: registered parameters and
//! the stop state live in the CPU, not in devices.
//!
//! # Where it lives
//!
//! The framework gives each family instruction its own hidden state words
//! ([`ExecCtx::state`](crate::instructions::ExecCtx), allocated at load) but no
//! storage shared between instructions. The family's registry therefore lives
//! in the state words of one S.PIDINIT/PIDINIT instruction, the **root**:
//!
//! * every PIDINIT reserves [`ROOT_WORDS`]; every other PID instruction one word
//!   (its cached root index + 1, 0 = not found yet);
//! * the first PIDINIT of a family to execute marks its block as the root
//!   (a family magic word followed by its own index xor [`MIX`]);
//! * any PID instruction finds the root by scanning the state words for that
//!   signature once, then caches the index. No root yet means PIDINIT has never
//!   run: error 4103.
//!
//! Every later PIDINIT of the family writes into the root, so "the last
//! PIDINIT executed before PIDCONT is valid" (001 §8.1.1 功能(2)) holds across
//! several PIDINIT instructions. The state words are zeroed when the CPU is
//! built, so a signature can only come from a PIDINIT of this program.

use super::params::MAX_LOOP_WORDS;
use super::{Family, MAX_LOOPS};

/// Mixed with the root's own index in its second signature word.
pub(crate) const MIX: u32 = 0x9E37_79B9;

// Offsets inside a PIDINIT's state block.
const CACHE: usize = 0;
const MAGIC: usize = 1;
const SELF: usize = 2;
const STATUS: usize = 3;
const LOOPS: usize = 4;
const PER_SCAN: usize = 5;
const STOPPED: usize = 6;
const BAD: usize = 7;
const PARAMS: usize = 8;
/// u32 words per loop's parameters (14 raw words, two per u32).
const PARAM_U32: usize = MAX_LOOP_WORDS / 2;

/// State words of a PIDINIT instruction (root candidate).
pub(crate) const ROOT_WORDS: u32 = (PARAMS + MAX_LOOPS * PARAM_U32) as u32;
/// State words of every other PID instruction (the cached root index).
pub(crate) const LINK_WORDS: u32 = 1;

/// Status bits.
const REGISTERED: u32 = 1;
const COMMON_ERROR: u32 = 2;
const CONT_SEEN: u32 = 4;

/// The family's root signature is at block `b` ([`registry`](self) module doc;
/// the storage of 001 §8.1.1/§9.1.1 "登录到 CPU 模块").
fn is_root(state: &[u32], b: usize, fam: Family) -> bool {
    state.get(b + MAGIC) == Some(&fam.magic()) && state.get(b + SELF) == Some(&(b as u32 ^ MIX))
}

/// Finds the family's registration (001 §8.1.1/§9.1.1) for the instruction whose state block starts at
/// `own` (cached after the first success). `None`: no PIDINIT of the family
/// has executed yet.
pub(crate) fn find(state: &mut [u32], own: usize, fam: Family) -> Option<usize> {
    let cached = state[own + CACHE] as usize;
    if cached != 0 && is_root(state, cached - 1, fam) {
        return Some(cached - 1);
    }
    let last = state.len().checked_sub(ROOT_WORDS as usize)?;
    let root = (0..=last).find(|&b| is_root(state, b, fam))?;
    state[own + CACHE] = root as u32 + 1;
    Some(root)
}

/// The root for a PIDINIT (001 §8.1.1/§9.1.1) at `own`: the existing one, or `own` itself when it
/// is the first PIDINIT of the family to execute.
pub(crate) fn find_or_become(state: &mut [u32], own: usize, fam: Family) -> usize {
    if let Some(r) = find(state, own, fam) {
        return r;
    }
    state[own + MAGIC] = fam.magic();
    state[own + SELF] = own as u32 ^ MIX;
    state[own + CACHE] = own as u32 + 1;
    own
}

/// A view of the registry in the root's state words: n and k (001 §5.1.1), the
/// loops' control data (001 §5.1(3)), the PIDSTOP bits (001 §8.1.3/§9.1.4).
pub(crate) struct Registry<'a>(&'a mut [u32]);

impl<'a> Registry<'a> {
    pub(crate) fn at(state: &'a mut [u32], root: usize) -> Registry<'a> {
        Registry(&mut state[root..root + ROOT_WORDS as usize])
    }

    /// S.PIDINIT/PIDINIT has executed (successfully or with a data error).
    pub(crate) fn registered(&self) -> bool {
        self.0[STATUS] & REGISTERED != 0
    }

    /// The last PIDINIT found an error in the common data (loops, loops per
    /// scan): no loop runs (001 §5.1 Table 5.2 "不执行所有环路的 PID 运算").
    pub(crate) fn common_error(&self) -> bool {
        self.0[STATUS] & COMMON_ERROR != 0
    }

    /// S.PIDCONT/PIDCONT has executed since power-on (PIDSTOP/PIDRUN need it,
    /// 001 §8.1.3/§9.1.4 errors).
    pub(crate) fn cont_seen(&self) -> bool {
        self.0[STATUS] & CONT_SEEN != 0
    }

    pub(crate) fn set_cont_seen(&mut self) {
        self.0[STATUS] |= CONT_SEEN;
    }

    /// Number of loops used (n) and loops per scan (k).
    pub(crate) fn loops(&self) -> usize {
        self.0[LOOPS] as usize
    }

    pub(crate) fn per_scan(&self) -> usize {
        self.0[PER_SCAN] as usize
    }

    /// Registers a common-data error: nothing runs until the next good PIDINIT.
    pub(crate) fn register_error(&mut self) {
        self.0[STATUS] = (self.0[STATUS] & CONT_SEEN) | REGISTERED | COMMON_ERROR;
        self.0[LOOPS] = 0;
        self.0[PER_SCAN] = 0;
    }

    /// Registers the common data; the loops follow with [`Registry::set_loop`].
    pub(crate) fn register(&mut self, n: usize, k: usize) {
        self.0[STATUS] = (self.0[STATUS] & CONT_SEEN) | REGISTERED;
        self.0[LOOPS] = n as u32;
        self.0[PER_SCAN] = k as u32;
    }

    /// Stores loop `i`'s (0-based) raw words; `ok` false marks the loop's data
    /// as invalid (PIDCONT skips it with 4100).
    pub(crate) fn set_loop(&mut self, i: usize, words: &[u16], ok: bool) {
        let base = PARAMS + i * PARAM_U32;
        for j in 0..PARAM_U32 {
            let lo = words.get(2 * j).copied().unwrap_or(0) as u32;
            let hi = words.get(2 * j + 1).copied().unwrap_or(0) as u32;
            self.0[base + j] = lo | hi << 16;
        }
        if ok {
            self.0[BAD] &= !(1 << i);
        } else {
            self.0[BAD] |= 1 << i;
        }
    }

    /// Loop `i`'s registered raw words (only the family's first 10/14 matter).
    pub(crate) fn loop_words(&self, i: usize) -> [u16; MAX_LOOP_WORDS] {
        let base = PARAMS + i * PARAM_U32;
        let mut w = [0u16; MAX_LOOP_WORDS];
        for j in 0..PARAM_U32 {
            let v = self.0[base + j];
            w[2 * j] = v as u16;
            w[2 * j + 1] = (v >> 16) as u16;
        }
        w
    }

    /// Loop `i`'s registered data was out of range.
    pub(crate) fn bad(&self, i: usize) -> bool {
        self.0[BAD] & (1 << i) != 0
    }

    /// Loop `i` stopped by PIDSTOP (survives PIDINIT, 001 §8.1.3 功能(1)(a)).
    pub(crate) fn stopped(&self, i: usize) -> bool {
        self.0[STOPPED] & (1 << i) != 0
    }

    pub(crate) fn set_stopped(&mut self, i: usize, stop: bool) {
        if stop {
            self.0[STOPPED] |= 1 << i;
        } else {
            self.0[STOPPED] &= !(1 << i);
        }
    }
}
