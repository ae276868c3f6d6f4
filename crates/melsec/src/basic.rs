//! Basic instructions (PM ch. 6): comparison contacts, BIN and real arithmetic,
//! MOV and the BIN/real conversions. The compiler lowers them into the ladder
//! machine's ops; their run-time kernels are `softplc_ir::kernels::basic`.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::instr::Instr;
use softplc_ir::kernels::basic::{test, Arith, Flt, Int, Move, Step};
use softplc_ir::ops::*;
use softplc_lang::compile::{Args, Compiler};
use softplc_lang::isa::{Class, Def, Doc, Pulse, Test, Use};

// ------------------------------------------------------------ definitions

/// What the comparison contacts compare: 16-bit, 32-bit (`D`), real (`E`)
/// and strings (`$`, an instruction's computed condition).
const CMP16: Test = Test::Compare(Num::I16);
const CMP32: Test = Test::Compare(Num::I32);
const CMP_REAL: Test = Test::Compare(Num::F32);
const CMP_STRING: Test = Test::Computed;

/// Comparison contacts, string comparison contacts, BIN/real arithmetic, MOV
/// and the BIN/real conversions (PM §6.1-6.4).
pub static DEFS: &[Def] = &[
    Def::contact("LD=", Join::Load, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LD<>", Join::Load, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LD>", Join::Load, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LD<=", Join::Load, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LD<", Join::Load, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LD>=", Join::Load, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDD=", Join::Load, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDD<>", Join::Load, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDD>", Join::Load, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDD<=", Join::Load, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDD<", Join::Load, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDD>=", Join::Load, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDE=", Join::Load, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDE<>", Join::Load, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDE>", Join::Load, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDE<=", Join::Load, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDE<", Join::Load, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LDE>=", Join::Load, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("AND=", Join::And, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("AND<>", Join::And, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("AND>", Join::And, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("AND<=", Join::And, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("AND<", Join::And, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("AND>=", Join::And, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDD=", Join::And, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDD<>", Join::And, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDD>", Join::And, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDD<=", Join::And, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDD<", Join::And, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDD>=", Join::And, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDE=", Join::And, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDE<>", Join::And, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDE>", Join::And, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDE<=", Join::And, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDE<", Join::And, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ANDE>=", Join::And, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("OR=", Join::Or, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("OR<>", Join::Or, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("OR>", Join::Or, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("OR<=", Join::Or, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("OR<", Join::Or, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("OR>=", Join::Or, CMP16, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORD=", Join::Or, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORD<>", Join::Or, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORD>", Join::Or, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORD<=", Join::Or, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORD<", Join::Or, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORD>=", Join::Or, CMP32, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORE=", Join::Or, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORE<>", Join::Or, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORE>", Join::Or, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORE<=", Join::Or, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORE<", Join::Or, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("ORE>=", Join::Or, CMP_REAL, &COMPARE, compare_contact).no_pulse(),
    Def::contact("LD$=", Join::Load, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact(
        "LD$<>",
        Join::Load,
        CMP_STRING,
        &STRING_COMPARE,
        str_compare,
    )
    .no_pulse(),
    Def::contact("LD$>", Join::Load, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact(
        "LD$<=",
        Join::Load,
        CMP_STRING,
        &STRING_COMPARE,
        str_compare,
    )
    .no_pulse(),
    Def::contact("LD$<", Join::Load, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact(
        "LD$>=",
        Join::Load,
        CMP_STRING,
        &STRING_COMPARE,
        str_compare,
    )
    .no_pulse(),
    Def::contact("AND$=", Join::And, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact(
        "AND$<>",
        Join::And,
        CMP_STRING,
        &STRING_COMPARE,
        str_compare,
    )
    .no_pulse(),
    Def::contact("AND$>", Join::And, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact(
        "AND$<=",
        Join::And,
        CMP_STRING,
        &STRING_COMPARE,
        str_compare,
    )
    .no_pulse(),
    Def::contact("AND$<", Join::And, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact(
        "AND$>=",
        Join::And,
        CMP_STRING,
        &STRING_COMPARE,
        str_compare,
    )
    .no_pulse(),
    Def::contact("OR$=", Join::Or, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact("OR$<>", Join::Or, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact("OR$>", Join::Or, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact("OR$<=", Join::Or, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact("OR$<", Join::Or, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::contact("OR$>=", Join::Or, CMP_STRING, &STRING_COMPARE, str_compare).no_pulse(),
    Def::lower("MOV", Class::Output, &MOV, |c, u| {
        application(c, u, App::Mov(Num::I16))
    })
    .pulse(Pulse::Suffix),
    Def::lower("DMOV", Class::Output, &MOV, |c, u| {
        application(c, u, App::Mov(Num::I32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("EMOV", Class::Output, &MOV, |c, u| {
        application(c, u, App::Mov(Num::F32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("+", Class::Output, &BIN16, |c, u| {
        application(c, u, App::Arith(ArithOp::Add, Num::I16))
    })
    .pulse(Pulse::Suffix),
    Def::lower("-", Class::Output, &BIN16, |c, u| {
        application(c, u, App::Arith(ArithOp::Sub, Num::I16))
    })
    .pulse(Pulse::Suffix),
    Def::lower("*", Class::Output, &BIN16, |c, u| {
        application(c, u, App::Arith(ArithOp::Mul, Num::I16))
    })
    .pulse(Pulse::Suffix),
    Def::lower("/", Class::Output, &BIN16, |c, u| {
        application(c, u, App::Arith(ArithOp::Div, Num::I16))
    })
    .pulse(Pulse::Suffix),
    Def::lower("D+", Class::Output, &BIN32, |c, u| {
        application(c, u, App::Arith(ArithOp::Add, Num::I32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("D-", Class::Output, &BIN32, |c, u| {
        application(c, u, App::Arith(ArithOp::Sub, Num::I32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("D*", Class::Output, &BIN32, |c, u| {
        application(c, u, App::Arith(ArithOp::Mul, Num::I32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("D/", Class::Output, &BIN32, |c, u| {
        application(c, u, App::Arith(ArithOp::Div, Num::I32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("E+", Class::Output, &REAL, |c, u| {
        application(c, u, App::Arith(ArithOp::Add, Num::F32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("E-", Class::Output, &REAL, |c, u| {
        application(c, u, App::Arith(ArithOp::Sub, Num::F32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("E*", Class::Output, &REAL, |c, u| {
        application(c, u, App::Arith(ArithOp::Mul, Num::F32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("E/", Class::Output, &REAL, |c, u| {
        application(c, u, App::Arith(ArithOp::Div, Num::F32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("INC", Class::Output, &INC, |c, u| {
        application(c, u, App::Step(Num::I16, 1))
    })
    .pulse(Pulse::Suffix),
    Def::lower("DEC", Class::Output, &INC, |c, u| {
        application(c, u, App::Step(Num::I16, -1))
    })
    .pulse(Pulse::Suffix),
    Def::lower("DINC", Class::Output, &INC, |c, u| {
        application(c, u, App::Step(Num::I32, 1))
    })
    .pulse(Pulse::Suffix),
    Def::lower("DDEC", Class::Output, &INC, |c, u| {
        application(c, u, App::Step(Num::I32, -1))
    })
    .pulse(Pulse::Suffix),
    Def::lower("FLT", Class::Output, &FLT, |c, u| {
        application(c, u, App::Flt(Num::I16))
    })
    .pulse(Pulse::Suffix),
    Def::lower("DFLT", Class::Output, &FLT, |c, u| {
        application(c, u, App::Flt(Num::I32))
    })
    .pulse(Pulse::Suffix),
    Def::lower("INT", Class::Output, &FLT, |c, u| {
        application(c, u, App::Int(Num::I16))
    })
    .pulse(Pulse::Suffix),
    Def::lower("DINT", Class::Output, &FLT, |c, u| {
        application(c, u, App::Int(Num::I32))
    })
    .pulse(Pulse::Suffix),
];

static COMPARE: Doc = Doc {
    family: "comparison",
    cite: "PM §6.1",
    notes:
        "LD/AND/OR with = <> > <= < >=; D: 32-bit, E: real; signed BIN; real: ±∞/NaN operand → 4100",
};
static STRING_COMPARE: Doc = Doc {
    family: "string comparison",
    cite: "PM §6.1",
    notes: "character codes, then length; no NUL → 4101",
};
static BIN16: Doc = Doc {
    family: "BIN 16-bit arithmetic",
    cite: "PM §6.2",
    notes: "2 and 3 operands; wrap; 32-bit product; quotient+remainder; ÷0 → 4100; digit destination K1-K8 (quotient only for /). The 2-operand `*` and `/` are accepted as an extension (D = D op S)",
};
static BIN32: Doc = Doc {
    family: "BIN 32-bit arithmetic",
    cite: "PM §6.2",
    notes: "64-bit product; quotient+remainder",
};
static REAL: Doc = Doc {
    family: "real arithmetic",
    cite: "PM §6.2; 004 §2.8",
    notes: "overflow/÷0/invalid input → 4100, underflow → 0",
};
static INC: Doc = Doc {
    family: "BIN increment",
    cite: "PM §6.2",
    notes: "wrap",
};
static FLT: Doc = Doc {
    family: "real conversion",
    cite: "PM §6.3",
    notes: "INT rounds half away from zero; out of range → 4100",
};
static MOV: Doc = Doc {
    family: "transfer",
    cite: "PM §6.4",
    notes: "digit spec K1-K4 / K1-K8; EMOV copies bits",
};

/// The application instructions the compiler lowers itself (MOV runs inline).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum App {
    Mov(Num),
    Arith(ArithOp, Num),
    Step(Num, i32),
    Flt(Num),
    Int(Num),
}

fn compare_contact(c: &mut Compiler<'_>, u: &Use<'_>) {
    let (i, m) = (u.instr, u.m);
    let Some((join, num, op)) = parse_compare(m) else {
        return c.unmatched(u);
    };
    if !c.count(i, m, &[2]) {
        c.contact_state(i, join);
        return;
    }
    let a = c.word_src(&i.operands[0], num);
    let b = c.word_src(&i.operands[1], num);
    let (Some(a), Some(b)) = (a, b) else {
        c.contact_state(i, join);
        return;
    };
    c.contact(
        i,
        join,
        Op::Compare(Box::new(Compare {
            join,
            op,
            num,
            a,
            b,
        })),
    );
}

fn application(c: &mut Compiler<'_>, u: &Use<'_>, app: App) {
    let (i, m, pulse) = (u.instr, u.m, u.pulse);
    let ops = &i.operands;
    let ok_count = match app {
        App::Mov(_) | App::Flt(_) | App::Int(_) => c.count(i, m, &[2]),
        App::Arith(..) => c.count(i, m, &[2, 3]),
        App::Step(..) => c.count(i, m, &[1]),
    };
    if !ok_count || !c.output(i, m) {
        return;
    }
    let x: Box<dyn Instr> = match app {
        App::Mov(num) => {
            let s = c.word_src(&ops[0], num);
            let d = c.word_dest(&ops[1], num, num.words());
            let (Some(s), Some(d)) = (s, d) else { return };
            match (&s, &d, num) {
                (WordArg::Const(k), WordArg::Word(d), Num::I16) => {
                    return c.pulsed(
                        pulse,
                        Op::MovK {
                            k: *k as u16,
                            d: *d,
                        },
                    )
                }
                (WordArg::Word(s), WordArg::Word(d), Num::I16) => {
                    return c.pulsed(pulse, Op::MovW { s: *s, d: *d })
                }
                (WordArg::Word(s), WordArg::Word(d), _) => {
                    return c.pulsed(pulse, Op::MovD { s: *s, d: *d })
                }
                (WordArg::Const(k), WordArg::Word(d), _) => {
                    return c.pulsed(pulse, Op::MovDK { k: *k, d: *d })
                }
                _ => Box::new(Move {
                    words: num.words() as u8,
                    s,
                    d,
                }),
            }
        }
        App::Arith(op, num) => {
            let dest_words = match (op, num) {
                (ArithOp::Mul | ArithOp::Div, Num::I16) => 2,
                (ArithOp::Mul | ArithOp::Div, Num::I32) => 4,
                _ => num.words(),
            };
            // A digit-specified `*`/`/` destination takes K1-K8 (the 32-bit
            // product or the quotient).
            let dest_num = match (op, num) {
                (ArithOp::Mul | ArithOp::Div, Num::I16) => Num::I32,
                _ => num,
            };
            let (s1, s2, d) = if ops.len() == 3 {
                (
                    c.word_src(&ops[0], num),
                    c.word_src(&ops[1], num),
                    c.word_dest(&ops[2], dest_num, dest_words),
                )
            } else {
                (
                    c.word_src(&ops[1], num),
                    c.word_src(&ops[0], num),
                    c.word_dest(&ops[1], dest_num, dest_words),
                )
            };
            let (Some(s1), Some(s2), Some(d)) = (s1, s2, d) else {
                return;
            };
            Box::new(Arith { op, num, s1, s2, d })
        }
        App::Step(num, delta) => {
            let Some(d) = c.word_dest(&ops[0], num, num.words()) else {
                return;
            };
            Box::new(Step::new(num, delta, d))
        }
        App::Flt(num) => {
            let s = c.word_src(&ops[0], num);
            let d = c.word_dest(&ops[1], Num::F32, 2);
            let (Some(s), Some(d)) = (s, d) else { return };
            Box::new(Flt { num, s, d })
        }
        App::Int(num) => {
            let s = c.word_src(&ops[0], Num::F32);
            let d = c.word_dest(&ops[1], num, num.words());
            let (Some(s), Some(d)) = (s, d) else { return };
            Box::new(Int { num, s, d })
        }
    };
    c.emit_instr(pulse, false, x);
}

/// `LD$=`, `AND$<>`, `OR$>` … → (join, operator).
fn parse_str_compare(m: &str) -> Option<(Join, CmpOp)> {
    let (join, rest) = if let Some(r) = m.strip_prefix("LD$") {
        (Join::Load, r)
    } else if let Some(r) = m.strip_prefix("AND$") {
        (Join::And, r)
    } else {
        (Join::Or, m.strip_prefix("OR$")?)
    };
    let op = match rest {
        "=" => CmpOp::Eq,
        "<>" => CmpOp::Ne,
        ">" => CmpOp::Gt,
        "<=" => CmpOp::Le,
        "<" => CmpOp::Lt,
        ">=" => CmpOp::Ge,
        _ => return None,
    };
    Some((join, op))
}

/// `LD=`, `ANDD<>`, `ORE>=` … → (join, number type, operator).
fn parse_compare(m: &str) -> Option<(Join, Num, CmpOp)> {
    let (join, rest) = if let Some(r) = m.strip_prefix("LD") {
        (Join::Load, r)
    } else if let Some(r) = m.strip_prefix("AND") {
        (Join::And, r)
    } else {
        (Join::Or, m.strip_prefix("OR")?)
    };
    let (num, rest) = match rest.as_bytes().first()? {
        b'D' => (Num::I32, &rest[1..]),
        b'E' => (Num::F32, &rest[1..]),
        _ => (Num::I16, rest),
    };
    let op = match rest {
        "=" => CmpOp::Eq,
        "<>" => CmpOp::Ne,
        ">" => CmpOp::Gt,
        "<=" => CmpOp::Le,
        "<" => CmpOp::Lt,
        ">=" => CmpOp::Ge,
        _ => return None,
    };
    Some((join, num, op))
}
/// `LD$= S1 S2` and friends: a string comparison contact.
fn str_compare(c: &mut Compiler<'_>, u: &Use<'_>) {
    let (i, m) = (u.instr, u.m);
    let Some((join, op)) = parse_str_compare(m) else {
        return c.unmatched(u);
    };
    let cmp = {
        let mut args = Args::new(c, i, m);
        super::strings::StrCompare::compile(&mut args)
    };
    match cmp {
        Some(cmp) => c.contact(
            i,
            join,
            Op::Cond(Box::new(CondOp {
                join,
                cond: Box::new(StrCondition { op, cmp }),
            })),
        ),
        None => {
            c.contact_state(i, join);
        }
    }
}

/// A string comparison contact: the strings' order tested against the operator.
#[derive(Debug)]
struct StrCondition {
    op: CmpOp,
    cmp: super::strings::StrCompare,
}

impl Condition for StrCondition {
    fn eval(&self, mem: &DeviceMemory) -> Result<bool, Fault> {
        Ok(test(self.op, self.cmp.ordering(mem)?))
    }
}
