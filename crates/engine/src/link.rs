//! Linking the program files of a CPU: what one file refers to in another is
//! resolved when the CPU is built, never while scanning.
//!
//! - Instructions that name a program file (PSCAN/PSTOP/POFF/PLOW: its name
//!   without extension) find its slot (`Instr::link`).
//! - CALL of a common pointer (from the "common pointer" parameter up to P4095,
//!   004 §10.9.2) reaches a subroutine in any file, typically a standby program.
//! - ECALL/EFCALL `"FILE" Pn` reaches local pointer Pn of program FILE
//!   (004 §10.9.1 (1)(a)); an unknown file or pointer is a load error.
//! - Each interrupt pointer and each common pointer may be defined once across
//!   all programs (004 L1201-1226; the family's error for common pointers).

use softplc_ir::fault::Fault;
use softplc_ir::ops::{Callee, Op, Program};
use softplc_ir::system::System;

/// A program's name: the file name without directory and extension, upper case
/// (`main.il` → `MAIN`).
pub(crate) fn program_name(file: &str) -> String {
    std::path::Path::new(file)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("")
        .to_ascii_uppercase()
}

/// Resolves cross-file references in place; returns the interrupt table
/// (In → (program, op index)).
pub(crate) fn link(
    programs: &mut [Program],
    system: &dyn System,
) -> Result<Vec<Option<(usize, u32)>>, String> {
    let names: Vec<String> = programs.iter().map(|p| program_name(&p.file)).collect();
    let mut interrupts: Vec<Option<(usize, u32)>> = vec![None; 256];
    let mut common: std::collections::HashMap<u32, (usize, u32)> = Default::default();
    for (i, p) in programs.iter().enumerate() {
        for &(n, pc) in &p.interrupts {
            if let Some((j, _)) = interrupts[n as usize] {
                return Err(format!(
                    "interrupt pointer I{n} is defined in {} and in {} (CAN'T SET(I)): each may be used once",
                    programs[j].file, p.file
                ));
            }
            interrupts[n as usize] = Some((i, pc));
        }
        for &(n, pc) in &p.common_labels {
            if let Some((j, _)) = common.insert(n, (i, pc)) {
                let code = system
                    .code(Fault::PointerTwice)
                    .map_or(String::new(), |c| format!(" (error {})", c.0));
                return Err(format!(
                    "common pointer P{n} is defined in {} and in {}{code}",
                    programs[j].file, p.file
                ));
            }
        }
    }
    let labels: Vec<Vec<(u32, u32)>> = programs.iter().map(|p| p.local_labels.clone()).collect();
    for p in programs.iter_mut() {
        for x in &mut p.ext {
            x.link(&names);
        }
        let file = p.file.clone();
        for op in &mut p.ops {
            if let Op::CallArgs(c) = op {
                c.callee = match &c.callee {
                    Callee::Common(n) => {
                        let Some(&(slot, pc)) = common.get(n) else {
                            return Err(format!(
                                "{file}: CALL P{n}: no program defines the common pointer P{n}"
                            ));
                        };
                        Callee::Far {
                            slot: slot as u16,
                            pc,
                        }
                    }
                    Callee::File { file: f, pointer } => {
                        let (slot, pc) = local_pointer(&names, &labels, f, *pointer)
                            .map_err(|e| format!("{file}: ECALL \"{f}\" P{pointer}: {e}"))?;
                        Callee::Far {
                            slot: slot as u16,
                            pc,
                        }
                    }
                    other => other.clone(),
                };
                continue;
            }
            if let Op::CallCommon(n) = op {
                let Some(&(slot, pc)) = common.get(n) else {
                    return Err(format!(
                        "{file}: CALL P{n}: no program defines the common pointer P{n}"
                    ));
                };
                *op = Op::CallFar {
                    slot: slot as u16,
                    pc,
                };
            }
        }
    }
    Ok(interrupts)
}

/// Program `file`'s slot and the op of its local pointer `pointer`.
fn local_pointer(
    names: &[String],
    labels: &[Vec<(u32, u32)>],
    file: &str,
    pointer: u32,
) -> Result<(usize, u32), String> {
    let slot = names
        .iter()
        .position(|n| n == file)
        .ok_or_else(|| format!("no program named {file} runs on this CPU"))?;
    let pc = labels[slot]
        .iter()
        .find(|(n, _)| *n == pointer)
        .map(|&(_, pc)| pc)
        .ok_or_else(|| format!("program {file} has no local pointer P{pointer}"))?;
    Ok((slot, pc))
}
