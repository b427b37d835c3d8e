// What the uPlot plots (plots.js) draw besides their lines, on uPlot's own canvas: the
// periodic regions (dead zones, constant regions, ramps) and the set-valued images, each
// WRAPPED across the period boundary, the extrema and fixed points, and the labelled Θᵢ
// bars in a strip under the θ axis. Also the data uPlot plots (one x array for every
// series, a gap at each jump) and the CSV export. Every piece drawn is recorded in θ on
// the plot (`plot.drawn`) so tests can compare it with the API's numbers.

import { mod } from "./geom.js";

export const COLOURS = {
  "band-dead": "rgba(158, 158, 158, 0.3)",
  "band-ramp": "rgba(255, 152, 0, 0.5)", // over a grey dead zone it still reads orange
  "band-image": "rgba(21, 101, 192, 0.3)",
  "image-edge": "#1565c0",
  "bar-interval": "#2e7d32",
  "mk-max": "#c62828", "mk-min": "#2e7d32", "mk-fixed": "#1565c0",
  ink: "#1d2733", muted: "#5b6773",
};
export const LANE = 12; // CSS px per Θᵢ row: a 4 px bar and its label never touch the next one

// The value of a series at x (linear between samples; null outside; across a jump, the
// nearer side's). O(log n).
export function valueAt(series, x) {
  const { xs, ys } = series;
  if (!(x >= xs[0] && x <= xs[xs.length - 1])) return null;
  let lo = 0, hi = xs.length - 1;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (xs[mid] <= x) lo = mid; else hi = mid; }
  if (xs[hi] === xs[lo]) return ys[lo];
  if (series.breakJumps && Math.abs(ys[hi] - ys[lo]) > series.breakJumps) return x - xs[lo] < xs[hi] - x ? ys[lo] : ys[hi];
  return ys[lo] + ((x - xs[lo]) / (xs[hi] - xs[lo])) * (ys[hi] - ys[lo]);
}

// uPlot's data: the union of every series' xs, plus a point between the samples of each
// jump of a `breakJumps` series where that series is null (a step drawn as a gap).
export function aligned(series) {
  const gaps = series.map((s) => {
    if (!s.breakJumps) return new Set();
    const g = new Set();
    for (let i = 1; i < s.xs.length; i++) if (Math.abs(s.ys[i] - s.ys[i - 1]) > s.breakJumps) g.add((s.xs[i] + s.xs[i - 1]) / 2);
    return g;
  });
  const xs = [...new Set([...series.flatMap((s) => s.xs), ...gaps.flatMap((g) => [...g])])].sort((a, b) => a - b);
  return [xs, ...series.map((s, k) => xs.map((x) => (gaps[k].has(x) ? null : valueAt(s, x))))];
}

export function toCsv(spec) {
  const rows = ["series,x,y"];
  spec.series.forEach((s, k) => {
    const name = s.label || s.cls || `series ${k + 1}`;
    s.xs.forEach((x, i) => rows.push(`${JSON.stringify(name)},${x},${s.ys[i]}`));
  });
  return rows.join("\n") + "\n";
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


// The view's x range and the canvas mapping of a plot.
function frame(u) {
  const { left, top, width, height } = u.bbox;
  return { x0: u.scales.x.min, x1: u.scales.x.max, left, top, width, height,
    px: (x) => u.valToPos(x, "x", true), py: (y) => u.valToPos(y, "y", true) };
}

// Regions of x (wrapped), one shade per kind: overlapping regions of a kind are not darker.
function drawBands(u, spec, drawn) {
  const f = frame(u), ctx = u.ctx, byClass = new Map();
  for (const b of spec.bands || []) {
    byClass.set(b.cls, [...(byClass.get(b.cls) || []), ...wrapSpans(b.x0, b.x1, f.x0, f.x1, spec.period)]);
  }
  for (const [cls, spans] of byClass) {
    ctx.fillStyle = COLOURS[cls];
    for (const [a, c] of union(spans)) {
      ctx.fillRect(f.px(a), f.top, f.px(c) - f.px(a), f.height);
      (drawn[cls] ||= []).push([a, c]);
    }
  }
}

// Set-valued images: each polygon and its copies shifted by k·T in x and in y (lifted), clipped.
function drawPolys(u, spec, drawn) {
  const f = frame(u), ctx = u.ctx;
  ctx.fillStyle = COLOURS["band-image"];
  ctx.strokeStyle = COLOURS["image-edge"];
  ctx.lineWidth = 0.5 * devicePixelRatio;
  for (const q of spec.polys || []) {
    const xs = q.points.map((p) => p[0]), lo = Math.min(...xs), hi = Math.max(...xs), T = q.period ?? spec.period;
    for (let k = Math.floor((f.x0 - hi) / T); k <= Math.ceil((f.x1 - lo) / T); k++) {
      if (hi + k * T <= f.x0 || lo + k * T >= f.x1) continue;
      ctx.beginPath();
      q.points.forEach(([x, y], i) => ctx[i ? "lineTo" : "moveTo"](f.px(x + k * T), f.py(y + k * T)));
      ctx.closePath();
      ctx.fill();
      ctx.stroke();
      (drawn.images ||= []).push(q.points.map(([x, y]) => [x + k * T, y + k * T]));
    }
  }
}

function drawMarkers(u, spec) {
  const f = frame(u), ctx = u.ctx, r = 3.5 * devicePixelRatio;
  for (const mk of spec.markers || []) {
    const x = f.x0 + mod(mk.x - f.x0, spec.period);
    if (x > f.x1) continue;
    ctx.fillStyle = COLOURS[mk.cls];
    ctx.beginPath();
    ctx.arc(f.px(x), f.py(mk.y), r, 0, 2 * Math.PI);
    ctx.fill();
  }
}

// The Θᵢ: one labelled row each in the strip under the θ axis (wrapped: two pieces, one label).
function drawLanes(u, spec, drawn, axisSize) {
  const f = frame(u), ctx = u.ctx, dpr = devicePixelRatio;
  const top = f.top + f.height + axisSize * dpr;
  ctx.font = `${10 * dpr}px system-ui, sans-serif`;
  ctx.textAlign = "right";
  ctx.textBaseline = "middle";
  (spec.lanes || []).forEach((b, i) => {
    const y = top + (i + 0.5) * LANE * dpr;
    ctx.fillStyle = COLOURS.muted;
    ctx.fillText(b.label, f.left - 6 * dpr, y);
    ctx.strokeStyle = COLOURS[b.cls];
    ctx.lineWidth = 4 * dpr;
    const pieces = wrapSpans(b.x0, b.x1, f.x0, f.x1, spec.period);
    for (const [a, c] of pieces) {
      ctx.beginPath();
      ctx.moveTo(f.px(a), y);
      ctx.lineTo(f.px(c), y);
      ctx.stroke();
    }
    (drawn.lanes ||= []).push({ label: b.label, pieces, y_css: y / dpr });
  });
}

// uPlot hooks: regions and images after the axes and grid, under the lines; markers and
// Θᵢ bars over everything. `plot.drawn` is rebuilt at every draw.
export function layerHooks(spec, plot, axisSize) {
  return {
    drawAxes: [(u) => {
      plot.drawn = {};
      const ctx = u.ctx, { left, top, width, height } = u.bbox;
      ctx.save();
      ctx.beginPath();
      ctx.rect(left, top, width, height);
      ctx.clip();
      drawBands(u, spec, plot.drawn);
      drawPolys(u, spec, plot.drawn);
      ctx.restore();
    }],
    draw: [(u) => {
      const ctx = u.ctx, { left, top, width, height } = u.bbox;
      ctx.save();
      ctx.beginPath();
      ctx.rect(left, top, width, height);
      ctx.clip();
      drawMarkers(u, spec);
      ctx.restore();
      ctx.save();
      drawLanes(u, spec, plot.drawn, axisSize);
      ctx.restore();
    }],
  };
}

// The marker near x (within `tol` of θ), for the read-out: "max 12.3 at 45.00° (stable)".
export function markerNear(spec, x, tol) {
  const P = spec.period;
  const near = (spec.markers || []).filter((m) => Math.abs(mod(m.x - x + P / 2, P) - P / 2) <= tol);
  return near.length ? near[0].label || "" : "";
}
