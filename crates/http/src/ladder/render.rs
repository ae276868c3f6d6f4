//! Drawing a laid-out rung: as text (snapshot tests, `GET /ladder.txt`) and
//! as SVG for the ladder monitor. In the SVG every contact and coil is a
//! `<g class="el k-KIND" id="e{program}-{id}" data-dev="NAME">` and every
//! word operand value a `<text class="v" data-v="NAME">`, which the page's
//! script colours and fills from the SSE values (contract §3.1 events).

use std::fmt::Write;

use super::build::{Fan, Item, Net, Rung, RungBody};
use super::grid::{terminals, Cell, Feed, Grid, Link};
use super::{Elem, Kind, LadderProgram};

/// Characters per cell in the text drawing.
const TW: usize = 12;

fn short(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_string()
    } else {
        s.chars().take(n.saturating_sub(1)).chain(['~']).collect()
    }
}

fn text_of(e: &Elem) -> String {
    let op = e.operands.join(" ");
    match e.kind {
        Kind::No => format!("| {} |", short(&op, 6)),
        Kind::Nc => format!("|/{} |", short(&op, 6)),
        Kind::Rise => format!("|^{} |", short(&op, 6)),
        Kind::Fall => format!("|v{} |", short(&op, 6)),
        Kind::RiseNot => format!("|^/{} |", short(&op, 5)),
        Kind::FallNot => format!("|v/{} |", short(&op, 5)),
        Kind::Compare => format!(
            "[{} {}]",
            e.mnemonic
                .trim_start_matches(['L', 'D', 'A', 'N', 'O', 'R']),
            short(&op, 6)
        ),
        Kind::Modifier => format!("[{}]", e.mnemonic),
        Kind::Coil => format!("( {op} )"),
        Kind::Set => format!("(S {op})"),
        Kind::Reset => format!("(R {op})"),
        Kind::Box | Kind::Standalone => {
            format!("[{} {}]", e.mnemonic, e.labels()).replace(" ]", "]")
        }
        Kind::Step => format!("[STL {op}]"),
    }
}

/// The rung as text: `|` is the left rail, `+` a branch point.
pub fn text(g: &Grid) -> String {
    if let Some(e) = g.standalone {
        return format!("|{}\n", text_of(e));
    }
    let out_col = g.cols;
    let mut rows: Vec<Vec<char>> = vec![vec![' '; 1 + out_col * TW]; g.rows];
    for r in rows.iter_mut() {
        r[0] = '|';
    }
    let mut outs: Vec<String> = vec![String::new(); g.rows];
    for (r, c, cell) in &g.cells {
        if *c == out_col {
            if let Cell::Elem(e) = cell {
                outs[*r] = format!("-{}", text_of(e));
            }
            continue;
        }
        let s = match cell {
            Cell::Wire(_) => "-".repeat(TW),
            Cell::Elem(e) => {
                let t = short(&text_of(e), TW - 2);
                let pad = TW - t.chars().count();
                format!("{}{}{}", "-".repeat(pad / 2), t, "-".repeat(pad - pad / 2))
            }
        };
        for (k, ch) in s.chars().enumerate() {
            rows[*r][1 + c * TW + k] = ch;
        }
    }
    for &Link {
        col: c,
        top,
        bottom,
        ..
    } in &g.links
    {
        let pos = c * TW;
        for (r, row) in rows.iter_mut().enumerate().take(bottom + 1).skip(top) {
            if pos == 0 || pos >= row.len() {
                continue;
            }
            let branch = r == top || r == bottom || row.get(pos + 1) == Some(&'-');
            row[pos] = if branch { '+' } else { '|' };
        }
    }
    let mut s = String::new();
    for (row, out) in rows.iter().zip(&outs) {
        let line: String = row.iter().collect();
        let line = format!("{line}{out}");
        s.push_str(line.trim_end());
        s.push('\n');
    }
    s
}

/// A whole program as text (`GET /ladder.txt`): the file's comment, each
/// POU's heading with its variables, rung comments, the steps an SFC body
/// rung is in, and the rungs.
pub fn program_text(p: &LadderProgram) -> String {
    let mut out = String::new();
    for l in &p.comment {
        let _ = writeln!(out, "/* {l} */");
    }
    for (k, r) in p.rungs.iter().enumerate() {
        for s in p.sections.iter().filter(|s| s.first == k) {
            let head = format!("== {} {}", s.title, s.vars.join(", "));
            let _ = writeln!(out, "{}", head.trim_end());
        }
        for c in &r.comment {
            let _ = writeln!(out, "// {c}");
        }
        if !r.bus.is_empty() {
            let _ = writeln!(out, "(in step {})", r.bus.join(" "));
        }
        out += &text(&Grid::of(r));
    }
    out
}

/// Cell size in the SVG drawing, px.
pub const W: usize = 92;
pub const H: usize = 46;
/// Width of the output column.
const OUT_W: usize = 230;

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// One element as SVG at cell origin (x, y); `w` is its width.
fn elem_svg(out: &mut String, prog: usize, e: &Elem, x: usize, y: usize, w: usize) {
    let dev = e
        .operands
        .first()
        .filter(|d| e.names.device_type(d).is_some())
        .map_or("", String::as_str);
    // A comparison's operands as the script compares them (typed names).
    let ops: Vec<String> = (0..e.operands.len())
        .map(|k| match e.kind {
            Kind::Compare => e.word_value(k).unwrap_or_else(|| e.operands[k].clone()),
            _ => e.operands[k].clone(),
        })
        .collect();
    let mid = y + H / 2 + 4;
    let _ = write!(
        out,
        r#"<g class="el k-{}" id="e{prog}-{}" data-dev="{}" data-ops="{}" data-m="{}"{}><title>{} {} (line {})</title>"#,
        e.kind.as_str(),
        e.id,
        esc(dev),
        esc(&ops.join(" ")),
        esc(&e.mnemonic),
        // A word-bit contact: the script reads the bit out of the word.
        e.word_bit()
            .map_or(String::new(), |b| format!(r#" data-bit="{}""#, esc(b))),
        esc(&e.mnemonic),
        esc(&e.labels()),
        e.line
    );

    let cx = x + w / 2;
    match e.kind {
        Kind::No | Kind::Nc | Kind::Rise | Kind::Fall | Kind::RiseNot | Kind::FallNot => {
            let _ = write!(
                out,
                r#"<line class="w in" x1="{x}" y1="{mid}" x2="{}" y2="{mid}"/><line class="w out" x1="{}" y1="{mid}" x2="{}" y2="{mid}"/><rect class="sym" x="{}" y="{}" width="16" height="22"/>"#,
                cx - 8,
                cx + 8,
                x + w,
                cx - 8,
                mid - 11
            );
            let mark = match e.kind {
                Kind::Nc => format!(
                    r#"<line class="mk" x1="{}" y1="{}" x2="{}" y2="{}"/>"#,
                    cx - 8,
                    mid + 11,
                    cx + 8,
                    mid - 11
                ),
                Kind::Rise => format!(r#"<text class="mk" x="{cx}" y="{}">↑</text>"#, mid + 5),
                Kind::Fall => format!(r#"<text class="mk" x="{cx}" y="{}">↓</text>"#, mid + 5),
                // The edge mark struck through, as the programming tool draws it.
                Kind::RiseNot | Kind::FallNot => format!(
                    r#"<text class="mk" x="{cx}" y="{}">{}</text><line class="mk" x1="{}" y1="{}" x2="{}" y2="{}"/>"#,
                    mid + 5,
                    if e.kind == Kind::RiseNot {
                        '↑'
                    } else {
                        '↓'
                    },
                    cx - 8,
                    mid + 11,
                    cx + 8,
                    mid - 11
                ),
                _ => String::new(),
            };
            out.push_str(&mark);
            let _ = write!(
                out,
                r#"<text class="n" x="{cx}" y="{}">{}</text>"#,
                mid - 15,
                esc(&short(&e.labels(), 16))
            );
        }
        Kind::Coil | Kind::Set | Kind::Reset => {
            let letter = match e.kind {
                Kind::Set => "S",
                Kind::Reset => "R",
                _ => "",
            };
            let _ = write!(
                out,
                r#"<line class="w" x1="{x}" y1="{mid}" x2="{}" y2="{mid}"/><circle class="sym" cx="{}" cy="{mid}" r="11"/><text class="mk" x="{}" y="{}">{letter}</text><text class="n" x="{}" y="{}">{}</text>"#,
                x + 40,
                x + 51,
                x + 51,
                mid + 4,
                x + 51,
                mid - 15,
                esc(&e.labels())
            );
            if let Some(cv) = e.operands.first().and_then(|d| e.names.current_value(d)) {
                let _ = write!(
                    out,
                    r#"<text class="v" x="{}" y="{}" data-v="{}"></text>"#,
                    x + 70,
                    mid + 4,
                    esc(&cv)
                );
            }
        }
        _ => {
            // Boxes: comparison contacts, modifiers, application instructions.
            let bw = w - 8;
            let _ = write!(
                out,
                r#"<rect class="sym box" x="{}" y="{}" width="{bw}" height="{}"/><text class="bx" x="{}" y="{}">{} {}</text>"#,
                x + 4,
                y + 6,
                H - 10,
                x + 8,
                y + 20,
                esc(&e.mnemonic),
                esc(&short(
                    &e.labels(),
                    if matches!(e.kind, Kind::Box | Kind::Step) {
                        26
                    } else {
                        9
                    }
                ))
            );
            let mut vx = x + 8;
            for d in e.values() {
                let _ = write!(
                    out,
                    r#"<text class="v" x="{vx}" y="{}" data-v="{}"></text>"#,
                    y + 35,
                    esc(&d)
                );
                vx += 60;
            }
        }
    }
    out.push_str("</g>");
}

/// The rung's structure for the page's power-flow script: a net is an
/// element id, `{"s": [...]}` (series) or `{"p": [...]}` (parallel); a fan is
/// `{"f": net or null, "i": [output id or fan, ...]}`.
pub fn structure(rung: &Rung) -> serde_json::Value {
    use serde_json::json;
    fn net(n: &Net) -> serde_json::Value {
        match n {
            Net::Elem(e) => json!(e.id),
            Net::Series(v) => json!({ "s": v.iter().map(net).collect::<Vec<_>>() }),
            Net::Parallel(v) => json!({ "p": v.iter().map(net).collect::<Vec<_>>() }),
        }
    }
    fn fan(f: &Fan) -> serde_json::Value {
        let items: Vec<_> = f
            .items
            .iter()
            .map(|i| match i {
                Item::Out(e) => json!(e.id),
                Item::Fan(c) => fan(c),
            })
            .collect();
        json!({ "f": f.prefix.as_ref().map(net), "i": items })
    }
    match &rung.body {
        RungBody::Fan(f) => fan(f),
        RungBody::Standalone(_) => serde_json::Value::Null,
    }
}

/// Where a wire's power comes from, for the page's script: `data-into="ID"`
/// (the power into element ID) or `data-after="ID ID"` (the OR of those
/// elements' outputs).
fn feed_attr(feed: Option<&Feed>) -> String {
    match feed {
        Some(Feed::Into(id)) => format!(r#" data-into="{id}""#),
        Some(Feed::After(n)) => {
            let ids: Vec<String> = terminals(n).iter().map(u32::to_string).collect();
            format!(r#" data-after="{}""#, ids.join(" "))
        }
        None => String::new(),
    }
}

/// Rung `index` of program `prog` as SVG (the numbers make the element ids).
/// An SFC step's rung names its steps in `data-bus`: the script gives its
/// rail power only while they are all ON.
pub fn svg(rung: &Rung, prog: usize, index: usize) -> String {
    let g = Grid::of(rung);
    let (label, line) = (rung.label.as_deref(), rung.line);
    let left = 44;
    let width = left + g.cols * W + OUT_W;
    let height = g.rows * H + 8;
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg class="rung" id="r{prog}-{index}" data-line="{line}" width="{width}" height="{height}" viewBox="0 0 {width} {height}""#
    );
    if let Some(r) = g.rung {
        let _ = write!(s, r#" data-net="{}""#, esc(&structure(r).to_string()));
    }
    if !rung.bus.is_empty() {
        let _ = write!(s, r#" data-bus="{}""#, esc(&rung.bus.join(" ")));
    }
    s.push('>');
    let _ = write!(
        s,
        r#"<text class="ln" x="2" y="14">{}</text><line class="rail" x1="{}" y1="0" x2="{}" y2="{height}"/>"#,
        esc(label.unwrap_or(&line.to_string())),
        left - 2,
        left - 2
    );
    if let Some(e) = g.standalone {
        elem_svg(&mut s, prog, e, left, 0, OUT_W.max(2 * W));
        s.push_str("</svg>");
        return s;
    }
    for (r, c, cell) in &g.cells {
        let x = left + c * W;
        let y = r * H;
        match cell {
            Cell::Wire(feed) => {
                let mid = y + H / 2 + 4;
                let _ = write!(
                    s,
                    r#"<line class="w"{} x1="{x}" y1="{mid}" x2="{}" y2="{mid}"/>"#,
                    feed_attr(Some(feed)),
                    x + W
                );
            }
            Cell::Elem(e) if *c == g.cols => elem_svg(&mut s, prog, e, x, y, OUT_W - 6),
            Cell::Elem(e) => elem_svg(&mut s, prog, e, x, y, W),
        }
    }
    for l in &g.links {
        let x = if l.col == 0 {
            left - 2
        } else {
            left + l.col * W
        };
        let _ = write!(
            s,
            r#"<line class="w link"{} x1="{x}" y1="{}" x2="{x}" y2="{}"/>"#,
            feed_attr(l.feed.as_ref()),
            l.top * H + H / 2 + 4,
            l.bottom * H + H / 2 + 4
        );
    }
    s.push_str("</svg>");
    s
}
