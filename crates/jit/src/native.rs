//! The compiled code of a program and the JIT's call boundary: the only
//! `unsafe` of the tier is here, each block with its reason.

use cranelift_codegen::isa::OwnedTargetIsa;
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use std::mem::offset_of;

use cranelift_codegen::control::ControlPlane;
use cranelift_codegen::ir::{types, AbiParam, FuncRef, Signature};
use cranelift_codegen::isa::TargetIsa;
use cranelift_codegen::Context;
use cranelift_jit::{ArenaMemoryProvider, JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, FuncId, Linkage, Module, ModuleReloc};
use softplc_engine::tier::{Host, NativeProgram, NativeState, Regs, LEAVE, NO_REGION};
use softplc_ir::ops::Program;

use crate::codegen;
use crate::plan::{Piece, Plan, Step};
use crate::shared::{self, TimerDesc};
use std::collections::HashMap;

/// What a chunk function works on: the rung registers, the addresses of
/// device bits (`bool`s), words and timer remainders, the timers' time
/// bases and scan time, and the interpreter to call back.
#[repr(C)]
pub(crate) struct Ctx<'h> {
    regs: Regs,
    mem: Mem,
    host: *mut (dyn Host + 'h),
}

/// The host's memory as native code addresses it.
#[repr(C)]
struct Mem {
    bits: *mut u8,
    words: *mut u16,
    rem: *mut u32,
    edges: *mut u8,
    timer_base_us: [u32; 2],
    scan_us: u32,
}

impl Mem {
    /// The addresses and timer figures of `st` (at entry and after every
    /// call into the host, which had them mutably).
    fn of(st: NativeState<'_>) -> Mem {
        Mem {
            bits: st.mem.bits.as_mut_ptr().cast::<u8>(),
            words: st.mem.words.as_mut_ptr(),
            rem: st.timer_rem.as_mut_ptr(),
            edges: st.edges.as_mut_ptr().cast::<u8>(),
            timer_base_us: st.timer_base_us,
            scan_us: st.scan_us,
        }
    }
}

/// Offsets in [`Ctx`] of what native code reads and writes.
pub(crate) const CX_ACC: i32 = (offset_of!(Ctx, regs) + offset_of!(Regs, acc)) as i32;
pub(crate) const CX_BLOCKS: i32 = (offset_of!(Ctx, regs) + offset_of!(Regs, blocks)) as i32;
pub(crate) const CX_MPS: i32 = (offset_of!(Ctx, regs) + offset_of!(Regs, mps)) as i32;
pub(crate) const CX_BITS: i32 = (offset_of!(Ctx, mem) + offset_of!(Mem, bits)) as i32;
pub(crate) const CX_WORDS: i32 = (offset_of!(Ctx, mem) + offset_of!(Mem, words)) as i32;
pub(crate) const CX_REM: i32 = (offset_of!(Ctx, mem) + offset_of!(Mem, rem)) as i32;
pub(crate) const CX_EDGES: i32 = (offset_of!(Ctx, mem) + offset_of!(Mem, edges)) as i32;
pub(crate) const CX_TIMER_BASE_US: i32 =
    (offset_of!(Ctx, mem) + offset_of!(Mem, timer_base_us)) as i32;
pub(crate) const CX_SCAN_US: i32 = (offset_of!(Ctx, mem) + offset_of!(Mem, scan_us)) as i32;

/// A chunk function (see `codegen`): context, entry op → next op.
type ChunkFn = unsafe extern "C" fn(*mut Ctx, u32) -> u32;

/// The name native code calls [`exec_op`] by.
const EXEC_OP: &str = "softplc_exec_op";
/// The JIT function that calls [`exec_op`] for every chunk (`codegen::trampoline`).
const TRAMPOLINE: &str = "softplc_exec_trampoline";

/// Most threads a program's chunks are compiled on.
const COMPILE_THREADS: usize = 8;

/// Address space reserved for a program's code: a base and an allowance per
/// op (a call of the interpreter takes about 60 bytes, a jump-table entry 4),
/// committed only as far as used.
const ARENA_BYTES: usize = 1 << 20;
const ARENA_BYTES_PER_OP: usize = 256;

/// Runs ops `from..to` in the interpreter for native code (`codegen`'s runs)
/// and returns the op to go on at.
extern "C" fn exec_op(cx: *mut Ctx, from: u32, to: u32) -> u32 {
    // SAFETY: native code passes on the `cx` that `Compiled::run` gave it:
    // a live, exclusive `Ctx` whose `host` is the `&mut dyn Host` borrowed
    // for that run. Native code does not touch `cx` while this runs.
    let cx = unsafe { &mut *cx };
    // SAFETY: as above; nothing else uses the host during the call.
    let host = unsafe { &mut *cx.host };
    let next = host.exec(from, to, &mut cx.regs);
    // The interpreter had the memory mutably: native code goes on with its
    // addresses as of now (the slices never change size).
    cx.mem = Mem::of(host.state());
    // A stretch that turned conditions OFF (an MC) returns to the
    // interpreter: marked, so that the call site tests one value.
    if cx.regs.mc_on == 0 && next != LEAVE {
        next | OFF_MARK
    } else {
        next
    }
}

/// Marks the op [`exec_op`] returns when conditions are OFF after the
/// stretch: native code returns it (unmarked) to the interpreter.
pub(crate) const OFF_MARK: u32 = 1 << 31;

/// [`exec_op`]'s signature on the host's calling convention.
fn exec_op_signature(call_conv: cranelift_codegen::isa::CallConv, ptr: types::Type) -> Signature {
    let mut sig = Signature::new(call_conv);
    sig.params.push(AbiParam::new(ptr));
    sig.params.push(AbiParam::new(types::I32));
    sig.params.push(AbiParam::new(types::I32));
    sig.returns.push(AbiParam::new(types::I32));
    sig
}

/// The host's code generator, built once per process.
pub(crate) fn isa() -> Result<OwnedTargetIsa, String> {
    static ISA: std::sync::OnceLock<Result<OwnedTargetIsa, String>> = std::sync::OnceLock::new();
    ISA.get_or_init(host_isa).clone()
}

fn host_isa() -> Result<OwnedTargetIsa, String> {
    let mut flags = settings::builder();
    let set = |f: &mut settings::Builder, k: &str, v: &str| {
        f.set(k, v)
            .map_err(|e| format!("cranelift setting {k}={v}: {e}"))
    };
    // No e-graph optimisation: `codegen` emits the code it wants (it keeps
    // the bits it knows in registers itself), and the e-graph would move each
    // and/or away from its load, so that x86 could no longer take the bit
    // from memory in the same instruction: the bit mix ran at 0.27 instead of
    // 0.22 ns per instruction, and compiling took twice as long
    // (docs/performance.md, "Code shape").
    set(&mut flags, "opt_level", "none")?;
    // Debug builds (the tests) verify the IR; in release the verifier took
    // a tenth of the compile time.
    let verify = if cfg!(debug_assertions) {
        "true"
    } else {
        "false"
    };
    set(&mut flags, "enable_verifier", verify)?;
    // The JIT's code is placed anywhere in memory (cranelift-jit's own
    // settings for native code).
    set(&mut flags, "use_colocated_libcalls", "false")?;
    set(&mut flags, "is_pic", "false")?;
    let builder =
        cranelift_native::builder().map_err(|e| format!("no native code for this host: {e}"))?;
    builder
        .finish(settings::Flags::new(flags))
        .map_err(|e| format!("no native code for this host: {e}"))
}

/// A program's native code.
pub(crate) struct Compiled {
    /// Owns the executable memory the functions live in (freed on drop).
    module: Option<JITModule>,
    /// The descriptors native code passes the timer function (by address:
    /// kept here, never moved, for as long as the code).
    _timers: Box<[(u32, TimerDesc)]>,
    fns: Vec<ChunkFn>,
    entries: Vec<u32>,
    native_ops: usize,
    short_run_ops: usize,
    /// Memory sizes the plan checked every index against.
    bit_len: usize,
    word_len: usize,
    /// Timer remainders native code uses: all are below this.
    timer_slots: usize,
    /// Edge memories native code uses: all are below this.
    edge_slots: usize,
}

impl Compiled {
    pub(crate) fn new(prog: &Program, plan: &Plan) -> Result<Compiled, String> {
        let err = |e: &dyn std::fmt::Display| format!("native code: {e}");
        let isa = isa()?;
        let call_conv = isa.default_call_conv();
        let ptr = isa.pointer_type();
        let mut builder = JITBuilder::with_isa(isa, default_libcall_names());
        builder.symbol(EXEC_OP, exec_op as *const u8);
        // One reserved region, so that the chunks' direct calls of the
        // trampoline reach it (within ±2 GiB).
        let reserve = ARENA_BYTES + prog.ops.len() * ARENA_BYTES_PER_OP;
        let arena = ArenaMemoryProvider::new_with_size(reserve).map_err(|e| err(&e))?;
        builder.memory_provider(Box::new(arena));
        let mut module = JITModule::new(builder);
        let sig = codegen::signature(call_conv, ptr);
        let exec_sig = exec_op_signature(call_conv, ptr);
        let exec_id = module
            .declare_function(EXEC_OP, Linkage::Import, &exec_sig)
            .map_err(|e| err(&e))?;
        let mut ctx = module.make_context();
        let mut fctx = FunctionBuilderContext::new();
        let tramp_id = module
            .declare_function(TRAMPOLINE, Linkage::Local, &exec_sig)
            .map_err(|e| err(&e))?;
        define(
            &mut module,
            &mut ctx,
            &mut fctx,
            tramp_id,
            &exec_sig,
            &[exec_id],
            |b, f| codegen::trampoline(b, f[0]),
        )
        .map_err(|e| err(&e))?;
        // The timer function every chunk calls, and the descriptors it
        // passes it (`descs` holds their final addresses: the box does not
        // move).
        let shared_sig = shared::signature(call_conv, ptr);
        let timer_id = module
            .declare_anonymous_function(&shared_sig)
            .map_err(|e| err(&e))?;
        define(
            &mut module,
            &mut ctx,
            &mut fctx,
            timer_id,
            &shared_sig,
            &[],
            |b, _| shared::timer(b, ptr),
        )
        .map_err(|e| err(&e))?;
        let timers = descriptors(plan);
        let descs: HashMap<u32, i64> = timers
            .iter()
            .map(|(pc, d)| (*pc, std::ptr::from_ref(d) as i64))
            .collect();
        let mut entries = vec![NO_REGION; prog.ops.len()];
        // Each chunk's function as IR, in order (declaring it and what it
        // calls needs the module), each in its own context.
        let mut funcs = Vec::new();
        for chunk in &plan.chunks {
            if !chunk.pieces.iter().any(|p| matches!(p, Piece::Entry(_))) {
                continue;
            }
            let unit = funcs.len() as u32;
            for p in &chunk.pieces {
                if let Piece::Entry(pc) = p {
                    entries[*pc as usize] = unit;
                }
            }
            let id = module
                .declare_anonymous_function(&sig)
                .map_err(|e| err(&e))?;
            let mut ctx = module.make_context();
            ctx.func.signature = sig.clone();
            let tramp_ref = module.declare_func_in_func(tramp_id, &mut ctx.func);
            let calls = codegen::Calls {
                timer: module.declare_func_in_func(timer_id, &mut ctx.func),
                descs: &descs,
            };
            let mut b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
            codegen::build(&mut b, chunk, ptr, tramp_ref, calls, prog.bit_len);
            b.finalize(module.target_config());
            funcs.push((id, ctx));
        }
        // Compiled on every core (most of the time is Cranelift's), then
        // placed in the module in order.
        compile_all(module.isa(), &mut funcs).map_err(|e| err(&e))?;
        for (id, ctx) in &funcs {
            let code = ctx
                .compiled_code()
                .ok_or_else(|| err(&"a chunk was not compiled"))?;
            let relocs: Vec<ModuleReloc> = code
                .buffer
                .relocs()
                .iter()
                .map(|r| ModuleReloc::from_mach_reloc(r, &ctx.func, *id))
                .collect();
            let align = u64::from(code.buffer.alignment);
            module
                .define_function_bytes(*id, align, code.code_buffer(), &relocs)
                .map_err(|e| err(&e))?;
        }
        let ids: Vec<FuncId> = funcs.iter().map(|(id, _)| *id).collect();
        module.finalize_definitions().map_err(|e| err(&e))?;
        let fns = ids
            .iter()
            .map(|id| {
                let code = module.get_finalized_function(*id);
                // SAFETY: `code` is a function just compiled with `sig`, the
                // host's default calling convention with (ptr, i32) → i32,
                // which is `ChunkFn`'s `extern "C"` ABI on the host;
                // `module` keeps it alive for as long as `fns`.
                unsafe { std::mem::transmute::<*const u8, ChunkFn>(code) }
            })
            .collect();
        Ok(Compiled {
            module: Some(module),
            _timers: timers,
            fns,
            entries,
            native_ops: plan.native.iter().filter(|n| **n).count(),
            short_run_ops: plan.short_run_ops,
            bit_len: prog.bit_len as usize,
            word_len: prog.word_len as usize,
            timer_slots: plan.timer_slots as usize,
            edge_slots: prog.edge_slots as usize,
        })
    }
}

/// Builds function `id` of `sig` (calling `imports`) with `body` and
/// compiles it into `module`.
fn define(
    module: &mut JITModule,
    ctx: &mut Context,
    fctx: &mut FunctionBuilderContext,
    id: FuncId,
    sig: &Signature,
    imports: &[FuncId],
    body: impl FnOnce(&mut FunctionBuilder, &[FuncRef]),
) -> Result<(), String> {
    ctx.func.signature = sig.clone();
    let refs: Vec<FuncRef> = imports
        .iter()
        .map(|i| module.declare_func_in_func(*i, &mut ctx.func))
        .collect();
    let mut b = FunctionBuilder::new(&mut ctx.func, fctx);
    body(&mut b, &refs);
    b.finalize(module.target_config());
    module
        .define_function(id, ctx)
        .map_err(|e| format!("{e:?}"))?;
    module.clear_context(ctx);
    Ok(())
}

/// Compiles every context's function, on as many threads as the machine
/// has cores (at most [`COMPILE_THREADS`]), each taking a share of
/// consecutive functions.
fn compile_all(isa: &dyn TargetIsa, funcs: &mut [(FuncId, Context)]) -> Result<(), String> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, COMPILE_THREADS)
        .min(funcs.len().max(1));
    let compile = |share: &mut [(FuncId, Context)]| -> Result<(), String> {
        for (_, ctx) in share {
            ctx.compile(isa, &mut ControlPlane::default())
                .map_err(|e| format!("{:?}", e.inner))?;
        }
        Ok(())
    };
    if threads == 1 {
        return compile(funcs);
    }
    let per = funcs.len().div_ceil(threads);
    std::thread::scope(|s| {
        let handles: Vec<_> = funcs
            .chunks_mut(per)
            .map(|share| s.spawn(move || compile(share)))
            .collect();
        handles.into_iter().try_for_each(|h| {
            h.join()
                .unwrap_or_else(|_| Err("a compile thread panicked".into()))
        })
    })
}

/// The descriptor of every timer native code runs, with its op.
fn descriptors(plan: &Plan) -> Box<[(u32, TimerDesc)]> {
    plan.chunks
        .iter()
        .flat_map(|c| &c.pieces)
        .filter_map(|p| match p {
            Piece::Step(Step::Timer(t)) => Some((t.pc, TimerDesc::of(t))),
            _ => None,
        })
        .collect()
}

impl NativeProgram for Compiled {
    fn entries(&self) -> &[u32] {
        &self.entries
    }

    fn run(&self, unit: u32, pc: u32, regs: &mut Regs, host: &mut dyn Host) -> u32 {
        let Some(f) = self.fns.get(unit as usize) else {
            return pc;
        };
        let st = host.state();
        if st.mem.bits.len() != self.bit_len
            || st.mem.words.len() != self.word_len
            || st.timer_rem.len() < self.timer_slots
            || st.edges.len() < self.edge_slots
            || st.timer_base_us.contains(&0)
        {
            return pc;
        }
        // The interpreter enters only while no master control (or POFF)
        // forces conditions OFF (`NativeProgram::run`): the code has no
        // case for it (`codegen`: a stretch that turns them OFF returns).
        debug_assert!(regs.mc_on != 0, "native code entered under an OFF MC");
        // Booleans stay 0/1 whatever the caller passed (they are stored into `bool`s).
        regs.acc = u32::from(regs.acc != 0);
        let mem = Mem::of(st);
        let mut cx = Ctx {
            regs: *regs,
            mem,
            host,
        };
        // SAFETY: `f` is this program's code (`new`) and follows `ChunkFn`.
        // It reads and writes `cx.regs` and only elements of `bits`/`words`/
        // `rem`/`edges` whose indices the plan checked against `bit_len`/
        // `word_len`/`timer_slots`/`edge_slots`, the (least) lengths of the host's slices (tested
        // above; they never change size), through the addresses in `cx`,
        // which `exec_op` renews after every call into the host; it divides
        // only by a time base, not 0 (tested above); a bit below `bit_len - 3` may be read
        // together with the three bytes after it (`codegen::Gen::bit`), still
        // inside the slice. Every value it stores into a `bool` is 0 or 1:
        // the low byte of loaded bools, `acc` (0/1 above, and as the host
        // leaves it) and their and/or/xor-with-1/and-not and comparison
        // results, whose low byte is 0 or 1 whatever bits 8-31 hold, and the
        // low bit of the stacks.
        let next = unsafe { f(&mut cx, pc) };
        *regs = cx.regs;
        next
    }

    fn native_ops(&self) -> usize {
        self.native_ops
    }

    fn short_run_ops(&self) -> usize {
        self.short_run_ops
    }
}

impl Drop for Compiled {
    fn drop(&mut self) {
        if let Some(module) = self.module.take() {
            // SAFETY: the only pointers into the module's code are `fns`,
            // dropped with `self`; no call can be running (`run` borrows self).
            unsafe { module.free_memory() }
        }
    }
}
