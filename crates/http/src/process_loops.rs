//! Faceplates of the process CPU's loops (000 §3.3.5): every loop tag that
//! the program's loop instructions own as their D2 (the loop memory their
//! definitions declare: `process::tag::LOOP_TAG`), with SV/PV/MV, MODE and
//! ALM, and the loop's constants, all from the declared layout the
//! instructions use (`process::tag::LoopTag`), so the page and the
//! instructions read the same words.

use softplc_core::instructions::process::tag::LOOP_TAG;
use softplc_ir::layout::{Field, FieldType};
use softplc_ir::listing::LoopUse;

use crate::ladder::LadderProgram;

/// One loop tag and the instructions that share it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProcessLoop {
    pub file: String,
    /// The loop tag's head device (`R1000`).
    pub tag: String,
    /// The instructions that own it, upper case, in program order.
    pub instructions: Vec<String>,
}

/// The loop tags of `programs`, in order of first use (see [`find_in`]).
pub fn find(programs: &[LadderProgram]) -> Vec<ProcessLoop> {
    find_in(
        programs
            .iter()
            .map(|p| (p.file.as_str(), p.loops.as_slice())),
    )
}

/// The loop tags of programs given as (file, loop memories), in order of
/// first use.
pub fn find_in<'a>(
    programs: impl IntoIterator<Item = (&'a str, &'a [LoopUse])>,
) -> Vec<ProcessLoop> {
    let mut out: Vec<ProcessLoop> = Vec::new();
    for (file, loops) in programs {
        for u in loops.iter().filter(|u| u.memory.is(&LOOP_TAG)) {
            let tag = u.block.to_ascii_uppercase();
            let m = u.mnemonic.to_ascii_uppercase();
            match out.iter_mut().find(|l| l.tag == tag) {
                Some(l) if !l.instructions.contains(&m) => l.instructions.push(m),
                Some(_) => {}
                None => out.push(ProcessLoop {
                    file: file.to_string(),
                    tag,
                    instructions: vec![m],
                }),
            }
        }
    }
    out
}

impl ProcessLoop {
    /// The device name of a layout field (`R1014:f32`).
    pub fn field(&self, f: &Field) -> Option<String> {
        let d = crate::loops::offset(&self.tag, f.offset as u64)?;
        Some(match f.ty {
            FieldType::F32 => format!("{d}:f32"),
            _ => d,
        })
    }

    /// The device name of the layout field `name`.
    pub fn named(&self, name: &str) -> Option<String> {
        self.field(LOOP_TAG.field(name)?)
    }

    /// The constants shown and editable on the faceplate: the loop-tag
    /// memory below the past values, other than what the bars and flags show.
    pub fn params(&self) -> Vec<(&'static str, String)> {
        const SHOWN: &[&str] = &["mode", "alm", "inh", "pv", "mv", "sv", "dv", "mvp"];
        LOOP_TAG
            .fields
            .iter()
            .filter(|f| f.offset < 96 && !SHOWN.contains(&f.name))
            .filter_map(|f| Some((f.name, self.field(f)?)))
            .collect()
    }
}

/// Appends the faceplates of `loops` to `body` and their devices to `names`.
pub fn render(loops: &[ProcessLoop], names: &mut Vec<String>, body: &mut String) {
    use std::fmt::Write;
    let esc = crate::pages::esc;
    for l in loops {
        let (Some(sv), Some(pv), Some(mv), Some(mode), Some(alm)) = (
            l.named("sv"),
            l.named("pv"),
            l.named("mv"),
            l.named("mode"),
            l.named("alm"),
        ) else {
            continue;
        };
        let _ = write!(
            body,
            r#"<div class="card loop"><h3>loop tag {t}</h3><p class="hint">{f}: {i}</p>
<table class="fp"><tr><th>SV</th><td class="v edit" data-v="{sv}"></td><td><div class="barbox"><div class="bar sv" data-bar="{sv}" data-scale="100"></div></div></td></tr>
<tr><th>PV</th><td class="v" data-v="{pv}"></td><td><div class="barbox"><div class="bar pv" data-bar="{pv}" data-scale="100"></div></div></td></tr>
<tr><th>MV %</th><td class="v edit" data-v="{mv}"></td><td><div class="barbox"><div class="bar mv" data-bar="{mv}" data-scale="100"></div></div></td></tr>
<tr><th>MODE</th><td class="v edit" data-v="{mode}"></td><td class="mode" data-pmode="{mode}"></td></tr>
<tr><th>ALM</th><td class="v edit" data-v="{alm}"></td><td class="alarm" data-palarm="{alm}"></td></tr></table>
<svg class="ltrend" width="320" height="90" data-scale="100" data-sv="{sv}" data-pv="{pv}" data-mv="{mv}"></svg>
<table class="prm">"#,
            t = esc(&l.tag),
            f = esc(&l.file),
            i = esc(&l.instructions.join(" → ")),
            sv = esc(&sv),
            pv = esc(&pv),
            mv = esc(&mv),
            mode = esc(&mode),
            alm = esc(&alm),
        );
        for (label, d) in l.params() {
            let _ = write!(
                body,
                r#"<tr><th>{}</th><td class="dn">{d}</td><td class="v edit" data-v="{d}"></td></tr>"#,
                esc(label),
                d = esc(&d)
            );
            names.push(d);
        }
        body.push_str("</table></div>");
        names.extend([sv, pv, mv, mode, alm]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loop_tags_from_the_loop_instructions_with_layout_fields() {
        let s = softplc_core::program::il::parse_il(
            "p.il",
            "LD SM400\nS.IN R0 R100 R200 R1000\nS.PID R40 R140 R240 R1000 SD1506\n\
             S.OUT1 R60 R160 R260 R1000\nS.2PID R440 R540 R640 D2000 SD1506\n\
             S.ADD R0 R2 R4 SD1506\nS.BC D0 D10 SD1506 D3000\n",
        )
        .unwrap();
        let loops = find(&[LadderProgram::from_source(&s)]);
        assert_eq!(loops.len(), 2, "{loops:?}");
        assert_eq!(loops[0].tag, "R1000");
        assert_eq!(loops[0].instructions, ["S.IN", "S.PID", "S.OUT1"]);
        assert_eq!(loops[1].tag, "D2000");
        assert_eq!(loops[0].named("sv").as_deref(), Some("R1014:f32"));
        assert_eq!(loops[0].named("mode").as_deref(), Some("R1001"));
        let p = loops[1].params();
        assert!(p.contains(&("p", "D2052:f32".to_string())), "{p:?}");
        assert!(p.contains(&("ct", "D2046:f32".to_string())));
        assert!(p.iter().all(|(n, _)| *n != "mv" && *n != "ct_flag"));
        let mut names = Vec::new();
        let mut body = String::new();
        render(&loops, &mut names, &mut body);
        assert!(body.contains(r#"data-pmode="R1001""#) && names.contains(&"D2010:f32".into()));
    }
}
