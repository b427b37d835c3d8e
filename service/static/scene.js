// The part between the jaws: world frame, y up, centre of mass at the origin unless a
// position is given. Jaws are parallel lines along (cos α, sin α) (conventions §2).

import { rotate, support } from "./geom.js";
import { el, path, text } from "./svg.js";

const RAD = Math.PI / 180;

// geometry: {outline, holes, hull, center_of_mass} in the part frame (API `geometry`).
export function sceneExtent(geometry) {
  const c = geometry.center_of_mass;
  return Math.max(...geometry.outline.map(([x, y]) => Math.hypot(x - c[0], y - c[1])));
}

// Draws into host. pose: {phi, x?, y?}; jaws: {alpha, lower?, higher?} where lower/higher are
// jaw offsets along n (part unit; default: touching the part), or null for no jaws.
export function drawScene(host, geometry, pose, jaws, opts = {}) {
  const R = sceneExtent(geometry) * (opts.zoom || 1.0);
  const span = 2.6 * R;
  const svg = el("svg", { viewBox: `${-span / 2} ${-span / 2} ${span} ${span}`, class: "scene", role: "img",
    "aria-label": opts.label || "part between the jaws" });
  const g = el("g", { transform: "scale(1,-1)" });
  const at = [pose.x || 0, pose.y || 0];
  const place = (pts) => rotate(pts, pose.phi, geometry.center_of_mass, at);
  const outline = place(geometry.outline);
  if (opts.ghost) {
    const gp = rotate(geometry.outline, opts.ghost.phi, geometry.center_of_mass, [opts.ghost.x || 0, opts.ghost.y || 0]);
    g.append(path(gp, { class: "ghost" }, true));
  }
  g.append(path(rotate(geometry.hull, pose.phi, geometry.center_of_mass, at), { class: "hull" }, true));
  g.append(path(outline, { class: "part" }, true));
  for (const h of geometry.holes) g.append(path(place(h), { class: "hole" }, true));
  g.append(el("circle", { cx: at[0], cy: at[1], r: R * 0.04, class: "com" }));
  // the body's x axis: shows the orientation φ
  const tip = rotate([[geometry.center_of_mass[0] + R * 0.5, geometry.center_of_mass[1]]], pose.phi, geometry.center_of_mass, at)[0];
  g.append(path([at, tip], { class: "body-axis" }));
  if (jaws) {
    const [lo, hi] = support(outline, jaws.alpha);
    drawJaw(g, jaws.alpha, jaws.lower ?? lo, -1, R);
    drawJaw(g, jaws.alpha, jaws.higher ?? hi, 1, R);
  }
  svg.append(g);
  if (opts.caption) svg.append(text(-span / 2 + span * 0.03, -span / 2 + span * 0.07, opts.caption, { class: "scene-caption", "font-size": span * 0.045 }));
  host.replaceChildren(svg);
}

function drawJaw(g, alphaDeg, offset, side, R) {
  const a = alphaDeg * RAD;
  const t = [Math.cos(a), Math.sin(a)], n = [-Math.sin(a), Math.cos(a)];
  const thick = R * 0.12;
  const c = offset + side * thick / 2;
  const corners = [[-1.1, c - thick / 2], [1.1, c - thick / 2], [1.1, c + thick / 2], [-1.1, c + thick / 2]]
    .map(([u, v]) => [t[0] * u * R + n[0] * v, t[1] * u * R + n[1] * v]);
  g.append(path(corners, { class: side < 0 ? "jaw jaw-lower" : "jaw jaw-higher" }, true));
}
