//! A chunk's plan → one Cranelift function.
//!
//! The function is `fn(cx: *mut Ctx, pc: u32) -> u32` (`native::Ctx`: the
//! rung registers, then the addresses of device bits and words). It loads the
//! registers into SSA variables, dispatches on `pc` to the entry there, runs
//! straight on, and stores the registers back where it returns the op where
//! the interpreter goes on (the plan's exit, or an op where the chunk has no
//! entry). A run of the plan has the interpreter run a stretch of ops
//! (`native::exec_op`, through `Host::exec`) with the registers stored before
//! and reloaded after; when it returns another op than the stretch's end,
//! the function dispatches on that op (a jump within the chunk stays in
//! native code).
//! Every device index was checked against the program's memory size by the
//! plan.

use std::collections::HashMap;

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::{
    types, AbiParam, Block, FuncRef, InstBuilder, MemFlagsData, Signature, Type, Value,
};
use cranelift_frontend::{FunctionBuilder, Switch, Variable};
use softplc_engine::tier::LEAVE;
use softplc_ir::ops::{CmpOp, Join};

use crate::native::{CX_ACC, CX_BITS, CX_BLOCKS, CX_EDGES, CX_MPS, CX_REM, CX_WORDS, OFF_MARK};
use crate::plan::{Action, BitSrc, Chunk, CounterStep, Piece, Step, Store, TimerStep, WordSrc};
use softplc_ir::word_op::Binary;

/// The signature of every chunk function on the host's calling convention:
/// (cx, pc) → next op.
pub fn signature(call_conv: cranelift_codegen::isa::CallConv, ptr: Type) -> Signature {
    let mut sig = Signature::new(call_conv);
    sig.params.push(AbiParam::new(ptr)); // cx
    sig.params.push(AbiParam::new(types::I32)); // pc
    sig.returns.push(AbiParam::new(types::I32));
    sig
}

/// What a chunk's code calls besides the interpreter: the program's timer
/// function (`shared`), and the address of each timer's descriptor by op
/// index.
#[derive(Clone, Copy)]
pub struct Calls<'a> {
    pub timer: FuncRef,
    pub descs: &'a HashMap<u32, i64>,
}

/// The rung registers and device addresses as SSA variables.
struct Gen<'a, 'b> {
    b: &'a mut FunctionBuilder<'b>,
    cx: Value,
    ptr: Type,
    /// `native::exec_op`, imported into the function.
    exec_op: FuncRef,
    /// The program's shared functions and descriptors.
    calls: Calls<'a>,
    /// Where a stretch of the interpreter came back with another op than
    /// its end (its parameter, as `native::exec_op` returns it).
    came_back: Block,
    bits: Variable,
    words: Variable,
    /// The timers' sub-unit remainders (`u32`s).
    rem: Variable,
    /// The program's edge memories (`bool`s).
    edges: Variable,
    acc: Variable,
    blocks: Variable,
    mps: Variable,
    /// Bits that may be read four bytes at a time (`bit_len - 3`).
    wide_bits: u32,
    /// Bits whose value native code holds, loaded or stored since the last
    /// call or entry, with the step that did so (oldest first).
    known: Vec<(u32, Value, u32)>,
    /// Words likewise: a word read or written in the last few steps is
    /// taken from its register (a chain of dependent MOVs does not wait
    /// for each store to reach the next load).
    known_words: Vec<KnownWord>,
    /// Bits stored in the last few steps (with the step): a bit next to one
    /// is read alone, not four bytes at a time, since a wide load over a
    /// byte still in the store buffer waits for it to reach the cache.
    stored: Vec<(u32, u32)>,
    /// Whether loads and stores add to `known`/`known_words`: not in the
    /// branches of a timer, counter or MC, whose values do not reach the
    /// code after them.
    learn: bool,
    /// Steps emitted so far.
    steps: u32,
}

/// A word native code holds in a register.
#[derive(Clone, Copy)]
struct KnownWord {
    index: u32,
    value: Value,
    form: Form,
    step: u32,
}

/// How a word sits in the 32 bits of its register.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Form {
    /// Zero-extended.
    Zext,
    /// Sign-extended.
    Sext,
    /// The low 16 bits; the others are whatever the operation left.
    Raw,
}

/// How many steps a known bit or word stays in a register: a rung or two,
/// so that the next rung's contact on the coil just set (or on the contact
/// just read) needs no load, without values kept alive across the chunk
/// (the register allocator would spill them, which costs more than a load).
const KNOWN_STEPS: u32 = 12;

/// How many steps a stored bit's byte counts as still in the store buffer
/// (`Gen::stored`).
const STORE_STEPS: u32 = 16;

/// Device memory is only reached through indices the plan checked, and
/// native code runs with no other access to it.
fn flags() -> MemFlagsData {
    MemFlagsData::trusted()
}

/// The body of the trampoline every chunk calls for an op in the
/// interpreter: it calls `exec_op` (the host's function, far from JIT code)
/// from this one place, so each op's call is a direct call near it and the
/// processor predicts one indirect call instead of one per op.
pub fn trampoline(b: &mut FunctionBuilder, exec_op: FuncRef) {
    let start = b.create_block();
    b.append_block_params_for_function_params(start);
    b.switch_to_block(start);
    let p = b.block_params(start).to_vec();
    let call = b.ins().call(exec_op, &p);
    let next = b.inst_results(call)[0];
    b.ins().return_(&[next]);
    b.seal_all_blocks();
}

/// Emits the body of `chunk`'s function into `b` (an empty function of
/// [`signature`]); `exec_op` calls the interpreter for one op (the
/// trampoline).
pub fn build(
    b: &mut FunctionBuilder,
    chunk: &Chunk,
    ptr: Type,
    exec_op: FuncRef,
    calls: Calls,
    bit_len: u32,
) {
    let start = b.create_block();
    b.append_block_params_for_function_params(start);
    b.switch_to_block(start);
    b.seal_block(start);
    let p = b.block_params(start).to_vec();
    let (cx, pc) = (p[0], p[1]);
    let dispatch = b.create_block();
    let target = b.append_block_param(dispatch, types::I32);
    let came_back = b.create_block();
    let back_at = b.append_block_param(came_back, types::I32);
    let mut g = Gen {
        cx,
        ptr,
        exec_op,
        calls,
        came_back,
        bits: b.declare_var(ptr),
        words: b.declare_var(ptr),
        rem: b.declare_var(ptr),
        edges: b.declare_var(ptr),
        acc: b.declare_var(types::I32),
        blocks: b.declare_var(types::I32),
        mps: b.declare_var(types::I32),
        wide_bits: bit_len.saturating_sub(3),
        known: Vec::new(),
        known_words: Vec::new(),
        stored: Vec::new(),
        learn: true,
        steps: 0,
        b,
    };
    g.load_regs();
    g.b.ins().jump(dispatch, &[pc.into()]);

    // One block per entry, reached through a switch on the op index (a
    // chunk has few entries: its first native op and jump targets).
    g.b.switch_to_block(dispatch);
    let mut entry_blocks = HashMap::new();
    let mut sw = Switch::new();
    for piece in &chunk.pieces {
        if let Piece::Entry(at) = piece {
            let blk = g.b.create_block();
            entry_blocks.insert(*at, blk);
            sw.set_entry(u128::from(*at), blk);
        }
    }
    let elsewhere = g.b.create_block();
    sw.emit(g.b, target, elsewhere);
    g.b.switch_to_block(elsewhere);
    g.b.seal_block(elsewhere);
    g.leave(target);

    // Whether the current block falls through into the next piece (every
    // chunk starts with an entry and ends with its exit).
    let mut open = false;
    for piece in &chunk.pieces {
        match piece {
            Piece::Entry(at) => {
                let blk = entry_blocks[at];
                if open {
                    g.b.ins().jump(blk, &[]);
                }
                g.b.switch_to_block(blk);
                g.forget_all();
                open = true;
            }
            Piece::Step(s) => g.step(s),
            Piece::Run {
                from,
                to,
                guarded: false,
            } => g.run(*from, *to),
            Piece::Run {
                from,
                to,
                guarded: true,
            } => g.run_while_on(*from, *to),
            Piece::Exit(at) => {
                let at = g.b.ins().iconst(types::I32, i64::from(*at));
                g.leave(at);
                open = false;
            }
        }
    }
    // Back from a stretch elsewhere than its end: to the interpreter when
    // it left conditions OFF (the registers in `cx` are its own), else on
    // at that op (a jump within the chunk stays in native code).
    g.b.switch_to_block(came_back);
    let (off, on) = (g.b.create_block(), g.b.create_block());
    let marked = g.b.ins().icmp_imm_u(
        IntCC::UnsignedGreaterThanOrEqual,
        back_at,
        i64::from(OFF_MARK),
    );
    let not_left =
        g.b.ins()
            .icmp_imm_u(IntCC::NotEqual, back_at, i64::from(LEAVE));
    let return_now = g.b.ins().band(marked, not_left);
    g.b.ins().brif(return_now, off, &[], on, &[]);
    g.b.seal_block(off);
    g.b.seal_block(on);
    g.b.switch_to_block(off);
    let at = g.b.ins().band_imm_u(back_at, i64::from(!OFF_MARK));
    g.b.ins().return_(&[at]);
    g.b.switch_to_block(on);
    g.load_regs();
    g.b.ins().jump(dispatch, &[back_at.into()]);

    // The dispatch, entry and came-back blocks, whose predecessors are known only now
    // (every other block is sealed as soon as they are: a block left
    // unsealed takes a parameter for every variable it uses, which made
    // compiling timers and counters 20 times slower).
    g.b.seal_all_blocks();
}

impl Gen<'_, '_> {
    /// The registers from `cx`: at the start and after every call.
    fn load_regs(&mut self) {
        for (var, off) in [
            (self.acc, CX_ACC),
            (self.blocks, CX_BLOCKS),
            (self.mps, CX_MPS),
        ] {
            let v = self.b.ins().load(types::I32, flags(), self.cx, off);
            self.b.def_var(var, v);
        }
        for (var, off) in [
            (self.bits, CX_BITS),
            (self.words, CX_WORDS),
            (self.rem, CX_REM),
            (self.edges, CX_EDGES),
        ] {
            let v = self.b.ins().load(self.ptr, flags(), self.cx, off);
            self.b.def_var(var, v);
        }
    }

    /// The registers native code changes back into `cx`.
    fn store_regs(&mut self) {
        let acc = self.acc_bit();
        self.b.ins().store(flags(), acc, self.cx, CX_ACC);
        for (var, off) in [(self.blocks, CX_BLOCKS), (self.mps, CX_MPS)] {
            let v = self.b.use_var(var);
            self.b.ins().store(flags(), v, self.cx, off);
        }
    }

    /// `acc` as a clean 0/1 (see [`Gen::bit`] for what its other bits hold).
    fn acc_bit(&mut self) -> Value {
        let a = self.b.use_var(self.acc);
        self.b.ins().band_imm_s(a, 1)
    }

    /// Returns op `at` to the interpreter.
    fn leave(&mut self, at: Value) {
        self.store_regs();
        self.b.ins().return_(&[at]);
    }

    /// The interpreter runs ops `from..to`; on natively when it returns
    /// `to`, else on at the chunk's `came_back`: back to the interpreter when
    /// the stretch turned conditions OFF (an MC; native code runs only while
    /// they are not, `NativeProgram::run`), else a dispatch on the op.
    fn run(&mut self, from: u32, to: u32) {
        self.store_regs();
        let from = self.b.ins().iconst(types::I32, i64::from(from));
        let to_v = self.b.ins().iconst(types::I32, i64::from(to));
        let call = self.b.ins().call(self.exec_op, &[self.cx, from, to_v]);
        let next = self.b.inst_results(call)[0];
        let on = self.b.create_block();
        let straight = self.b.ins().icmp_imm_u(IntCC::Equal, next, i64::from(to));
        self.b
            .ins()
            .brif(straight, on, &[], self.came_back, &[next.into()]);
        self.b.switch_to_block(on);
        self.b.seal_block(on);
        self.load_regs();
        self.forget_all();
    }

    /// [`Gen::run`] only while the condition is ON: for a stretch of
    /// instructions that do nothing while it is OFF.
    fn run_while_on(&mut self, from: u32, to: u32) {
        let c = self.acc_bit();
        let (on, after) = (self.b.create_block(), self.b.create_block());
        self.b.ins().brif(c, on, &[], after, &[]);
        self.b.seal_block(on);
        self.b.switch_to_block(on);
        self.run(from, to);
        self.b.ins().jump(after, &[]);
        self.b.switch_to_block(after);
        self.b.seal_block(after);
        self.forget_all();
    }

    /// `now` (0/1) into edge memory `slot`, and its rising (`now` and not
    /// before) or falling edge against the value it held.
    fn edge(&mut self, slot: u32, now: Value, rising: bool) -> Value {
        let edges = self.b.use_var(self.edges);
        let (base, off) = self.addr(edges, slot, 1);
        let before = self.b.ins().uload8(types::I32, flags(), base, off);
        self.b.ins().istore8(flags(), now, base, off);
        let (on, was) = if rising { (now, before) } else { (before, now) };
        let not_was = self.b.ins().bxor_imm_s(was, 1);
        self.b.ins().band(on, not_was)
    }

    /// The address of `base[index]` with elements of `size` bytes.
    fn addr(&mut self, base: Value, index: u32, size: u32) -> (Value, i32) {
        let off = u64::from(index) * u64::from(size);
        match i32::try_from(off) {
            Ok(off) => (base, off),
            Err(_) => {
                let a = self.b.ins().iadd_imm_s(base, off as i64);
                (a, 0)
            }
        }
    }

    /// Bit `i` in the low byte of an i32: 0 or 1 there, while bits 8-31
    /// hold whatever follows in memory. A bit is read four bytes at a time
    /// (within the memory: below `wide_bits`) so that x86 takes it straight
    /// into an and/or from memory (Cranelift merges only loads of 32 bits or
    /// more; the code is a third shorter, and long programs run from the
    /// level-2 cache, where code size is the speed). and/or/xor-with-1 keep
    /// the low byte exact, stores write only it, and the few places that
    /// need the whole value take bit 0 ([`Gen::acc_bit`]).
    fn bit(&mut self, i: u32) -> Value {
        if let Some(&(_, v, _)) = self.known.iter().find(|k| k.0 == i) {
            return v;
        }
        let v = self.load_bit(i);
        self.know(i, v);
        v
    }

    /// Bit `i` from memory (as [`Gen::bit`] describes it).
    fn load_bit(&mut self, i: u32) -> Value {
        let bits = self.b.use_var(self.bits);
        let (base, off) = self.addr(bits, i, 1);
        let oldest = self.steps.saturating_sub(STORE_STEPS);
        let near_store = self
            .stored
            .iter()
            .any(|&(b, step)| step >= oldest && (i..i + 4).contains(&b));
        if i < self.wide_bits && !near_store {
            self.b.ins().load(types::I32, flags(), base, off)
        } else {
            self.b.ins().uload8(types::I32, flags(), base, off)
        }
    }

    /// Stores the low byte of `v` (0 or 1) as bit `i`.
    fn store_bit(&mut self, i: u32, v: Value) {
        let bits = self.b.use_var(self.bits);
        let (base, off) = self.addr(bits, i, 1);
        self.b.ins().istore8(flags(), v, base, off);
        self.note_store(i);
        self.know(i, v);
    }

    /// Records that bit `i` was stored now (see `stored`).
    fn note_store(&mut self, i: u32) {
        let oldest = self.steps.saturating_sub(STORE_STEPS);
        self.stored.retain(|&(b, step)| b != i && step >= oldest);
        self.stored.push((i, self.steps));
    }

    /// Records that bit `i` holds `v` now.
    fn know(&mut self, i: u32, v: Value) {
        let oldest = self.steps.saturating_sub(KNOWN_STEPS);
        self.known.retain(|k| k.0 != i && k.2 >= oldest);
        if self.learn {
            self.known.push((i, v, self.steps));
        }
    }

    /// Records that word `index` holds `value` (in `form`) now.
    fn know_word(&mut self, index: u32, value: Value, form: Form) {
        let oldest = self.steps.saturating_sub(KNOWN_STEPS);
        self.known_words
            .retain(|k| k.index != index && k.step >= oldest);
        if self.learn {
            self.known_words.push(KnownWord {
                index,
                value,
                form,
                step: self.steps,
            });
        }
    }

    fn forget_all(&mut self) {
        self.known.clear();
        self.known_words.clear();
    }

    fn forget_bit(&mut self, i: u32) {
        self.known.retain(|k| k.0 != i);
    }

    fn forget_word(&mut self, i: u32) {
        self.known_words.retain(|k| k.index != i);
    }

    /// Word `i` as held, or loaded (zero-extended) and then held.
    fn word_as_held(&mut self, i: u32) -> (Value, Form) {
        if let Some(k) = self.known_words.iter().find(|k| k.index == i) {
            return (k.value, k.form);
        }
        let words = self.b.use_var(self.words);
        let (base, off) = self.addr(words, i, 2);
        let v = self.b.ins().uload16(types::I32, flags(), base, off);
        self.know_word(i, v, Form::Zext);
        (v, Form::Zext)
    }

    /// Word `i` in the low 16 bits (the others undefined).
    fn word_raw(&mut self, i: u32) -> Value {
        self.word_as_held(i).0
    }

    /// Word `i` zero-extended.
    fn word(&mut self, i: u32) -> Value {
        match self.word_as_held(i) {
            (v, Form::Zext) => v,
            (v, _) => self.b.ins().band_imm_s(v, 0xFFFF),
        }
    }

    /// Word `i` sign-extended.
    fn word_signed(&mut self, i: u32) -> Value {
        if let Some(k) = self.known_words.iter().find(|k| k.index == i).copied() {
            if k.form == Form::Sext {
                return k.value;
            }
            let h = self.b.ins().ireduce(types::I16, k.value);
            return self.b.ins().sextend(types::I32, h);
        }
        let words = self.b.use_var(self.words);
        let (base, off) = self.addr(words, i, 2);
        let v = self.b.ins().sload16(types::I32, flags(), base, off);
        self.know_word(i, v, Form::Sext);
        v
    }

    /// Stores the low 16 bits of `v` (in `form`) as word `i`. Not a store
    /// of an immediate, even for a constant: x86's 16-bit immediate store
    /// stalls the legacy decoders (a length-changing prefix), which decode
    /// all of a long program's code (MOV K chains took 0.85 instead of
    /// 0.54 ns).
    fn store_word(&mut self, i: u32, v: Value, form: Form) {
        let words = self.b.use_var(self.words);
        let (base, off) = self.addr(words, i, 2);
        self.b.ins().istore16(flags(), v, base, off);
        self.know_word(i, v, form);
    }

    /// A 32-bit value as words `i` (low) and `i + 1`.
    fn store_dword(&mut self, i: u32, v: Value) {
        self.store_word(i, v, Form::Raw);
        let hi = self.b.ins().ushr_imm_s(v, 16);
        self.store_word(i + 1, hi, Form::Zext);
    }

    /// A word operand: 16-bit sign-extended, or 32-bit low word first.
    fn value(&mut self, s: WordSrc, wide: bool) -> Value {
        match (s, wide) {
            (WordSrc::Const(k), false) => {
                self.b.ins().iconst(types::I32, i64::from(k as u16 as i16))
            }
            (WordSrc::Const(k), true) => self.b.ins().iconst(types::I32, i64::from(k as i32)),
            (WordSrc::Word(i), false) => self.word_signed(i),
            (WordSrc::Word(i), true) => {
                let lo = self.word(i);
                let hi = self.word_raw(i + 1);
                let hi = self.b.ins().ishl_imm_s(hi, 16);
                self.b.ins().bor(lo, hi)
            }
        }
    }

    /// A 16-bit operand in the low 16 bits (the others undefined).
    fn value_raw(&mut self, s: WordSrc) -> Value {
        match s {
            WordSrc::Const(k) => self.b.ins().iconst(types::I32, i64::from(k & 0xFFFF)),
            WordSrc::Word(i) => self.word_raw(i),
        }
    }

    /// The address of timer remainder `slot`.
    fn rem_addr(&mut self, slot: u32) -> (Value, i32) {
        let rem = self.b.use_var(self.rem);
        self.addr(rem, slot, 4)
    }

    fn join(&mut self, join: Join, v: Value) {
        let r = match join {
            Join::Load => v,
            Join::And => {
                let a = self.b.use_var(self.acc);
                self.b.ins().band(a, v)
            }
            Join::Or => {
                let a = self.b.use_var(self.acc);
                self.b.ins().bor(a, v)
            }
        };
        self.b.def_var(self.acc, r);
    }

    /// Pushes `acc` on the bit stack `var`.
    fn push(&mut self, var: Variable) {
        let s = self.b.use_var(var);
        let a = self.acc_bit();
        let s = self.b.ins().ishl_imm_s(s, 1);
        let s = self.b.ins().bor(s, a);
        self.b.def_var(var, s);
    }

    /// The newest bit of stack `var`, popped or not.
    fn top(&mut self, var: Variable, pop: bool) -> Value {
        let s = self.b.use_var(var);
        let top = self.b.ins().band_imm_s(s, 1);
        if pop {
            let rest = self.b.ins().ushr_imm_s(s, 1);
            self.b.def_var(var, rest);
        }
        top
    }

    fn step(&mut self, s: &Step) {
        self.steps += 1;
        match s {
            Step::Contact { join, negate, src } => {
                let v = match *src {
                    BitSrc::Bit(i) => self.bit(i),
                    BitSrc::WordBit(w, bit) => {
                        let v = self.word_raw(w);
                        let v = self.b.ins().ushr_imm_s(v, i64::from(bit));
                        self.b.ins().band_imm_s(v, 1)
                    }
                };
                match (*negate, *join) {
                    // acc & !v: one andn with BMI1 (bits 1-7 stay 0, as
                    // acc's are).
                    (true, Join::And) => {
                        let a = self.b.use_var(self.acc);
                        let n = self.b.ins().bnot(v);
                        let r = self.b.ins().band(a, n);
                        self.b.def_var(self.acc, r);
                    }
                    (true, join) => {
                        let n = self.b.ins().bxor_imm_s(v, 1);
                        self.join(join, n);
                    }
                    (false, join) => self.join(join, v),
                }
            }
            Step::EdgeContact {
                join,
                negate,
                rising,
                src,
                slot,
            } => {
                let v = match *src {
                    BitSrc::Bit(i) => self.bit(i),
                    BitSrc::WordBit(w, bit) => {
                        let v = self.word_raw(w);
                        self.b.ins().ushr_imm_s(v, i64::from(bit))
                    }
                };
                let v = self.b.ins().band_imm_s(v, 1);
                let e = self.edge(*slot, v, *rising);
                let e = if *negate {
                    self.b.ins().bxor_imm_s(e, 1)
                } else {
                    e
                };
                self.join(*join, e);
            }
            Step::EdgeOfResult { rising, slot } => {
                let a = self.acc_bit();
                let e = self.edge(*slot, a, *rising);
                self.b.def_var(self.acc, e);
            }
            Step::PulseCoil { rising, slot, bit } => {
                let a = self.acc_bit();
                let e = self.edge(*slot, a, *rising);
                self.forget_bit(*bit);
                self.store_bit(*bit, e);
            }
            Step::Compare {
                join,
                op,
                wide,
                a,
                b,
            } => {
                let a = self.value(*a, *wide);
                let b = self.value(*b, *wide);
                let cc = match op {
                    CmpOp::Eq => IntCC::Equal,
                    CmpOp::Ne => IntCC::NotEqual,
                    CmpOp::Gt => IntCC::SignedGreaterThan,
                    CmpOp::Le => IntCC::SignedLessThanOrEqual,
                    CmpOp::Lt => IntCC::SignedLessThan,
                    CmpOp::Ge => IntCC::SignedGreaterThanOrEqual,
                };
                let c = self.b.ins().icmp(cc, a, b);
                let c = self.b.ins().uextend(types::I32, c);
                self.join(*join, c);
            }
            Step::Push => self.push(self.blocks),
            Step::Mps => self.push(self.mps),
            Step::Anb | Step::Orb => {
                let top = self.top(self.blocks, true);
                let j = if *s == Step::Anb { Join::And } else { Join::Or };
                self.join(j, top);
            }
            Step::Mrd | Step::Mpp => {
                let top = self.top(self.mps, *s == Step::Mpp);
                self.b.def_var(self.acc, top);
            }
            Step::Inv => {
                let a = self.b.use_var(self.acc);
                let a = self.b.ins().bxor_imm_s(a, 1);
                self.b.def_var(self.acc, a);
            }
            Step::Coil { store, bit } => {
                // The condition is `acc` itself: no master control forces it
                // OFF while native code runs.
                let c = self.b.use_var(self.acc);
                // SET/RST write the value they leave (unchanged when OFF):
                // no branch, same memory as the interpreter's.
                let v = match store {
                    Store::Out => c,
                    Store::Set => {
                        let old = self.bit(*bit);
                        self.b.ins().bor(old, c)
                    }
                    Store::Rst => {
                        let old = self.bit(*bit);
                        let keep = self.b.ins().bxor_imm_s(c, 1);
                        self.b.ins().band(old, keep)
                    }
                };
                self.store_bit(*bit, v);
            }
            Step::Actions(run) => self.actions(run),
            Step::Timer(t) => self.timer(t),
            Step::Counter(c) => self.counter(c),
            Step::Mc { pc, bit } => self.mc(*pc, *bit),
            // No MC forces conditions OFF while native code runs, so MCR
            // clears nothing.
            Step::Mcr => {}
        }
    }

    /// A run of actions under one test of the condition.
    fn actions(&mut self, run: &[Action]) {
        // The condition, as for coils (bit 0: brif tests the whole value).
        let c = self.acc_bit();
        let then = self.b.create_block();
        let after = self.b.create_block();
        self.b.ins().brif(c, then, &[], after, &[]);
        self.b.switch_to_block(then);
        self.b.seal_block(then);
        // What is held before the test holds after it, but for what the
        // actions write; what they learn stays in their block.
        let (bits, words) = (self.known.clone(), self.known_words.clone());
        for a in run {
            self.action(a);
        }
        self.b.ins().jump(after, &[]);
        self.b.switch_to_block(after);
        self.b.seal_block(after);
        self.known = bits;
        self.known_words = words;
        for a in run {
            match *a {
                Action::Move { words, d, .. } => {
                    (0..u32::from(words)).for_each(|k| self.forget_word(d + k))
                }
                Action::Binary { wide, d, .. } => {
                    self.forget_word(d);
                    if wide {
                        self.forget_word(d + 1);
                    }
                }
                Action::Bit { d, .. } => self.forget_word(d),
                Action::ResetTc { value, contact, .. } => {
                    self.forget_word(value);
                    self.forget_bit(contact);
                }
            }
        }
    }

    fn action(&mut self, a: &Action) {
        // Each action is a step of its own for how long values stay held
        // (a run of thousands of MOVs holds the last few).
        self.steps += 1;
        match *a {
            Action::Move { words, s, d } => {
                // DMOV reads both words before writing (DMOV D0 D1 overlaps).
                let mut v = [None; 2];
                for (k, slot) in v.iter_mut().enumerate().take(usize::from(words)) {
                    let k = k as u32;
                    *slot = Some(match s {
                        WordSrc::Word(i) => self.word_as_held(i + k),
                        WordSrc::Const(c) => {
                            let half = (c >> (16 * k)) & 0xFFFF;
                            (self.b.ins().iconst(types::I32, i64::from(half)), Form::Zext)
                        }
                    });
                }
                for (k, val) in v.into_iter().enumerate() {
                    if let Some((val, form)) = val {
                        self.store_word(d + k as u32, val, form);
                    }
                }
            }
            Action::Binary { op, wide, a, b, d } => {
                let (x, y) = if wide {
                    (self.value(a, true), self.value(b, true))
                } else {
                    (self.value_raw(a), self.value_raw(b))
                };
                let r = match op {
                    Binary::Add => self.b.ins().iadd(x, y),
                    Binary::Sub => self.b.ins().isub(x, y),
                    Binary::And => self.b.ins().band(x, y),
                    Binary::Or => self.b.ins().bor(x, y),
                    Binary::Xor => self.b.ins().bxor(x, y),
                };
                if wide {
                    self.store_dword(d, r);
                } else {
                    self.store_word(d, r, Form::Raw);
                }
            }
            Action::Bit { set, d, n } => {
                let v = self.word_raw(d);
                let r = match (n, set) {
                    (WordSrc::Const(n), true) => self.b.ins().bor_imm_s(v, 1 << (n & 15)),
                    (WordSrc::Const(n), false) => self.b.ins().band_imm_s(v, !(1 << (n & 15))),
                    (WordSrc::Word(i), _) => {
                        let n = self.word_raw(i);
                        let n = self.b.ins().band_imm_s(n, 15);
                        let one = self.b.ins().iconst(types::I32, 1);
                        let mask = self.b.ins().ishl(one, n);
                        if set {
                            self.b.ins().bor(v, mask)
                        } else {
                            let keep = self.b.ins().bnot(mask);
                            self.b.ins().band(v, keep)
                        }
                    }
                };
                self.store_word(d, r, Form::Raw);
            }
            Action::ResetTc {
                value,
                contact,
                slot,
            } => {
                let zero = self.b.ins().iconst(types::I32, 0);
                self.store_word(value, zero, Form::Zext);
                let bits = self.b.use_var(self.bits);
                let (base, off) = self.addr(bits, contact, 1);
                self.b.ins().istore8(flags(), zero, base, off);
                self.note_store(contact);
                self.forget_bit(contact);
                if let Some(slot) = slot {
                    let (base, off) = self.rem_addr(slot);
                    self.b.ins().store(flags(), zero, base, off);
                }
            }
        }
    }

    /// `OUT T`/`OUT ST`: the two paths a timer takes on most scans inline
    /// (OFF: the coil OFF and, unless it retains, the timer reset; ON and
    /// up: the coil ON), the rest (ON and timing) a call of the program's
    /// timer function (`shared::timer`), which returns 1 when the
    /// interpreter must run the op (a negative set value in a word).
    fn timer(&mut self, t: &TimerStep) {
        self.forget_bit(t.coil);
        self.forget_bit(t.contact);
        self.forget_word(t.value);
        let learn = std::mem::replace(&mut self.learn, false);
        let (on, off) = self.branch_on_condition();
        let merge = self.b.create_block();

        self.b.switch_to_block(off);
        let zero = self.b.ins().iconst(types::I32, 0);
        self.raw_store_bit(t.coil, zero);
        if !t.retentive {
            self.store_word(t.value, zero, Form::Zext);
            self.raw_store_bit(t.contact, zero);
            let (base, off) = self.rem_addr(t.slot);
            self.b.ins().store(flags(), zero, base, off);
        }
        self.b.ins().jump(merge, &[]);

        // ON and up: the coil ON. A set value in a word is checked first
        // (the function does; the interpreter faults when it is negative).
        let timing = if let WordSrc::Const(_) = t.set {
            self.b.switch_to_block(on);
            let bits = self.b.use_var(self.bits);
            let (base, off) = self.addr(bits, t.contact, 1);
            let up = self.b.ins().uload8(types::I32, flags(), base, off);
            let (is_up, timing) = (self.b.create_block(), self.b.create_block());
            self.b.ins().brif(up, is_up, &[], timing, &[]);
            self.b.seal_block(is_up);
            self.b.seal_block(timing);
            self.b.switch_to_block(is_up);
            let one = self.b.ins().iconst(types::I32, 1);
            self.raw_store_bit(t.coil, one);
            self.b.ins().jump(merge, &[]);
            timing
        } else {
            on
        };

        self.b.switch_to_block(timing);
        self.call_timer(t, merge);
        self.b.switch_to_block(merge);
        self.b.seal_block(merge);
        self.learn = learn;
    }

    /// A set value: the constant (not negative, the plan checked), or the
    /// word, with a branch to the returned block (for [`Gen::slow_path`]:
    /// the interpreter runs the op, which faults) when it is negative. Leaves the builder on the fast path.
    fn set_value(&mut self, set: WordSrc) -> (Value, Option<Block>) {
        let v = self.value(set, false);
        if let WordSrc::Const(_) = set {
            return (v, None);
        }
        let (slow, fast) = (self.b.create_block(), self.b.create_block());
        let neg = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, v, 0);
        self.b.ins().brif(neg, slow, &[], fast, &[]);
        self.b.seal_block(slow);
        self.b.switch_to_block(fast);
        self.b.seal_block(fast);
        (v, Some(slow))
    }

    /// Emits `slow` (the interpreter runs op `pc`) jumping to `merge`.
    fn slow_path(&mut self, slow: Option<Block>, pc: u32, merge: Block) {
        if let Some(slow) = slow {
            self.b.switch_to_block(slow);
            self.run(pc, pc + 1);
            self.b.ins().jump(merge, &[]);
        }
    }

    /// `OUT C` as `sequence::counter` does it, without a branch: +1 on the
    /// coil's rising edge while not up and below 32767; the contact ON at
    /// the set value (0 counts as 1).
    fn counter(&mut self, c: &CounterStep) {
        let merge = self.b.create_block();
        let learn = self.learn;
        if let WordSrc::Word(_) = c.set {
            self.forget_bit(c.coil);
            self.forget_bit(c.contact);
            self.forget_word(c.value);
            self.learn = false;
        }
        // A set value of 0 counts as 1.
        let (set, slow) = self.set_value(c.set);
        let set = match c.set {
            WordSrc::Const(k) if k as u16 as i16 == 0 => self.b.ins().iconst(types::I32, 1),
            WordSrc::Const(_) => set,
            WordSrc::Word(_) => {
                let one = self.b.ins().iconst(types::I32, 1);
                self.b.ins().smax(set, one)
            }
        };
        let cond = self.acc_bit();
        let old = self.bit(c.coil);
        let not_old = self.b.ins().bnot(old);
        let rising = self.b.ins().band(cond, not_old);
        self.store_bit(c.coil, cond);
        let up = self.bit(c.contact);
        let cur = self.word_signed(c.value);
        let below = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, cur, 32767);
        let below = self.b.ins().uextend(types::I32, below);
        let not_up = self.b.ins().bnot(up);
        let inc = self.b.ins().band(rising, not_up);
        let inc = self.b.ins().band(inc, below);
        let cur = self.b.ins().iadd(cur, inc);
        let reached = self.b.ins().icmp(IntCC::SignedGreaterThanOrEqual, cur, set);
        let reached = self.b.ins().uextend(types::I32, reached);
        let up = self.b.ins().bor(up, reached);
        self.store_bit(c.contact, up);
        self.store_word(c.value, cur, Form::Sext);
        if slow.is_some() {
            self.b.ins().jump(merge, &[]);
            self.slow_path(slow, c.pc, merge);
            self.b.switch_to_block(merge);
            self.b.seal_block(merge);
            self.learn = learn;
            self.forget_all();
        }
    }

    /// Calls the program's timer function for `t` (its condition ON) and
    /// jumps to `merge`; the interpreter runs the op instead when the
    /// function returns 1 (a negative set value in a word), and when `t` has
    /// no descriptor (never: `native::descriptors` takes them from the same
    /// plan).
    fn call_timer(&mut self, t: &TimerStep, merge: Block) {
        let Some(&desc) = self.calls.descs.get(&t.pc) else {
            self.run(t.pc, t.pc + 1);
            self.forget_all();
            self.b.ins().jump(merge, &[]);
            return;
        };
        let desc = self.b.ins().iconst(self.ptr, desc);
        let on = self.b.ins().iconst(types::I32, 1);
        let call = self.b.ins().call(self.calls.timer, &[self.cx, on, desc]);
        self.note_store(t.coil);
        self.note_store(t.contact);
        if let WordSrc::Word(_) = t.set {
            let slow = self.b.inst_results(call)[0];
            let run = self.b.create_block();
            self.b.ins().brif(slow, run, &[], merge, &[]);
            self.b.seal_block(run);
            self.b.switch_to_block(run);
            self.run(t.pc, t.pc + 1);
            self.forget_all();
        }
        self.b.ins().jump(merge, &[]);
    }

    /// MC: its bit ON while the condition is; with the condition OFF the
    /// interpreter runs it (and the ops up to MCR with conditions OFF).
    fn mc(&mut self, pc: u32, bit: u32) {
        let (on, off) = self.branch_on_condition();
        let merge = self.b.create_block();
        self.b.switch_to_block(on);
        let one = self.b.ins().iconst(types::I32, 1);
        self.raw_store_bit(bit, one);
        self.b.ins().jump(merge, &[]);
        self.b.switch_to_block(off);
        self.run(pc, pc + 1);
        self.b.ins().jump(merge, &[]);
        self.b.switch_to_block(merge);
        self.b.seal_block(merge);
        self.forget_all();
    }

    /// Branches on the condition: the blocks where it is ON and OFF.
    fn branch_on_condition(&mut self) -> (Block, Block) {
        let c = self.acc_bit();
        let (on, off) = (self.b.create_block(), self.b.create_block());
        self.b.ins().brif(c, on, &[], off, &[]);
        self.b.seal_block(on);
        self.b.seal_block(off);
        (on, off)
    }

    /// Stores bit `i` in a branch (nothing learnt).
    fn raw_store_bit(&mut self, i: u32, v: Value) {
        let bits = self.b.use_var(self.bits);
        let (base, off) = self.addr(bits, i, 1);
        self.b.ins().istore8(flags(), v, base, off);
        self.note_store(i);
    }
}
