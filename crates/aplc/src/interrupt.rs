//! Interrupt routines (002 chapter 9 L10064-10310; spec aplc.md §3.5,
//! decision D3): `POU INT_<n> EVENT <e>`, EI/DI, CIRET.
//!
//! Decision (virtual time): events are taken at the start of each scan,
//! before MAIN, in the order they occurred: the edges of X0-X7 since the
//! previous scan (events 0-7 rising, 10-17 falling, enabled by SM40-SM47;
//! also those of a pulse that ended before the scan, which the input image
//! recorded: at most one event an edge) and
//! the timed interrupts 0-2 (events 26-28, period SD66-SD68 in ms, 1-32767,
//! enabled by SM66-SM68; enabling restarts the timing, L10151). An event
//! needs the global enable (EI) too. The 8-deep FIFO holds what one scan
//! start finds; a ninth event is lost with run error 67 (L10117). Routines
//! run one at a time, each with fresh LM/V. The serial events of PORT1
//! (34 char TX, 35 char RX, 36 frame TX, 37 frame RX, enabled by SM52-SM55)
//! are those the communication phase after END recorded in PORT1's mailbox
//! (`comm::mailbox::EVENTS`), taken after the timed ones; PORT0's 30-33
//! never occur (softplc has no PORT0, L10341).
//!
//! Compiled as a dispatch section at the start of the program: `Scan`
//! (collect the events), then a loop `Pop` · `Ld(routine bit)` · `Call` … that
//! calls each routine through the engine's CALL, until the queue is empty.

use softplc_ir::device::{DeviceKind, DeviceMap};
use softplc_ir::fault::{ErrorCode, Fault};
use softplc_ir::instr::{ExecCtx, Instr, LocalSlot, LocalState};
use softplc_ir::ops::Op;
use softplc_lang::compile::Compiler;
use softplc_lang::isa::{Class, Def, Doc, Steps, Use};

use crate::comm::mailbox;
use crate::devices::{EI_BIT, INPUT_EDGES, INT_ANY_BIT, INT_BITS, MAX_INT};

static DOC: Doc = Doc {
    family: "interrupts",
    cite: "002 ch. 9 L10064-10310, §6.1 L3699-3733",
    notes: "events taken at each scan start before MAIN: X0-X7 edges (SM40-SM47; also of a pulse that ended between two scans), timed 0-2 (SD66-SD68 ms, SM66-SM68), global EI/DI; 8-deep FIFO, overflow error 67; CIRET returns early; serial 34-37 (PORT1, SM52-SM55) from the communication phase; PORT0's 30-33 never occur",
};

pub static DEFS: &[Def] = &[
    // 002 §6.1 L3699 EI
    Def::lower("EI", Class::Output, &DOC, ei_di).steps(Steps::Fixed(1)),
    // 002 §6.1 L3710 DI
    Def::lower("DI", Class::Output, &DOC, ei_di).steps(Steps::Fixed(1)),
    // 002 §6.1 L3725 CIRET (compiled by the driver)
    Def::lower("CIRET", Class::Output, &DOC, ei_di).steps(Steps::Fixed(1)),
];

/// 67: interrupt request queue overflow.
const E_QUEUE: Fault = Fault::Family(ErrorCode(67));
/// The FIFO's depth (L10113).
const DEPTH: usize = 8;

#[derive(Debug)]
struct SetEi {
    bit: u32,
    on: bool,
}

impl Instr for SetEi {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.mem.bits[self.bit as usize] = self.on;
        Ok(())
    }
}

// 002 §6.1 L3699-3723 EI / DI: with power flow, enable / disable interrupts.
// CIRET here is outside an interrupt routine (the driver compiles it inside).
fn ei_di(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let on = match u.m {
        "EI" => Some(true),
        "DI" => Some(false),
        "CIRET" => None,
        _ => return c.unmatched(u),
    };
    if !c.count(i, u.m, &[0]) || !c.output(i, u.m) {
        return;
    }
    let Some(on) = on else {
        return c.err(
            &i.mnemonic,
            "CIRET outside an interrupt routine (APLC programming manual §6.1.9)",
        );
    };
    let x = c.ext.len() as u32;
    let bit = c.map.base(DeviceKind::V) + EI_BIT;
    c.ext.push(Box::new(SetEi { bit, on }));
    c.emit(Op::Ext(x));
}

/// One timed interrupt's schedule (SM66-SM68, SD66-SD68).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Timed {
    /// Timing since the scan that found it enabled.
    running: bool,
    /// The next due time, ms of PLC time.
    due_ms: u64,
}

/// The dispatcher's state: X0-X7 at the previous scan, the timed
/// interrupts, and the routines waiting, oldest first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct DispatchState {
    prev_x: u32,
    timed: [Timed; 3],
    len: usize,
    queue: [u32; DEPTH],
}

/// Its state words, in this order: prev_x, 3 × (running, due low, due
/// high), the queue length, the queue.
impl LocalState for DispatchState {
    const WORDS: u32 = 1 + 3 * 3 + 1 + DEPTH as u32;

    fn load(words: &[u32]) -> Self {
        let mut w = words.iter().copied();
        let mut next = move || w.next().unwrap_or(0);
        let prev_x = next();
        let timed = [(); 3].map(|_| Timed {
            running: next() != 0,
            due_ms: next() as u64 | (next() as u64) << 32,
        });
        let len = (next() as usize).min(DEPTH);
        let queue = [(); DEPTH].map(|_| next());
        DispatchState {
            prev_x,
            timed,
            len,
            queue,
        }
    }

    fn store(self, words: &mut [u32]) {
        let mut w = words.iter_mut();
        let mut put = |v: u32| {
            if let Some(x) = w.next() {
                *x = v;
            }
        };
        put(self.prev_x);
        for t in self.timed {
            put(t.running as u32);
            put(t.due_ms as u32);
            put((t.due_ms >> 32) as u32);
        }
        put(self.len as u32);
        for r in self.queue {
            put(r);
        }
    }
}

/// What the dispatcher reads and writes.
#[derive(Debug)]
struct Dispatch {
    /// (event, routine index) of the program's routines.
    routines: Vec<(u8, u32)>,
    x: u32,
    sm: u32,
    sd: u32,
    v: u32,
    /// PORT1's mailbox word of serial events.
    events: u32,
    /// The input edges the scan start recorded (`devices::INPUT_EDGES`).
    edges: u32,
    state: LocalSlot<DispatchState>,
}

#[derive(Debug)]
struct Scan(Dispatch);

#[derive(Debug)]
struct Pop(Dispatch);

impl Dispatch {
    fn push(&self, st: &mut DispatchState, event: u8, lost: &mut bool) {
        let Some(&(_, r)) = self.routines.iter().find(|(e, _)| *e == event) else {
            return; // no routine: acknowledged as a no-op (L10125)
        };
        if st.len >= DEPTH {
            *lost = true;
        } else {
            st.queue[st.len] = r;
            st.len += 1;
        }
    }
}

impl Instr for Scan {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.off(cx)
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let d = &self.0;
        let mut st = cx.local(&d.state);
        let ei = cx.mem.bits[(d.v + EI_BIT) as usize];
        let mut lost = false;
        // X0-X7 edges since the previous scan: X's change, and the changes
        // of the input image the scan start recorded (a pulse that ended
        // before the scan). A program binds one edge of an input (§9.4), so
        // the order of its rising and falling events never matters.
        let prev = st.prev_x;
        let mut now_x = 0u32;
        for k in 0..8 {
            now_x |= (cx.mem.bits[(d.x + k) as usize] as u32) << k;
        }
        st.prev_x = now_x;
        let edges = std::mem::take(&mut cx.mem.words[d.edges as usize]) as u32;
        let rises = (now_x & !prev) | (edges & 0xFF);
        let falls = (!now_x & prev) | (edges >> 8);
        for k in 0..8u32 {
            if !ei || !cx.mem.bits[(d.sm + 40 + k) as usize] {
                continue;
            }
            if rises >> k & 1 != 0 {
                d.push(&mut st, k as u8, &mut lost);
            }
            if falls >> k & 1 != 0 {
                d.push(&mut st, 10 + k as u8, &mut lost);
            }
        }
        // Timed interrupts 0-2: SM66-SM68, SD66-SD68.
        let now_ms = cx.now_us / 1000;
        for t in 0..3u32 {
            let on = cx.mem.bits[(d.sm + 66 + t) as usize];
            let period = cx.mem.words[(d.sd + 66 + t) as usize] as i16;
            let mut timed = st.timed[t as usize];
            if !on || period < 1 {
                st.timed[t as usize].running = false;
                continue;
            }
            if !timed.running {
                timed.running = true;
                timed.due_ms = now_ms + period as u64;
            }
            while now_ms >= timed.due_ms {
                if ei {
                    d.push(&mut st, 26 + t as u8, &mut lost);
                }
                timed.due_ms += period as u64;
            }
            st.timed[t as usize] = timed;
        }
        // Serial events of PORT1 recorded by the communication phase.
        let at = d.events as usize;
        let serial = std::mem::take(&mut cx.mem.words[at]);
        for k in 0..4u32 {
            if serial >> k & 1 != 0 && ei && cx.mem.bits[(d.sm + 52 + k) as usize] {
                d.push(&mut st, 34 + k as u8, &mut lost);
            }
        }
        cx.set_local(&d.state, st);
        if lost {
            Err(E_QUEUE)
        } else {
            Ok(())
        }
    }
}

impl Instr for Pop {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.off(cx)
    }
    /// Takes the head of the queue: its routine's bit ON, the others OFF, and
    /// the "any" bit when one was taken.
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let d = &self.0;
        let mut st = cx.local(&d.state);
        let bits = (d.v + INT_BITS) as usize;
        cx.mem.bits[bits..bits + MAX_INT as usize].fill(false);
        let any = st.len > 0;
        if any {
            let r = st.queue[0] as usize;
            st.queue.copy_within(1..st.len, 0);
            st.len -= 1;
            cx.set_local(&d.state, st);
            if let Some(b) = cx.mem.bits.get_mut(bits + r) {
                *b = true;
            }
        }
        cx.mem.bits[(d.v + INT_ANY_BIT) as usize] = any;
        Ok(())
    }
}

/// Emits the dispatch section for `routines` (event of each, in routine
/// order); returns the op indices of the `Call`s, routine by routine.
pub fn dispatch(c: &mut Compiler<'_>, events: &[u8]) -> Vec<usize> {
    let map: &DeviceMap = c.map;
    let d = Dispatch {
        routines: events
            .iter()
            .enumerate()
            .map(|(r, e)| (*e, r as u32))
            .collect(),
        x: map.base(DeviceKind::X),
        sm: map.base(DeviceKind::SM),
        sd: map.base(DeviceKind::SD),
        v: map.base(DeviceKind::V),
        events: map.base(DeviceKind::SW) + mailbox::base(1) + mailbox::EVENTS,
        edges: map.base(DeviceKind::SW) + INPUT_EDGES,
        state: LocalSlot::new(c.state_words),
    };
    let pop = Dispatch {
        routines: d.routines.clone(),
        state: LocalSlot::new(c.state_words),
        ..d
    };
    c.state_words += DispatchState::WORDS;
    let v = d.v;
    let x = c.ext.len() as u32;
    c.ext.push(Box::new(Scan(d)));
    c.emit(Op::ExtAlways(x));
    let top = c.ops.len() as u32;
    let x = c.ext.len() as u32;
    c.ext.push(Box::new(Pop(pop)));
    c.emit(Op::ExtAlways(x));
    let mut calls = Vec::new();
    for r in 0..events.len() as u32 {
        c.emit(Op::Ld(v + INT_BITS + r));
        calls.push(c.emit(Op::Call(0)));
    }
    c.emit(Op::Ld(v + INT_ANY_BIT));
    c.emit(Op::Cj {
        target: top,
        always: false,
    });
    calls
}
