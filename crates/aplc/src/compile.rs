//! The `.apl` compiler driver: each POU's instructions through the APLC
//! [`Isa`](softplc_lang::isa::Isa) on the shared [`Compiler`] (rung
//! structure, ops, labels), with the APLC's rules: no END (MAIN ends with its
//! last instruction, an implicit END is appended), labels per POU, MAIN's
//! locals zeroed at each entry.

use softplc_ir::device::{DeviceKind, DeviceMap};
use softplc_ir::fault::Fault;
use softplc_ir::instr::{ExecCtx, Instr};
use softplc_ir::ops::{Op, Program};
use softplc_lang::compile::{Args, Compiler};
use softplc_lang::isa::{Drive, Found, Kind, Use};
use softplc_lang::{Diagnostic, Diagnostics, Source, SourceInstr, Token};

use crate::pou::{PouKind, Unit};

/// Clears LM and V when a POU is entered (L1910, L1938, contract §1.1 item 8).
#[derive(Debug)]
struct EnterPou {
    lm: (u32, u32),
    v: (u32, u32),
}

impl Instr for EnterPou {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        self.off(cx)
    }
    fn off(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        cx.mem.bits[self.lm.0 as usize..self.lm.1 as usize].fill(false);
        cx.mem.words[self.v.0 as usize..self.v.1 as usize].fill(0);
        Ok(())
    }
}

/// Compiles a parsed file.
pub fn compile(file: &str, unit: &Unit) -> Result<Program, Diagnostics> {
    let cfg = crate::devices::device_config();
    let map = DeviceMap::new(&cfg);
    let mut c = Compiler::new(file, &map, crate::dialect());
    for p in &unit.pous {
        let what = match p.kind {
            PouKind::Main => continue,
            PouKind::Sbr(_) => "subroutines",
            PouKind::Int { .. } => "interrupt routines",
        };
        c.err(
            &p.header,
            format!(
                "`{}`: {what} are not implemented yet in softplc",
                p.header.text
            ),
        );
    }
    let last = Token {
        text: String::new(),
        line: 1,
        col: 1,
    };
    let Some(main) = unit.pous.iter().find(|p| p.kind == PouKind::Main) else {
        c.err(&last, "the program has no instruction (an empty MAIN)");
        return finish(c, last);
    };
    let range = |k: DeviceKind| (map.base(k), map.base(k) + map.points(k));
    c.ext.push(Box::new(EnterPou {
        lm: range(DeviceKind::B),
        v: range(DeviceKind::W),
    }));
    c.emit(Op::ExtAlways(0));
    for i in &main.body {
        instr(&mut c, i);
    }
    let last = main
        .body
        .last()
        .map_or(main.header.clone(), |i| i.mnemonic.clone());
    finish(c, last)
}

fn instr(c: &mut Compiler<'_>, i: &SourceInstr) {
    let m = i.mnemonic.text.to_ascii_uppercase();
    c.cur_step = c.step;
    c.cur_line = i.mnemonic.line;
    let errors = c.diags.len();
    let (steps, class) = match crate::isa().lookup(&m) {
        Found::Def(def, false) => {
            let u = Use {
                def,
                instr: i,
                m: &m,
                pulse: false,
            };
            match def.kind {
                Kind::Lower(f) => f(c, &u),
                Kind::Rejected(why) => {
                    c.err(&i.mnemonic, format!("unsupported instruction `{m}`: {why}"))
                }
                Kind::Instr(compile) => {
                    if c.output(i, &m) {
                        let mut args = Args::new(c, i, &m);
                        if let Some(x) = compile(&mut args) {
                            let at = c.ext.len() as u32;
                            c.ext.push(x);
                            c.emit(match def.drive {
                                Drive::WhenOn => Op::Ext(at),
                                Drive::Always => Op::ExtAlways(at),
                            });
                        }
                    }
                }
            }
            (def.steps.count(&i.operands), Some(def.class))
        }
        _ if m == "END" => {
            c.err(&i.mnemonic, "unknown instruction `END`: the APLC has no END, a POU ends with its last line (L3676)");
            (1, None)
        }
        _ => {
            c.err(&i.mnemonic, format!("unknown instruction `{m}`"));
            (1, None)
        }
    };
    if c.diags.len() > errors {
        c.recover(class);
    }
    c.step = c.cur_step + steps;
}

fn finish(mut c: Compiler<'_>, last: Token) -> Result<Program, Diagnostics> {
    if c.has_rung && !c.after_output {
        c.err(&last, "the last contacts of the POU lead to no output");
    }
    c.close_rung(&last);
    for tok in std::mem::take(&mut c.for_open) {
        let at = Token {
            text: "FOR".into(),
            ..tok
        };
        c.err(&at, "FOR without its NEXT in this POU (L3580)");
    }
    for (n, tok) in std::mem::take(&mut c.mc_open) {
        c.err(&tok, format!("MC {n} without MCR {n}"));
    }
    let fixups = std::mem::take(&mut c.fixups);
    for (at, n, tok) in fixups {
        if c.labels.contains_key(&n) {
            c.fixups.push((at, n, tok));
        } else if n > 127 {
            // The skip of a FOR without NEXT, reported above.
        } else {
            c.err(&tok, format!("CJ {n}: no LBL {n} in this POU (L3646)"));
        }
    }
    c.cur_line = last.line;
    c.cur_step = c.step;
    c.emit(Op::End);
    c.end_seen = Some(last.clone());
    let src = Source {
        file: c.file.to_string(),
        items: Vec::new(),
    };
    c.finish(&src)
}

/// A diagnostic for the whole file (no position).
pub fn file_error(file: &str, message: String) -> Diagnostics {
    Diagnostics(vec![Diagnostic {
        file: file.to_string(),
        line: 0,
        col: 0,
        message,
    }])
}
