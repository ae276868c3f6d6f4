//! Rules of the QCPU manual on a project's programs taken together, checked
//! once every file has compiled (MELSEC projects; an APLC-TCP project has one
//! program).
//!
//! - Timers (`OUT T`/`OUTH T`/`OUT ST`/`OUTH ST`) must not be used in
//!   interrupt, fixed-scan or standby programs (004 §4.1.4 (5)(c), §4.2.4
//!   (3)(a), §10.2.10 (c)): `OUT T` updates the current value and switches the
//!   contact, so a timer there cannot measure time. The manual states a rule
//!   without an error code; softplc refuses the project at load, naming the
//!   file and line, rather than run a timer that keeps no time.
//! - An edge relay V number may be used once in all the programs the CPU
//!   runs (004 §10.2.6 (1)(b)): two `EGP`/`EGF` sharing one V would each see
//!   the other's result as their previous one. A load error too (no code in
//!   the manual).
//! - The step relay `S` is a device of SFC programs only: a sequence program
//!   that uses it stops the CPU with an SFC error (004 §10.2.9, L6380-6382).
//!   softplc loads no SFC program, so every `S` operand is refused at load,
//!   naming the file and line (the single-file loader checks it too).
//! - Local pointers: each program takes P0 up to its highest local pointer,
//!   and all programs together at most 4096 points, or before the first
//!   common pointer when `[cpu] common_pointer` is set; beyond, the CPU stops
//!   with error 4020 (004 §10.9.1 (2), §10.9.2 (2)).

use crate::engine::{CpuConfig, ExecType, LoadedProgram};
use crate::program::Diagnostic;
use softplc_ir::device::{parse_operand_in, DeviceKind, DeviceMap, Operand, MELSEC_Q};
use softplc_ir::listing::Entry;
use softplc_ir::ops::{Op, Program};

/// Pointer points of a CPU (004 §10.9: P0-P4095).
const POINTERS: u32 = 4096;

/// Every diagnostic of the rules over `programs` (their `file` as the
/// diagnostics' file); `common_pointer` is `[cpu] common_pointer`.
pub(crate) fn check(
    programs: &[LoadedProgram],
    config: &CpuConfig,
    common_pointer: Option<u32>,
) -> Vec<Diagnostic> {
    let files: Vec<Ruled<'_>> = programs
        .iter()
        .map(|l| Ruled {
            program: &l.program,
            exec: l.exec,
            local_devices: l.local_devices,
        })
        .collect();
    check_files(&files, config, common_pointer)
}

/// A program file as the rules see it: its program and its parameters.
pub(crate) struct Ruled<'a> {
    pub program: &'a Program,
    pub exec: ExecType,
    pub local_devices: bool,
}

/// [`check`] over programs held elsewhere (a CPU's, one of them replaced by
/// a program written during RUN).
pub(crate) fn check_files(
    programs: &[Ruled<'_>],
    config: &CpuConfig,
    common_pointer: Option<u32>,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for l in programs {
        step_relays(l.program, &mut out);
        timers(l, &mut out);
    }
    // Local V (004 §10.13.1) is each file's own: the same number in two
    // files is two relays.
    let base = DeviceMap::new(&config.devices).base(DeviceKind::V);
    let local_v: Vec<(u32, u32)> = config
        .local_devices
        .iter()
        .filter(|r| r.kind == DeviceKind::V)
        .map(|r| (base + r.start, base + r.end))
        .collect();
    edge_relays(programs, &local_v, &mut out);
    local_pointers(programs, common_pointer, &mut out);
    out
}

fn at(file: &str, line: u32, message: String) -> Diagnostic {
    Diagnostic {
        file: file.to_string(),
        line,
        col: 1,
        message,
    }
}

/// Every instruction of sequence program `p` with an `S` operand (plain,
/// digit-specified or index-modified).
pub(crate) fn step_relays(p: &Program, out: &mut Vec<Diagnostic>) {
    for e in &p.listing.entries {
        let Entry::Instr(i) = e else {
            continue;
        };
        let step = i.operands.iter().find(|o| {
            matches!(
                parse_operand_in(&MELSEC_Q, &o.to_ascii_uppercase()),
                Ok(Operand::Device { dev, .. }) if dev.kind == DeviceKind::S
            )
        });
        if let Some(op) = step {
            out.push(at(
                &p.file,
                i.line,
                format!(
                    "`{op}`: the step relay S is a device of SFC programs only; a sequence \
                     program that uses it stops the CPU with an SFC error (QCPU manual \
                     §10.2.9), and softplc loads no SFC program: use M or L instead"
                ),
            ));
        }
    }
}

/// A timer coil in a fixed-scan or standby program, or in an interrupt
/// program (In … IRET) of any program.
fn timers(l: &Ruled<'_>, out: &mut Vec<Diagnostic>) {
    let p = l.program;
    let whole = match l.exec {
        ExecType::FixedScan => Some("a fixed-scan program"),
        ExecType::Standby => Some("a standby program"),
        _ => None,
    };
    // The op ranges of the interrupt programs: from In to the next IRET.
    let interrupts: Vec<(u8, usize, usize)> = p
        .interrupts
        .iter()
        .map(|&(n, pc)| {
            let start = pc as usize;
            let end = p.ops[start.min(p.ops.len())..]
                .iter()
                .position(|op| matches!(op, Op::Iret))
                .map_or(p.ops.len(), |i| start + i);
            (n, start, end)
        })
        .collect();
    for (pc, op) in p.ops.iter().enumerate() {
        if !matches!(op, Op::Timer(_)) {
            continue;
        }
        let interrupt = interrupts
            .iter()
            .find(|(_, a, b)| (*a..*b).contains(&pc))
            .map(|(n, _, _)| format!("interrupt program I{n}"));
        let Some(place) = interrupt.or(whole.map(str::to_string)) else {
            continue;
        };
        let line = p.op_line.get(pc).copied().unwrap_or(1);
        out.push(at(
            &p.file,
            line,
            format!(
                "a timer coil (OUT T/OUT ST) in {place}: timers must not be used in interrupt, \
                 fixed-scan or standby programs, where they cannot measure time (QCPU manual, \
                 timers); use a timer in a scan program, or count the program's runs"
            ),
        ));
    }
}

/// An edge relay V number used by more than one EGP/EGF in all programs
/// (`local_v`: the flat bit spans of the local V ranges, inclusive).
fn edge_relays(programs: &[Ruled<'_>], local_v: &[(u32, u32)], out: &mut Vec<Diagnostic>) {
    // Keyed by (the file for a local V, the V's bit).
    let mut seen: std::collections::HashMap<(Option<usize>, u32), (&str, u32)> = Default::default();
    for (i, l) in programs.iter().enumerate() {
        let p = l.program;
        for (pc, op) in p.ops.iter().enumerate() {
            let Op::EdgeRelay { v, .. } = op else {
                continue;
            };
            let line = p.op_line.get(pc).copied().unwrap_or(1);
            let local = l.local_devices && local_v.iter().any(|(a, b)| (*a..=*b).contains(v));
            let key = (local.then_some(i), *v);
            match seen.get(&key) {
                Some(&(file, first)) => out.push(at(
                    &p.file,
                    line,
                    format!(
                        "this edge relay V is already used at {}:{first}: an edge relay number \
                         may be used once in all programs (QCPU manual, edge relay V)",
                        short(file)
                    ),
                )),
                None => {
                    seen.insert(key, (&p.file, line));
                }
            }
        }
    }
}

/// The file name without its directory, as a message names another file.
fn short(file: &str) -> String {
    std::path::Path::new(file)
        .file_name()
        .map_or(file.to_string(), |f| f.to_string_lossy().into_owned())
}

/// The sum over programs of (highest local pointer + 1) against the budget.
fn local_pointers(programs: &[Ruled<'_>], common_pointer: Option<u32>, out: &mut Vec<Diagnostic>) {
    let budget = common_pointer.unwrap_or(POINTERS);
    let mut total = 0u32;
    let mut uses = Vec::new();
    for l in programs {
        let p = l.program;
        let highest = p
            .listing
            .entries
            .iter()
            .filter_map(|e| match e {
                Entry::Label { text, line } => Some((pointer(text)?, *line)),
                Entry::Instr(_) => None,
            })
            .filter(|(n, _)| *n < budget)
            .max_by_key(|(n, _)| *n);
        if let Some((n, line)) = highest {
            total += n + 1;
            uses.push((&p.file, n, line));
        }
    }
    if total <= budget {
        return;
    }
    let Some(&(file, n, line)) = uses.last() else {
        return;
    };
    let list: Vec<String> = uses
        .iter()
        .map(|(f, n, _)| format!("{} P0-P{n}", short(f)))
        .collect();
    let limit = match common_pointer {
        Some(c) => format!("the {c} points before the first common pointer P{c}"),
        None => format!("{POINTERS} points"),
    };
    out.push(at(
        file,
        line,
        format!(
            "local pointers take {total} points in all programs ({}), more than {limit} \
             (error 4020, CAN'T SET(P)): each program takes P0 up to its highest local \
             pointer (P{n} here), so number each program's pointers from P0",
            list.join(", ")
        ),
    ));
}

/// `Pn` (any case) as n.
fn pointer(text: &str) -> Option<u32> {
    let d = text.strip_prefix(['P', 'p'])?;
    if d.is_empty() || !d.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    d.parse().ok()
}
