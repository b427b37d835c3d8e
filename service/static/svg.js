// Small SVG helpers: elements, line plots with labelled axes, bands, markers and a
// hover cursor. Written here rather than vendored: a plotting library would weigh more
// than the whole page (the page must stay under 1 MB and work without internet).

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

// A line plot in `host` (replacing its content). spec: {title, xLabel, yLabel, xDomain,
// yDomain?, series: [{xs, ys, cls, label, breakJumps?}], bands: [{x0, x1, cls, label}],
// polys: [{points, cls}], hbars: [{x0, x1, y, cls}], markers: [{x, y, cls, label}], onHover(x)}.
// Returns {setCursor(x)}.
export function linePlot(host, spec) {
  const W = 520, H = 230, m = { l: 56, r: 12, t: 24, b: 44 };
  const [x0, x1] = spec.xDomain;
  const ys = spec.series.flatMap((s) => s.ys).concat((spec.hbars || []).map((b) => b.y));
  let [y0, y1] = spec.yDomain || [Math.min(...ys), Math.max(...ys)];
  if (!(y1 > y0)) { y0 -= 1; y1 += 1; }
  const pad = spec.yDomain ? 0 : (y1 - y0) * 0.08;
  y0 -= pad; y1 += pad;
  const sx = (x) => m.l + ((x - x0) / (x1 - x0)) * (W - m.l - m.r);
  const sy = (y) => H - m.b - ((y - y0) / (y1 - y0)) * (H - m.t - m.b);
  const svg = el("svg", { viewBox: `0 0 ${W} ${H}`, class: "plot", role: "img", "aria-label": spec.title });
  svg.append(text(m.l, 15, spec.title, { class: "plot-title" }));
  for (const b of spec.bands || []) {
    const a = Math.max(b.x0, x0), c = Math.min(b.x1, x1);
    if (c > a) svg.append(el("rect", { x: sx(a), y: m.t, width: sx(c) - sx(a), height: H - m.t - m.b, class: b.cls }));
  }
  const axes = el("g", { class: "axes" });
  axes.append(path([[m.l, m.t], [m.l, H - m.b], [W - m.r, H - m.b]], { class: "axis" }));
  for (const v of ticks(x0, x1, 6)) {
    axes.append(path([[sx(v), H - m.b], [sx(v), H - m.b + 4]], { class: "axis" }));
    axes.append(text(sx(v), H - m.b + 15, `${v}`, { class: "tick", "text-anchor": "middle" }));
  }
  for (const v of ticks(y0, y1, 4)) {
    axes.append(path([[m.l - 4, sy(v)], [m.l, sy(v)]], { class: "axis" }));
    axes.append(text(m.l - 6, sy(v) + 4, `${+v.toPrecision(4)}`, { class: "tick", "text-anchor": "end" }));
  }
  axes.append(text((m.l + W - m.r) / 2, H - 8, spec.xLabel, { class: "label", "text-anchor": "middle" }));
  axes.append(text(14, (m.t + H - m.b) / 2, spec.yLabel, { class: "label", "text-anchor": "middle",
    transform: `rotate(-90 14 ${(m.t + H - m.b) / 2})` }));
  svg.append(axes);
  for (const s of spec.series) {
    let seg = [];
    const flush = () => { if (seg.length > 1) svg.append(path(seg, { class: `line ${s.cls || ""}` })); seg = []; };
    s.xs.forEach((x, i) => {
      // a jump (a step boundary) is drawn as a gap, not a vertical line
      if (s.breakJumps && i && Math.abs(s.ys[i] - s.ys[i - 1]) > s.breakJumps) flush();
      seg.push([sx(x), sy(s.ys[i])]);
    });
    flush();
  }
  for (const q of spec.polys || []) svg.append(path(q.points.map(([x, y]) => [sx(x), sy(y)]), { class: q.cls }, true));
  for (const b of spec.hbars || []) {
    svg.append(el("line", { x1: sx(Math.max(b.x0, x0)), x2: sx(Math.min(b.x1, x1)), y1: sy(b.y), y2: sy(b.y), class: b.cls }));
  }
  for (const mk of spec.markers || []) {
    const c = el("circle", { cx: sx(mk.x), cy: sy(mk.y), r: 3.5, class: mk.cls });
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
  const cursor = el("line", { y1: m.t, y2: H - m.b, class: "cursor", visibility: "hidden" });
  svg.append(cursor);
  const setCursor = (x) => {
    const v = x0 + mod(x - x0, x1 - x0);
    cursor.setAttribute("x1", sx(v));
    cursor.setAttribute("x2", sx(v));
    cursor.setAttribute("visibility", "visible");
  };
  if (spec.onHover) {
    svg.addEventListener("pointermove", (ev) => {
      const r = svg.getBoundingClientRect();
      const x = x0 + (((ev.clientX - r.left) * W) / r.width - m.l) / (W - m.l - m.r) * (x1 - x0);
      if (x >= x0 && x <= x1) spec.onHover(x);
    });
  }
  host.replaceChildren(svg);
  return { setCursor };
}

function mod(x, p) {
  return ((x % p) + p) % p;
}
