//! Sequence instructions (PM ch. 5): contacts, connection instructions, coils,
//! timers and counters, annunciators, master control and END. The compiler
//! lowers them into the ladder machine's own ops; their run-time behaviour is
//! in the interpreter and [`super::sequence`].

use super::annunciator::{Annunciator, Coil as AnnCoil, Ledr, List};
use softplc_ir::device::{parse_operand, Constant, DeviceKind, Operand};
use softplc_ir::kernels::basic::Move;
use softplc_ir::ops::*;
use softplc_lang::compile::{Compiler, MAX_MPS};
use softplc_lang::isa::{Class, CoilRole, Def, Doc, Link, Pulse, Steps, Test, Use};
use softplc_lang::resolve::timer_slot;
use softplc_lang::rung::{MpsLimit, RungStack};
use softplc_lang::Token;

/// The sequence instructions.
pub static DEFS: &[Def] = &[
    Def::contact("LD", Join::Load, Test::Open, &CONTACTS, contact).steps(Steps::Basic),
    Def::contact("LDI", Join::Load, Test::Closed, &CONTACTS, contact).steps(Steps::Basic),
    Def::contact("AND", Join::And, Test::Open, &CONTACTS, contact).steps(Steps::Basic),
    Def::contact("ANI", Join::And, Test::Closed, &CONTACTS, contact).steps(Steps::Basic),
    Def::contact("OR", Join::Or, Test::Open, &CONTACTS, contact).steps(Steps::Basic),
    Def::contact("ORI", Join::Or, Test::Closed, &CONTACTS, contact).steps(Steps::Basic),
    Def::contact("LDP", Join::Load, Test::Rising, &EDGE_CONTACTS, contact).steps(Steps::Basic),
    Def::contact("LDF", Join::Load, Test::Falling, &EDGE_CONTACTS, contact).steps(Steps::Basic),
    Def::contact("ANDP", Join::And, Test::Rising, &EDGE_CONTACTS, contact).steps(Steps::Basic),
    Def::contact("ANDF", Join::And, Test::Falling, &EDGE_CONTACTS, contact).steps(Steps::Basic),
    Def::contact("ORP", Join::Or, Test::Rising, &EDGE_CONTACTS, contact).steps(Steps::Basic),
    Def::contact("ORF", Join::Or, Test::Falling, &EDGE_CONTACTS, contact).steps(Steps::Basic),
    Def::link("ANB", Link::BlockAnd, &CONNECTION, anb_orb).steps(Steps::Basic),
    Def::link("ORB", Link::BlockOr, &CONNECTION, anb_orb).steps(Steps::Basic),
    Def::link("MPS", Link::Push, &CONNECTION, mps).steps(Steps::Basic),
    Def::link("MRD", Link::Read, &CONNECTION, mps).steps(Steps::Basic),
    Def::link("MPP", Link::Pop, &CONNECTION, mps).steps(Steps::Basic),
    Def::link("INV", Link::Invert, &CONNECTION_2, inv_mep).steps(Steps::Basic),
    Def::link("MEP", Link::Rising, &CONNECTION_2, inv_mep).steps(Steps::Basic),
    Def::link("MEF", Link::Falling, &CONNECTION_2, inv_mep).steps(Steps::Basic),
    Def::link("EGP", Link::Rising, &CONNECTION_2, egp).steps(Steps::Basic),
    Def::link("EGF", Link::Falling, &CONNECTION_2, egp).steps(Steps::Basic),
    Def::coil("OUT", CoilRole::Out, &COILS, out).steps(Steps::Rule(out_steps)),
    Def::coil("SET", CoilRole::Set, &COILS, set_rst).steps(Steps::Basic),
    Def::coil("RST", CoilRole::Reset, &COILS, set_rst).steps(Steps::Rule(rst_steps)),
    Def::coil("PLS", CoilRole::Pulse, &COILS, pls).steps(Steps::Fixed(2)),
    Def::coil("PLF", CoilRole::Pulse, &COILS, pls).steps(Steps::Fixed(2)),
    Def::coil("FF", CoilRole::Pulse, &COILS, pls).steps(Steps::Fixed(2)),
    Def::lower("OUTH", Class::Output, &TIMERS, out).steps(Steps::Rule(outh_steps)),
    Def::lower("LEDR", Class::Output, &ANNUNCIATORS, |c, u| {
        ledr(c, u, true)
    }),
    Def::lower("ANS", Class::Output, &ANNUNCIATORS, ans),
    Def::lower("ANR", Class::Output, &ANNUNCIATORS, |c, u| {
        ledr(c, u, false)
    })
    .pulse(Pulse::Suffix),
    Def::lower("MC", Class::Output, &MASTER_CONTROL, mc).steps(Steps::Fixed(2)),
    Def::lower("MCR", Class::Standalone, &MASTER_CONTROL, mcr).steps(Steps::Basic),
    Def::lower("NOP", Class::Standalone, &END, nop).steps(Steps::Basic),
    Def::lower("END", Class::Standalone, &END, end).steps(Steps::Basic),
    Def::lower("FEND", Class::Standalone, &END, end).steps(Steps::Basic),
];

/// The pulse NOT contacts of the Universal models (registered in
/// [`crate::qnu`], rejected on the other CPUs).
pub static QNU_DEFS: &[Def] = &[
    Def::contact(
        "LDPI",
        Join::Load,
        Test::NotRising,
        &PULSE_NOT_CONTACTS,
        contact,
    )
    .steps(Steps::Basic),
    Def::contact(
        "LDFI",
        Join::Load,
        Test::NotFalling,
        &PULSE_NOT_CONTACTS,
        contact,
    )
    .steps(Steps::Basic),
    Def::contact(
        "ANDPI",
        Join::And,
        Test::NotRising,
        &PULSE_NOT_CONTACTS,
        contact,
    )
    .steps(Steps::Basic),
    Def::contact(
        "ANDFI",
        Join::And,
        Test::NotFalling,
        &PULSE_NOT_CONTACTS,
        contact,
    )
    .steps(Steps::Basic),
    Def::contact(
        "ORPI",
        Join::Or,
        Test::NotRising,
        &PULSE_NOT_CONTACTS,
        contact,
    )
    .steps(Steps::Basic),
    Def::contact(
        "ORFI",
        Join::Or,
        Test::NotFalling,
        &PULSE_NOT_CONTACTS,
        contact,
    )
    .steps(Steps::Basic),
];

static CONTACTS: Doc = Doc {
    family: "contact",
    cite: "PM §5.1 contact instructions",
    notes: "bit devices, word bit `D0.F`, index `X0Z1`",
};
static EDGE_CONTACTS: Doc = Doc {
    family: "contact (edge)",
    cite: "PM §5.1",
    notes: "one hidden edge memory per instruction",
};
/// SH-080809ENG §5.1.3: LDPI/ANDPI/ORPI are OFF only on the scan the device
/// rises (OFF→ON) and ON otherwise; LDFI/ANDFI/ORFI OFF only on the scan it
/// falls. The negation of LDP/LDF, on the same hidden edge memory.
static PULSE_NOT_CONTACTS: Doc = Doc {
    family: "contact (pulse NOT, QnU)",
    cite: "SH-080809ENG §5.1.3",
    notes: "Universal models only; OFF only on the rising (…PI) or falling (…FI) edge; one hidden edge memory per instruction",
};
static CONNECTION: Doc = Doc {
    family: "connection",
    cite: "PM §5.2",
    notes: "≤16 open blocks / MPS levels, checked at load",
};
static CONNECTION_2: Doc = Doc {
    family: "connection",
    cite: "PM §5.2; 004 §10.2.5 (V)",
    notes: "EGP/EGF on V without index",
};
static COILS: Doc = Doc {
    family: "output",
    cite: "PM §5.3",
    notes: "X may be written (004 L6085); RST of T/ST/C clears value and contact, of a word writes 0; OUT T/ST/C with a set value: see timers and counters",
};
static TIMERS: Doc = Doc {
    family: "timer",
    cite: "004 §10.2.10",
    notes: "OUT T/ST n (100 ms / 10 ms bases, configurable), OUTH T/ST n (high speed); see decisions. OUT C n: counter (004 §10.2.11), counts on the coil's rising edge; set value 0 counts as 1",
};
static ANNUNCIATORS: Doc = Doc {
    family: "annunciator",
    cite: "004 §10.2.4",
    notes: "OUT/SET/RST F, SD62-SD79 list, SM62, error 9000 logged; ANS = OUT T + SET F on the timer's contact; LEDR clears a continuation error that outranks the annunciators (SD207-SD209) first, ANR annunciators only",
};
static MASTER_CONTROL: Doc = Doc {
    family: "master control",
    cite: "PM §5.5",
    notes: "N0-N14, ascending nesting checked at load; OFF: coils OFF, timers reset, SET/RST/counters hold",
};
static END: Doc = Doc {
    family: "termination / other",
    cite: "PM §5.6-5.7; 004 §4.1",
    notes: "missing END is a load error (4010)",
};

/// OUT: 4 steps with a set value (OUT T/C), else the basic rule.
fn out_steps(ops: &[Token]) -> u32 {
    if ops.len() == 2 {
        4
    } else {
        softplc_lang::isa::basic_steps(ops)
    }
}

/// OUTH: 4 steps with a set value, else 1 + operands.
fn outh_steps(ops: &[Token]) -> u32 {
    if ops.len() == 2 {
        4
    } else {
        1 + ops.len() as u32
    }
}

/// RST: 2 steps for timers, counters and word devices, else the basic rule.
fn rst_steps(ops: &[Token]) -> u32 {
    let u = ops
        .first()
        .map(|t| t.text.to_ascii_uppercase())
        .unwrap_or_default();
    if ["T", "C", "ST", "D", "W", "R"]
        .iter()
        .any(|p| u.starts_with(p))
    {
        2
    } else {
        softplc_lang::isa::basic_steps(ops)
    }
}

/// Every contact: LD/AND/OR, with `I` negated (LDI, ANI, ORI), `P`/`F` on
/// an edge, `PI`/`FI` the negation of the edge (the QnU's LDPI … ORFI,
/// [`QNU_DEFS`]).
fn contact(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    let (join, negate, edge) = match m {
        "LD" => (Join::Load, false, Edge::None),
        "LDI" => (Join::Load, true, Edge::None),
        "AND" => (Join::And, false, Edge::None),
        "ANI" => (Join::And, true, Edge::None),
        "OR" => (Join::Or, false, Edge::None),
        "ORI" => (Join::Or, true, Edge::None),
        "LDP" => (Join::Load, false, Edge::Rising),
        "LDF" => (Join::Load, false, Edge::Falling),
        "ANDP" => (Join::And, false, Edge::Rising),
        "ANDF" => (Join::And, false, Edge::Falling),
        "ORP" => (Join::Or, false, Edge::Rising),
        "ORF" => (Join::Or, false, Edge::Falling),
        "LDPI" => (Join::Load, true, Edge::Rising),
        "LDFI" => (Join::Load, true, Edge::Falling),
        "ANDPI" => (Join::And, true, Edge::Rising),
        "ANDFI" => (Join::And, true, Edge::Falling),
        "ORPI" => (Join::Or, true, Edge::Rising),
        "ORFI" => (Join::Or, true, Edge::Falling),
        _ => return c.unmatched(u),
    };
    if !c.count(i, m, &[1]) {
        return;
    }
    let Some((src, direct)) = c.contact_operand(&ops[0]) else {
        c.contact_state(i, join);
        return;
    };
    // `DX<n>`: X<n> takes the module's value first, then the contact reads X.
    if let (true, BitArg::Bit(b)) = (direct, &src) {
        c.emit(Op::DirectIn(b - c.map.base(DeviceKind::X)));
    }
    let op = match (&src, edge) {
        (BitArg::Bit(b), Edge::None) => match (join, negate) {
            (Join::Load, false) => Op::Ld(*b),
            (Join::Load, true) => Op::Ldi(*b),
            (Join::And, false) => Op::And(*b),
            (Join::And, true) => Op::Ani(*b),
            (Join::Or, false) => Op::Or(*b),
            (Join::Or, true) => Op::Ori(*b),
        },
        _ => {
            let slot = if edge == Edge::None { 0 } else { c.slot() };
            Op::Contact(Box::new(Contact {
                join,
                negate,
                edge,
                slot,
                src,
            }))
        }
    };
    c.contact(i, join, op);
}

/// MPS nests 16 deep (PM §3.6).
const MPS_LIMIT: MpsLimit = MpsLimit {
    depth: MAX_MPS as usize,
    excess: "nested MPS",
};

/// ANB, ORB (PM §3.5): the rung-stack rules of `softplc_lang::rung`.
fn anb_orb(c: &mut Compiler<'_>, u: &Use<'_>) {
    let op = match u.m {
        "ANB" => RungStack::Anb,
        "ORB" => RungStack::Orb,
        _ => return c.unmatched(u),
    };
    if c.count(u.instr, u.m, &[0]) {
        c.rung_stack(u.instr, u.m, op, MPS_LIMIT);
    }
}

/// MPS, MRD, MPP (PM §3.6): the rung-stack rules of `softplc_lang::rung`.
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

fn inv_mep(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if !c.count(i, m, &[0]) || !c.need_rung(i, m) {
        return;
    }
    c.after_output = false;
    let op = match m {
        "INV" => Op::Inv,
        "MEP" => Op::Mep(c.slot()),
        "MEF" => Op::Mef(c.slot()),
        _ => return c.unmatched(u),
    };
    c.emit(op);
}

fn egp(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    let rising = match m {
        "EGP" => true,
        "EGF" => false,
        _ => return c.unmatched(u),
    };
    if !c.count(i, m, &[1]) || !c.need_rung(i, m) {
        return;
    }
    c.after_output = false;
    if let Some(v) = c.edge_relay(&ops[0]) {
        c.emit(Op::EdgeRelay { rising, v });
    }
}

fn set_rst(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    let reset = match m {
        "SET" => false,
        "RST" => true,
        _ => return c.unmatched(u),
    };
    if !c.count(i, m, &[1]) || !c.output(i, m) {
        return;
    }
    if let Some(n) = annunciator(c, &ops[0]) {
        let coil = if reset { AnnCoil::Rst } else { AnnCoil::Set };
        annunciator_coil(c, coil, n);
        return;
    }
    if reset {
        rst(c, &ops[0]);
        return;
    }
    if let Some(dst) = c.bit_dest(&ops[0]) {
        match dst {
            BitArg::Bit(b) => c.emit(Op::Set(b)),
            dst => c.emit(Op::Coil(Box::new(Coil {
                kind: CoilKind::Set,
                dst,
            }))),
        };
    }
}

fn pls(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    let kind: fn(u32) -> CoilKind = match m {
        "PLS" => CoilKind::Pls,
        "PLF" => CoilKind::Plf,
        "FF" => CoilKind::Ff,
        _ => return c.unmatched(u),
    };
    if !c.count(i, m, &[1]) || !c.output(i, m) {
        return;
    }
    if let Some(dst) = c.bit_dest(&ops[0]) {
        let kind = kind(c.slot());
        c.emit(Op::Coil(Box::new(Coil { kind, dst })));
    }
}

/// LEDR (`errors_first`: a continuation error that outranks the
/// annunciators is cleared first) and ANR (annunciators only).
fn ledr(c: &mut Compiler<'_>, u: &Use<'_>, errors_first: bool) {
    let i = u.instr;
    let m = u.m;
    // ANR resets the annunciator shown first (SD62), as LEDR does for
    // annunciators; ANRP (its pulse form) on the rising edge.
    if c.count(i, m, &[0]) && c.output(i, m) {
        let x = Ledr {
            errors_first,
            f: c.map.base(DeviceKind::F) as usize,
            points: c.map.points(DeviceKind::F) as usize,
            list: List::of(c.map),
        };
        c.emit_instr(u.pulse, false, Box::new(x));
    }
}

fn mc(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if !c.count(i, m, &[2]) || !c.output(i, m) {
        return;
    }
    let level = c.nesting(&ops[0]);
    let dst = c.bit_dest(&ops[1]);
    if let Some(level) = level {
        if let Some((open, _)) = c.mc_open.last() {
            if level <= *open {
                let open = *open;
                c.err(
                    &ops[0],
                    format!("MC N{level} inside MC N{open}: nesting numbers must ascend"),
                );
            }
        }
        c.mc_open.push((level, ops[0].clone()));
        if let Some(dst) = dst {
            c.emit(Op::Mc(Box::new(MasterControl {
                level: level as u8,
                dst,
            })));
        }
    }
}

fn mcr(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let ops = &u.instr.operands;
    if !c.count(i, m, &[1]) || !c.standalone(i, m) {
        return;
    }
    if let Some(level) = c.nesting(&ops[0]) {
        match c.mc_open.iter().position(|(l, _)| *l == level) {
            Some(p) => c.mc_open.truncate(p),
            None => c.err(
                &ops[0],
                format!("MCR N{level} without a matching MC N{level}"),
            ),
        }
        c.emit(Op::Mcr(level as u8));
    }
}

fn nop(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    if c.count(i, m, &[0]) {
        c.emit(Op::Nop);
    }
}

fn end(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let m = u.m;
    let fend = match m {
        "END" => false,
        "FEND" => true,
        _ => return c.unmatched(u),
    };
    if !c.count(i, m, &[0]) || !c.standalone(i, m) {
        return;
    }
    if fend {
        c.fend_seen = true;
        c.emit(Op::Fend);
    } else {
        c.emit(Op::End);
        c.end_seen = Some(i.mnemonic.clone());
    }
}

fn out(c: &mut Compiler<'_>, u: &Use<'_>) {
    let (i, m) = (u.instr, u.m);
    let ops = &i.operands;
    let high_speed = match m {
        "OUT" => false,
        "OUTH" => true,
        _ => return c.unmatched(u),
    };
    if ops.is_empty() {
        c.count(i, m, &[1, 2]);
        return;
    }
    if !c.output(i, m) {
        return;
    }
    let op0 = match parse_operand(&ops[0].text) {
        Ok(o) => o,
        Err(e) => return c.err(&ops[0], e.message),
    };
    let tc = match &op0 {
        Operand::Device {
            dev,
            digits: None,
            bit: None,
            index,
        } if matches!(dev.kind, DeviceKind::TS | DeviceKind::STS | DeviceKind::CS)
            && dev.generic =>
        {
            Some((*dev, *index))
        }
        _ => None,
    };
    let Some((dev, index)) = tc else {
        if high_speed {
            return c.err(
                &ops[0],
                format!("OUTH needs a timer (T or ST), found `{}`", ops[0].text),
            );
        }
        if ops.len() != 1 {
            return c.err(&ops[1], format!("`OUT {}` takes no set value", ops[0].text));
        }
        if let Some(n) = annunciator(c, &ops[0]) {
            annunciator_coil(c, AnnCoil::Out, n);
            return;
        }
        if let Some(dst) = c.bit_dest(&ops[0]) {
            match dst {
                BitArg::Bit(b) => c.emit(Op::Out(b)),
                dst => c.emit(Op::Coil(Box::new(Coil {
                    kind: CoilKind::Out,
                    dst,
                }))),
            };
        }
        return;
    };
    if index.is_some() {
        return c.err(
            &ops[0],
            "unsupported: index modification of a timer or counter coil",
        );
    }
    let name = dev
        .kind
        .format(dev.number)
        .replace("TS", "T")
        .replace("CS", "C");
    if ops.len() != 2 {
        return c.err(
            &ops[0],
            format!(
                "`{m} {}` needs a set value, e.g. `{m} {} K10`",
                ops[0].text, ops[0].text
            ),
        );
    }
    let counter = dev.kind == DeviceKind::CS;
    if counter && high_speed {
        return c.err(&i.mnemonic, "OUTH is for timers; counters use OUT");
    }
    let (coil_k, value_k) = match dev.kind {
        DeviceKind::TS => (DeviceKind::TC, DeviceKind::TN),
        DeviceKind::STS => (DeviceKind::STC, DeviceKind::STN),
        _ => (DeviceKind::CC, DeviceKind::CN),
    };
    let Some(contact) = c.map.index(dev.kind, dev.number) else {
        return c.range_err(&ops[0], dev.kind, dev.number, &name);
    };
    let set = set_value(c, &ops[1]);
    let coil = c.map.base(coil_k) + dev.number;
    let value = c.map.base(value_k) + dev.number;
    let Some(set) = set else { return };
    if counter {
        c.emit(Op::Counter(Box::new(Counter {
            coil,
            contact,
            value,
            set,
        })));
    } else {
        let retentive = dev.kind == DeviceKind::STS;
        let slot = timer_slot(c.map, retentive, dev.number);
        c.emit(Op::Timer(Box::new(Timer {
            coil,
            contact,
            value,
            slot,
            set,
            high_speed,
            retentive,
        })));
    }
}

/// `ANS T n F`: annunciator F is set when the condition has been ON for
/// n × 100 ms, timed by timer T (004 §10.2.4; PM ANS). Compiled as `OUT T n`
/// followed by `SET F` driven by the timer's contact, leaving the rung's
/// operation result unchanged (MPS … MPP).
fn ans(c: &mut Compiler<'_>, u: &Use<'_>) {
    let i = u.instr;
    let ops = &i.operands;
    if !c.count(i, "ANS", &[3]) || !c.output(i, "ANS") {
        return;
    }
    let timer = match parse_operand(&ops[0].text) {
        Ok(Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) if dev.generic && dev.kind == DeviceKind::TS => dev,
        _ => return c.err(&ops[0], format!("`{}`: ANS needs a timer T", ops[0].text)),
    };
    let Some(n) = annunciator(c, &ops[2]) else {
        return c.err(
            &ops[2],
            format!("`{}`: ANS needs an annunciator F", ops[2].text),
        );
    };
    let Some(contact) = c.map.index(DeviceKind::TS, timer.number) else {
        return c.range_err(&ops[0], DeviceKind::TS, timer.number, &ops[0].text);
    };
    let Some(set) = set_value(c, &ops[1]) else {
        return;
    };
    c.emit(Op::Timer(Box::new(Timer {
        coil: c.map.base(DeviceKind::TC) + timer.number,
        contact,
        value: c.map.base(DeviceKind::TN) + timer.number,
        slot: timer_slot(c.map, false, timer.number),
        set,
        high_speed: false,
        retentive: false,
    })));
    c.emit(Op::Mps);
    c.emit(Op::Ld(contact));
    annunciator_coil(c, AnnCoil::Set, n);
    c.emit(Op::Mpp);
}

/// `Fn` written plainly: OUT/SET/RST make it an annunciator (004 §10.2.4).
/// OUT (at every execution), SET or RST of annunciator F`n`.
fn annunciator_coil(c: &mut Compiler<'_>, coil: AnnCoil, n: u16) {
    let x = Annunciator {
        coil,
        n,
        f: (c.map.base(DeviceKind::F) + n as u32) as usize,
        list: List::of(c.map),
    };
    c.emit_instr(false, coil == AnnCoil::Out, Box::new(x));
}

fn annunciator(c: &mut Compiler<'_>, tok: &Token) -> Option<u16> {
    match parse_operand(&tok.text) {
        Ok(Operand::Device {
            dev,
            digits: None,
            bit: None,
            index: None,
        }) if dev.kind == DeviceKind::F && dev.number < c.map.points(DeviceKind::F) => {
            Some(dev.number as u16)
        }
        _ => None,
    }
}

/// RST of a word device: writes 0 (inline for a plain word).
fn clear_word(c: &mut Compiler<'_>, d: WordArg) {
    match d {
        WordArg::Word(d) => {
            c.emit(Op::MovK { k: 0, d });
        }
        d => {
            let x = Move {
                words: 1,
                s: WordArg::Const(0),
                d,
            };
            c.emit_instr(false, false, Box::new(x));
        }
    }
}

fn set_value(c: &mut Compiler<'_>, tok: &Token) -> Option<WordArg> {
    if let Ok(Operand::Const(Constant::Int { value, .. })) = parse_operand(&tok.text) {
        if !(0..=32767).contains(&value) {
            c.err(
                tok,
                format!("set value `{}` out of range (K0-K32767)", tok.text),
            );
            return None;
        }
    }
    c.word_src(tok, Num::I16)
}

fn rst(c: &mut Compiler<'_>, tok: &Token) {
    let op = match parse_operand(&tok.text) {
        Ok(o) => o,
        Err(e) => return c.err(tok, e.message),
    };
    if let Operand::Device {
        dev,
        digits: None,
        bit: None,
        index: None,
    } = &op
    {
        let timer = match dev.kind {
            DeviceKind::TS | DeviceKind::TC | DeviceKind::TN => {
                Some((DeviceKind::TS, DeviceKind::TN, false))
            }
            DeviceKind::STS | DeviceKind::STC | DeviceKind::STN => {
                Some((DeviceKind::STS, DeviceKind::STN, true))
            }
            DeviceKind::CS | DeviceKind::CC | DeviceKind::CN => {
                Some((DeviceKind::CS, DeviceKind::CN, false))
            }
            _ => None,
        };
        if let Some((ck, vk, retentive)) = timer {
            if dev.kind == DeviceKind::TN && !dev.generic
                || dev.kind == DeviceKind::CN
                || dev.kind == DeviceKind::STN
            {
                // RST TN0: clear the current value word only.
            } else {
                let Some(contact) = c.map.index(ck, dev.number) else {
                    return c.range_err(tok, ck, dev.number, &tok.text);
                };
                let slot = if ck == DeviceKind::CS {
                    u32::MAX
                } else {
                    timer_slot(c.map, retentive, dev.number)
                };
                let x = ResetTc {
                    contact,
                    value: c.map.base(vk) + dev.number,
                    slot,
                };
                c.emit_instr(false, false, Box::new(x));
                return;
            }
        }
        if !dev.kind.is_bit() || dev.generic {
            // RST of a word device writes 0.
            if let Some(d) = c.word_dest(tok, Num::I16, 1) {
                clear_word(c, d);
            }
            return;
        }
    }
    if let Operand::Device {
        dev,
        bit: None,
        digits: None,
        ..
    } = &op
    {
        if !dev.kind.is_bit() {
            if let Some(d) = c.word_dest(tok, Num::I16, 1) {
                clear_word(c, d);
            }
            return;
        }
    }
    if let Some(dst) = c.bit_dest(tok) {
        match dst {
            BitArg::Bit(b) => c.emit(Op::Rst(b)),
            dst => c.emit(Op::Coil(Box::new(Coil {
                kind: CoilKind::Rst,
                dst,
            }))),
        };
    }
}
