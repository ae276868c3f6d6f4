//! S.PIDCONT / SP.PIDCONT (001 §8.1.2) and PIDCONT / PIDCONTP (001 §9.1.2):
//! sampling-time measurement (001 §5.1.2), loops per scan with its priority
//! (001 §5.1.1), the first-processing flag (001 §5.2(4) 3)), bumpless
//! manual/auto transfer (001 §4.3.1) and the per-loop PID operation
//! ([`super::algo::sample`]).
//!
//! # One execution
//!
//! 1. No PIDINIT of the family yet → 4103. Common-data error registered by the
//!    last PIDINIT → 4100, nothing runs. The area `10 + 23·n` / `10 + 18·n`
//!    words past the device's end → 4101, nothing runs (001 §5.2(4) 5)).
//! 2. Time: the scan time measured at the previous END (`ExecCtx::scan_us`) is
//!    added, in whole milliseconds, to every running loop's accumulator; the
//!    sub-millisecond rest is carried in common work word +1 (001 §5.1.2(1)
//!    "每次执行 … 将一次扫描的测定时间累加"). A pulse form (SP.PIDCONT,
//!    PIDCONTP) therefore only counts the scans in which it executes
//!    (\[DECISION\] pid-instructions.md §4: allowed, not useful).
//! 3. Each loop 1..n, in order:
//!    * registered data out of range → 4100 for that loop, skipped;
//!    * stopped by PIDSTOP → skipped, its accumulator held at 0, so the first
//!      sample after PIDRUN comes Ts later with the held history
//!      (\[DECISION\] pid-instructions.md §4 PIDSTOP/PIDRUN);
//!    * MAN/AUTO ∉ {0,1} → 4100 for that loop, skipped (state untouched);
//!    * first processing not done: with flag word +0 = 0 it runs now, whatever
//!      the loops per scan; otherwise the loop is due and competes for the k
//!      slots below ("0 以外 … 每次扫描中处理环路的数量是所设置的一次扫描执行的环路数量");
//!    * otherwise: a change of MAN/AUTO since the previous execution copies
//!      MV_MAN → MV (manual→auto, also into the MV state) or MV → MV_MAN
//!      (auto→manual) now (\[DECISION\] §1.3: at that execution); the loop is
//!      due when its accumulator ≥ Ts.
//! 4. At most k due loops are computed (001 §5.1.1(3)): first those deferred
//!    in the previous scan, then the others, each group in loop-number order
//!    (001 §5.1.1 要点). The rest are marked deferred and keep accumulating
//!    (\[DECISION\] §1.8), so their Ts used is longer.
//! 5. A computed loop uses `ts = ⌊acc / 10 ms⌋` in the formulas and keeps the
//!    rest: `acc −= 10·ts` (001 §5.1.2(2); \[DECISION\] §1.7 carry). The first
//!    processing uses the configured Ts (\[DECISION\] §1.7) and restarts the
//!    accumulator at 0; its history is seeded by [`first_processing`].
//!
//! The first error found is returned after every loop has been processed
//! (\[DECISION\] pid-instructions.md §6: the other loops run).

use super::algo::{self, LoopIo, Range};
use super::params::LoopParams;
use super::registry::Registry;
use super::work::{LoopState, F_AUTO, F_DEFERRED, F_INIT, WORK};
use super::Family;
use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;

/// Everything one PIDCONT execution needs besides the registry (001 §5.1.2
/// measured scan time, §4.3.4 SM794/SM774, §4.3.5 SD794/SD795, SD774/SD775).
pub(crate) struct Env {
    /// Scan time measured at the previous END, µs.
    pub scan_us: u32,
    /// SM794/SM774 OFF: PV → SV in manual mode (001 §4.3.4).
    pub track: bool,
    /// SD794/SD795 (SD774/SD775): bit = 1 means "without range limits" (001 §4.3.5).
    pub unlimited: u32,
}

/// Seeds a loop's history for its first processing (\[DECISION\]
/// pid-instructions.md §2.6 "First processing"): PVfn−1 = PVfn−2 = PVn (so PVfn
/// = PVn and no derivative kick), Dn−1 = 0, EVn−1 = 0 (passed as `first` to
/// [`algo::sample`]), MVn−1 = the auto-MV word, PVn−1 = PVn (no PV alarm), the
/// current MAN/AUTO as the previous mode, accumulator 0.
fn first_processing(io: &[u16], range: Range, auto: bool) -> LoopState {
    let pv = range.mv(LoopIo::pv.get(io)) as f64;
    LoopState {
        flags: F_INIT | if auto { F_AUTO } else { 0 },
        mv: LoopIo::mv.get(io) as f64,
        pvf1: pv,
        pvf2: pv,
        sv1: 0,
        pv1: pv as i16,
        acc_ms: 0,
        d1: 0.0,
    }
}

/// Runs one PIDCONT execution (001 §8.1.2/§9.1.2; steps 2–5 of the module doc)
/// on the I/O area starting at flat word `start`
/// (already bounds-checked for `10 + per·n` words).
pub(crate) fn run(
    fam: Family,
    reg: &Registry<'_>,
    mem: &mut DeviceMemory,
    start: usize,
    env: &Env,
) -> Result<(), Fault> {
    let n = reg.loops();
    let per = fam.io_words();
    let work = fam.work_words();
    let area = &mut mem.words[start..start + 10 + per * n];
    // Time since the previous execution, whole ms; µs rest in common word +1.
    let total = (area[1] % 1000) as u64 + env.scan_us as u64;
    area[1] = (total % 1000) as u16;
    let add_ms = (total / 1000).min(u16::MAX as u64) as u16;
    let batch_first = area[0] == 0;

    let mut error: Option<Fault> = None;
    let mut due_deferred = 0u32;
    let mut due_new = 0u32;
    for i in 0..n {
        let range = Range {
            limited: env.unlimited & (1 << i) == 0,
        };
        let io = &mut area[10 + i * per..10 + (i + 1) * per];
        let (head, rest) = io.split_at_mut(WORK);
        let w = &mut rest[..work];
        if reg.bad(i) {
            error.get_or_insert(Fault::Operation);
            continue;
        }
        if reg.stopped(i) {
            let mut st = LoopState::load(fam, w);
            st.acc_ms = 0;
            st.set(F_DEFERRED, false);
            st.store(fam, w);
            continue;
        }
        let auto = match LoopIo::mode.get(head) {
            0 => false,
            1 => true,
            _ => {
                error.get_or_insert(Fault::Operation);
                continue;
            }
        };
        let mut st = LoopState::load(fam, w);
        if !st.has(F_INIT) {
            if batch_first {
                compute(fam, reg, i, range, env, head, w, None);
            } else if st.has(F_DEFERRED) {
                due_deferred |= 1 << i;
            } else {
                due_new |= 1 << i;
            }
            continue;
        }
        st.acc_ms = st.acc_ms.saturating_add(add_ms);
        // Bumpless transfer (001 §4.3.1(2)).
        if auto != st.has(F_AUTO) {
            if auto {
                let man = range.mv(LoopIo::mvman.get(head));
                LoopIo::mv.set(head, man);
                st.mv = man as f64;
            } else {
                LoopIo::mvman.set(head, LoopIo::mv.get(head));
            }
            st.set(F_AUTO, auto);
        }
        let ts_ms = reg.loop_words(i)[1] as u32 * 10;
        if st.acc_ms as u32 >= ts_ms {
            if st.has(F_DEFERRED) {
                due_deferred |= 1 << i;
            } else {
                due_new |= 1 << i;
            }
        } else {
            st.set(F_DEFERRED, false);
        }
        st.store(fam, w);
    }

    // At most k due loops: deferred ones first, each group in loop order.
    let mut budget = reg.per_scan();
    for set in [due_deferred, due_new] {
        let mut bits = set;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let io = &mut area[10 + i * per..10 + (i + 1) * per];
            let (head, w) = io.split_at_mut(WORK);
            let w = &mut w[..work];
            if budget == 0 {
                let mut st = LoopState::load(fam, w);
                st.set(F_DEFERRED, true);
                st.store(fam, w);
                continue;
            }
            budget -= 1;
            let range = Range {
                limited: env.unlimited & (1 << i) == 0,
            };
            let st = LoopState::load(fam, w);
            let ts = st.has(F_INIT).then_some(st.acc_ms / 10);
            compute(fam, reg, i, range, env, head, w, ts);
        }
    }
    error.map_or(Ok(()), Err)
}

/// Computes loop `i` now: a regular sample using `ts` (10 ms units, 001
/// §5.1.2(2)), or the first processing (`ts` = None) with the configured Ts
/// (001 §5.2(4) 3) "视为已到达所设置的采样周期"; \[DECISION\] notes §1.7).
#[allow(clippy::too_many_arguments)]
fn compute(
    fam: Family,
    reg: &Registry<'_>,
    i: usize,
    range: Range,
    env: &Env,
    head: &mut [u16],
    w: &mut [u16],
    ts: Option<u16>,
) {
    // The data was validated when registered (bad loops never get here).
    let Some(p) = LoopParams::decode(fam, &reg.loop_words(i)[..fam.param_words()]) else {
        return;
    };
    let auto = LoopIo::mode.get(head) == 1;
    let (mut st, ts, first) = match ts {
        Some(ts) => {
            let mut st = LoopState::load(fam, w);
            st.acc_ms -= ts * 10;
            (st, ts, false)
        }
        None => (first_processing(head, range, auto), p.ts, true),
    };
    st.set(F_DEFERRED, false);
    algo::sample(fam, &p, range, env.track, auto, head, &mut st, ts, first);
    st.store(fam, w);
}
