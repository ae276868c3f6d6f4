//! Loop faceplates (issue #15): the PID loops of the program (each
//! instruction whose loop memory keeps its loops' settings elsewhere:
//! PIDCONT / S.PIDCONT, with the PIDINIT / S.PIDINIT before it) with their
//! I/O data words (SV, PV, MV, MVMAN, MAN/AUTO, ALARM; 001 §5.2(4) Table
//! 5.4) and tuning parameters (001 §5.1 Table 5.2). Where each loop's words
//! are, and their labels, come from the loop memory the instructions declare
//! (`Program::listing`'s loops and their layouts). The number of loops is
//! read from the control data when the page is served.
//!
//! Parameters written here take effect when the program registers them again
//! (PIDINIT / PIDPRMW), as on the CPU.

use softplc_ir::layout::Field;
use softplc_ir::listing::{LoopMemory, LoopUse};

use crate::ladder::LadderProgram;

/// One PIDCONT and the PIDINIT that registers its loops.
#[derive(Clone, Debug)]
pub struct PidSet {
    pub file: String,
    /// `PIDCONT` or `S.PIDCONT` as written (upper case).
    pub mnemonic: String,
    /// The I/O data head (`D600`) and the control data head (`D500`).
    pub io: String,
    pub init: Option<String>,
    /// The I/O data's declaration; its `settings` the control data's.
    pub memory: &'static LoopMemory,
}

/// One loop's device names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loop {
    pub title: String,
    pub sv: String,
    pub pv: String,
    pub mv: String,
    pub mvman: String,
    pub mode: String,
    pub alarm: String,
    /// (label, device) of the tuning parameters.
    pub params: Vec<(&'static str, String)>,
}

/// The label a faceplate shows for a field: its doc up to the first `: `.
pub fn label(f: &Field) -> &'static str {
    let doc = f.doc.trim();
    doc.split_once(": ").map_or(doc, |(head, _)| head)
}

/// The PID loop sets of `programs` (see [`find_in`]).
pub fn find(programs: &[LadderProgram]) -> Vec<PidSet> {
    find_in(
        programs
            .iter()
            .map(|p| (p.file.as_str(), p.loops.as_slice())),
    )
}

/// The PID loop sets of programs given as (file, loop memories): each
/// instruction whose loop memory has its settings in another memory, with
/// the last block of that memory before it.
pub fn find_in<'a>(programs: impl IntoIterator<Item = (&'a str, &'a [LoopUse])>) -> Vec<PidSet> {
    let mut out = Vec::new();
    for (file, loops) in programs {
        for (k, u) in loops.iter().enumerate() {
            let Some(settings) = u.memory.settings else {
                continue;
            };
            let init = loops[..k]
                .iter()
                .rev()
                .find(|v| v.memory.is(settings))
                .map(|v| v.block.clone());
            out.push(PidSet {
                file: file.to_string(),
                mnemonic: u.mnemonic.to_ascii_uppercase(),
                io: u.block.clone(),
                init,
                memory: u.memory,
            });
        }
    }
    out
}

/// `D600` + `k` → `D610`, in the device's numbering.
pub(crate) fn offset(name: &str, k: u64) -> Option<String> {
    let (p, n) = crate::pages::split_name(name)?;
    let n = u32::try_from(n as u64 + k).ok()?;
    let s = if crate::pages::hex_kind(&p) {
        format!("{p}{n:X}")
    } else {
        format!("{p}{n}")
    };
    softplc_core::access::DeviceSpec::parse(&s).ok().map(|_| s)
}

impl PidSet {
    /// The device holding the number of loops (the control data's count
    /// word), if known.
    pub fn count_device(&self) -> Option<String> {
        let count = self.memory.settings?.count?;
        offset(self.init.as_ref()?, count as u64)
    }

    /// The words of loop `k` (0-based); `None` past the device's end.
    pub fn loop_at(&self, k: u32) -> Option<Loop> {
        let io = |name: &str| {
            let f = self.memory.field(name)?;
            offset(&self.io, self.memory.offset(k, f))
        };
        let mut params = Vec::new();
        if let (Some(init), Some(data)) = (&self.init, self.memory.settings) {
            for f in data.fields {
                params.push((label(f), offset(init, data.offset(k, f))?));
            }
        }
        Some(Loop {
            title: format!("{} {} loop {}", self.mnemonic, self.io, k as u64 + 1),
            sv: io("sv")?,
            pv: io("pv")?,
            mv: io("mv")?,
            mvman: io("mvman")?,
            mode: io("mode")?,
            alarm: io("alarm")?,
            params,
        })
    }
}

/// `/loops`: a faceplate per PID loop: SV/PV/MV bars and trend, mode,
/// alarms and the tuning parameters (click to change, with the token).
pub async fn page(
    axum::extract::State(app): axum::extract::State<std::sync::Arc<crate::App>>,
) -> axum::response::Response {
    use axum::response::IntoResponse;
    use std::fmt::Write;
    let ladder = app.ladder_now(0).await;
    let sets = find(&ladder);
    // The loop counts, from one END.
    let heads: Vec<Option<String>> = sets.iter().map(PidSet::count_device).collect();
    let counts = tokio::time::timeout(
        crate::api::END_WAIT,
        app.engine.at_end(move |s| {
            heads
                .iter()
                .map(|h| {
                    h.as_ref()
                        .and_then(|h| softplc_core::access::DeviceSpec::parse(h).ok())
                        .and_then(|d| s.cpu().read_device(&d).ok())
                        .and_then(|v| match v {
                            softplc_core::access::Value::Int(n) => Some(n.clamp(1, 32) as u32),
                            _ => None,
                        })
                        .unwrap_or(1)
                })
                .collect::<Vec<u32>>()
        }),
    )
    .await
    .ok()
    .and_then(Result::ok)
    .unwrap_or_default();
    let esc = crate::pages::esc;
    let mut names = Vec::new();
    let mut body = String::from(r#"<section class="cards">"#);
    let process = crate::process_loops::find(&ladder);
    if sets.is_empty() && process.is_empty() {
        body.push_str(
            "<p>No control loop (PIDCONT, S.PIDCONT, or a process-control loop tag) in the program.</p>",
        );
    }
    for (set, n) in sets
        .iter()
        .zip(counts.iter().copied().chain(std::iter::repeat(1)))
    {
        for k in 0..n {
            let Some(l) = set.loop_at(k) else { continue };
            let _ = write!(
                body,
                r#"<div class="card loop"><h3>{t}</h3><p class="hint">{f}</p>
<table class="fp"><tr><th>SV</th><td class="v edit" data-v="{sv}"></td><td><div class="barbox"><div class="bar sv" data-bar="{sv}"></div></div></td></tr>
<tr><th>PV</th><td class="v" data-v="{pv}"></td><td><div class="barbox"><div class="bar pv" data-bar="{pv}"></div></div></td></tr>
<tr><th>MV</th><td class="v" data-v="{mv}"></td><td><div class="barbox"><div class="bar mv" data-bar="{mv}"></div></div></td></tr>
<tr><th>MV man</th><td class="v edit" data-v="{mvman}"></td><td></td></tr>
<tr><th>mode</th><td class="v edit" data-v="{mode}"></td><td class="mode" data-mode="{mode}"></td></tr>
<tr><th>alarm</th><td class="v" data-v="{alarm}"></td><td class="alarm" data-alarm="{alarm}"></td></tr></table>
<svg class="ltrend" width="320" height="90" data-sv="{sv}" data-pv="{pv}" data-mv="{mv}"></svg>
<table class="prm">"#,
                t = esc(&l.title),
                f = esc(&set.file),
                sv = esc(&l.sv),
                pv = esc(&l.pv),
                mv = esc(&l.mv),
                mvman = esc(&l.mvman),
                mode = esc(&l.mode),
                alarm = esc(&l.alarm),
            );
            for (label, d) in &l.params {
                let _ = write!(
                    body,
                    r#"<tr><th>{}</th><td class="dn">{d}</td><td class="v edit" data-v="{d}"></td></tr>"#,
                    esc(label),
                    d = esc(d)
                );
                names.push(d.clone());
            }
            body.push_str("</table></div>");
            names.extend([l.sv, l.pv, l.mv, l.mvman, l.mode, l.alarm]);
        }
    }
    crate::process_loops::render(&process, &mut names, &mut body);
    body.push_str("</section>");
    crate::pages::frame(&app, "Loops", "loops", &names, &body).into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prog(src: &str) -> Vec<LadderProgram> {
        let s = softplc_core::program::il::parse_il("p.il", src).unwrap();
        vec![LadderProgram::from_source(&s)]
    }

    #[test]
    fn loops_of_both_families() {
        let sets = find(&prog(
            "LD X0\nPIDINIT D500\nLD SM400\nPIDCONT D600\nS.PIDINIT D700\nSP.PIDCONT D800\n",
        ));
        assert_eq!(sets.len(), 2);
        let l = sets[0].loop_at(1).unwrap();
        assert_eq!(
            (l.sv.as_str(), l.pv.as_str(), l.mv.as_str()),
            ("D628", "D629", "D630")
        );
        assert_eq!((l.mode.as_str(), l.alarm.as_str()), ("D633", "D634"));
        assert_eq!(l.params[0], ("action (0 fwd, 1 rev)", "D512".to_string()));
        assert_eq!(l.params.len(), 10);
        let s = sets[1].loop_at(0).unwrap();
        assert!(sets[1]
            .memory
            .is(&softplc_core::instructions::pid::S_PID_IO));
        assert_eq!(s.sv, "D810");
        assert_eq!(s.params[2].1, "D704");
        assert_eq!(s.params.last().unwrap().1, "D713");
        // Past any device number: no loop, no overflow.
        assert!(sets[0].loop_at(u32::MAX).is_none());
    }
}
