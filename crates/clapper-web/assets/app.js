// clapper's page: chart explorer, bell diagnosis, listening test.
// Plain JavaScript, no libraries: everything the page needs is served by
// `clapper serve` itself.
"use strict";

const $ = (id) => document.getElementById(id);
const fmt = (v, d) => (v === null || v === undefined || !Number.isFinite(v) ? "–" : v.toFixed(d));
const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);

async function postJson(url, body) {
  const res = await fetch(url, { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
  if (!res.ok) {
    let msg = res.statusText;
    try { msg = (await res.json()).error; } catch (_) { /* not JSON */ }
    throw new Error(msg);
  }
  return res;
}

function showError(el, e) {
  el.textContent = String(e.message || e);
  el.classList.add("error");
}
function showStatus(el, text) {
  el.textContent = text;
  el.classList.remove("error");
}

// ---------- tabs ----------
for (const b of document.querySelectorAll("button.tab")) {
  b.addEventListener("click", () => selectTab(b.dataset.tab));
}
function selectTab(name) {
  for (const b of document.querySelectorAll("button.tab")) b.classList.toggle("active", b.dataset.tab === name);
  for (const s of document.querySelectorAll("section.panel")) s.hidden = s.id !== "tab-" + name;
  if (name === "chart" && !chart.cells && !chart.running) drawChart();
  // The markers' names are placed by their drawn sizes, which a hidden tab has not.
  if (name === "chart") renderMarkers();
}

// ---------- chart explorer ----------
const PLOT = { left: 62, right: 12, top: 12, bottom: 48 };
const QUANTITIES = {
  style: { label: "styles sustained", index: null },
  strike: { label: "first strike angle θ (deg)", index: 1, digits: 1 },
  phidot: { label: "strike velocity φ' (rad/s)", index: 2, digits: 2 },
  liftoff: { label: "lift-off angle θ (deg)", index: 3, digits: 1 },
  d: { label: "double strike index D (scale cut at 60)", index: 4, digits: 2, cap: 60 },
  odd: { label: "odd-struckness, hand minus back (ms)", index: 5, digits: 1, symmetric: true },
};
const STYLE_COLOURS = { neither: "#ffffff", right: "#3182bd", wrong: "#e6550d", both: "#74c476", failed: "#999999" };
// pending: blocks of cells arrived and not yet drawn, as [start, count];
// drawn together DRAW_EVERY_MS later, only they (the whole canvas only when
// a quantity's colour scale widens).
const DRAW_EVERY_MS = 150;
const chart = { cells: null, spec: null, running: false, markers: [], controller: null, pending: [], frame: 0, drawnRange: null };

// Viridis, by eleven stops.
const VIRIDIS = [[68, 1, 84], [72, 36, 117], [65, 68, 135], [53, 95, 141], [42, 120, 142], [33, 145, 140], [34, 168, 132], [68, 190, 112], [122, 209, 81], [189, 223, 38], [253, 231, 37]];
function viridis(t) {
  t = Math.min(1, Math.max(0, t)) * (VIRIDIS.length - 1);
  const i = Math.min(VIRIDIS.length - 2, Math.floor(t));
  const f = t - i;
  const c = VIRIDIS[i].map((a, k) => Math.round(a + f * (VIRIDIS[i + 1][k] - a)));
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}

// A number field's number. Empty, it means the page's default: the
// field's first value, shown as its placeholder (undefined where it has
// none, or where `given` asks for what was typed only, for the caller to
// leave the option out); never 0. Text that is not a number is refused
// with a message beside the field.
function fieldNumber(inp, given = false) {
  clearFieldError(inp);
  const text = inp.value.trim();
  if (text === "" && !(inp.validity && inp.validity.badInput)) {
    const d = given ? "" : inp.defaultValue.trim();
    return d === "" ? undefined : Number(d);
  }
  const v = Number(text);
  if (text === "" || !Number.isFinite(v)) throw fieldError(inp, "not a number");
  return v;
}
function num(id) { return fieldNumber($(id)); }

function fieldError(inp, text) {
  clearFieldError(inp);
  const label = inp.closest("label");
  const name = (label ? label.textContent : inp.id || inp.dataset.key || "a field").trim();
  const span = document.createElement("span");
  span.className = "field-error error";
  span.textContent = text;
  inp.after(span);
  inp.setAttribute("aria-invalid", "true");
  inp.focus();
  return new Error(`${name}: ${text}`);
}
function clearFieldError(inp) {
  if (inp.nextElementSibling && inp.nextElementSibling.classList.contains("field-error")) inp.nextElementSibling.remove();
  inp.removeAttribute("aria-invalid");
}
// Each number field with a default shows it when emptied; the bell form's
// values are an example, not defaults.
for (const inp of document.querySelectorAll("input[type=number]")) {
  if (!inp.placeholder && inp.defaultValue !== "" && !inp.closest("#bell-form")) inp.placeholder = inp.defaultValue;
  inp.addEventListener("input", () => clearFieldError(inp));
}

function chartRequest() {
  const req = {
    grid: [num("nx"), num("ny")],
    r_range: [num("r-lo"), num("r-hi")],
    lb_range: [num("lb-lo"), num("lb-hi")],
    theta0: num("theta0"),
    restitution: num("restitution"),
    phi_max: num("phi-max"),
    style: "both",
  };
  if ($("contact").value === "penalty") { req.contact = "penalty"; req.stiffness = num("stiffness"); }
  // R2: left empty, the bounces after the first impact take R too.
  const r2 = num("restitution-later");
  if (r2 !== undefined) req.restitution_later = r2;
  // An odd-struck bell: pivot offset (mm here, m in the API) and unequal contact angles.
  const offset = num("pivot-offset");
  if (offset !== undefined) req.pivot_offset = offset / 1000;
  const [hand, back] = [num("phi-max-hand"), num("phi-max-back")];
  if (hand !== undefined) req.phi_max_hand = hand;
  if (back !== undefined) req.phi_max_back = back;
  return req;
}

async function drawChart() {
  if (chart.controller) chart.controller.abort();
  const controller = new AbortController();
  chart.controller = controller;
  chart.running = true;
  const status = $("chart-status");
  showStatus(status, "Starting the sweep…");
  $("chart-box").dataset.done = "0";
  const t0 = performance.now();
  try {
    const req = chartRequest();
    const res = await fetch("/api/chart", {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(req), signal: controller.signal,
    });
    if (!res.ok) {
      let msg = res.statusText;
      try { msg = (await res.json()).error; } catch (_) { /* not JSON */ }
      throw new Error(msg);
    }
    chart.request = req;
    const reader = res.body.getReader();
    const decoder = new TextDecoder();
    let buf = "";
    for (;;) {
      const { value, done } = await reader.read();
      if (done) break;
      buf += decoder.decode(value, { stream: true });
      let nl;
      while ((nl = buf.indexOf("\n")) >= 0) {
        const line = buf.slice(0, nl);
        buf = buf.slice(nl + 1);
        if (line.trim()) onChartLine(JSON.parse(line), status, t0);
      }
    }
  } catch (e) {
    if (e.name !== "AbortError") showError(status, e);
  } finally {
    if (chart.controller === controller) { chart.running = false; chart.controller = null; }
  }
}

function onChartLine(msg, status, t0) {
  if (msg.type === "start") {
    if (chart.frame) clearTimeout(chart.frame);
    chart.spec = msg;
    // The cells' edges, once: every point drawn needs them.
    msg.xe = edges(msg.xs);
    msg.ye = edges(msg.ys);
    chart.cells = new Array(msg.total).fill(null);
    chart.filled = 0;
    chart.pending = [];
    chart.frame = 0;
    renderChart();
  } else if (msg.type === "cells") {
    msg.cells.forEach((c, k) => { chart.cells[msg.start + k] = c; });
    chart.filled += msg.cells.length;
    chart.pending.push([msg.start, msg.cells.length]);
    // A few draws a second: each repaints the page, which on a machine
    // without a GPU costs the cores the server sweeps on.
    if (!chart.frame) chart.frame = setTimeout(drawPending, DRAW_EVERY_MS);
  } else if (msg.type === "done") {
    // What is still to draw, drawn now: the time shown is the time until
    // the whole chart is on the page, not the server's computing alone.
    if (chart.frame) { clearTimeout(chart.frame); drawPending(); }
    const secs = (performance.now() - t0) / 1000;
    showStatus(status, `${msg.strokes} strokes in ${secs.toFixed(2)} s (computed in ${msg.seconds.toFixed(2)} s, the rest sending and drawing)` +
      (msg.errors ? `, ${msg.errors} failed (grey)` : "") + ". Hover for values; click a point to see its stroke.");
    const box = $("chart-box");
    box.dataset.seconds = secs.toFixed(3);
    box.dataset.serverSeconds = msg.seconds.toFixed(3);
    box.dataset.done = "1";
  } else if (msg.type === "error") {
    showError(status, msg.message);
  }
}

// Draw the cells that arrived since the last draw: only their points,
// unless the colour scale of the quantity shown has widened, which
// recolours every point.
function drawPending() {
  chart.frame = 0;
  const blocks = chart.pending;
  chart.pending = [];
  const s = chart.spec;
  if (!s || !blocks.length) return;
  showStatus($("chart-status"), `Sweeping: ${chart.filled} of ${s.total} strokes…`);
  const q = $("quantity").value, style = $("show-style").value;
  const range = q === "style" ? null : valueRange(q, style);
  if (range && !(chart.drawnRange && range[0] === chart.drawnRange[0] && range[1] === chart.drawnRange[1])) {
    renderChart();
    return;
  }
  const g = $("chart-canvas").getContext("2d");
  const xe = s.xe, ye = s.ye, ns = s.styles.length;
  for (const [start, count] of blocks) {
    const p1 = Math.floor((start + count - 1) / ns);
    for (let p = Math.floor(start / ns); p <= p1; p++) drawCell(g, p % s.nx, Math.floor(p / s.nx), q, style, range, xe, ye);
  }
  const a = plotArea();
  g.strokeStyle = "#333"; g.lineWidth = 1; g.strokeRect(a.x, a.y, a.w, a.h);
}

function drawCell(g, i, j, q, style, range, xe, ye) {
  const col = cellColour(i, j, q, style, range);
  if (!col) return;
  const [px0, py1] = toPx(xe[i], ye[j]);
  const [px1, py0] = toPx(xe[i + 1], ye[j + 1]);
  g.fillStyle = col;
  g.fillRect(px0, py0, px1 - px0 + 0.6, py1 - py0 + 0.6);
}

function cellAt(i, j, style) {
  const s = chart.spec;
  const k = s.styles.indexOf(style);
  if (k < 0) return null;
  return chart.cells[(j * s.nx + i) * s.styles.length + k];
}

function plotArea() {
  const c = $("chart-canvas");
  return { x: PLOT.left, y: PLOT.top, w: c.width - PLOT.left - PLOT.right, h: c.height - PLOT.top - PLOT.bottom };
}

function edges(axis) {
  // Cell edges halfway between grid points.
  const n = axis.length;
  if (n === 1) return [axis[0] - 0.5, axis[0] + 0.5];
  const out = [axis[0] - (axis[1] - axis[0]) / 2];
  for (let i = 0; i < n - 1; i++) out.push((axis[i] + axis[i + 1]) / 2);
  out.push(axis[n - 1] + (axis[n - 1] - axis[n - 2]) / 2);
  return out;
}

function valueRange(q, style) {
  let lo = Infinity, hi = -Infinity;
  const qi = QUANTITIES[q];
  for (let j = 0; j < chart.spec.ny; j++) for (let i = 0; i < chart.spec.nx; i++) {
    const c = cellAt(i, j, style);
    if (!c || c[0] !== 1) continue;
    let v = c[qi.index];
    if (v === null) continue;
    if (qi.cap) v = Math.min(v, qi.cap);
    lo = Math.min(lo, v); hi = Math.max(hi, v);
  }
  if (!Number.isFinite(lo)) return [0, 1];
  if (qi.cap) lo = 0;
  // Early and late alike: a scale centred on 0.
  if (qi.symmetric) { hi = Math.max(Math.abs(lo), Math.abs(hi), 1e-3); lo = -hi; }
  if (hi - lo < 1e-9) hi = lo + 1;
  return [lo, hi];
}

function cellColour(i, j, q, style, range) {
  if (q === "style") {
    const r = cellAt(i, j, "right"), w = cellAt(i, j, "wrong");
    if (!r && !w) return null;
    if ((r && r[0] < 0) || (w && w[0] < 0)) return STYLE_COLOURS.failed;
    const rs = r && r[0] === 1, ws = w && w[0] === 1;
    return rs && ws ? STYLE_COLOURS.both : rs ? STYLE_COLOURS.right : ws ? STYLE_COLOURS.wrong : STYLE_COLOURS.neither;
  }
  const c = cellAt(i, j, style);
  if (!c) return null;
  if (c[0] < 0) return STYLE_COLOURS.failed;
  if (c[0] !== 1) return "#ffffff";
  const qi = QUANTITIES[q];
  let v = c[qi.index];
  if (v === null) return "#ffffff";
  if (qi.cap) v = Math.min(v, qi.cap);
  return viridis((v - range[0]) / (range[1] - range[0]));
}

function toPx(x, y) {
  const a = plotArea(), s = chart.spec;
  const xe = s.xe, ye = s.ye;
  const [x0, x1, y0, y1] = [xe[0], xe[xe.length - 1], ye[0], ye[ye.length - 1]];
  return [a.x + (x - x0) / (x1 - x0) * a.w, a.y + a.h - (y - y0) / (y1 - y0) * a.h];
}

function renderChart() {
  const c = $("chart-canvas"), g = c.getContext("2d"), s = chart.spec;
  if (!s) return;
  const q = $("quantity").value, style = $("show-style").value;
  const a = plotArea();
  g.fillStyle = "#fff"; g.fillRect(0, 0, c.width, c.height);
  const xe = s.xe, ye = s.ye;
  const range = q === "style" ? null : valueRange(q, style);
  chart.drawnRange = range;
  for (let j = 0; j < s.ny; j++) for (let i = 0; i < s.nx; i++) drawCell(g, i, j, q, style, range, xe, ye);
  // Axes, ticks, labels.
  g.strokeStyle = "#333"; g.lineWidth = 1; g.strokeRect(a.x, a.y, a.w, a.h);
  g.fillStyle = "#222"; g.font = "12px sans-serif"; g.textAlign = "center";
  for (const t of ticks(xe[0], xe[xe.length - 1])) {
    const [px] = toPx(t, ye[0]);
    g.beginPath(); g.moveTo(px, a.y + a.h); g.lineTo(px, a.y + a.h + 5); g.stroke();
    g.fillText(+t.toFixed(3), px, a.y + a.h + 18);
  }
  g.fillText("r / L_c  (clapper pivot offset over clapper length)", a.x + a.w / 2, a.y + a.h + 40);
  g.textAlign = "right";
  for (const t of ticks(ye[0], ye[ye.length - 1])) {
    const [, py] = toPx(xe[0], t);
    g.beginPath(); g.moveTo(a.x - 5, py); g.lineTo(a.x, py); g.stroke();
    g.fillText(+t.toFixed(3), a.x - 8, py + 4);
  }
  g.save(); g.translate(16, a.y + a.h / 2); g.rotate(-Math.PI / 2); g.textAlign = "center";
  g.fillText("L_b / L_c  (bell over clapper pendulum length)", 0, 0); g.restore();
  renderScale(q, range);
  renderMarkers();
}

function ticks(lo, hi) {
  const span = hi - lo, raw = span / 6, p = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * p).find((s) => span / s <= 7);
  const out = [];
  for (let t = Math.ceil(lo / step) * step; t <= hi + 1e-9; t += step) out.push(Math.abs(t) < 1e-12 ? 0 : t);
  return out;
}

function renderScale(q, range) {
  const c = $("colourbar"), g = c.getContext("2d");
  g.clearRect(0, 0, c.width, c.height);
  g.font = "12px sans-serif"; g.fillStyle = "#222";
  if (q === "style") {
    const items = [["right only", STYLE_COLOURS.right], ["wrong only", STYLE_COLOURS.wrong], ["right and wrong", STYLE_COLOURS.both], ["neither", STYLE_COLOURS.neither], ["failed", STYLE_COLOURS.failed]];
    g.fillText("styles sustained", 4, PLOT.top + 10);
    items.forEach(([label, col], k) => {
      const y = PLOT.top + 24 + k * 24;
      g.fillStyle = col; g.fillRect(4, y, 18, 16); g.strokeStyle = "#333"; g.strokeRect(4, y, 18, 16);
      g.fillStyle = "#222"; g.fillText(label, 28, y + 12);
    });
    return;
  }
  const a = plotArea(), x = 8, w = 22;
  for (let k = 0; k < a.h; k++) {
    g.fillStyle = viridis(1 - k / a.h);
    g.fillRect(x, a.y + k, w, 1.5);
  }
  g.strokeStyle = "#333"; g.strokeRect(x, a.y, w, a.h);
  g.fillStyle = "#222";
  for (const t of ticks(range[0], range[1])) {
    const y = a.y + a.h - (t - range[0]) / (range[1] - range[0]) * a.h;
    g.fillText(+t.toFixed(3), x + w + 5, y + 4);
  }
  g.save(); g.translate(c.width - 8, a.y + a.h / 2); g.rotate(-Math.PI / 2); g.textAlign = "center";
  g.fillText(QUANTITIES[q].label + ", " + $("show-style").value, 0, 0); g.restore();
}

// The diagnosed bells on the chart, each with its name beside it. Bells
// of a ring sit close together: each name takes the first place, right or
// left of its marker and then stepping up and down, that covers no other
// name or marker, with a line to its marker when moved off its row.
const MARKER_R = 9, LABEL_MAX = 24;
function renderMarkers() {
  const box = $("markers");
  box.innerHTML = "";
  if (!chart.spec) return;
  const a = plotArea();
  const shown = [];
  chart.markers.forEach((m, k) => {
    const [px, py] = toPx(m.x, m.y);
    if (px < a.x || px > a.x + a.w || py < a.y || py > a.y + a.h) return;
    const d = document.createElement("div");
    d.className = "marker";
    d.dataset.index = k;
    d.style.left = px + 1 + "px"; d.style.top = py + 1 + "px";
    d.title = `${m.label}: r/L_c = ${m.x.toFixed(3)}, L_b/L_c = ${m.y.toFixed(3)}; click for its stroke`;
    const name = m.label.length > LABEL_MAX ? m.label.slice(0, LABEL_MAX - 1) + "…" : m.label;
    d.innerHTML = `<span>${esc(name)}</span>`;
    box.appendChild(d);
    shown.push({ d });
  });
  // Where each marker is drawn, in #chart-box's px: its centre, and the
  // corner its name is placed from.
  const origin = $("chart-box").getBoundingClientRect();
  for (const s of shown) {
    const r = s.d.getBoundingClientRect();
    s.x = r.left + r.width / 2 - origin.left; s.y = r.top + r.height / 2 - origin.top;
    s.ox = r.left + s.d.clientLeft - origin.left; s.oy = r.top + s.d.clientTop - origin.top;
  }
  const lines = document.createElementNS("http://www.w3.org/2000/svg", "svg");
  lines.setAttribute("class", "marker-lines");
  lines.setAttribute("width", $("chart-canvas").width); lines.setAttribute("height", $("chart-canvas").height);
  box.prepend(lines);
  const taken = shown.map((s) => ({ x0: s.x - MARKER_R, y0: s.y - MARKER_R, x1: s.x + MARKER_R, y1: s.y + MARKER_R }));
  const clear = (r) => r.x0 >= a.x && r.x1 <= a.x + a.w && r.y0 >= a.y && r.y1 <= a.y + a.h &&
    taken.every((t) => r.x1 <= t.x0 || r.x0 >= t.x1 || r.y1 <= t.y0 || r.y0 >= t.y1);
  // Top to bottom, so that a cluster's names stack in its order.
  for (const s of [...shown].sort((p, q) => p.y - q.y)) {
    const span = s.d.querySelector("span");
    const w = span.offsetWidth, h = span.offsetHeight;
    let place = null;
    for (let step = 0; step <= 12 && !place; step++) {
      for (const dy of step ? [step, -step] : [0]) {
        for (const right of [true, false]) {
          const x0 = right ? s.x + MARKER_R + 3 : s.x - MARKER_R - 3 - w;
          const y0 = s.y - h / 2 + dy * (h + 2);
          const r = { x0, y0, x1: x0 + w, y1: y0 + h };
          if (clear(r)) { place = r; break; }
        }
        if (place) break;
      }
    }
    // Nowhere free: the name stays in the marker's tooltip only.
    if (!place) { span.hidden = true; continue; }
    taken.push(place);
    span.style.left = place.x0 - s.ox + "px"; span.style.top = place.y0 - s.oy + "px";
    if (Math.abs(place.y0 + h / 2 - s.y) > 1) {
      const l = document.createElementNS("http://www.w3.org/2000/svg", "line");
      const ex = place.x0 > s.x ? place.x0 : place.x1;
      l.setAttribute("x1", s.x); l.setAttribute("y1", s.y); l.setAttribute("x2", ex); l.setAttribute("y2", place.y0 + h / 2);
      lines.appendChild(l);
    }
  }
}

function pointAt(ev) {
  const s = chart.spec;
  if (!s) return null;
  const rect = $("chart-canvas").getBoundingClientRect();
  const px = ev.clientX - rect.left, py = ev.clientY - rect.top;
  const a = plotArea();
  if (px < a.x || px > a.x + a.w || py < a.y || py > a.y + a.h) return null;
  const i = Math.min(s.nx - 1, Math.floor((px - a.x) / a.w * s.nx));
  const j = Math.min(s.ny - 1, Math.floor((a.y + a.h - py) / a.h * s.ny));
  return { i, j, x: s.xs[i], y: s.ys[j], px, py };
}

function describeCell(c) {
  if (!c) return "not computed yet";
  if (c[0] < 0) return "failed to simulate";
  const parts = [c[0] === 1 ? "sustained" : "not sustained"];
  if (c[1] !== null) parts.push(`strike ${fmt(c[1], 1)} deg`);
  if (c[2] !== null) parts.push(`φ' ${fmt(c[2], 2)} rad/s`);
  if (c[3] !== null) parts.push(`lift-off ${fmt(c[3], 1)} deg`);
  if (c[4] !== null) parts.push(`D ${fmt(c[4], 2)}`);
  // Only a bell off the ideal is odd-struck; a symmetric bell's 0 is noise here.
  if (c[5] !== null && c[5] !== undefined && c[5] !== 0) parts.push(`odd-struck ${fmt(c[5], 1)} ms`);
  return parts.join(", ");
}

// On #chart-box, not the canvas, so that the markers above it answer too.
$("chart-box").addEventListener("mousemove", (ev) => {
  const p = pointAt(ev), tip = $("tooltip");
  if (!p) { tip.hidden = true; return; }
  const lines = [`r/L_c = ${p.x.toFixed(3)}, L_b/L_c = ${p.y.toFixed(3)}`];
  for (const st of chart.spec.styles) lines.push(`${st}: ${describeCell(cellAt(p.i, p.j, st))}`);
  tip.textContent = lines.join("\n");
  tip.hidden = false;
  tip.style.left = Math.min(p.px + 14, 330) + "px";
  tip.style.top = p.py + 14 + "px";
});
$("chart-box").addEventListener("mouseleave", () => { $("tooltip").hidden = true; });
$("chart-box").addEventListener("click", (ev) => {
  // A bell's marker shows that bell's stroke; elsewhere, the chart point's.
  const m = ev.target.closest(".marker");
  if (m) { showBellStroke(chart.markers[Number(m.dataset.index)]); return; }
  const p = pointAt(ev);
  if (p) showStroke(p);
});

// A diagnosed bell's own stroke (its mass properties or tower
// measurements, its own R), ringing the way it usually rings.
async function showBellStroke(m) {
  if (!m.source) return;
  $("stroke-panel").dataset.bell = "1";
  const body = { ...m.source, style: m.style, strokes: 2 };
  const title = `Stroke of ${m.label} (r/L_c = ${m.x.toFixed(3)}, L_b/L_c = ${m.y.toFixed(3)}), ringing ${m.style}`;
  await simulateStroke(body, title);
}

async function simulateStroke(body, title) {
  $("stroke-panel").hidden = false;
  $("stroke-title").textContent = title + ": simulating…";
  try {
    const res = await (await postJson("/api/stroke", body)).json();
    $("stroke-title").textContent = title;
    $("stroke-numbers").innerHTML = strokeTable(res.report);
    $("stroke-plot").innerHTML = res.plot_svg;
  } catch (e) {
    $("stroke-title").textContent = "Stroke: " + e.message;
    return;
  }
  strokeBody = body;
  await animateStrokes([body]);
}

// The stroke view's animation: the bell (and a variant beside it) drawn
// from the simulation, with its sound, by the player /player.js serves.
let strokeBody = null;
let player = null;
async function animateStrokes(bodies) {
  const status = $("anim-status");
  status.textContent = "animating…";
  status.classList.remove("error");
  try {
    const res = await (await postJson("/api/animate", { bells: bodies })).json();
    if (player && player.playing) player.pause();
    player = ClapperPlayer.mount($("stroke-anim"), res.animation, "data:audio/wav;base64," + res.audio_wav_base64);
    status.textContent = "";
  } catch (e) {
    showError(status, e);
  }
}

$("cmp-go").addEventListener("click", () => {
  if (!strokeBody) return;
  const other = { ...strokeBody };
  const style = $("cmp-style").value;
  if (style) other.style = style;
  try {
    for (const [id, key] of [["cmp-theta0", "theta0"], ["cmp-restitution", "restitution"], ["cmp-phi-max", "phi_max"]]) {
      const v = num(id);
      if (v !== undefined) other[key] = v;
    }
  } catch (e) { showError($("anim-status"), e); return; }
  animateStrokes([strokeBody, other]);
});

async function showStroke(p) {
  const q = $("quantity").value;
  let style = $("show-style").value;
  if (q === "style") {
    const r = cellAt(p.i, p.j, "right"), w = cellAt(p.i, p.j, "wrong");
    style = r && r[0] === 1 ? "right" : w && w[0] === 1 ? "wrong" : "right";
  }
  const req = chart.request || chartRequest();
  const body = { chart_point: [p.x, p.y], style, theta0: req.theta0, restitution: req.restitution, phi_max: req.phi_max, strokes: 2 };
  if (req.contact) { body.contact = req.contact; body.stiffness = req.stiffness; }
  if (req.restitution_later !== undefined) body.restitution_later = req.restitution_later;
  for (const k of ["pivot_offset", "phi_max_hand", "phi_max_back"]) if (req[k] !== undefined) body[k] = req[k];
  $("stroke-panel").dataset.bell = "0";
  await simulateStroke(body, `Stroke at r/L_c = ${p.x.toFixed(3)}, L_b/L_c = ${p.y.toFixed(3)} (the chart's bell), ringing ${style}`);
}

function strokeTable(r) {
  const instead = r.sustains_instead === "neither" ? "; it sustains neither style"
    : r.sustains_instead ? `; it sustains ringing ${esc(r.sustains_instead)} instead` : "";
  let h = `<p><b>The bell ${r.sustained ? "sustains" : "does not sustain"} ringing ${esc(r.style)}${instead}</b> · T<sub>b</sub> = ${fmt(r.bell.tb_s, 3)} s, T<sub>c</sub> = ${fmt(r.bell.tc_s, 3)} s, φ<sub>max</sub> = ${fmt(r.bell.phi_max_deg, 1)} deg · ${r.odd_struck_ms === null || r.odd_struck_ms === undefined
    ? `odd-struck not defined${r.odd_struck_undefined ? ` (${esc(r.odd_struck_undefined)}: it compares strokes of one style)` : ""}`
    : `odd-struck ${fmt(r.odd_struck_ms, 1)} ms (handstroke minus backstroke)`}</p>`;
  h += "<table><tr><th>stroke</th><th>style</th><th>lift-off (deg)</th><th>first strike θ (deg)</th><th>at (s)</th><th>bottom to strike (ms)</th><th>φ' (rad/s)</th><th>2nd impact after (ms)</th><th>amplitude ratio</th><th>D</th><th>impacts</th><th>sustained</th></tr>";
  for (const s of r.strokes) {
    const f = s.first_strike || {};
    h += `<tr><td>${s.number} (${s.number % 2 ? "hand" : "back"})</td><td>${esc(s.style)}</td><td>${fmt(s.liftoff_theta_deg, 1)}</td><td>${fmt(f.theta_deg, 1)}</td><td>${fmt(f.t_s, 3)}</td><td>${fmt(s.bdc_to_strike_ms, 1)}</td><td>${fmt(f.phidot_rad_s, 2)}</td><td>${fmt(s.second_strike_delay_ms, 1)}</td><td>${fmt(s.amplitude_ratio, 3)}</td><td>${fmt(s.double_strike_index, 2)}</td><td>${s.impacts.length}</td><td>${s.sustained ? "yes" : "no"}</td></tr>`;
  }
  return h + "</table>";
}

$("draw-chart").addEventListener("click", drawChart);
$("quantity").addEventListener("change", renderChart);
$("show-style").addEventListener("change", renderChart);

// ---------- bells ----------
const ring = { bells: [], text: null, kind: null }; // entered bells, or an uploaded file's text

const LAB = { bell_mass_kg: 45.8, clapper_mass_kg: 1.65, a_m: 0.24, b_m: 0.25, bell_inertia_kg_m2: 4.1, clapper_inertia_kg_m2: 0.093, r_m: 0.1, phi_max_deg: 26 };

function bellKind() { return document.querySelector("input[name=bell-kind]:checked").value; }
for (const r of document.querySelectorAll("input[name=bell-kind]")) {
  r.addEventListener("change", () => {
    $("tower-fields").hidden = bellKind() !== "tower";
    $("mass-fields").hidden = bellKind() !== "mass";
  });
}
$("fill-lab").addEventListener("click", () => {
  document.querySelector("input[name=bell-kind][value=mass]").checked = true;
  $("tower-fields").hidden = true; $("mass-fields").hidden = false;
  $("bell-name").value = "Lab bell";
  for (const inp of $("mass-fields").querySelectorAll("input")) inp.value = LAB[inp.dataset.key];
});

function tomlString(s) { return '"' + String(s).replace(/\\/g, "\\\\").replace(/"/g, '\\"') + '"'; }

$("add-bell").addEventListener("click", () => {
  const kind = bellKind();
  const fields = { name: $("bell-name").value.trim() || `bell ${ring.bells.length + 1}` };
  const inputs = [...$(kind === "tower" ? "tower-fields" : "mass-fields").querySelectorAll("input"), ...$("hanging-fields").querySelectorAll("input")];
  for (const inp of inputs) {
    let v;
    // A measurement left empty is not given (the form's values are an example).
    try { v = fieldNumber(inp, true); } catch (e) { showError($("diagnosis-status"), e); return; }
    if (v !== undefined) fields[inp.dataset.key] = v;
  }
  const clapper = clapperParts();
  if (clapper === null) return;
  let note = "";
  if (Object.keys(clapper).length) {
    // The parts stand for these keys: a bell file refuses both.
    const replaced = ["clapper_period_s", "clapper_mass_kg", "b_m", "clapper_inertia_kg_m2"].filter((k) => k in fields);
    for (const k of replaced) delete fields[k];
    fields.clapper = clapper;
    if (replaced.length) note = ` The clapper's parts stand for ${replaced.join(", ")}.`;
  }
  if (ring.text) { ring.text = null; ring.bells = []; }
  ring.bells.push({ kind, fields });
  forgetDiagnosis();
  showStatus($("diagnosis-status"), `${ring.bells.length} bell(s) entered.${note} Press “Diagnose”.`);
  renderRing();
});

// The clapper's parts as entered: {} if none, null (and an error shown) if
// one is not a number.
function clapperParts() {
  const parts = {};
  for (const inp of $("clapper-fields").querySelectorAll("input, select")) {
    if (inp.tagName === "SELECT") { if (inp.value) parts[inp.dataset.key] = inp.value; continue; }
    let v;
    try { v = fieldNumber(inp, true); } catch (e) { showError($("diagnosis-status"), e); return null; }
    if (v !== undefined) parts[inp.dataset.key] = v;
  }
  return parts;
}

// What the parts give (m, b, I_c, T_c), as the user types.
async function showClapperFigures() {
  const out = $("clapper-figures");
  const parts = clapperParts();
  if (!parts || !Object.keys(parts).length) { out.textContent = ""; return; }
  const tb = Number(document.querySelector('#tower-fields input[data-key="bell_period_s"]').value);
  const req = { clapper: parts };
  if (bellKind() === "tower" && tb > 0) req.bell_period_s = tb;
  try {
    const r = await (await postJson("/api/design-clapper", req)).json();
    let t = `m ${fmt(r.m_kg, 2)} kg, b ${fmt(r.b_m, 3)} m, I_c ${fmt(r.ic_kg_m2, 3)} kg m², T_c ${fmt(r.tc_s, 3)} s`;
    if (r.bell) t += `; T_c/T_b ${fmt(r.bell.period_ratio, 3)} (${r.bell.cccbr_rule_met ? "meets" : "misses"} the 90 % rule)`;
    out.textContent = t;
    out.classList.remove("error");
  } catch (e) { out.textContent = String(e.message || e); out.classList.add("error"); }
}
for (const inp of $("clapper-figures").parentElement.querySelectorAll("input, select")) inp.addEventListener("change", showClapperFigures);

function tomlValue(k, v) { return typeof v === "string" ? tomlString(v) : v; }

function ringToml() {
  return ring.bells.map((b) => {
    const plain = Object.entries(b.fields).filter(([k]) => k !== "clapper");
    let t = "[[bell]]\n" + plain.map(([k, v]) => `${k} = ${tomlValue(k, v)}`).join("\n");
    if (b.fields.clapper) t += "\n\n[bell.clapper]\n" + Object.entries(b.fields.clapper).map(([k, v]) => `${k} = ${tomlValue(k, v)}`).join("\n");
    return t;
  }).join("\n\n") + "\n";
}

function renderRing() {
  const body = $("ring-list").querySelector("tbody");
  body.innerHTML = "";
  if (ring.text) {
    body.innerHTML = `<tr><td>${esc(ring.fileName)}</td><td>${ring.kind} file</td><td></td></tr>`;
    $("ring-toml").textContent = ring.text;
    return;
  }
  ring.bells.forEach((b, k) => {
    const tr = document.createElement("tr");
    tr.innerHTML = `<td>${esc(b.fields.name)}</td><td>${b.kind === "tower" ? "tower measurements" : "mass properties"}</td><td><button type="button">remove</button></td>`;
    tr.querySelector("button").addEventListener("click", () => { ring.bells.splice(k, 1); forgetDiagnosis(); renderRing(); });
    body.appendChild(tr);
  });
  $("ring-toml").textContent = ring.bells.length ? ringToml() : "";
}

// What the server takes (bytes), from /api/health; its defaults until then.
const serverLimits = { max_body_bytes: 1 << 20, max_recording_bytes: 64 << 20 };
const mb = (bytes) => (bytes / (1 << 20)).toFixed(bytes < 10 << 20 ? 1 : 0) + " MB";
const SOUND_NAME = /\.(wav|wave|bwf|rf64|mp3|flac|ogg|oga|opus|m4a|aac|aif|aiff|caf|wma)$/i;

// Is `f` a sound file, by its name or its first bytes?
async function isSound(f) {
  const magic = String.fromCharCode(...new Uint8Array(await f.slice(0, 12).arrayBuffer()));
  return SOUND_NAME.test(f.name) || /^(RIFF|RIFX|RF64|ID3|fLaC|OggS|FORM)/.test(magic) || magic.slice(4, 8) === "ftyp";
}

// Why a file picked as a text file of the page's (`kind`, in words) is
// not one, or null: a recording, a binary file, or one too large for the
// server to take (a ring of 64 bells is a few tens of kB, as are 100
// listeners' answers). Asked when the file is picked, not when the server
// refuses it.
async function notATextFile(f, kind) {
  if (await isSound(f)) return `${f.name} is a recording, not ${kind}. The strikes in a recording are heard on the “Strikes from a recording” tab.`;
  const head = new Uint8Array(await f.slice(0, 4096).arrayBuffer());
  if (head.includes(0)) return `${f.name} is not a text file: not ${kind}.`;
  // The request carries the text, quoted, and a little more.
  if (f.size > serverLimits.max_body_bytes - 1024) return `${f.name} is ${mb(f.size)}: more than ${kind} holds and more than this server takes (${mb(serverLimits.max_body_bytes)}).`;
  return null;
}
const RING_FILE = "a ring file (a bell file in TOML or a ring CSV)";

$("ring-file").addEventListener("change", async (ev) => {
  const inp = ev.target, f = inp.files[0];
  clearFieldError(inp);
  if (!f) return;
  const why = await notATextFile(f, RING_FILE);
  if (why) {
    inp.value = "";
    fieldError(inp, why);
    showError($("diagnosis-status"), why);
    if (await isSound(f)) offerRecording(f);
    return;
  }
  ring.text = await f.text();
  ring.kind = /\.csv$/i.test(f.name) ? "csv" : "toml";
  ring.fileName = f.name;
  ring.bells = [];
  forgetDiagnosis();
  showStatus($("diagnosis-status"), `Read ${f.name}. Press “Diagnose”.`);
  renderRing();
});

// A button beside the ring file's message that takes the recording to the
// Strikes tab's Recording field.
function offerRecording(f) {
  const msg = $("ring-file").nextElementSibling;
  if (!msg) return;
  const b = document.createElement("button");
  b.type = "button"; b.id = "use-as-recording"; b.textContent = "Listen to it on the Strikes tab";
  b.addEventListener("click", () => {
    const dt = new DataTransfer();
    dt.items.add(f);
    $("recording").files = dt.files;
    clearFieldError($("ring-file"));
    showStatus($("diagnosis-status"), "");
    selectTab("strikes");
    showStatus($("strikes-status"), `${f.name} is ready: give the bells' nominals (Hz), treble first, and press “Find the strikes”.`);
    $("nominals").focus();
  });
  msg.append(" ", b);
}

$("clear-bells").addEventListener("click", () => {
  ring.bells = []; ring.text = null; renderRing();
  forgetDiagnosis();
  showStatus($("diagnosis-status"), "");
});

// The diagnosed ring is forgotten wherever it is used once the bells
// change: its table, its markers on the chart and a marker's stroke, the
// ring in rounds, and the Strikes tab's bells set beside what is heard.
function forgetDiagnosis() {
  lastDiagnosis = null;
  chart.markers = [];
  renderMarkers();
  $("diagnosis").innerHTML = "";
  if (roundsPlayer && roundsPlayer.playing) roundsPlayer.pause();
  roundsPlayer = null;
  $("rounds-anim").innerHTML = "";
  showStatus($("rounds-status"), "");
  $("rounds-box").hidden = true;
  if ($("stroke-panel").dataset.bell === "1") {
    if (player && player.playing) player.pause();
    $("stroke-panel").hidden = true;
    strokeBody = null;
  }
  if (lastStrikes) renderStrikes();
}

function diagnoseRequest() {
  if (ring.text) return ring.kind === "csv" ? { csv: ring.text } : { toml: ring.text };
  if (!ring.bells.length) throw new Error("Enter a bell (and press “Add bell”) or choose a ring file first.");
  return { toml: ringToml() };
}

$("diagnose").addEventListener("click", async () => {
  const status = $("diagnosis-status");
  try {
    const req = diagnoseRequest();
    showStatus(status, "Diagnosing…");
    const rep = await (await postJson("/api/diagnose", req)).json();
    lastDiagnosis = rep;
    chart.markers = rep.bells.map((b, k) => ({
      x: b.r_over_lc, y: b.lb_over_lc, label: b.name, source: rep.simulate[k], style: b.usual_style || "right",
    }));
    $("diagnosis").innerHTML = diagnosisHtml(rep);
    $("rounds-box").hidden = rep.bells.length < 2;
    showStatus(status, `${rep.bells.length} bell(s) diagnosed; they are marked on the clapping chart.`);
    renderMarkers();
    if (lastStrikes) renderStrikes();
  } catch (e) { showError(status, e); }
});

// The diagnosed ring ringing rounds: every bell's own file, rung right,
// two whole pulls, animated with its sound and a striking diagram.
let roundsPlayer = null;
$("ring-rounds").addEventListener("click", async () => {
  const status = $("rounds-status");
  if (!lastDiagnosis) return;
  try {
    showStatus(status, "Ringing…");
    const bells = lastDiagnosis.simulate.slice(0, 16).map((src) => ({ ...src, style: "right", strokes: 4 }));
    const res = await (await postJson("/api/animate", { bells, arrangement: "rounds" })).json();
    if (roundsPlayer && roundsPlayer.playing) roundsPlayer.pause();
    roundsPlayer = ClapperPlayer.mount($("rounds-anim"), res.animation, "data:audio/wav;base64," + res.audio_wav_base64);
    showStatus(status, `${bells.length} bells, ${(res.animation.rounds_interval_s * 1000).toFixed(0)} ms between blows. Press Play.`);
  } catch (e) { showError(status, e); }
});

$("report").addEventListener("click", async () => {
  const status = $("diagnosis-status");
  try {
    const req = diagnoseRequest();
    showStatus(status, "Writing the report…");
    const blob = await (await postJson("/api/diagnose/report", req)).blob();
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob); a.download = "clapper-diagnosis.html";
    document.body.appendChild(a); a.click(); a.remove();
    showStatus(status, "Report downloaded (clapper-diagnosis.html).");
  } catch (e) { showError(status, e); }
});

function diagnosisHtml(rep) {
  let h = "<h2>Diagnosis</h2><p>Fully up from 171 deg, R = 0.2 for the verdicts; D at R = 0.05, 0.1 and 0.2.</p>";
  h += "<table><tr><th>bell</th><th>r/L<sub>c</sub></th><th>L<sub>b</sub>/L<sub>c</sub></th><th>rings</th><th>first strike (deg)</th><th>φ' (rad/s)</th><th>lift-off (deg)</th><th>D, R=0.05</th><th>D, R=0.1</th><th>D, R=0.2</th><th>rings right from (deg)</th><th>goes up</th></tr>";
  for (const b of rep.bells) {
    const d = b.double_strike_index;
    h += `<tr class="bell-row"><td>${esc(b.name)}</td><td>${fmt(b.r_over_lc, 3)}</td><td>${fmt(b.lb_over_lc, 3)}</td><td>${esc(b.verdict)}</td><td>${fmt(b.first_strike_theta_deg, 1)}</td><td>${fmt(b.strike_phidot_rad_s, 2)}</td><td>${fmt(b.liftoff_theta_deg, 1)}</td><td>${fmt(d["0.05"], 1)}</td><td>${fmt(d["0.1"], 1)}</td><td>${fmt(d["0.2"], 1)}</td><td>${fmt(b.min_theta0_right_deg, 1)}</td><td class="goes-up">${esc(b.goes_up)}</td></tr>`;
    // A bell hung out of true: its backstroke too (its problems are judged from the worse stroke).
    const k = b.backstroke;
    if (k) h += `<tr class="back-row"><td>&nbsp;&nbsp;backstroke</td><td></td><td></td><td></td><td>${fmt(k.first_strike_theta_deg, 1)}</td><td>${fmt(k.strike_phidot_rad_s, 2)}</td><td>${fmt(k.liftoff_theta_deg, 1)}</td><td>${fmt(k.double_strike_index["0.05"], 1)}</td><td>${fmt(k.double_strike_index["0.1"], 1)}</td><td>${fmt(k.double_strike_index["0.2"], 1)}</td><td></td><td></td></tr>`;
  }
  h += "</table>";
  for (const b of rep.bells) {
    h += `<div class="bell-detail"><b>${esc(b.name)}</b>: T<sub>b</sub> = ${fmt(b.tb_s, 2)} s, T<sub>c</sub> = ${fmt(b.tc_s, 2)} s, r = ${fmt(b.r_mm, 0)} mm. Rings <b>${esc(b.verdict)}</b> when fully up`;
    h += b.usual_style ? `, usually ${esc(b.usual_style)}.` : ".";
    if (b.striking_speed_m_s !== null) h += ` Strikes at ${fmt(b.striking_speed_m_s, 2)} m/s` + (b.strike_energy_j !== null ? ` (${fmt(b.strike_energy_j, 1)} J).` : ".");
    if (b.assumed.length) h += `<br>Assumed, not measured: ${esc(b.assumed.join(", "))}`;
    // odd_struck_ms is null where the bell sustains neither style: its words then say why.
    const odd = b.odd_struck;
    if (odd && odd.odd_struck_ms === null) h += `<br><span class="odd-struck">${esc(odd.words)}</span>`;
    else if (odd) h += `<br><span class="${Math.abs(odd.odd_struck_ms) > odd.tolerance_ms ? "problem" : ""} odd-struck">Odd-struck: ${esc(odd.words)}</span>`;
    for (const p of b.problems) h += `<br><span class="problem">Problem: ${esc(p)}</span>`;
    h += `<br>Goes up <b>${esc(b.goes_up)}</b> (rung up from rest).`;
    if (b.changes.length) {
      h += `<br>Changes, in the order a hanger would try them:<ol class="changes">`;
      for (const c of b.changes) {
        h += `<li class="${c.last_resort ? "last-resort" : ""}">${esc(c.words)}`;
        if (c.clapper_toml) h += `<details><summary>the changed clapper as a bell file's table</summary><pre>${esc(c.clapper_toml)}</pre></details>`;
        h += "</li>";
      }
      h += "</ol>";
    } else if (b.problems.length) h += "<br>No change of the flight, ball, shaft, a new clapper or the pivot within the searches cures any of it.";
    if (b.frame) h += `<br>${esc(b.frame.words.charAt(0).toUpperCase() + b.frame.words.slice(1))}.`;
    for (const s of b.stands_apart) h += `<br><span class="problem">Stands apart: ${esc(s)}</span>`;
    h += "</div>";
  }
  return h;
}

// ---------- listening test ----------
const listen = { answers: JSON.parse(localStorage.getItem("clapper-answers") || "[]"), sheet: null, trial: 0, listener: null, audio: null, active: false };

// While a listener is answering, the results are out of sight: seeing the
// score map (or others' answers) would bias the answers still to come.
function setListening(active) {
  listen.active = active;
  $("trial-box").hidden = !active;
  for (const id of ["analyse", "download-answers", "upload-answers", "clear-answers"]) $(id).disabled = active;
  $("results-controls").title = active ? "End this listener's turn to see the results" : "";
  if (active) $("listen-result").innerHTML = "";
}

function saveAnswers() {
  localStorage.setItem("clapper-answers", JSON.stringify(listen.answers));
  const who = new Set(listen.answers.map((a) => a.listener));
  $("answer-count").textContent = listen.answers.length
    ? `${listen.answers.length} answer(s) from ${who.size} listener(s).`
    : "No answers yet.";
}

function play(url) {
  if (listen.audio) listen.audio.pause();
  listen.audio = new Audio(url);
  listen.audio.play().catch(() => { /* autoplay refused: the listener presses Play */ });
}

$("start-listener").addEventListener("click", async () => {
  const name = $("listener-name").value.trim();
  if (!name) { $("answer-count").textContent = "Give the listener a name."; return; }
  const names = [...new Set(listen.answers.map((a) => a.listener))];
  const index = names.includes(name) ? names.indexOf(name) : names.length;
  try {
    const seed = Math.max(0, Math.floor(num("seed")));
    const res = await fetch(`/api/listening/sheet?listener=${index}&seed=${seed}`);
    if (!res.ok) throw new Error((await res.json()).error);
    listen.sheet = await res.json();
    listen.listener = name;
    // Carry on where this listener stopped.
    const done = new Set(listen.answers.filter((a) => a.listener === name).map((a) => a.stimulus));
    listen.trial = listen.sheet.trials.findIndex((t) => !done.has(t.stimulus));
    setListening(true);
    nextTrial();
  } catch (e) { showError($("answer-count"), e); }
});

function nextTrial() {
  if (listen.trial < 0 || listen.trial >= listen.sheet.trials.length) {
    setListening(false);
    $("answer-count").textContent = `${listen.listener} has answered all 100. Next listener, please: change the name and press Start.`;
    return;
  }
  for (const b of document.querySelectorAll("button.answer")) b.disabled = false;
  const t = listen.sheet.trials[listen.trial];
  $("trial-label").textContent = `${listen.listener}: trial ${listen.trial + 1} of ${listen.sheet.trials.length}. One strike or two?`;
  play(t.url);
}

function answer(value) {
  const t = listen.sheet.trials[listen.trial];
  listen.answers.push({ listener: listen.listener, trial: t.trial, stimulus: t.stimulus, amplitude_ratio: t.amplitude_ratio, delay_ms: t.delay_ms, answer: value });
  saveAnswers();
  listen.trial += 1;
  nextTrial();
}
$("ans-single").addEventListener("click", () => answer(1));
$("finish-listener").addEventListener("click", () => {
  if (listen.audio) listen.audio.pause();
  setListening(false);
  saveAnswers();
});
$("ans-double").addEventListener("click", () => answer(-1));
$("play").addEventListener("click", () => { if (listen.sheet && listen.trial >= 0 && listen.trial < 100) play(listen.sheet.trials[listen.trial].url); });
$("play-reference").addEventListener("click", () => play("/api/listening/stimulus/reference.wav"));

$("analyse").addEventListener("click", async () => {
  const out = $("listen-result");
  out.innerHTML = "<p class=status>Analysing…</p>";
  try {
    const res = await (await postJson("/api/listening/analyse", { answers: listen.answers })).json();
    const a = res.analysis;
    let h = `<p>${a.answers} answer(s); used ${a.listeners_used.length} listener(s)`;
    if (a.excluded.length) h += `; left out ${a.excluded.map((e) => `${esc(e.listener)} (correlation ${fmt(e.correlation, 2)})`).join(", ")}`;
    h += ".</p>";
    h += a.fit
      ? `<p>Zero contour (A − a)(Δt − b) = c: a = ${fmt(a.fit.a, 3)} ± ${fmt(a.fit.sigma_a, 3)}, b = ${fmt(a.fit.b_ms, 1)} ± ${fmt(a.fit.sigma_b_ms, 1)} ms, c = ${fmt(a.fit.c_ms, 2)} ± ${fmt(a.fit.sigma_c_ms, 2)} ms (the paper: a = 0.2, b = 22 ms, c = 2.25 ms).</p>`
      : "<p>The score map has no clear zero contour to fit yet: more answers are needed.</p>";
    out.innerHTML = h + res.plot_svg;
  } catch (e) { out.innerHTML = ""; const p = document.createElement("p"); out.appendChild(p); showError(p, e); }
});

$("download-answers").addEventListener("click", () => {
  const rows = ["listener,trial,stimulus,amplitude_ratio,delay_ms,answer"];
  for (const a of listen.answers) rows.push([JSON.stringify(a.listener), a.trial ?? "", a.stimulus ?? "", a.amplitude_ratio, a.delay_ms, a.answer].join(","));
  const blob = new Blob([rows.join("\n") + "\n"], { type: "text/csv" });
  const link = document.createElement("a");
  link.href = URL.createObjectURL(blob); link.download = "clapper-answers.csv";
  document.body.appendChild(link); link.click(); link.remove();
});

$("upload-answers").addEventListener("change", async (ev) => {
  const f = ev.target.files[0];
  clearFieldError(ev.target);
  if (!f) return;
  const why = await notATextFile(f, "an answers file (CSV)");
  if (why) { ev.target.value = ""; fieldError(ev.target, why); showError($("answer-count"), why); return; }
  try {
    const res = await (await postJson("/api/listening/parse", { csv: await f.text() })).json();
    listen.answers.push(...res.answers);
    saveAnswers();
  } catch (e) { showError($("answer-count"), e); }
  ev.target.value = "";
});
$("clear-answers").addEventListener("click", () => {
  if (listen.answers.length && !confirm(`Forget all ${listen.answers.length} answers?`)) return;
  listen.answers = []; saveAnswers();
});

// ---------- start ----------
fetch("/api/health").then((r) => r.json()).then((h) => {
  $("version").textContent = h.version;
  for (const k of Object.keys(serverLimits)) if (Number.isFinite(h[k])) serverLimits[k] = h[k];
}).catch(() => {});
saveAnswers();
renderRing();
selectTab("chart");

// ---------- strikes from a recording ----------
let lastDiagnosis = null;
let lastStrikes = null;

function download(name, type, text) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  document.body.appendChild(a); a.click(); a.remove();
}

$("listen-recording").addEventListener("click", async () => {
  const status = $("strikes-status");
  try {
    const file = $("recording").files[0];
    if (!file) throw new Error("choose a recording (.wav) first");
    const nominals = $("nominals").value.split(/[,\s]+/).filter((v) => v !== "");
    const bells = $("strikes-bells").value.trim();
    // The bells: their nominals, or how many ring (their nominals learned), as clapper strikes --bells N.
    if (nominals.length === 0 && bells === "") throw new Error("give the bells' nominals (Hz), treble first, or how many bells ring");
    if (nominals.length > 0 && bells !== "") throw new Error("give the bells' nominals or how many bells ring, not both");
    const q = new URLSearchParams(nominals.length ? { nominals: nominals.join(",") } : { bells });
    q.set("double_min_ratio", num("double-min-ratio"));
    if ($("strikes-handbells").checked) q.set("handbells", "true");
    q.set("timing", $("strikes-timing").value);
    showStatus(status, `Listening to ${file.name}…`);
    const res = await fetch("/api/strikes?" + q, { method: "POST", headers: { "Content-Type": "audio/wav" }, body: file });
    if (!res.ok) {
      let msg = res.statusText;
      try { msg = (await res.json()).error; } catch (_) { /* not JSON */ }
      throw new Error(msg);
    }
    lastStrikes = await res.json();
    renderStrikes();
    const s = lastStrikes.report.summary;
    const learned = lastStrikes.report.learned_nominals_hz;
    showStatus(status, `${s.strikes} strike(s) heard in ${fmt(s.duration_s, 1)} s.` +
      (learned ? ` Nominals learned from the recording: ${learned.map((b) => `${b.bell}: ${fmt(b.nominal_hz, 1)} Hz (${fmt(100 * b.confidence, 0)} % sure)`).join(", ")}.` : "") +
      (s.warnings.length ? ` ${s.warnings.length} warning(s): see below.` : ""));
  } catch (e) { showError(status, e); }
});

// A recording is checked when picked: a sound file, within what the server takes.
$("recording").addEventListener("change", async (ev) => {
  const inp = ev.target, f = inp.files[0];
  clearFieldError(inp);
  if (!f) return;
  let why = null;
  if (!(await isSound(f))) why = `${f.name} is not a recording: give a WAV file (a bell file or ring CSV goes on the “Your bells” tab).`;
  else if (f.size > serverLimits.max_recording_bytes) why = `${f.name} is ${mb(f.size)}, more than this server takes (${mb(serverLimits.max_recording_bytes)}): cut it, or use clapper strikes.`;
  if (why) { inp.value = ""; fieldError(inp, why); showError($("strikes-status"), why); }
});

// The last recording's striking, beside the bells diagnosed now (if any).
function renderStrikes() {
  $("strikes-result").innerHTML = strikesHtml(lastStrikes.report);
  $("download-strikes-json").addEventListener("click", () =>
    download("strikes.json", "application/json", JSON.stringify(lastStrikes.report, null, 2)));
  $("download-strikes-csv").addEventListener("click", () => download("strikes.csv", "text/csv", lastStrikes.csv));
}

function strikesHtml(r) {
  const s = r.summary;
  const doubted = r.per_bell.filter((b) => b.timing_doubt);
  const sure = doubted.length && s.rms_error_sure_ms !== null
    ? ` (${fmt(s.rms_error_sure_ms, 1)} ms leaving out bell${doubted.length > 1 ? "s" : ""} ${doubted.map((b) => b.bell).join(", ")}, whose timing is in doubt)` : "";
  const beside = lastDiagnosis && lastDiagnosis.bells.length > 0;
  let h = `<h2>Striking</h2><p>${s.strikes} strikes in ${s.rows} rows (${s.full_rows} full${s.placed_rows > s.full_rows ? `, ${s.placed_rows - s.full_rows} lacking one bell` : ''}); interval ${fmt(s.interval_ms, 1)} ms,
    handstroke gap ${fmt(s.handstroke_gap_intervals, 2)} interval(s), RMS striking error ${fmt(s.rms_error_ms, 1)} ms${sure},
    ${s.double_strikes} double strike(s).
    <button type="button" id="download-strikes-json">Download JSON</button>
    <button type="button" id="download-strikes-csv">Download CSV</button></p>`;
  // As clapper strikes prints them (clapper-app's strikes/text.rs): the ring's warnings, most serious first, before
  // the table; a warning about one bell heard (kind "bell") with that bell after it.
  const { ring, own } = splitWarnings(r);
  if (ring.length) h += `<ul id="strikes-warnings" class="warnings">${ring.map((w) => `<li class="problem">Warning: ${esc(w)}</li>`).join("")}</ul>`;
  h += "<table id=\"strikes-table\"><tr><th>bell</th><th>strikes</th><th>hand mean ± sd (ms)</th><th>back mean ± sd (ms)</th><th>odd-struck (ms)</th><th>double strikes</th><th>mean D</th>";
  if (beside) h += "<th>bell diagnosed</th><th>odd-struck, model (ms)</th><th>D, model (R = 0.1)</th>";
  h += "</tr>";
  const ms = (st) => (st.mean_error_ms === null ? "–" : `${fmt(st.mean_error_ms, 1)} ± ${fmt(st.spread_ms, 1)}`);
  for (const b of r.per_bell) {
    h += `<tr><td>${b.bell}${b.timing_doubt ? "?" : ""}</td><td>${b.strikes}</td><td>${ms(b.hand)}</td><td>${ms(b.back)}</td>
      <td>${b.odd_struck_ms === null ? "–" + (b.odd_struck_doubt ? " ?" : "") : fmt(b.odd_struck_ms, 1) + (b.odd_struck_se_ms === null ? "" : " ± " + fmt(b.odd_struck_se_ms, 1)) + (b.odd_struck_doubt ? " ?" : "")}</td>
      <td>${b.double_strikes} (${fmt(100 * b.double_rate, 0)} %)${(s.doubles_doubted || []).includes(b.bell) ? "?" : ""}</td><td>${fmt(b.mean_d, 1)}</td>`;
    if (beside) {
      const d = lastDiagnosis.bells[b.bell - 1];
      h += d
        ? `<td>${esc(d.name)}</td><td class="odd-model">${d.odd_struck ? fmt(d.odd_struck.odd_struck_ms, 1) : "0.0"}</td><td>${fmt(d.double_strike_index["0.1"], 1)}</td>`
        : "<td>–</td><td>–</td><td>–</td>";
    }
    h += "</tr>";
  }
  h += "</table>";
  const odd = r.per_bell.filter((b) => b.odd_struck_doubt);
  if (odd.length) h += `<p>Odd-struckness in doubt (marked ? in its column):</p><ul class="warnings">${odd.map((b) => `<li>Bell ${b.bell}: ${esc(b.odd_struck_doubt)}</li>`).join("")}</ul>`;
  // About each bell: why its timing is in doubt (marked ? in the table), then its own warnings.
  const each = r.per_bell.filter((b) => b.timing_doubt || own[b.bell]);
  if (each.length) {
    h += `<p>About each bell (one marked ? in the table the listener may have timed, or placed in rows, wrongly, so that its figures may show that error rather than the ringer's striking):</p>`;
    h += `<ul id="strikes-doubts" class="warnings">${each.map((b) => [b.timing_doubt ? `Bell ${b.bell}: ${b.timing_doubt}` : null, ...(own[b.bell] || [])]
      .filter((w) => w).map((w) => `<li class="problem">${esc(w)}</li>`).join("")).join("")}</ul>`;
  }
  h += `<div class="plot">${lastStrikes.plot_svg}</div>`;
  return h;
}

// The report's warnings (already in the order a ringer reads them) split as the CLI splits them: those about one bell
// heard (kind "bell", their words starting "bell N:" or "bell N (") by bell, the rest for before the table.
function splitWarnings(r) {
  const s = r.summary, kinds = s.warning_kinds || [], ring = [], own = {};
  const heard = (n) => r.per_bell.some((b) => b.bell === n && b.strikes > 0);
  s.warnings.forEach((w, i) => {
    const m = kinds[i] === "bell" ? /^bell (\d+)(:| \()/.exec(w) : null;
    const b = m && heard(+m[1]) ? +m[1] : null;
    if (b === null) ring.push(w); else (own[b] = own[b] || []).push(w);
  });
  return { ring, own };
}
