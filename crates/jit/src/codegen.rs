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
use softplc_ir::ops::{CmpOp, Join};

use crate::native::{CX_ACC, CX_BITS, CX_BLOCKS, CX_MC_ON, CX_MPS, CX_WORDS};
use crate::plan::{BitSrc, Chunk, Move, Piece, Step, Store, WordSrc};

/// The signature of every chunk function on the host's calling convention:
/// (cx, pc) → next op.
pub fn signature(call_conv: cranelift_codegen::isa::CallConv, ptr: Type) -> Signature {
    let mut sig = Signature::new(call_conv);
    sig.params.push(AbiParam::new(ptr)); // cx
    sig.params.push(AbiParam::new(types::I32)); // pc
    sig.returns.push(AbiParam::new(types::I32));
    sig
}

/// The rung registers and device addresses as SSA variables.
struct Gen<'a, 'b> {
    b: &'a mut FunctionBuilder<'b>,
    cx: Value,
    ptr: Type,
    /// `native::exec_op`, imported into the function.
    exec_op: FuncRef,
    /// Dispatches on its parameter (an op index) to the entry there.
    dispatch: Block,
    bits: Variable,
    words: Variable,
    acc: Variable,
    blocks: Variable,
    mps: Variable,
    /// Bits that may be read four bytes at a time (`bit_len - 3`).
    wide_bits: u32,
    /// Bits whose value native code holds, loaded or stored since the last
    /// call or entry, with the step that did so (oldest first).
    known: Vec<(u32, Value, u32)>,
    /// Steps emitted so far.
    steps: u32,
}

/// How many steps a known bit stays in a register: a rung or two, so that
/// the next rung's contact on the coil just set (or on the contact just
/// read) needs no load, without values kept alive across the chunk (the
/// register allocator would spill them, which costs more than a load).
const KNOWN_STEPS: u32 = 12;

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
pub fn build(b: &mut FunctionBuilder, chunk: &Chunk, ptr: Type, exec_op: FuncRef, bit_len: u32) {
    let start = b.create_block();
    b.append_block_params_for_function_params(start);
    b.switch_to_block(start);
    let p = b.block_params(start).to_vec();
    let (cx, pc) = (p[0], p[1]);
    let dispatch = b.create_block();
    let target = b.append_block_param(dispatch, types::I32);
    let mut g = Gen {
        cx,
        ptr,
        exec_op,
        dispatch,
        bits: b.declare_var(ptr),
        words: b.declare_var(ptr),
        acc: b.declare_var(types::I32),
        blocks: b.declare_var(types::I32),
        mps: b.declare_var(types::I32),
        wide_bits: bit_len.saturating_sub(3),
        known: Vec::new(),
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
                g.known.clear();
                open = true;
            }
            Piece::Step(s) => g.step(s),
            Piece::Run { from, to } => g.run(*from, *to),
            Piece::Exit(at) => {
                let at = g.b.ins().iconst(types::I32, i64::from(*at));
                g.leave(at);
                open = false;
            }
        }
    }
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
        for (var, off) in [(self.bits, CX_BITS), (self.words, CX_WORDS)] {
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
    /// `to`, else dispatch on the op it returned, but return to the
    /// interpreter at once when the stretch turned conditions OFF (an MC):
    /// native code runs only while they are not (`NativeProgram::run`).
    fn run(&mut self, from: u32, to: u32) {
        self.store_regs();
        let from = self.b.ins().iconst(types::I32, i64::from(from));
        let to_v = self.b.ins().iconst(types::I32, i64::from(to));
        let call = self.b.ins().call(self.exec_op, &[self.cx, from, to_v]);
        let next = self.b.inst_results(call)[0];
        let mc_on = self.b.ins().load(types::I32, flags(), self.cx, CX_MC_ON);
        let (on, check, off) = (
            self.b.create_block(),
            self.b.create_block(),
            self.b.create_block(),
        );
        self.b.ins().brif(mc_on, check, &[], off, &[]);
        // The registers in `cx` are the interpreter's: nothing to store.
        self.b.switch_to_block(off);
        self.b.ins().return_(&[next]);
        self.b.switch_to_block(check);
        self.load_regs();
        self.known.clear();
        let straight = self.b.ins().icmp_imm_u(IntCC::Equal, next, i64::from(to));
        self.b
            .ins()
            .brif(straight, on, &[], self.dispatch, &[next.into()]);
        self.b.switch_to_block(on);
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
        let bits = self.b.use_var(self.bits);
        let (base, off) = self.addr(bits, i, 1);
        let v = if i < self.wide_bits {
            self.b.ins().load(types::I32, flags(), base, off)
        } else {
            self.b.ins().uload8(types::I32, flags(), base, off)
        };
        self.know(i, v);
        v
    }

    /// Records that bit `i` holds `v` now.
    fn know(&mut self, i: u32, v: Value) {
        let oldest = self.steps.saturating_sub(KNOWN_STEPS);
        self.known.retain(|k| k.0 != i && k.2 >= oldest);
        self.known.push((i, v, self.steps));
    }

    fn word(&mut self, i: u32) -> Value {
        let words = self.b.use_var(self.words);
        let (base, off) = self.addr(words, i, 2);
        self.b.ins().uload16(types::I32, flags(), base, off)
    }

    /// Stores the low 16 bits of `v` as word `i`. Not a store of an
    /// immediate, even for a constant: x86's 16-bit immediate store stalls
    /// the legacy decoders (a length-changing prefix), which decode all of
    /// a long program's code (MOV K chains took 0.85 instead of 0.54 ns).
    fn store_word(&mut self, i: u32, v: Value) {
        let words = self.b.use_var(self.words);
        let (base, off) = self.addr(words, i, 2);
        self.b.ins().istore16(flags(), v, base, off);
    }

    /// A word operand: 16-bit sign-extended, or 32-bit low word first.
    fn value(&mut self, s: WordSrc, wide: bool) -> Value {
        match (s, wide) {
            (WordSrc::Const(k), false) => {
                self.b.ins().iconst(types::I32, i64::from(k as u16 as i16))
            }
            (WordSrc::Const(k), true) => self.b.ins().iconst(types::I32, i64::from(k as i32)),
            (WordSrc::Word(i), false) => {
                let words = self.b.use_var(self.words);
                let (base, off) = self.addr(words, i, 2);
                self.b.ins().sload16(types::I32, flags(), base, off)
            }
            (WordSrc::Word(i), true) => {
                let lo = self.word(i);
                let hi = self.word(i + 1);
                let hi = self.b.ins().ishl_imm_s(hi, 16);
                self.b.ins().bor(lo, hi)
            }
        }
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
                        let v = self.word(w);
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
                let bits = self.b.use_var(self.bits);
                let (base, off) = self.addr(bits, *bit, 1);
                self.b.ins().istore8(flags(), v, base, off);
                self.know(*bit, v);
            }
            Step::Movs(run) => self.movs(run),
        }
    }

    /// A run of MOVs under one test of the condition.
    fn movs(&mut self, run: &[Move]) {
        // The condition, as for coils (bit 0: brif tests the whole value).
        let c = self.acc_bit();
        let then = self.b.create_block();
        let after = self.b.create_block();
        self.b.ins().brif(c, then, &[], after, &[]);
        self.b.switch_to_block(then);
        for m in run {
            // DMOV reads both words before writing (DMOV D0 D1 overlaps).
            let mut v = [None; 2];
            for (k, slot) in v.iter_mut().enumerate().take(usize::from(m.words)) {
                let k = k as u32;
                *slot = Some(match m.s {
                    WordSrc::Word(i) => self.word(i + k),
                    WordSrc::Const(c) => {
                        let half = (c >> (16 * k)) & 0xFFFF;
                        self.b.ins().iconst(types::I32, i64::from(half))
                    }
                });
            }
            for (k, val) in v.into_iter().enumerate() {
                if let Some(val) = val {
                    self.store_word(m.d + k as u32, val);
                }
            }
        }
        self.b.ins().jump(after, &[]);
        self.b.switch_to_block(after);
    }
}
