// Small SVG helpers for the drawings that are not plots: the part outline, the scene
// between the jaws, the playback and the editor (plots are uPlot's: plots.js).

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
