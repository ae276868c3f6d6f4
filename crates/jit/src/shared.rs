//! The timing path of timers as one native function per program, which an
//! `OUT T`/`OUT ST` calls with a descriptor of its devices while its
//! condition is ON and it is not up (`codegen` inlines the other paths).
//!
//! Inline, a timer was ~40 IR instructions in ten blocks, and Cranelift
//! spends about a microsecond per IR instruction: a program of timers and
//! counters compiled at ~13 µs per instruction. The function does what
//! `sequence::timer` does (the interpreter's, which stays the reference: the
//! differential test runs both).

use std::mem::offset_of;

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{types, AbiParam, InstBuilder, MemFlagsData, Signature, Type, Value};
use cranelift_frontend::FunctionBuilder;

use crate::native::{CX_BITS, CX_REM, CX_SCAN_US, CX_TIMER_BASE_US, CX_WORDS};
use crate::plan::{TimerStep, WordSrc};

/// The set value is the word at `set` (else the constant `set`).
const SET_WORD: u32 = 1;
/// A timer of the high-speed time base.
const HIGH_SPEED: u32 = 2;
/// A retentive timer (`OUT ST`): it keeps its value while OFF.
const RETENTIVE: u32 = 4;

/// What a timer's call site passes: flat indices of its devices.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimerDesc {
    coil: u32,
    contact: u32,
    value: u32,
    /// Its sub-unit remainder.
    slot: u32,
    /// The constant (not negative: the plan checked) or the word index.
    set: u32,
    flags: u32,
}

impl TimerDesc {
    pub fn of(t: &TimerStep) -> TimerDesc {
        let (set, word) = set_value(t.set);
        TimerDesc {
            coil: t.coil,
            contact: t.contact,
            value: t.value,
            slot: t.slot,
            set,
            flags: word
                | if t.high_speed { HIGH_SPEED } else { 0 }
                | if t.retentive { RETENTIVE } else { 0 },
        }
    }
}

/// A set value as (constant or word index, [`SET_WORD`] or 0).
fn set_value(s: WordSrc) -> (u32, u32) {
    match s {
        WordSrc::Const(k) => (u32::from(k as u16), 0),
        WordSrc::Word(i) => (i, SET_WORD),
    }
}

/// `(cx, condition 0/1, descriptor) -> 1` when the interpreter must run the
/// op instead (a negative set value read from a word: it faults), else 0.
pub fn signature(call_conv: cranelift_codegen::isa::CallConv, ptr: Type) -> Signature {
    let mut sig = Signature::new(call_conv);
    sig.params.push(AbiParam::new(ptr));
    sig.params.push(AbiParam::new(types::I32));
    sig.params.push(AbiParam::new(ptr));
    sig.returns.push(AbiParam::new(types::I32));
    sig
}

/// Device memory and descriptors are reached only through indices the
/// plan checked.
fn flags() -> MemFlagsData {
    MemFlagsData::trusted()
}

/// The function's body and the addresses its code uses.
struct Body<'a, 'b> {
    b: &'a mut FunctionBuilder<'b>,
    ptr: Type,
    cx: Value,
    d: Value,
    bits: Value,
    words: Value,
}

impl Body<'_, '_> {
    /// Starts the function: (cx, cond, d), the memory's addresses.
    fn start<'a, 'b>(b: &'a mut FunctionBuilder<'b>, ptr: Type) -> (Body<'a, 'b>, Value) {
        let entry = b.create_block();
        b.append_block_params_for_function_params(entry);
        b.switch_to_block(entry);
        b.seal_block(entry);
        let p = b.block_params(entry).to_vec();
        let bits = b.ins().load(ptr, flags(), p[0], CX_BITS);
        let words = b.ins().load(ptr, flags(), p[0], CX_WORDS);
        let body = Body {
            b,
            ptr,
            cx: p[0],
            d: p[2],
            bits,
            words,
        };
        (body, p[1])
    }

    /// A `u32` field of the descriptor.
    fn field(&mut self, offset: usize) -> Value {
        self.b
            .ins()
            .load(types::I32, flags(), self.d, offset as i32)
    }

    /// `base + field * size`: the address of the element a field indexes.
    fn element(&mut self, base: Value, offset: usize, size: i64) -> Value {
        let i = self.b.ins().uload32(flags(), self.d, offset as i32);
        let i = if self.ptr == types::I64 {
            i
        } else {
            self.b.ins().ireduce(self.ptr, i)
        };
        let scaled = self.b.ins().imul_imm_s(i, size);
        self.b.ins().iadd(base, scaled)
    }

    fn ret(&mut self, v: i64) {
        let v = self.b.ins().iconst(types::I32, v);
        self.b.ins().return_(&[v]);
    }

    /// The set value (a word's, signed), or return 1 when a word's is
    /// negative.
    fn set_value(&mut self, set_off: usize, flags_v: Value) -> Value {
        let (word, konst, go) = (
            self.b.create_block(),
            self.b.create_block(),
            self.b.create_block(),
        );
        let set = self.b.append_block_param(go, types::I32);
        let is_word = self.b.ins().band_imm_u(flags_v, i64::from(SET_WORD));
        self.b.ins().brif(is_word, word, &[], konst, &[]);
        self.b.seal_block(word);
        self.b.seal_block(konst);

        self.b.switch_to_block(word);
        let a = self.element(self.words, set_off, 2);
        let v = self.b.ins().sload16(types::I32, flags(), a, 0);
        let (slow, ok) = (self.b.create_block(), self.b.create_block());
        let neg = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, v, 0);
        self.b.ins().brif(neg, slow, &[], ok, &[]);
        self.b.seal_block(slow);
        self.b.seal_block(ok);
        self.b.switch_to_block(slow);
        self.ret(1);
        self.b.switch_to_block(ok);
        self.b.ins().jump(go, &[v.into()]);

        self.b.switch_to_block(konst);
        let k = self.field(set_off);
        self.b.ins().jump(go, &[k.into()]);
        self.b.seal_block(go);
        self.b.switch_to_block(go);
        set
    }
}

/// The timer function: `sequence::timer` on the descriptor's devices. The
/// coil follows the condition; while ON and not yet up, the scan time
/// accumulates in the remainder and whole time-base units count up to the
/// set value; OFF resets a timer that does not retain.
pub fn timer(b: &mut FunctionBuilder, ptr: Type) {
    let (mut f, cond) = Body::start(b, ptr);
    let coil_a = f.element(f.bits, offset_of!(TimerDesc, coil), 1);
    let fl = f.field(offset_of!(TimerDesc, flags));
    let zero = f.b.ins().iconst(types::I32, 0);
    let one = f.b.ins().iconst(types::I32, 1);
    let (on, off) = (f.b.create_block(), f.b.create_block());
    f.b.ins().brif(cond, on, &[], off, &[]);
    f.b.seal_block(on);
    f.b.seal_block(off);

    // OFF: the coil OFF; a timer that does not retain is reset.
    f.b.switch_to_block(off);
    f.b.ins().istore8(flags(), zero, coil_a, 0);
    let (reset, done) = (f.b.create_block(), f.b.create_block());
    let keeps = f.b.ins().band_imm_u(fl, i64::from(RETENTIVE));
    f.b.ins().brif(keeps, done, &[], reset, &[]);
    f.b.seal_block(reset);
    f.b.seal_block(done);
    f.b.switch_to_block(reset);
    let va = f.element(f.words, offset_of!(TimerDesc, value), 2);
    f.b.ins().istore16(flags(), zero, va, 0);
    let ca = f.element(f.bits, offset_of!(TimerDesc, contact), 1);
    f.b.ins().istore8(flags(), zero, ca, 0);
    let rem = f.b.ins().load(ptr, flags(), f.cx, CX_REM);
    let ra = f.element(rem, offset_of!(TimerDesc, slot), 4);
    f.b.ins().store(flags(), zero, ra, 0);
    f.ret(0);
    f.b.switch_to_block(done);
    f.ret(0);

    // ON.
    f.b.switch_to_block(on);
    let set = f.set_value(offset_of!(TimerDesc, set), fl);
    let was_on = f.b.ins().uload8(types::I32, flags(), coil_a, 0);
    f.b.ins().istore8(flags(), one, coil_a, 0);
    let ca = f.element(f.bits, offset_of!(TimerDesc, contact), 1);
    let up = f.b.ins().uload8(types::I32, flags(), ca, 0);
    let (counting, is_up) = (f.b.create_block(), f.b.create_block());
    f.b.ins().brif(up, is_up, &[], counting, &[]);
    f.b.seal_block(counting);
    f.b.seal_block(is_up);
    f.b.switch_to_block(is_up);
    f.ret(0);

    f.b.switch_to_block(counting);
    let va = f.element(f.words, offset_of!(TimerDesc, value), 2);
    let cur = f.b.ins().sload16(types::I32, flags(), va, 0);
    let (accumulate, check) = (f.b.create_block(), f.b.create_block());
    let at_check = f.b.append_block_param(check, types::I32);
    f.b.ins()
        .brif(was_on, accumulate, &[], check, &[cur.into()]);
    f.b.seal_block(accumulate);

    f.b.switch_to_block(accumulate);
    let rem = f.b.ins().load(ptr, flags(), f.cx, CX_REM);
    let ra = f.element(rem, offset_of!(TimerDesc, slot), 4);
    // In 64 bits, as the interpreter adds them.
    let r = f.b.ins().uload32(flags(), ra, 0);
    let scan = f.b.ins().uload32(flags(), f.cx, CX_SCAN_US);
    // The time base of the timer's speed: `timer_base_us[high]`.
    let high = f.b.ins().band_imm_u(fl, i64::from(HIGH_SPEED));
    let high = f.b.ins().uextend(ptr, high);
    let high = f.b.ins().imul_imm_s(high, 2); // HIGH_SPEED (2) → 4 bytes
    let base_a = f.b.ins().iadd(f.cx, high);
    let base = f.b.ins().uload32(flags(), base_a, CX_TIMER_BASE_US);
    let total = f.b.ins().iadd(r, scan);
    let (under, over) = (f.b.create_block(), f.b.create_block());
    let short = f.b.ins().icmp(IntCC::UnsignedLessThan, total, base);
    f.b.ins().brif(short, under, &[], over, &[]);
    f.b.seal_block(under);
    f.b.seal_block(over);
    // Less than one unit so far: no division.
    f.b.switch_to_block(under);
    f.b.ins().istore32(flags(), total, ra, 0);
    f.b.ins().jump(check, &[cur.into()]);
    f.b.switch_to_block(over);
    let units = f.b.ins().udiv(total, base);
    let left = f.b.ins().urem(total, base);
    f.b.ins().istore32(flags(), left, ra, 0);
    let cur64 = f.b.ins().sextend(types::I64, cur);
    let sum = f.b.ins().iadd(cur64, units);
    let max = f.b.ins().iconst(types::I64, 32767);
    let sum = f.b.ins().smin(sum, max);
    let sum = f.b.ins().ireduce(types::I32, sum);
    f.b.ins().jump(check, &[sum.into()]);
    f.b.seal_block(check);

    // Up at the set value: the contact ON, the value the set value.
    f.b.switch_to_block(check);
    let (reach, store) = (f.b.create_block(), f.b.create_block());
    let stored = f.b.append_block_param(store, types::I32);
    let reached =
        f.b.ins()
            .icmp(IntCC::SignedGreaterThanOrEqual, at_check, set);
    f.b.ins()
        .brif(reached, reach, &[], store, &[at_check.into()]);
    f.b.seal_block(reach);
    f.b.switch_to_block(reach);
    f.b.ins().istore8(flags(), one, ca, 0);
    f.b.ins().jump(store, &[set.into()]);
    f.b.seal_block(store);
    f.b.switch_to_block(store);
    f.b.ins().istore16(flags(), stored, va, 0);
    f.ret(0);
    f.b.seal_all_blocks();
}
