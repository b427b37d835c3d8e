// The part between the jaws: world frame, y up, centre of mass at the origin unless a
// position is given. Jaws are parallel lines along (cos α, sin α) (conventions §2). The
// view is framed on what is drawn: the part and both jaws (or a box given for a whole
// animation, so the view stays still while they move).

import { bounds, rotate, support } from "./geom.js";
import { el, path, text } from "./svg.js";

const RAD = Math.PI / 180;
const JAW_HALF_LENGTH = 1.1; // × the part's extent R, on either side of the gripper's centre

// geometry: {outline, holes, hull, center_of_mass} in the part frame (API `geometry`).
export function sceneExtent(geometry) {
  const c = geometry.center_of_mass;
  return Math.max(...geometry.outline.map(([x, y]) => Math.hypot(x - c[0], y - c[1])));
}

function placed(geometry, pose) {
  return rotate(geometry.outline, pose.phi, geometry.center_of_mass, [pose.x || 0, pose.y || 0]);
}

// The jaws' outlines: [lower, higher], each a rectangle outside the part's side of its offset.
function jawOutlines(outline, jaws, R) {
  const [lo, hi] = support(outline, jaws.alpha);
  return [jawCorners(jaws.alpha, jaws.lower ?? lo, -1, R), jawCorners(jaws.alpha, jaws.higher ?? hi, 1, R)];
}

// The world box {x0, x1, y0, y1} of the part at pose and the jaws (null: none) of one frame.
export function frameOf(geometry, pose, jaws) {
  const R = sceneExtent(geometry);
  const outline = placed(geometry, pose);
  const pts = jaws ? [...outline, ...jawOutlines(outline, jaws, R).flat()] : outline;
  return bounds(pts);
}

export function unionBox(boxes) {
  return boxes.reduce((a, b) => ({ x0: Math.min(a.x0, b.x0), x1: Math.max(a.x1, b.x1), y0: Math.min(a.y0, b.y0), y1: Math.max(a.y1, b.y1) }));
}

// Draws into host. pose: {phi, x?, y?}; jaws: {alpha, lower?, higher?} where lower/higher are
// jaw offsets along n (part unit; default: touching the part), or null for no jaws.
// opts: {view (a world box to frame; default this frame's part and jaws), ghost, caption, label,
// wedge: {range: [lo, hi] where the body axis can be (deg), all: arcs it can be in from any
// start, step}}.
export function drawScene(host, geometry, pose, jaws, opts = {}) {
  const R = sceneExtent(geometry);
  const at = [pose.x || 0, pose.y || 0];
  const outline = placed(geometry, pose);
  const box = opts.view || frameOf(geometry, pose, jaws);
  const pad = 0.06 * Math.max(box.x1 - box.x0, box.y1 - box.y0);
  const w = box.x1 - box.x0 + 2 * pad, h = box.y1 - box.y0 + 2 * pad;
  const band = opts.caption ? 0.09 * Math.max(w, h) : 0; // the caption's own strip, above the scene
  const svg = el("svg", { viewBox: `${box.x0 - pad} ${-box.y1 - pad - band} ${w} ${h + band}`, class: "scene", role: "img",
    "aria-label": opts.label || "part between the jaws" });
  svg.dataset.view = JSON.stringify(box);
  const g = el("g", { transform: "scale(1,-1)" });
  const place = (pts) => rotate(pts, pose.phi, geometry.center_of_mass, at);
  if (opts.ghost) {
    const gp = rotate(geometry.outline, opts.ghost.phi, geometry.center_of_mass, [opts.ghost.x || 0, opts.ghost.y || 0]);
    g.append(path(gp, { class: "ghost" }, true));
  }
  g.append(path(place(geometry.hull), { class: "hull" }, true));
  g.append(path(outline, { class: "part" }, true));
  for (const h of geometry.holes) g.append(path(place(h), { class: "hole" }, true));
  if (opts.wedge) g.append(...wedges(opts.wedge, at, R));
  g.append(el("circle", { cx: at[0], cy: at[1], r: R * 0.04, class: "com" }));
  // the body's x axis: shows the orientation φ
  const tip = rotate([[geometry.center_of_mass[0] + R * 0.5, geometry.center_of_mass[1]]], pose.phi, geometry.center_of_mass, at)[0];
  g.append(path([at, tip], { class: "body-axis" }));
  if (jaws) {
    const [lower, higher] = jawOutlines(outline, jaws, R);
    g.append(path(lower, { class: "jaw jaw-lower" }, true), path(higher, { class: "jaw jaw-higher" }, true));
  }
  svg.append(g);
  if (opts.caption) {
    const size = Math.min(band * 0.55, w * 0.04);
    svg.append(text(box.x0 - pad + w * 0.02, -box.y1 - pad - band * 0.3, opts.caption, { class: "scene-caption", "font-size": size }));
  }
  host.replaceChildren(svg);
}

// The uncertainty wedge: the sector of body-axis directions [lo, hi] about the centre of
// mass (a line when the plan is exact), over faint sectors of every arc from any start.
function wedges(w, at, R) {
  const sector = ([lo, hi], r, attrs) => {
    const n = Math.max(1, Math.ceil((hi - lo) / 3));
    const pts = [at];
    for (let i = 0; i <= n; i++) {
      const a = (lo + ((hi - lo) * i) / n) * RAD;
      pts.push([at[0] + r * Math.cos(a), at[1] + r * Math.sin(a)]);
    }
    return path(pts, attrs, hi - lo > 1e-9);
  };
  const out = (w.all || []).map((arc) => sector(arc, R * 0.75, { class: "wedge-all" }));
  const main = sector(w.range, R * 0.9, { class: "wedge" });
  main.dataset.lo = String(w.range[0]);
  main.dataset.hi = String(w.range[1]);
  if (w.step) main.dataset.step = String(w.step);
  if (w.done) main.dataset.done = "true";
  out.push(main);
  return out;
}

function jawCorners(alphaDeg, offset, side, R) {
  const a = alphaDeg * RAD;
  const t = [Math.cos(a), Math.sin(a)], n = [-Math.sin(a), Math.cos(a)];
  const thick = R * 0.12;
  const c = offset + side * thick / 2;
  const L = JAW_HALF_LENGTH;
  return [[-L, c - thick / 2], [L, c - thick / 2], [L, c + thick / 2], [-L, c + thick / 2]]
    .map(([u, v]) => [t[0] * u * R + n[0] * v, t[1] * u * R + n[1] * v]);
}

// A still view for a part turning about its centre of mass at the origin between jaws along
// α = 0 (touching it): the part's circle and the jaws' length.
export function turningView(geometry) {
  const R = sceneExtent(geometry);
  return { x0: -JAW_HALF_LENGTH * R, x1: JAW_HALF_LENGTH * R, y0: -1.13 * R, y1: 1.13 * R };
}
