//! Basic instructions (002 chapter 5, L2522-3101; spec aplc.md §4.1):
//! contacts, coils, SET/RST, block and stack connections, edges, INV, NOP,
//! MC/MCR. They lower to the shared ladder ops.

use softplc_ir::device::DeviceKind;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{BitArg, Coil, CoilKind, Join, MasterControl, Op};
use softplc_lang::compile::Compiler;
use softplc_lang::isa::{Class, CoilRole, Def, Doc, Link, Steps, Test, Use};
use softplc_lang::rung::{MpsLimit, RungStack};

use crate::devices::{counter_word, is_counter32, parse_device, Dev};
use crate::resolve::{self, at, BitUse};

static CONTACTS: Doc = Doc {
    family: "contacts",
    cite: "002 §5.1 L2569-2731",
    notes: "LD/LDI/AND/ANI/OR/ORI on X, Y, M, S, LM, SM, T, C; no index (L2574)",
};
static COILS: Doc = Doc {
    family: "coils",
    cite: "002 §5.1 L2733-2747, L2912-2954",
    notes: "OUT on Y, M, S, LM, SM; SET/RST also on T and C (RST clears the value)",
};
static CONNECT: Doc = Doc {
    family: "connections",
    cite: "002 §5.1 L2753-2910",
    notes: "ANB/ORB without operand (erratum L2757); MPS depth 8 (L2808-2820); EU/ED edges of the power flow",
};
static MASTER: Doc = Doc {
    family: "master control",
    cite: "002 §5.1 L2972-3017",
    notes: "MC n / MCR n, n = 0-7; OFF: OUT coils OFF, TON/TOF reset, others hold",
};

/// Depth of the MPS stack (L2808-2820).
const MPS_LIMIT: MpsLimit = MpsLimit {
    depth: 8,
    excess: "MPS without MPP (L2808-2820)",
};

pub static DEFS: &[Def] = &[
    // 002 §5.1 L2569 LD
    Def::contact("LD", Join::Load, Test::Open, &CONTACTS, contact).steps(Steps::Fixed(1)),
    // 002 §5.1 L2595 LDI
    Def::contact("LDI", Join::Load, Test::Closed, &CONTACTS, contact).steps(Steps::Fixed(1)),
    // 002 §5.1 L2621 AND
    Def::contact("AND", Join::And, Test::Open, &CONTACTS, contact).steps(Steps::Fixed(1)),
    // 002 §5.1 L2649 ANI
    Def::contact("ANI", Join::And, Test::Closed, &CONTACTS, contact).steps(Steps::Fixed(1)),
    // 002 §5.1 L2677 OR
    Def::contact("OR", Join::Or, Test::Open, &CONTACTS, contact).steps(Steps::Fixed(1)),
    // 002 §5.1 L2705 ORI
    Def::contact("ORI", Join::Or, Test::Closed, &CONTACTS, contact).steps(Steps::Fixed(1)),
    // 002 §5.1 L2733 OUT
    Def::coil("OUT", CoilRole::Out, &COILS, coil).steps(Steps::Fixed(1)),
    // 002 §5.1 L2912 SET
    Def::coil("SET", CoilRole::Set, &COILS, coil).steps(Steps::Fixed(1)),
    // 002 §5.1 L2932 RST
    Def::coil("RST", CoilRole::Reset, &COILS, coil).steps(Steps::Fixed(1)),
    // 002 §5.1 L2753 ANB
    Def::link("ANB", Link::BlockAnd, &CONNECT, anb_orb).steps(Steps::Fixed(1)),
    // 002 §5.1 L2776 ORB
    Def::link("ORB", Link::BlockOr, &CONNECT, anb_orb).steps(Steps::Fixed(1)),
    // 002 §5.1 L2808 MPS
    Def::link("MPS", Link::Push, &CONNECT, mps).steps(Steps::Fixed(1)),
    // 002 §5.1 L2822 MRD
    Def::link("MRD", Link::Read, &CONNECT, mps).steps(Steps::Fixed(1)),
    // 002 §5.1 L2832 MPP
    Def::link("MPP", Link::Pop, &CONNECT, mps).steps(Steps::Fixed(1)),
    // 002 §5.1 L2846 EU
    Def::link("EU", Link::Rising, &CONNECT, edge).steps(Steps::Fixed(2)),
    // 002 §5.1 L2860 ED
    Def::link("ED", Link::Falling, &CONNECT, edge).steps(Steps::Fixed(2)),
    // 002 §5.1 L2890 INV
    Def::link("INV", Link::Invert, &CONNECT, edge).steps(Steps::Fixed(1)),
    // 002 §5.1 L2956 NOP
    Def::link("NOP", Link::Nothing, &CONNECT, nop).steps(Steps::Fixed(1)),
    // 002 §5.1 L2972 MC
    Def::lower("MC", Class::Output, &MASTER, mc).steps(Steps::Fixed(3)),
    // 002 §5.1 L2984 MCR
    Def::lower("MCR", Class::Standalone, &MASTER, mcr).steps(Steps::Fixed(1)),
];

fn contact(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    if !c.count(i, u.m, &[1]) {
        return;
    }
    let r = resolve::bit(c.map, &i.operands[0].text, BitUse::Contact);
    let Some(BitArg::Bit(b)) = at(c, &i.operands[0], r) else {
        return;
    };
    let (join, op) = match u.m {
        "LD" => (Join::Load, Op::Ld(b)),
        "LDI" => (Join::Load, Op::Ldi(b)),
        "AND" => (Join::And, Op::And(b)),
        "ANI" => (Join::And, Op::Ani(b)),
        "OR" => (Join::Or, Op::Or(b)),
        "ORI" => (Join::Or, Op::Ori(b)),
        _ => return c.unmatched(u),
    };
    c.contact(i, join, op);
}

/// `RST T`/`RST C` (L2932): the contact and the current value (both words of
/// C200-C255).
#[derive(Debug)]
struct ResetTc {
    contact: u32,
    value: u32,
    words: u32,
}

impl Instr for ResetTc {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), softplc_ir::fault::Fault> {
        cx.mem.bits[self.contact as usize] = false;
        let v = self.value as usize;
        cx.mem.words[v..v + self.words as usize].fill(0);
        Ok(())
    }
}

fn coil(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let kind = match u.m {
        "OUT" => CoilKind::Out,
        "SET" => CoilKind::Set,
        "RST" => CoilKind::Rst,
        _ => return c.unmatched(u),
    };
    if !c.count(i, u.m, &[1]) || !c.output(i, u.m) {
        return;
    }
    let tok = &i.operands[0];
    let what = if kind == CoilKind::Out {
        BitUse::Coil
    } else {
        BitUse::SetRst
    };
    let r = resolve::bit(c.map, &tok.text, what);
    let Some(BitArg::Bit(b)) = at(c, tok, r) else {
        return;
    };
    let dev = parse_device(&tok.text.to_ascii_uppercase()).ok().flatten();
    match (kind, dev) {
        (CoilKind::Out, _) => {
            c.emit(Op::Out(b));
        }
        (CoilKind::Set, _) => {
            c.emit(Op::Set(b));
        }
        (_, Some(d)) if matches!(d.dev, Dev::T | Dev::C) => {
            let (kind, n, words) = match d.dev {
                Dev::T => (DeviceKind::TN, d.n, 1),
                _ => (
                    DeviceKind::CN,
                    counter_word(d.n),
                    if is_counter32(d.n) { 2 } else { 1 },
                ),
            };
            let x = ResetTc {
                contact: b,
                value: c.map.base(kind) + n,
                words,
            };
            let at = c.ext.len() as u32;
            c.ext.push(Box::new(x));
            c.emit(Op::Ext(at));
        }
        _ => {
            c.emit(Op::Coil(Box::new(Coil {
                kind: CoilKind::Rst,
                dst: BitArg::Bit(b),
            })));
        }
    }
}

/// ANB, ORB (L2757-2782): the rung-stack rules of `softplc_lang::rung`.
fn anb_orb(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let op = match u.m {
        "ANB" => RungStack::Anb,
        "ORB" => RungStack::Orb,
        _ => return c.unmatched(u),
    };
    if !i.operands.is_empty() {
        c.err(
            &i.operands[0],
            format!(
                "`{}` takes no operand (an erratum in the APLC programming manual §5.1.8, §5.1.9)",
                u.m
            ),
        );
        return;
    }
    c.rung_stack(i, u.m, op, MPS_LIMIT);
}

/// MPS, MRD, MPP (L2791-2820): the rung-stack rules of `softplc_lang::rung`.
fn mps(c: &mut Compiler<'_>, u: &Use<'_>) {
    let op = match u.m {
        "MPS" => RungStack::Mps,
        "MRD" => RungStack::Mrd,
        "MPP" => RungStack::Mpp,
        _ => return c.unmatched(u),
    };
    if c.count(u.instr, u.m, &[0]) {
        c.rung_stack(u.instr, u.m, op, MPS_LIMIT);
    }
}

/// EU/ED (rising/falling edge of the power flow, per instance) and INV.
fn edge(c: &mut Compiler<'_>, u: &Use<'_>) {
    let (i, m) = (u.instr, u.m);
    if !c.count(i, m, &[0]) || !c.need_rung(i, m) {
        return;
    }
    c.after_output = false;
    let op = match m {
        "INV" => Op::Inv,
        "EU" => Op::Mep(c.slot()),
        "ED" => Op::Mef(c.slot()),
        _ => return c.unmatched(u),
    };
    c.emit(op);
}

fn nop(c: &mut Compiler<'_>, u: &Use<'_>) {
    if c.count(u.instr, u.m, &[0]) {
        c.emit(Op::Nop);
    }
}

fn mc(c: &mut Compiler<'_>, u: &Use<'_>) {
    let (i, m) = (u.instr, u.m);
    if !c.count(i, m, &[1]) || !c.output(i, m) {
        return;
    }
    let tok = &i.operands[0];
    let Some(n) = at(c, tok, resolve::number(&tok.text, 0, 7)) else {
        return;
    };
    if let Some((_, t)) = c.mc_open.iter().find(|(l, _)| *l == n) {
        let line = t.line;
        c.err(
            tok,
            format!(
                "MC {n} is already open (line {line}): nested MC need different numbers (APLC programming manual §5.2.2)"
            ),
        );
        return;
    }
    // The engine's level is the nesting depth (the APLC numbers are names).
    let level = c.mc_open.len() as u32;
    c.mc_open.push((n, tok.clone()));
    let dst = BitArg::Bit(c.map.base(DeviceKind::V) + level);
    c.emit(Op::Mc(Box::new(MasterControl {
        level: level as u8,
        dst,
    })));
}

fn mcr(c: &mut Compiler<'_>, u: &Use<'_>) {
    let (i, m) = (u.instr, u.m);
    if !c.count(i, m, &[1]) || !c.standalone(i, m) {
        return;
    }
    let tok = &i.operands[0];
    let Some(n) = at(c, tok, resolve::number(&tok.text, 0, 7)) else {
        return;
    };
    match c.mc_open.iter().position(|(l, _)| *l == n) {
        Some(p) if p + 1 == c.mc_open.len() => {
            c.mc_open.pop();
            c.emit(Op::Mcr(p as u8));
        }
        Some(_) => c.err(
            tok,
            format!("MCR {n} crosses an inner MC: structures may not cross (APLC programming manual §5.2.2)"),
        ),
        None => c.err(tok, format!("MCR {n} without a matching MC {n}")),
    }
}
