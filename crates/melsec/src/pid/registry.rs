//! The CPU-internal PID registration of one family: what S.PIDINIT/PIDINIT
//! registers (001 §8.1.1/§9.1.1 "登录到 CPU 模块"), the loops stopped by
//! PIDSTOP (001 §8.1.3/§9.1.4) and whether PIDCONT has run (the 4103 rule of
//! PIDSTOP/PIDRUN). Notes `pid-instructions.md` §3.4: registered parameters and
//! the stop state live in the CPU, not in devices.
//!
//! # Where it lives
//!
//! In the CPU-wide shared state of the instruction framework
//! ([`ExecCtx::shared`](softplc_ir::instr::ExecCtx)), one block per family, so
//! a PIDINIT in one program file (an initial program, say) registers the loops
//! that PIDCONT in another file runs, as on the CPU. The shared state is
//! cleared at power-on and STOP→RUN: PIDINIT must run again (SM402), as the
//! manual's examples do.

use super::params::MAX_LOOP_WORDS;
use super::MAX_LOOPS;

// Offsets inside a family's registry block.
const STATUS: usize = 0;
const LOOPS: usize = 1;
const PER_SCAN: usize = 2;
const STOPPED: usize = 3;
const BAD: usize = 4;
const PARAMS: usize = 5;
/// u32 words per loop's parameters (14 raw words, two per u32).
const PARAM_U32: usize = MAX_LOOP_WORDS / 2;

/// Words of one family's registry.
pub(crate) const REGISTRY_WORDS: usize = PARAMS + MAX_LOOPS * PARAM_U32;

/// Status bits.
const REGISTERED: u32 = 1;
const COMMON_ERROR: u32 = 2;
const CONT_SEEN: u32 = 4;

/// A view of the registry in the root's state words: n and k (001 §5.1.1), the
/// loops' control data (001 §5.1(3)), the PIDSTOP bits (001 §8.1.3/§9.1.4).
pub(crate) struct Registry<'a>(&'a mut [u32]);

impl<'a> Registry<'a> {
    pub(crate) fn at(shared: &'a mut [u32], at: usize) -> Registry<'a> {
        Registry(&mut shared[at..at + REGISTRY_WORDS])
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
