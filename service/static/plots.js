// Interactive plots of functions of θ, drawn by uPlot 1.6.32 (vendored in vendor/uplot/,
// loaded by index.html as the global `uPlot`; SOURCE.md says where from). uPlot gives the
// canvas, axes, lines, the hover cursor and drag-to-zoom; this module adds zoom with the
// wheel about the pointer, pan (Shift+drag, or ← / →), the + / − / Reset buttons, a hover
// read-out of θ and the plotted value, PNG (the canvas with its title) and CSV export, the
// page's θ cursor, and (plotlayers.js) the wrapped regions, images, markers and Θᵢ bars.

import { aligned, COLOURS, LANE, layerHooks, markerNear, toCsv, valueAt } from "./plotlayers.js";

const HEIGHT = 220; // CSS px of the plot with its axes, without the Θᵢ strip
const X_AXIS = 44; // CSS px under the plot area: ticks, values and the θ label
const MIN_ZOOM = 200; // the narrowest view: the whole domain / MIN_ZOOM
const FONT = "10px system-ui, sans-serif", LABEL_FONT = "11px system-ui, sans-serif";

function save(blob, filename) {
  const url = URL.createObjectURL(blob);
  const a = Object.assign(document.createElement("a"), { href: url, download: filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

const slug = (s) => s.replace(/[^\w]+/g, "-").replace(/^-|-$/g, "").slice(0, 40) || "plot";

// The plot as a PNG: its title over uPlot's canvas, on white, scaled up to 2 px per CSS px
// on a 1× screen (uPlot draws at the screen's pixel ratio only).
function toPng(u, title) {
  const src = u.ctx.canvas, dpr = devicePixelRatio, scale = Math.max(1, 2 / dpr);
  const head = Math.round(22 * dpr * scale);
  const canvas = Object.assign(document.createElement("canvas"), { width: src.width * scale, height: src.height * scale + head });
  const g = canvas.getContext("2d");
  g.fillStyle = "#fff";
  g.fillRect(0, 0, canvas.width, canvas.height);
  g.fillStyle = COLOURS.ink;
  g.font = `600 ${12 * dpr * scale}px system-ui, sans-serif`;
  g.textBaseline = "middle";
  g.fillText(title, 8 * dpr * scale, head / 2, canvas.width - 16 * dpr * scale);
  g.imageSmoothingQuality = "high";
  g.drawImage(src, 0, head, src.width * scale, src.height * scale);
  return new Promise((ok) => canvas.toBlob(ok, "image/png"));
}

// The x range a zoom or pan asks for, kept inside the domain and no narrower than MIN_ZOOM allows.
function clamp(full, min, max) {
  const span = full[1] - full[0];
  if (!(min < max) || max - min >= span) return [...full];
  const w = Math.max(span / MIN_ZOOM, max - min);
  const lo = Math.min(Math.max(min, full[0]), full[1] - w);
  return [lo, lo + w];
}

function seriesOpts(s) {
  const width = s.cls === "identity" ? 1 : 1.5;
  const stroke = s.cls === "identity" ? "#bbb" : s.cls === "alt" ? COLOURS["image-edge"] : COLOURS.ink;
  // a jump is a gap, not a vertical line: the gap's clip widened by the line's width
  const wider = (u, i, i0, i1, gaps) => gaps.map(([a, b]) => [a - 2 * devicePixelRatio, b + 2 * devicePixelRatio]);
  return { label: s.label || s.cls || "value", stroke, width, dash: s.cls === "identity" ? [3, 3] : undefined,
    points: { show: false }, spanGaps: false, ...(s.breakJumps ? { gaps: wider } : {}) };
}

function axesOpts(spec) {
  const axis = { font: FONT, labelFont: LABEL_FONT, stroke: COLOURS.muted, ticks: { stroke: COLOURS.ink, width: 1, size: 4 } };
  const lanes = (spec.lanes || []).length;
  const strip = lanes ? [{ scale: "x", side: 2, size: lanes * LANE + 8, grid: { show: false }, ticks: { show: false },
    values: (u, splits) => splits.map(() => "") }] : [];
  return [
    { ...axis, label: spec.xLabel, size: X_AXIS - 16, labelSize: 16, grid: { show: false } },
    { ...axis, label: spec.yLabel, size: 52, labelSize: 18, grid: { stroke: "#eceff1", width: 1 } },
    ...strip,
  ];
}

function options(host, spec, plot, xs) {
  const full = spec.xDomain;
  // the samples' extent (uPlot's first view, a double click) means the whole domain
  const range = (u, min, max) => (min <= xs[0] && max >= xs[xs.length - 1] ? [...full] : clamp(full, min, max));
  const lanes = (spec.lanes || []).length;
  return {
    title: spec.title, width: Math.max(320, host.clientWidth - 2), height: HEIGHT + (lanes ? lanes * LANE + 8 : 0),
    legend: { show: false },
    scales: {
      x: { time: false, auto: false, range },
      y: { range: spec.yDomain ? () => [...spec.yDomain] : (u, min, max) => {
        const pad = (max - min) * 0.08 || 1;
        return [min - pad, max + pad];
      } },
    },
    cursor: {
      y: false, points: { show: false }, drag: { x: true, y: false, setScale: true },
      // Shift+drag pans (pan.js below): uPlot's own drag-to-zoom ignores it
      bind: { mousedown: (u, targ, handle) => (e) => { if (e.button === 0 && !e.shiftKey) handle(e); return null; } },
    },
    series: [{ label: "θ" }, ...spec.series.map(seriesOpts)],
    axes: axesOpts(spec),
    hooks: {
      ...layerHooks(spec, plot, X_AXIS),
      setCursor: [(u) => readout(u, spec, plot)],
      setScale: [(u, key) => { if (key === "x") showDomain(u, host, plot); }],
      ready: [(u) => showDomain(u, host, plot)],
    },
  };
}

function showDomain(u, host, plot) {
  host.dataset.domain = JSON.stringify([u.scales.x.min, u.scales.x.max].map((v) => +v.toFixed(9)));
  placeCursor(u, plot);
}

// The read-out under the pointer: θ and the value of the first series that is not the
// identity line (interpolated between its samples), and a marker's label near it.
function readout(u, spec, plot) {
  const left = u.cursor.left;
  if (!(left >= 0)) return;
  const x = u.posToVal(left, "x");
  const main = spec.series.find((s) => s.cls !== "identity") || spec.series[0];
  const y = valueAt(main, x);
  const mk = markerNear(spec, x, (u.scales.x.max - u.scales.x.min) / 120);
  plot.out.textContent = `θ = ${x.toFixed(2)}°` + (y === null ? "" : `, ${spec.yLabel.split(" (")[0]} = ${y.toPrecision(5)}`) + (mk ? ` — ${mk}` : "");
  plot.out.dataset.x = String(x);
  plot.out.dataset.y = y === null ? "" : String(y);
  if (spec.onHover) spec.onHover(x);
}

// The page's θ cursor: a line over the plot at the copy of θ in view, if any.
function placeCursor(u, plot) {
  const line = plot.cursor;
  if (plot.theta === null) { line.hidden = true; return; }
  const { min, max } = u.scales.x, P = plot.period;
  const v = min + (((plot.theta - min) % P) + P) % P;
  line.hidden = v > max;
  line.style.left = `${u.valToPos(v, "x")}px`;
}

function zoomBy(u, full, factor, at) {
  const { min, max } = u.scales.x, c = at ?? (min + max) / 2;
  const [a, b] = clamp(full, c - (c - min) * factor, c + (max - c) * factor);
  u.setScale("x", { min: a, max: b });
}

function panBy(u, full, dx) {
  const { min, max } = u.scales.x;
  const [a, b] = clamp(full, min + dx, max + dx);
  u.setScale("x", { min: a, max: b });
}

// Wheel: zoom about the pointer. Shift+drag: pan by what the pointer moved.
function wireMouse(u, full) {
  u.over.addEventListener("wheel", (ev) => {
    ev.preventDefault();
    const r = u.over.getBoundingClientRect();
    zoomBy(u, full, ev.deltaY < 0 ? 0.8 : 1.25, u.posToVal(ev.clientX - r.left, "x"));
  }, { passive: false });
  u.over.addEventListener("mousedown", (ev) => {
    if (ev.button !== 0 || !ev.shiftKey) return;
    const perPx = (u.scales.x.max - u.scales.x.min) / u.over.clientWidth;
    let last = ev.clientX;
    const move = (e) => { panBy(u, full, (last - e.clientX) * perPx); last = e.clientX; };
    const up = () => { window.removeEventListener("mousemove", move); window.removeEventListener("mouseup", up); };
    window.addEventListener("mousemove", move);
    window.addEventListener("mouseup", up);
  });
}

function toolbar(u, spec, plot) {
  const full = spec.xDomain;
  const button = (label, title, fn) => {
    const b = Object.assign(document.createElement("button"), { type: "button", textContent: label, title, className: "plot-btn" });
    b.setAttribute("aria-label", `${title}: ${spec.title}`);
    b.addEventListener("click", fn);
    return b;
  };
  const width = () => u.scales.x.max - u.scales.x.min;
  const bar = Object.assign(document.createElement("div"), { className: "plot-tools" });
  bar.append(button("+", "zoom in", () => zoomBy(u, full, 0.5)), button("−", "zoom out", () => zoomBy(u, full, 2)),
    button("←", "pan left", () => panBy(u, full, -width() / 4)), button("→", "pan right", () => panBy(u, full, width() / 4)),
    button("Reset", "reset zoom", () => u.setScale("x", { min: full[0], max: full[1] })),
    button("PNG", "export PNG", async () => save(await toPng(u, spec.title), `${slug(spec.title)}.png`)),
    button("CSV", "export CSV", () => save(new Blob([toCsv(spec)], { type: "text/csv" }), `${slug(spec.title)}.csv`)),
    plot.out);
  return bar;
}

// The Θᵢ as text beside the canvas (what a screen reader says; the canvas says nothing).
function laneList(spec) {
  const ul = Object.assign(document.createElement("ul"), { className: "plot-lanes visually-hidden" });
  for (const b of spec.lanes || []) {
    ul.append(Object.assign(document.createElement("li"), { textContent: `${b.label}: [${b.x0.toFixed(2)}°, ${b.x1.toFixed(2)}°)` }));
  }
  return ul;
}

// A line plot in `host` (replacing its content and any plot drawn there before).
// spec: {title, xLabel, yLabel, xDomain, period? (of x; default the domain's width),
// yDomain?, series: [{xs, ys, cls ("identity" | "alt" | none), label?, breakJumps?}],
// bands: [{x0, x1, cls}] (x only, wrapped), polys: [{points, cls, period?}] (with their
// copies shifted by whole periods in x and y: lifted images), lanes: [{x0, x1, label, cls}],
// markers: [{x, y, cls, label}], onHover(x)}. Returns {setCursor(x), uplot, drawn}.
export function linePlot(host, spec) {
  if (host.plot) host.plot.destroy();
  spec = { ...spec, period: spec.period ?? spec.xDomain[1] - spec.xDomain[0] };
  const plot = { theta: null, period: spec.period, drawn: {},
    out: Object.assign(document.createElement("output"), { className: "plot-readout" }),
    cursor: Object.assign(document.createElement("div"), { className: "plot-theta", hidden: true }) };
  host.replaceChildren();
  const data = aligned(spec.series);
  const u = new globalThis.uPlot(options(host, spec, plot, data[0]), data, host);
  u.root.setAttribute("role", "img");
  u.root.setAttribute("aria-label", spec.title);
  u.over.append(plot.cursor);
  host.append(toolbar(u, spec, plot), laneList(spec));
  wireMouse(u, spec.xDomain);
  const resize = new ResizeObserver(() => {
    const w = Math.max(320, host.clientWidth - 2);
    if (host.clientWidth && Math.abs(w - u.width) > 1) u.setSize({ width: w, height: u.height });
  });
  resize.observe(host);
  host.plot = Object.assign(plot, {
    uplot: u,
    setCursor: (x) => { plot.theta = x; placeCursor(u, plot); },
    destroy: () => { resize.disconnect(); u.destroy(); delete host.plot; },
  });
  return host.plot;
}

// The host emptied, its plot (if any) destroyed.
export function clearPlot(host) {
  if (host.plot) host.plot.destroy();
  host.replaceChildren();
  delete host.dataset.domain;
}
