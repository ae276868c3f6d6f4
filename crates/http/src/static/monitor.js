// softplc web monitor: live values from /api/v1/events (contract §3.1),
// writes with the bearer token typed in the header (sessionStorage, never a
// cookie). One hand-written script, no build step.
"use strict";
(function () {
  const $ = (s, r) => (r || document).querySelector(s);
  const $$ = (s, r) => Array.from((r || document).querySelectorAll(s));
  const page = document.body.dataset.page;
  const names = document.body.dataset.names;
  // A multi-CPU system: this page's CPU (1-based) and the prefix of its
  // names (none for CPU 1); the ladder shows its names without it.
  const cpu = document.body.dataset.cpu;
  const prefix = document.body.dataset.prefix || "";
  // A ladder watches a program's local devices as NAME@FILE; its
  // elements name them without the suffix.
  const local = {};
  (names || "").split(",").forEach((w) => { const m = /^(?:CPU\d\/)?(.*)@[^@]*$/i.exec(w); if (m) local[m[1]] = w; });
  const own = (n) => local[n] || (prefix && !/^CPU\d\//i.test(n) ? prefix + n : n);
  let values = {};
  let forced = {};

  const tokenInput = $("#token");
  if (tokenInput) {
    tokenInput.value = sessionStorage.getItem("softplc-token") || "";
    tokenInput.addEventListener("change", () => sessionStorage.setItem("softplc-token", tokenInput.value));
  }
  function say(text, bad) {
    const m = $("#msg");
    m.textContent = text;
    m.className = bad ? "bad" : "ok";
  }
  async function api(method, path, body) {
    const h = { "Content-Type": "application/json" };
    const t = tokenInput && tokenInput.value;
    if (t) h["Authorization"] = "Bearer " + t;
    const r = await fetch(path, { method, headers: h, credentials: "omit",
      body: body === undefined ? undefined : JSON.stringify(body) });
    let j = null;
    try { j = await r.json(); } catch (e) { j = { error: r.statusText }; }
    if (!r.ok) { say(r.status + ": " + (j && j.error), true); throw new Error(j && j.error); }
    return j;
  }
  window.softplc = { api, values: () => values };

  // --- the CPU bar and the overview ---
  function fmtErr(e) { return e ? e.code + " " + e.message + (e.file ? " (" + e.file + ":" + e.line + ")" : "") : "none"; }
  async function poll() {
    try {
      const r = await fetch("/api/v1/status", { credentials: "omit" });
      const all = await r.json();
      // The bar shows this page's CPU; each tab its CPU's state.
      (all.cpus || []).forEach((c) => {
        const el = $("#cpu-state-" + c.cpu);
        if (el) { el.textContent = c.state + (c.error ? " " + c.error.code : ""); el.className = "state s-" + c.state; }
      });
      const c = cpu && all.cpus ? all.cpus[Number(cpu) - 1] : null;
      const s = c ? Object.assign({}, all, { state: c.state, scan: c.scans, scan_time_us: c.scan_time_us, error: c.error, model: c.model, overruns: c.overruns }) : all;
      $("#state").textContent = s.state;
      $("#state").className = "state s-" + s.state;
      $("#scan").textContent = s.scan;
      $("#stime").textContent = s.scan_time_us.last + " (" + s.scan_time_us.min + "–" + s.scan_time_us.max + ")";
      $("#err").textContent = s.error ? "error " + fmtErr(s.error) : "";
      forced = s.forced || {};
      markForced();
      if (page === "overview") overview(s);
    } catch (e) { $("#state").textContent = "offline"; }
  }
  function overview(s) {
    const set = (id, v) => { const el = $("#" + id); if (el) el.textContent = v; };
    set("o-model", s.model); set("o-state", s.state); set("o-scan", s.scan);
    set("o-last", s.scan_time_us.last); set("o-min", s.scan_time_us.min); set("o-max", s.scan_time_us.max);
    set("o-over", s.overruns); set("o-error", fmtErr(s.error));
    const tb = $("#o-history tbody");
    tb.innerHTML = "";
    (s.history || []).slice().reverse().forEach((h) => {
      const tr = document.createElement("tr");
      [new Date(h.time * 1000).toISOString().replace("T", " ").slice(0, 19), h.code, h.message, h.detail == null ? "" : h.detail]
        .forEach((v) => { const td = document.createElement("td"); td.textContent = v; tr.appendChild(td); });
      tb.appendChild(tr);
    });
    const f = Object.keys(forced);
    set("o-forced", f.length ? f.map((k) => k + "=" + (forced[k] ? "ON" : "OFF")).join(", ") : "none");
    set("o-bp", s.breakpoint ? s.breakpoint.when + (s.breakpoint.hit != null ? " (paused at scan " + s.breakpoint.hit + ")" : "") : "none");
  }
  setInterval(poll, 500);
  poll();

  $$("button[data-op]").forEach((b) => b.addEventListener("click", async () => {
    const op = b.dataset.op;
    const q = [];
    if (op === "step") q.push("scans=" + ($("#nscans").value || 1));
    if (cpu) q.push("cpu=" + cpu);
    const path = "/api/v1/cpu/" + op + (q.length ? "?" + q.join("&") : "");
    try { const r = await api("POST", path); say(op.toUpperCase() + ": " + r.state + (r.scan != null ? " at scan " + r.scan : "")); poll(); } catch (e) {}
  }));

  // --- forcing and writing ---
  async function force(name, on) { await api("POST", "/api/v1/force", { [name]: on }); say(name + " forced " + (on ? "ON" : "OFF")); poll(); }
  async function release(name) { await api("DELETE", "/api/v1/force", [name]); say(name + " released"); poll(); }
  async function write(name, v) { const r = await api("POST", "/api/v1/devices", { [name]: v }); say(name + " = " + v + " at scan " + r.scan); }
  function parseInput(name, text, fmt, old) {
    if (typeof old === "boolean") return /^(1|on|true)$/i.test(text.trim());
    if (fmt === "float" || /:f32$/i.test(name)) return parseFloat(text);
    if (fmt === "str" || /:str$/i.test(name)) return text;
    if (fmt === "hex") return "H" + text.trim().replace(/^(0x|h)/i, "");
    const n = Number(text);
    return Number.isInteger(n) ? n : text.trim();
  }
  const io = (n) => /^(CPU\d\/)?[XY][0-9A-F]+$/i.test(n || "");
  const menu = $("#menu");
  function showMenu(ev, name) {
    ev.preventDefault();
    const v = values[name];
    const items = [];
    if (typeof v === "boolean") {
      items.push(["set ON", () => write(name, true)], ["set OFF", () => write(name, false)]);
    } else {
      items.push(["change value…", () => { const t = prompt(name + " =", v); if (t !== null) write(name, parseInput(name, t, "dec", v)); }]);
    }
    if (io(name)) items.push(["force ON", () => force(name, true)], ["force OFF", () => force(name, false)], ["release", () => release(name)]);
    menu.innerHTML = "<b></b>";
    menu.firstChild.textContent = name;
    items.forEach(([t, f]) => { const b = document.createElement("button"); b.textContent = t; b.dataset.act = t;
      b.addEventListener("click", () => { menu.hidden = true; f().catch(() => {}); }); menu.appendChild(b); });
    menu.style.left = ev.pageX + "px"; menu.style.top = ev.pageY + "px"; menu.hidden = false;
  }
  document.addEventListener("click", (e) => { if (!menu.contains(e.target) && !e.target.closest(".el")) menu.hidden = true; });
  $$(".el").forEach((g) => { if (g.dataset.dev) g.addEventListener("click", (e) => showMenu(e, own(g.dataset.dev))); });
  $$("td.edit").forEach((td) => {
    td.addEventListener("click", () => {
      const n = td.dataset.v; const old = values[n];
      const t = prompt(n + " =", td.textContent);
      if (t !== null) write(n, parseInput(n, t, td.dataset.fmt, old)).catch(() => {});
    });
    td.addEventListener("contextmenu", (e) => showMenu(e, td.dataset.v));
  });
  $$("#f-on,#f-off,#f-rel").forEach((b) => b.addEventListener("click", () => {
    const n = $("#f-name").value.trim();
    (b.id === "f-rel" ? release(n) : force(n, b.id === "f-on")).catch(() => {});
  }));
  const bpSet = $("#bp-set");
  if (bpSet) {
    bpSet.addEventListener("click", () => api("POST", "/api/v1/breakpoint", { when: $("#bp-when").value }).then(() => { say("breakpoint set"); poll(); }).catch(() => {}));
    $("#bp-clear").addEventListener("click", () => api("DELETE", "/api/v1/breakpoint").then(() => { say("breakpoint cleared"); poll(); }).catch(() => {}));
  }

  // --- live values ---
  // Constants of both dialects: MELSEC K5, H1F, E1.5; APLC 5, -3, 1.5E3,
  // 16#1F, 8#17, 2#101 (contract §1 and §1.1 item 5).
  function konst(t) {
    if (t in values) return values[t];
    let m = /^K(-?\d+)$/i.exec(t); if (m) return Number(m[1]);
    m = /^H([0-9A-F]+)$/i.exec(t); if (m) return parseInt(m[1], 16);
    m = /^E(.+)$/i.exec(t); if (m) return parseFloat(m[1]);
    m = /^(16|8|2)#([0-9A-F]+)$/i.exec(t); if (m) return parseInt(m[2], Number(m[1]));
    if (/^[+-]?\d+(\.\d*)?(E[+-]?\d+)?$/i.test(t)) return Number(t);
    return undefined;
  }
  function compare(m, ops) {
    const op = m.replace(/^(LD|AND|OR)/, "").replace(/^[DER]/, "");
    const a = konst(ops[0]), b = konst(ops[1]);
    if (a === undefined || b === undefined) return undefined;
    return { "=": a === b, "<>": a !== b, ">": a > b, "<": a < b, ">=": a >= b, "<=": a <= b }[op];
  }
  function show(v, fmt) {
    if (v === undefined) return "";
    if (v === null) return "?";
    if (typeof v === "boolean") return v ? "ON" : "OFF";
    if (fmt === "hex" && typeof v === "number") return "H" + (v >>> 0).toString(16).toUpperCase().padStart(4, "0");
    if (typeof v === "number" && !Number.isInteger(v)) return v.toPrecision(7).replace(/\.?0+$/, "");
    return String(v);
  }
  // Power flow from the left rail: a closed contact passes power, series
  // needs all, parallel any; INV inverts; outputs and boxes with power get "pw".
  // The rail of an SFC step's rung (data-bus) has power while its steps are
  // ON. A wire is coloured from what flows into an element (data-into) or
  // out of the elements ending a branch (data-after).
  function powerFlow() {
    $$("svg.rung[data-net]").forEach((svg) => {
      const prog = svg.id.slice(1).split("-")[0];
      const el = (id) => document.getElementById("e" + prog + "-" + id);
      const into = {}, outOf = {};
      const net = (n, p) => {
        if (typeof n === "number") {
          const g = el(n); if (!g) return p;
          const k = g.classList;
          const out = k.contains("k-mod") ? (g.dataset.m === "INV" ? !p : p) : p && k.contains("on");
          k.toggle("pw", p);
          into[n] = p; outOf[n] = out;
          return out;
        }
        if (n.s) return n.s.reduce((q, m) => net(m, q), p);
        if (n.p) return n.p.map((m) => net(m, p)).some((x) => x);
        return p;
      };
      const fan = (f, p) => {
        const q = f.f == null ? p : net(f.f, p);
        f.i.forEach((i) => { if (typeof i === "number") { into[i] = q; const g = el(i); if (g) g.classList.toggle("pw", q); } else fan(i, q); });
      };
      const bus = svg.dataset.bus;
      const rail = bus ? bus.split(" ").every((d) => values[d] === true) : true;
      try { fan(JSON.parse(svg.dataset.net), rail); } catch (e) {}
      $$("line.w[data-into]", svg).forEach((w) => w.classList.toggle("pw", into[w.dataset.into] === true));
      $$("line.w[data-after]", svg).forEach((w) => w.classList.toggle("pw", w.dataset.after.split(" ").some((id) => outOf[id] === true)));
    });
  }
  function markForced() {
    $$(".el").forEach((g) => g.classList.toggle("forced", own(g.dataset.dev) in forced));
    $$("td.fx").forEach((td) => { const f = forced[td.dataset.f]; td.textContent = f === undefined ? "" : "forced " + (f ? "ON" : "OFF"); });
  }
  function update(dev) {
    Object.assign(values, dev);
    // The ladder's elements name this CPU's devices without the prefix.
    if (prefix) Object.keys(dev).forEach((k) => { if (k.startsWith(prefix)) values[k.slice(prefix.length)] = dev[k]; });
    Object.keys(local).forEach((n) => { if (local[n] in dev) values[n] = dev[local[n]]; });
    $$(".el").forEach((g) => {
      let v = values[g.dataset.dev];
      // A word-bit contact (APLC BLD D0 5): bit 5 of D0's value.
      if (g.dataset.bit !== undefined) v = typeof v === "number" ? ((v >> Number(g.dataset.bit)) & 1) === 1 : undefined;
      const k = g.classList;
      let on;
      if (k.contains("k-cmp")) on = compare(g.dataset.m, g.dataset.ops.split(" "));
      else if (k.contains("k-step")) on = g.dataset.ops.split(" ").every((d) => values[d] === true);
      else if (k.contains("k-nc")) on = v === false;
      // A pulse-NOT contact (LDPI …) depends on the last scan's value too: not shown.
      else if (k.contains("k-box") || k.contains("k-mod") || k.contains("k-end") || k.contains("k-risenot") || k.contains("k-fallnot")) on = undefined;
      else on = v === true;
      k.toggle("on", on === true);
    });
    powerFlow();
    $$("[data-v]").forEach((el) => { el.textContent = show(values[el.dataset.v], el.dataset.fmt); });
    if (page === "trend") trendAdd(dev);
    if (page === "loops") loopsUpdate();
  }

  // --- loop faceplates: bars over 0..2000 (the PID digital range), mode, alarms, a small trend ---
  const loopHist = new Map();
  function loopsUpdate() {
    $$("[data-bar]").forEach((b) => { const v = values[b.dataset.bar]; const sc = Number(b.dataset.scale || 2000); if (typeof v === "number") b.style.width = Math.max(0, Math.min(100, v / sc * 100)) + "%"; });
    // Process loop tags (000 §3.3.5): MODE one bit set, ALM bits (spec §1.5, §1.6).
    const PMODES = [[0x8, "MAN"], [0x10, "AUT"], [0x20, "CAS"], [0x40, "CMB"], [0x80, "CAB"], [0x100, "CCB"], [0x200, "CMV"], [0x400, "CSV"], [0x1, "LCC"], [0x2, "LCA"], [0x4, "LCM"]];
    const PALARMS = [[0x4000, "SPA (stopped)"], [0x800, "DMLA"], [0x200, "SEA"], [0x100, "HHA"], [0x80, "LLA"], [0x40, "PHA"], [0x20, "PLA"], [0x10, "DPPA"], [0x8, "DPNA"], [0x4, "DVLA"], [0x2, "MHA"], [0x1, "MLA"]];
    $$("[data-pmode]").forEach((td) => { const v = values[td.dataset.pmode] || 0; td.textContent = PMODES.filter(([b]) => v & b).map(([, n]) => n).join(" "); });
    $$("[data-palarm]").forEach((td) => { const v = values[td.dataset.palarm] || 0;
      td.textContent = PALARMS.filter(([b]) => v & b).map(([, n]) => n).join(", "); td.classList.toggle("on", v !== 0); });
    $$("[data-mode]").forEach((td) => { const v = values[td.dataset.mode]; td.textContent = v === 1 ? "AUTO" : v === 0 ? "MANUAL" : ""; });
    $$("[data-alarm]").forEach((td) => { const v = values[td.dataset.alarm] || 0;
      td.textContent = [(v & 1) ? "PV rate" : "", (v & 2) ? "MV rate" : ""].filter((x) => x).join(", ");
      td.classList.toggle("on", v !== 0); });
    $$("svg.ltrend").forEach((svg) => {
      const h = loopHist.get(svg) || []; loopHist.set(svg, h);
      h.push([values[svg.dataset.sv], values[svg.dataset.pv], values[svg.dataset.mv]]);
      if (h.length > 300) h.shift();
      const sc = Number(svg.dataset.scale || 2000);
      const pts = (i) => h.map((s, k) => (k * 320 / 299).toFixed(1) + "," + (88 - Math.max(0, Math.min(sc, s[i] || 0)) / sc * 86).toFixed(1)).join(" ");
      svg.innerHTML = ["#36c", "#0a7", "#c80"].map((c, i) => '<polyline fill="none" stroke="' + c + '" points="' + pts(i) + '"/>').join("");
    });
  }
  if (names) {
    const es = new EventSource("/api/v1/events?names=" + encodeURIComponent(names));
    // An event's scan is CPU 1's: another CPU's bar takes its scans from status.
    es.onmessage = (e) => { const d = JSON.parse(e.data); if (!cpu || cpu === "1") $("#scan").textContent = d.scan; update(d.devices); };
    es.onerror = () => say("live values interrupted; retrying", true);
  }

  // --- trend: END samples as SVG polylines ---
  const samples = [];
  let paused = false;
  const colours = ["#0a7", "#c33", "#36c", "#c80", "#909", "#077", "#555", "#a50"];
  function trendAdd(dev) {
    if (paused) return;
    samples.push([Date.now(), names.split(",").map((n) => { const v = dev[n]; return typeof v === "boolean" ? (v ? 1 : 0) : v; })]);
    if (samples.length > 600) samples.shift();
    const svg = $("#trend"); const W = 900, H = 320;
    const ns = names.split(",");
    let html = "";
    ns.forEach((n, i) => {
      const ys = samples.map((s) => s[1][i]).filter((v) => typeof v === "number");
      if (!ys.length) return;
      const lo = Math.min(...ys), hi = Math.max(...ys), span = hi - lo || 1;
      const pts = samples.map((s, k) => (k * W / 599).toFixed(1) + "," + (H - 10 - (s[1][i] - lo) / span * (H - 20)).toFixed(1)).join(" ");
      html += '<polyline fill="none" stroke="' + colours[i % 8] + '" stroke-width="1.5" points="' + pts + '"/>';
    });
    svg.innerHTML = html;
    $("#legend").innerHTML = "";
    ns.forEach((n, i) => { const s = document.createElement("span"); s.style.color = colours[i % 8];
      s.textContent = n + " = " + show(values[n]) + "  "; $("#legend").appendChild(s); });
  }
  const tp = $("#t-pause");
  if (tp) {
    tp.addEventListener("click", () => { paused = !paused; tp.textContent = paused ? "resume" : "pause"; });
    $("#t-csv").addEventListener("click", () => {
      const rows = ["time," + names].concat(samples.map((s) => new Date(s[0]).toISOString() + "," + s[1].join(",")));
      const a = document.createElement("a");
      a.href = URL.createObjectURL(new Blob([rows.join("\n")], { type: "text/csv" }));
      a.download = "trend.csv"; a.click();
    });
  }
})();
