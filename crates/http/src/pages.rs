//! The pages (issue #15; contract §3.1 says only that `/` is the ladder
//! monitor): server-rendered HTML with one small hand-written script
//! (`/monitor.js`) that takes live values from the SSE stream, colours the
//! ladder and fills the device tables, and sends writes with the token the
//! user typed (kept in `sessionStorage`, sent as `Authorization: Bearer`,
//! never a cookie).

use crate::ladder::LadderProgram;
use std::collections::HashMap;
use std::fmt::Write;
use std::sync::Arc;

use axum::extract::{Query, State};
use axum::http::{header, StatusCode};
use axum::response::{Html, IntoResponse, Response};

use crate::ladder::render;
use crate::App;

/// Rungs per ladder page (a large program pages instead of freezing the browser).
pub const RUNGS_PER_PAGE: usize = 60;
/// Rows of a device batch monitor.
pub const MAX_ROWS: u32 = 256;

type Q = Query<HashMap<String, String>>;

pub(crate) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The page frame: navigation, the CPU bar (state, scan, buttons, token).
pub(crate) fn frame(
    app: &App,
    title: &str,
    page: &str,
    names: &[String],
    body: &str,
) -> Html<String> {
    frame_at(app, 0, title, page, names, body)
}

/// [`frame`] of CPU `cpu` (0-based): a multi-CPU system's pages have a tab
/// per CPU with its state, and the bar and buttons are that CPU's.
pub(crate) fn frame_at(
    app: &App,
    cpu: usize,
    title: &str,
    page: &str,
    names: &[String],
    body: &str,
) -> Html<String> {
    let mut uniq: Vec<&str> = Vec::new();
    for n in names.iter().take(crate::values::MAX_NAMES) {
        if !uniq.contains(&n.as_str()) {
            uniq.push(n);
        }
    }
    let ro = if app.cfg.token.is_none() {
        r#"<span class="ro" title="started without --http-token">read-only</span>"#
    } else {
        r#"<label>token <input id="token" type="password" size="12" autocomplete="off"></label>"#
    };
    let nav = [
        ("/", "Ladder"),
        ("/overview", "Overview"),
        ("/devices", "Devices"),
        ("/trend", "Trend"),
        ("/loops", "Loops"),
    ]
    .iter()
    .map(|(h, t)| {
        let cls = if *t == title { " class=\"cur\"" } else { "" };
        format!(r#"<a href="{h}"{cls}>{t}</a>"#)
    })
    .collect::<String>();
    let (cpu_attrs, tabs) = if app.cpus() > 1 {
        let tabs: String = (1..=app.cpus())
            .map(|n| {
                let cls = if n == cpu + 1 { " cur" } else { "" };
                format!(
                    r#"<a href="/?cpu={n}" class="cpu-tab{cls}">CPU {n} <span class="state" id="cpu-state-{n}">?</span></a>"#
                )
            })
            .collect();
        (
            format!(
                r#" data-cpu="{}" data-prefix="{}""#,
                cpu + 1,
                crate::values::cpu_prefix(cpu)
            ),
            format!(r#"<span id="cpus">{tabs}</span>"#),
        )
    } else {
        (String::new(), String::new())
    };
    Html(format!(
        r#"<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>softplc · {title}</title>
<link rel="stylesheet" href="/monitor.css"></head>
<body data-page="{page}" data-names="{names}"{cpu_attrs}>
<header><b>softplc</b> <span id="model">{model}</span> <nav>{nav}</nav>{tabs}
<span id="cpu"><span id="state" class="state">?</span> scan <span id="scan">?</span>
 · <span id="stime">?</span> µs <span id="err"></span></span>
<span class="ops"><button data-op="run">RUN</button><button data-op="stop">STOP</button><button data-op="pause">PAUSE</button><button data-op="reset">RESET</button>
<button data-op="step" id="step">STEP</button><input id="nscans" type="number" min="1" max="10000" value="1" title="scans per step"> {ro}</span>
<span id="msg"></span></header>
<main>{body}</main>
<div id="menu" hidden></div>
<script src="/monitor.js"></script>
</body></html>"#,
        names = esc(&uniq.join(",")),
        model = esc(&app.cfg.model),
    ))
}

/// `/`: the ladder monitor (`?prog=I&page=P`; a multi-CPU system's CPU
/// `?cpu=N`, default 1).
pub async fn ladder(State(app): State<Arc<App>>, Query(q): Q) -> Response {
    let cpu = match crate::api::cpu_param(&app, &q) {
        Ok(c) => c,
        Err(r) => return r,
    };
    let progs = app.ladder_now(cpu).await;
    // Links keep the CPU; its names carry its prefix (none for CPU 1).
    let at = if cpu > 0 {
        format!("cpu={}&", cpu + 1)
    } else {
        String::new()
    };
    let prefix = crate::values::cpu_prefix(cpu);
    let pi: usize = q.get("prog").and_then(|p| p.parse().ok()).unwrap_or(0);
    let page: usize = q.get("page").and_then(|p| p.parse().ok()).unwrap_or(0);
    let mut body = String::new();
    body.push_str(r#"<div class="tabs">"#);
    for (i, p) in progs.iter().enumerate() {
        let cls = if i == pi { " class=\"cur\"" } else { "" };
        let name = short_file(&p.file);
        let _ = write!(
            body,
            r#"<a href="/?{at}prog={i}"{cls} title="{}">{}</a>"#,
            esc(&p.file),
            esc(&name)
        );
    }
    body.push_str("</div>");
    let Some(prog) = progs.get(pi) else {
        body.push_str("<p>No program to show.</p>");
        return frame_at(&app, cpu, "Ladder", "ladder", &[], &body).into_response();
    };
    let pages = prog.rungs.len().div_ceil(RUNGS_PER_PAGE).max(1);
    let page = page.min(pages - 1);
    if pages > 1 {
        body.push_str(r#"<div class="pager">"#);
        for k in 0..pages {
            let cls = if k == page { " class=\"cur\"" } else { "" };
            let _ = write!(
                body,
                r#"<a href="/?{at}prog={pi}&page={k}"{cls}>{}</a>"#,
                k + 1
            );
        }
        body.push_str("</div>");
    }
    if prog.rungs.is_empty() {
        body.push_str("<p>The program's source could not be read for the ladder.</p>");
    }
    let mut names = Vec::new();
    body.push_str(r#"<div id="ladder">"#);
    if page == 0 && !prog.comment.is_empty() {
        let _ = write!(
            body,
            r#"<pre class="note">{}</pre>"#,
            esc(&prog.comment.join("\n"))
        );
    }
    let first = page * RUNGS_PER_PAGE;
    for (k, r) in prog
        .rungs
        .iter()
        .enumerate()
        .skip(first)
        .take(RUNGS_PER_PAGE)
    {
        // A POU's heading where it starts (an empty POU's too), and the
        // current POU's above a page's first rung.
        let starting: Vec<_> = prog.sections.iter().filter(|s| s.first == k).collect();
        let carried = prog.sections.iter().rev().find(|s| s.first < k);
        let headings = match carried {
            Some(c) if k == first && starting.is_empty() => vec![c],
            _ => starting,
        };
        for s in headings {
            let _ = write!(body, r#"<h3 class="pou">{}</h3>"#, esc(&s.title));
            if !s.vars.is_empty() {
                let _ = write!(
                    body,
                    r#"<p class="vars">VAR {}</p>"#,
                    esc(&s.vars.join(" · "))
                );
            }
        }
        if !r.comment.is_empty() {
            let _ = write!(body, r#"<p class="note">{}</p>"#, esc(&r.comment.join(" ")));
        }
        r.for_each(&mut |e| {
            names.extend(
                e.watched()
                    .into_iter()
                    .filter(|n| !prog.unreadable.contains(n))
                    .map(|n| watched(&prefix, n, prog)),
            )
        });
        names.extend(r.bus.iter().map(|n| format!("{prefix}{n}")));
        body.push_str(&render::svg(r, pi, k));
    }
    body.push_str("</div>");
    frame_at(&app, cpu, "Ladder", "ladder", &names, &body).into_response()
}

/// The name a program's ladder watches for operand `n`: with the CPU's
/// prefix, and `@FILE` when the program has its own copy of it (a local
/// device), so that the page shows that program's values.
fn watched(prefix: &str, n: String, prog: &LadderProgram) -> String {
    if prog.local.contains(&n) {
        format!("{prefix}{n}@{}", short_file(&prog.file))
    } else {
        format!("{prefix}{n}")
    }
}

/// A program file's name without its directory.
fn short_file(file: &str) -> String {
    std::path::Path::new(file)
        .file_name()
        .map_or(file.to_string(), |n| n.to_string_lossy().into_owned())
}

/// `/ladder.txt?prog=I[&cpu=N]`: the ladder of program I as text, with the
/// device names of its dialect (what the snapshot tests compare).
pub async fn ladder_text(State(app): State<Arc<App>>, Query(q): Q) -> Response {
    let cpu = match crate::api::cpu_param(&app, &q) {
        Ok(c) => c,
        Err(r) => return r,
    };
    let pi: usize = q.get("prog").and_then(|p| p.parse().ok()).unwrap_or(0);
    let progs = app.ladder_now(cpu).await;
    match progs.get(pi) {
        Some(p) => (
            [(header::CONTENT_TYPE, "text/plain; charset=utf-8")],
            render::program_text(p),
        )
            .into_response(),
        None => crate::api::error(
            StatusCode::NOT_FOUND,
            format!("no program {pi}: there are {}", progs.len()),
        ),
    }
}

/// `/overview`: model, state, scan times, error and its history, forces, breakpoint.
pub async fn overview(State(app): State<Arc<App>>) -> Response {
    let body = r#"<section class="cards">
<div class="card"><h3>CPU</h3><table>
<tr><th>model</th><td id="o-model"></td></tr><tr><th>state</th><td id="o-state"></td></tr>
<tr><th>scan</th><td id="o-scan"></td></tr>
<tr><th>scan time µs</th><td>last <span id="o-last"></span> · min <span id="o-min"></span> · max <span id="o-max"></span></td></tr>
<tr><th>overruns</th><td id="o-over"></td></tr></table></div>
<div class="card"><h3>Error</h3><div id="o-error">none</div><h4>History</h4>
<table id="o-history"><thead><tr><th>time</th><th>code</th><th>message</th><th>step</th></tr></thead><tbody></tbody></table></div>
<div class="card"><h3>Forced</h3><div id="o-forced">none</div>
<p><input id="f-name" placeholder="X0" size="6"> <button id="f-on">force ON</button> <button id="f-off">force OFF</button> <button id="f-rel">release</button></p></div>
<div class="card"><h3>Breakpoint</h3><p>Pause at END when the condition becomes true.</p><div id="o-bp">none</div>
<p><input id="bp-when" placeholder="D0 >= 100" size="14"> <button id="bp-set">set</button> <button id="bp-clear">clear</button></p></div>
</section>"#;
    frame(&app, "Overview", "overview", &[], body).into_response()
}

/// Hexadecimal device kinds of MELSEC names (`--show` §2).
pub(crate) fn hex_kind(prefix: &str) -> bool {
    matches!(prefix, "X" | "Y" | "B" | "W" | "SB" | "SW" | "DX" | "DY")
}

/// `D100` → ("D", 100), `X1F` → ("X", 31), `U2\G10` → ("U2\G", 10): the
/// number after a unit's `\` for buffer memory; a CPU prefix stays with the
/// device (`CPU2/D5` → ("CPU2/D", 5)).
pub(crate) fn split_name(name: &str) -> Option<(String, u32)> {
    let u = name.trim().to_ascii_uppercase();
    if let Some((cpu, rest)) = u.split_once('/') {
        let (p, n) = split_name(rest)?;
        return Some((format!("{cpu}/{p}"), n));
    }
    let from = u.rfind('\\').map_or(0, |b| b + 1);
    let at = from + u[from..].find(|c: char| c.is_ascii_digit())?;
    let (p, n) = u.split_at(at);
    let n = if hex_kind(p) {
        u32::from_str_radix(n, 16).ok()?
    } else {
        n.parse().ok()?
    };
    Some((p.to_string(), n))
}

/// The names of a batch monitor: `count` points from `start` in `fmt`.
pub fn batch_names(start: &str, count: u32, fmt: &str) -> Result<Vec<String>, String> {
    let (p, n) = split_name(start)
        .ok_or_else(|| format!("`{start}`: expected a device such as D0 or X10"))?;
    let count = count.clamp(1, MAX_ROWS);
    let (step, suffix) = match fmt {
        "float" => (2, ":f32"),
        "str" => (8, ":str"),
        "hex" => (1, ":u16"),
        _ => (1, ""),
    };
    // `CPU2/` of a multi-CPU system's device.
    let (cpu, p) = match p.rsplit_once('/') {
        Some((c, d)) => (format!("{c}/"), d.to_string()),
        None => (String::new(), p),
    };
    softplc_core::system::names::split(&format!("{cpu}D0"), 4)?;
    let mut names = Vec::with_capacity(count as usize);
    for k in 0..count {
        let num = n + k * step;
        let name = if hex_kind(&p) {
            format!("{p}{num:X}")
        } else {
            format!("{p}{num}")
        };
        let bit = softplc_core::access::DeviceSpec::parse(&name)
            .map_err(|e| e.to_string())?
            .ty
            == softplc_core::access::ValueType::Bit;
        names.push(if bit {
            format!("{cpu}{name}")
        } else {
            format!("{cpu}{name}{suffix}")
        });
    }
    Ok(names)
}

/// `/devices?start=D0&count=32&fmt=dec|hex|float|str` or `?names=D0,M0`.
pub async fn devices(State(app): State<Arc<App>>, Query(q): Q) -> Response {
    let start = q.get("start").map_or("D0", String::as_str);
    let fmt = q.get("fmt").map_or("dec", String::as_str);
    let count: u32 = q.get("count").and_then(|c| c.parse().ok()).unwrap_or(32);
    let names = match q.get("names").filter(|n| !n.trim().is_empty()) {
        Some(list) => crate::values::prefixed_list(Some(list)),
        None => batch_names(start, count, fmt),
    };
    let names = match names {
        Ok(n) => n,
        Err(e) => {
            let mut r = frame(
                &app,
                "Devices",
                "devices",
                &[],
                &format!("<p class=\"bad\">{}</p>", esc(&e)),
            )
            .into_response();
            *r.status_mut() = StatusCode::BAD_REQUEST;
            return r;
        }
    };
    let sel = |v: &str| if v == fmt { " selected" } else { "" };
    let mut body = format!(
        r#"<form class="bar" method="get" action="/devices">start <input name="start" value="{}" size="8">
count <input name="count" type="number" min="1" max="{MAX_ROWS}" value="{count}">
<select name="fmt"><option value="dec"{}>decimal</option><option value="hex"{}>hex</option><option value="float"{}>float</option><option value="str"{}>string</option></select>
<button>show</button> · watch list <input name="names" value="{}" size="24" placeholder="D0,M0,D10:f32"></form>
<p class="hint">Click a value to change it (needs the token). X/Y: right-click to force.</p>
<table class="devs" data-fmt="{}"><thead><tr><th>device</th><th>value</th><th></th></tr></thead><tbody>"#,
        esc(start),
        sel("dec"),
        sel("hex"),
        sel("float"),
        sel("str"),
        esc(q.get("names").map_or("", String::as_str)),
        esc(fmt),
    );
    for n in &names {
        let _ = write!(
            body,
            r#"<tr><th>{n}</th><td class="v edit" data-v="{n}" data-fmt="{f}"></td><td class="fx" data-f="{n}"></td></tr>"#,
            n = esc(n),
            f = esc(fmt)
        );
    }
    body.push_str("</tbody></table>");
    frame(&app, "Devices", "devices", &names, &body).into_response()
}

/// `/trend?names=D0,D1`: a live trend of END samples (SVG polylines).
pub async fn trend(State(app): State<Arc<App>>, Query(q): Q) -> Response {
    let list = q.get("names").map_or("D0", String::as_str);
    let names: Vec<String> = match crate::values::prefixed_list(Some(list)) {
        Ok(v) => v.into_iter().take(8).collect(),
        Err(e) => {
            let mut r = frame(
                &app,
                "Trend",
                "trend",
                &[],
                &format!("<p class=\"bad\">{}</p>", esc(&e)),
            )
            .into_response();
            *r.status_mut() = StatusCode::BAD_REQUEST;
            return r;
        }
    };
    let body = format!(
        r#"<form class="bar" method="get" action="/trend">devices <input name="names" value="{}" size="30"> <button>show</button>
 <button type="button" id="t-pause">pause</button> <button type="button" id="t-csv">export CSV</button></form>
<svg id="trend" width="900" height="320" viewBox="0 0 900 320"></svg><div id="legend"></div>"#,
        esc(&names.join(","))
    );
    frame(&app, "Trend", "trend", &names, &body).into_response()
}

pub async fn script() -> Response {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        include_str!("static/monitor.js"),
    )
        .into_response()
}

pub async fn style() -> Response {
    (
        [(header::CONTENT_TYPE, "text/css; charset=utf-8")],
        include_str!("static/monitor.css"),
    )
        .into_response()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_names_follow_numbering_and_format() {
        assert_eq!(batch_names("D0", 3, "dec").unwrap(), ["D0", "D1", "D2"]);
        assert_eq!(
            batch_names("D10", 2, "float").unwrap(),
            ["D10:f32", "D12:f32"]
        );
        assert_eq!(batch_names("X8", 3, "hex").unwrap(), ["X8", "X9", "XA"]);
        assert_eq!(
            batch_names("W1E", 2, "hex").unwrap(),
            ["W1E:u16", "W1F:u16"]
        );
        assert!(batch_names("zz", 2, "dec").is_err());
        // A multi-CPU system's device keeps its CPU.
        assert_eq!(
            batch_names("CPU2/X8", 2, "hex").unwrap(),
            ["CPU2/X8", "CPU2/X9"]
        );
        assert_eq!(batch_names("cpu3/D0", 1, "dec").unwrap(), ["CPU3/D0"]);
        assert!(batch_names("CPU9/D0", 1, "dec").is_err());
        assert_eq!(
            batch_names("M0", 100_000, "dec").unwrap().len(),
            MAX_ROWS as usize
        );
    }
}
