// Small SVG helpers: elements, line plots with labelled axes, bands, markers and a
// hover cursor; plotui.js adds zoom, pan, the hover read-out and PNG/CSV export. Written
// here rather than vendored: no plotting library could be installed offline (README).

import { interact, valueAt } from "./plotui.js";

const NS = "http://www.w3.org/2000/svg";

export function el(tag, attrs = {}, children = []) {
  const node = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  for (const c of children) node.append(c);
  return node;
}

export function text(x, y, s, attrs = {}) {
  const t = el("text", { x, y, ...attrs });
  t.textContent = s;
  return t;
}

export function path(points, attrs = {}, closed = false) {
  if (!points.length) return el("path", attrs);
  const d = points.map((p, i) => `${i ? "L" : "M"}${p[0].toFixed(3)},${p[1].toFixed(3)}`).join("") + (closed ? "Z" : "");
  return el("path", { d, ...attrs });
}

function ticks(lo, hi, n) {
  const raw = (hi - lo) / n;
  const mag = 10 ** Math.floor(Math.log10(raw || 1));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw) || raw;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(+v.toFixed(10));
  return out;
}

// The pieces of the interval [a, b] inside [lo, hi] on an axis of period P: the interval
// and its copies shifted by whole periods, so a region crossing the period boundary is
// drawn as two pieces (conventions §1: every function of θ is periodic).
export function wrapSpans(a, b, lo, hi, P) {
  if (!(b > a)) return [];
  if (!(P > 0)) return b > lo && a < hi ? [[Math.max(a, lo), Math.min(b, hi)]] : [];
  if (b - a >= P) return [[lo, hi]];
  const out = [];
  for (let k = Math.floor((lo - b) / P); k <= Math.ceil((hi - a) / P); k++) {
    const s = Math.max(a + k * P, lo), e = Math.min(b + k * P, hi);
    if (e - s > 1e-9) out.push([s, e]);
  }
  return out;
}

function union(spans) {
  const out = [];
  for (const [a, b] of [...spans].sort((p, q) => p[0] - q[0])) {
    if (out.length && a <= out[out.length - 1][1] + 1e-9) out[out.length - 1][1] = Math.max(out[out.length - 1][1], b);
    else out.push([a, b]);
  }
  return out;
}

let clipIds = 0;
const LANE = 12; // px per Θᵢ row: a 4 px bar and its label never touch the next one

// A line plot in `host` (replacing its content). spec: {title, xLabel, yLabel, xDomain,
// period? (of x; default the domain's width), yDomain?, series: [{xs, ys, cls, label,
// breakJumps?}], bands: [{x0, x1, cls}] (x only, wrapped), polys: [{points, cls}] (drawn
// with their copies shifted by whole periods (their own `period`, or the axis's) in x and y — lifted images — and clipped),
// lanes: [{x0, x1, label, cls}] (one labelled row each under the axis, wrapped),
// markers: [{x, y, cls, label}], legend, onHover(x)}. Returns {setCursor(x)}; the plot
// zooms, pans, reads out and exports (plotui.js), keeping its view while redrawn.
export function linePlot(host, spec) {
  const full = spec.xDomain;
  const period = spec.period ?? full[1] - full[0];
  let cursorAt = null;
  interact(host, spec, full, (domain) => {
    const drawn = drawPlot({ ...spec, xDomain: domain, period });
    if (cursorAt !== null) drawn.setCursor(cursorAt);
    return drawn;
  });
  return {
    setCursor: (x) => {
      cursorAt = x;
      const svg = host.querySelector("svg.plot");
      if (svg && svg.setCursor) svg.setCursor(x);
    },
  };
}

function drawPlot(spec) {
  const lanes = spec.lanes || [];
  const W = 520, PH = 162, m = { l: 56, r: 12, t: 24 };
  const yb = m.t + PH; // the x axis
  const laneTop = yb + 26;
  const H = laneTop + lanes.length * LANE + (lanes.length ? 22 : 18);
  const [x0, x1] = spec.xDomain;
  const P = spec.period ?? x1 - x0;
  const ys = spec.series.flatMap((s) => s.ys);
  let [y0, y1] = spec.yDomain || [Math.min(...ys), Math.max(...ys)];
  if (!(y1 > y0)) { y0 -= 1; y1 += 1; }
  const pad = spec.yDomain ? 0 : (y1 - y0) * 0.08;
  y0 -= pad; y1 += pad;
  const sx = (x) => m.l + ((x - x0) / (x1 - x0)) * (W - m.l - m.r);
  const sy = (y) => yb - ((y - y0) / (y1 - y0)) * PH;
  const svg = el("svg", { viewBox: `0 0 ${W} ${H}`, class: "plot", role: "img", "aria-label": spec.title });
  const title = text(8, 15, spec.title, { class: "plot-title" });
  title.append(el("title", {}, [spec.title])); // the whole title on hover if the width cuts it
  svg.append(title);
  const clipId = `plot-clip-${++clipIds}`;
  const area = { x: m.l, y: m.t, width: W - m.l - m.r, height: PH };
  svg.append(el("clipPath", { id: clipId }, [el("rect", area)]));
  svg.append(el("rect", { ...area, class: "plot-area", fill: "none" }));
  const bands = el("g", { class: "bands" });
  const byClass = new Map();
  for (const b of spec.bands || []) {
    byClass.set(b.cls, [...(byClass.get(b.cls) || []), ...wrapSpans(b.x0, b.x1, x0, x1, P)]);
  }
  for (const [cls, spans] of byClass) { // overlapping regions of a kind: one shade, not darker twice
    for (const [a, c] of union(spans)) {
      bands.append(el("rect", { x: sx(a), y: m.t, width: sx(c) - sx(a), height: PH, class: cls }));
    }
  }
  svg.append(bands);
  const axes = el("g", { class: "axes" });
  axes.append(path([[m.l, m.t], [m.l, yb], [W - m.r, yb]], { class: "axis" }));
  for (const v of ticks(x0, x1, 6)) {
    axes.append(path([[sx(v), yb], [sx(v), yb + 4]], { class: "axis" }));
    axes.append(text(sx(v), yb + 15, `${v}`, { class: "tick", "text-anchor": "middle" }));
  }
  for (const v of ticks(y0, y1, 4)) {
    axes.append(path([[m.l - 4, sy(v)], [m.l, sy(v)]], { class: "axis" }));
    axes.append(text(m.l - 6, sy(v) + 4, `${+v.toPrecision(4)}`, { class: "tick", "text-anchor": "end" }));
  }
  axes.append(text((m.l + W - m.r) / 2, H - 6, spec.xLabel, { class: "label", "text-anchor": "middle" }));
  axes.append(text(14, m.t + PH / 2, spec.yLabel, { class: "label", "text-anchor": "middle",
    transform: `rotate(-90 14 ${m.t + PH / 2})` }));
  svg.append(axes);
  const data = el("g", { "clip-path": `url(#${clipId})` });
  for (const q of spec.polys || []) {
    const xs = q.points.map((p) => p[0]);
    const lo = Math.min(...xs), hi = Math.max(...xs);
    const T = q.period ?? P;
    for (let k = Math.floor((x0 - hi) / T); k <= Math.ceil((x1 - lo) / T); k++) {
      if (hi + k * T <= x0 || lo + k * T >= x1) continue;
      data.append(path(q.points.map(([x, y]) => [sx(x + k * T), sy(y + k * T)]), { class: q.cls }, true));
    }
  }
  for (const s of spec.series) {
    let seg = [];
    const flush = () => { if (seg.length > 1) data.append(path(seg, { class: `line ${s.cls || ""}` })); seg = []; };
    s.xs.forEach((x, i) => {
      // a jump (a step boundary) is drawn as a gap, not a vertical line
      if (s.breakJumps && i && Math.abs(s.ys[i] - s.ys[i - 1]) > s.breakJumps) flush();
      seg.push([sx(x), sy(s.ys[i])]);
    });
    flush();
  }
  svg.append(data);
  lanes.forEach((b, i) => {
    const y = laneTop + i * LANE + LANE / 2;
    const g = el("g", { class: "lane", "data-label": b.label });
    g.append(text(m.l - 6, y + 4, b.label, { class: "tick lane-label", "text-anchor": "end" }));
    for (const [a, c] of wrapSpans(b.x0, b.x1, x0, x1, P)) {
      g.append(el("line", { x1: sx(a), x2: sx(c), y1: y, y2: y, class: b.cls }));
    }
    svg.append(g);
  });
  for (const mk of spec.markers || []) {
    const c = el("circle", { cx: sx(x0 + mod(mk.x - x0, P)), cy: sy(mk.y), r: 3.5, class: mk.cls });
    if (mk.label) c.append(el("title", {}, [mk.label]));
    svg.append(c);
  }
  if (spec.legend) {
    spec.legend.forEach((l, i) => {
      const y = m.t + 4 + i * 13;
      svg.append(el("rect", { x: W - m.r - 150, y, width: 10, height: 8, class: l.cls }));
      svg.append(text(W - m.r - 136, y + 8, l.label, { class: "tick" }));
    });
  }
  const cursor = el("line", { y1: m.t, y2: yb, class: "cursor", visibility: "hidden" });
  svg.append(cursor);
  const setCursor = (x) => {
    const v = x0 + mod(x - x0, P); // the copy of x in view, if any
    cursor.setAttribute("x1", sx(v));
    cursor.setAttribute("x2", sx(v));
    cursor.setAttribute("visibility", v <= x1 ? "visible" : "hidden");
  };
  svg.setCursor = setCursor;
  const toData = (clientX) => {
    const r = svg.getBoundingClientRect();
    return x0 + (((clientX - r.left) * W) / r.width - m.l) / (W - m.l - m.r) * (x1 - x0);
  };
  if (spec.onHover) {
    svg.addEventListener("pointermove", (ev) => {
      const x = toData(ev.clientX);
      if (x >= x0 && x <= x1) spec.onHover(x);
    });
  }
  // the read-out: θ and the value of the first series that is not the identity line
  const main = spec.series.find((s) => s.cls !== "identity") || spec.series[0];
  const readout = (x) => {
    if (!(x >= x0 && x <= x1)) return null;
    const y = valueAt(main, x);
    return { x, y, text: `θ = ${x.toFixed(2)}°` + (y === null ? "" : `, ${spec.yLabel.split(" (")[0]} = ${y.toPrecision(5)}`) };
  };
  return { svg, setCursor, toData, readout, fit: () => fitTitle(title, W - 16) };
}

// A title longer than the plot is squeezed to its width, never cut (measured once shown).
function fitTitle(title, width) {
  const len = title.getComputedTextLength ? title.getComputedTextLength() : 0;
  if (len > width) {
    title.setAttribute("textLength", width);
    title.setAttribute("lengthAdjust", "spacingAndGlyphs");
  }
}

function mod(x, p) {
  return ((x % p) + p) % p;
}
