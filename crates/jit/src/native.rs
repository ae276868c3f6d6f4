//! The compiled code of a program and the JIT's call boundary: the only
//! `unsafe` of the tier is here, each block with its reason.

use cranelift_codegen::isa::OwnedTargetIsa;
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, Module};
use softplc_engine::tier::{NativeProgram, Regs, NO_REGION};
use softplc_ir::device::DeviceMemory;
use softplc_ir::ops::Program;

use crate::codegen;
use crate::plan::{Piece, Plan};

/// A chunk function (see `codegen`): regs, bits, words, entry op → next op.
type ChunkFn = unsafe extern "C" fn(*mut Regs, *mut u8, *mut u16, u32) -> u32;

/// The host's code generator at `opt_level=speed`.
pub(crate) fn isa() -> Result<OwnedTargetIsa, String> {
    let mut flags = settings::builder();
    let set = |f: &mut settings::Builder, k: &str, v: &str| {
        f.set(k, v)
            .map_err(|e| format!("cranelift setting {k}={v}: {e}"))
    };
    set(&mut flags, "opt_level", "speed")?;
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
    fns: Vec<ChunkFn>,
    entries: Vec<u32>,
    native_ops: usize,
    /// Memory sizes the plan checked every index against.
    bit_len: usize,
    word_len: usize,
}

impl Compiled {
    pub(crate) fn new(prog: &Program, plan: &Plan) -> Result<Compiled, String> {
        let err = |e: &dyn std::fmt::Display| format!("native code: {e}");
        let isa = isa()?;
        let call_conv = isa.default_call_conv();
        let ptr = isa.pointer_type();
        let mut module = JITModule::new(JITBuilder::with_isa(isa, default_libcall_names()));
        let sig = codegen::signature(call_conv, ptr);
        let mut ctx = module.make_context();
        let mut fctx = FunctionBuilderContext::new();
        let mut ids = Vec::new();
        let mut entries = vec![NO_REGION; prog.ops.len()];
        for chunk in &plan.chunks {
            if !chunk.pieces.iter().any(|p| matches!(p, Piece::Entry(_))) {
                continue;
            }
            let unit = ids.len() as u32;
            for p in &chunk.pieces {
                if let Piece::Entry(pc) = p {
                    entries[*pc as usize] = unit;
                }
            }
            let id = module
                .declare_anonymous_function(&sig)
                .map_err(|e| err(&e))?;
            ctx.func.signature = sig.clone();
            let mut b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
            codegen::build(&mut b, chunk);
            b.finalize(module.target_config());
            module
                .define_function(id, &mut ctx)
                .map_err(|e| err(&format!("{e:?}")))?;
            module.clear_context(&mut ctx);
            ids.push(id);
        }
        module.finalize_definitions().map_err(|e| err(&e))?;
        let fns = ids
            .iter()
            .map(|id| {
                let code = module.get_finalized_function(*id);
                // SAFETY: `code` is a function just compiled with `sig`, the
                // host's default calling convention with (ptr, ptr, ptr, i32)
                // → i32, which is `ChunkFn`'s `extern "C"` ABI on the host;
                // `module` keeps it alive for as long as `fns`.
                unsafe { std::mem::transmute::<*const u8, ChunkFn>(code) }
            })
            .collect();
        Ok(Compiled {
            module: Some(module),
            fns,
            entries,
            native_ops: plan.native.iter().filter(|n| **n).count(),
            bit_len: prog.bit_len as usize,
            word_len: prog.word_len as usize,
        })
    }
}

impl NativeProgram for Compiled {
    fn entries(&self) -> &[u32] {
        &self.entries
    }

    fn run(&self, unit: u32, pc: u32, regs: &mut Regs, mem: &mut DeviceMemory) -> u32 {
        let Some(f) = self.fns.get(unit as usize) else {
            return pc;
        };
        if mem.bits.len() != self.bit_len || mem.words.len() != self.word_len {
            return pc;
        }
        // Booleans stay 0/1 whatever the caller passed (they are stored into `bool`s).
        regs.acc = u32::from(regs.acc != 0);
        regs.mc_on = u32::from(regs.mc_on != 0);
        // SAFETY: `f` is this program's code (`new`) and follows `ChunkFn`.
        // It reads and writes `regs` (a `repr(C)` struct of four u32) and
        // only elements of `bits`/`words` whose indices the plan checked
        // against `bit_len`/`word_len`, the lengths of these very slices
        // (tested above); nothing else can touch them while `mem` is borrowed
        // mutably. Every value it stores into a `bool` is 0 or 1: loaded
        // bools, `acc`/`mc_on` (0/1 above) and their and/or/xor-with-1 and
        // comparison results, and the low bit of the stacks.
        unsafe {
            f(
                regs,
                mem.bits.as_mut_ptr().cast::<u8>(),
                mem.words.as_mut_ptr(),
                pc,
            )
        }
    }

    fn native_ops(&self) -> usize {
        self.native_ops
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
