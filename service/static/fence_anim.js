// A part carried along the belt through a fence layout (conventions §9): belt along +x,
// y across from the right rail (0) to the left (W), part units. The part's orientation is
// read off the fence document's own trace of each whole-degree start (`follow_deg`) and each fence's `image_deg`, with
// motion.js, as the Plan page reads a plan's: passing fence i maps φ to p(φ − α_i) + α_i,
// a gripper action at α_i. No planner here. Degrees, as the documents.

import { rotate } from "./geom.js";
import { claimSaid, markFinal, middle } from "./motion.js";
import { el as svgEl } from "./svg.js";

const RAD = Math.PI / 180;
const FRAMES = 30; // per leg of the path
const TURN = 0.6; // the turn against a fence ends this far along it (the rest: aligned)

// An SVG element (svg.js's), appended to ``parent`` when given.
function el(tag, attrs, parent) {
  const e = svgEl(tag, attrs);
  if (parent) parent.append(e);
  return e;
}

// The fence document as a plan motion.js reads: one step per fence at its angle, then the
// exit guide's (guide: true) where the layout has one.
export function fencePlan(doc) {
  const steps = doc.fences.map((f) => ({ gripper_angle_deg: f.angle_deg, image_deg: f.image_deg }));
  if (doc.exit) steps.push({ gripper_angle_deg: doc.exit.angle_deg, image_deg: doc.exit.image_deg || [], guide: true });
  return { ...doc, steps };
}

// [lo, hi] widened by the turn a part may take over the tip of a wall at world angle α
// (deg): towards the belt direction by up to its steepness, clockwise on the right rail
// (α < 90°), counter-clockwise on the left (the core's exit_turn, conventions §9).
const overTip = ([lo, hi], alpha) => (alpha < 90 ? [lo - alpha, hi] : [lo, hi + (180 - alpha)]);

// Per fence, then the exit guide, {alpha, before, after, all} from a whole-degree φ₀: the
// arc after each is the document's own trace of that start (`follow_deg`: the push tilted
// by the fence friction at the fence's angle, which is not one function the page could read
// off `images`); before it, in the design's model, the turn over the previous tip (always
// before the guide). The trace past the guide includes its own tip's turn.
export function followFences(doc, phi0) {
  const steps = fencePlan(doc).steps;
  const trace = doc.follow_deg[((Math.round(phi0) % 360) + 360) % 360];
  let r = [phi0, phi0];
  return steps.map((s, i) => {
    if (i > 0 && (doc.exit_turns || s.guide)) r = overTip(r, steps[i - 1].gripper_angle_deg);
    const before = r;
    r = trace[i];
    return { alpha: s.gripper_angle_deg, before, after: r, all: s.image_deg };
  });
}

export const hasImages = (doc) => Boolean(doc.follow_deg && doc.follow_deg.length === 360 && doc.fences.every((f) => f.image_deg));

// Fence f's wall: root on its rail, tip, unit direction root → tip, face normal n (towards
// the oncoming part, conventions §9: n = (−sin α, cos α)).
export function wall(doc, f) {
  const s = f.side === "right" ? 1 : -1, a = f.angle_deg * RAD;
  const root = [f.position, f.side === "right" ? 0 : doc.belt_width];
  const dir = [s * Math.cos(a), s * Math.sin(a)];
  return { root, tip: [root[0] + f.length * dir[0], root[1] + f.length * dir[1]], dir, n: [-Math.sin(a), Math.cos(a)] };
}

const add = (p, q, k = 1) => [p[0] + k * q[0], p[1] + k * q[1]];
const lerp = (p, q, u) => [p[0] + (q[0] - p[0]) * u, p[1] + (q[1] - p[1]) * u];
const ease = (u) => 0.5 - 0.5 * Math.cos(Math.PI * Math.min(1, Math.max(0, u)));

// Frames {at: centre, range: [lo, hi] (deg), fence: index or -1}: into the first fence,
// along each (turning over its first TURN), across to the next, and off the last one.
function frames(doc, phases) {
  const a = doc.cover_radius, out = [];
  const legs = [];
  doc.fences.forEach((f, i) => {
    const w = wall(doc, f);
    const from = add(add(w.root, w.dir, 0.25 * f.length), w.n, a), to = add(w.tip, w.n, a);
    if (i === 0) legs.push({ from: [from[0] - 4 * a, from[1]], to: from, range: () => phases[0].before, fence: -1 });
    else legs.push({ from: legs[legs.length - 1].to, to: from, range: () => phases[i].before, fence: -1 });
    const ph = phases[i];
    legs.push({ from, to, fence: i, range: (u) => lerp(ph.before, ph.after, ease(u / TURN)) });
  });
  if (doc.exit && phases.length > doc.fences.length) { // along the exit guide (its tip's turn: at its end)
    const ph = phases[doc.fences.length], e = doc.exit, al = e.angle_deg * RAD;
    const n = [-Math.sin(al), Math.cos(al)], from = add(e.start, n, a), to = add(e.end, n, a);
    legs.push({ from: legs[legs.length - 1].to, to: from, range: () => ph.before, fence: -1 });
    legs.push({ from, to, fence: doc.fences.length, range: (u) => lerp(ph.before, ph.after, ease(u / TURN)) });
  }
  const last = legs[legs.length - 1].to;
  legs.push({ from: last, to: [last[0] + 4 * a, last[1]], range: () => phases[phases.length - 1].after, fence: -1 });
  for (const leg of legs) {
    for (let k = 0; k <= FRAMES; k++) out.push({ at: lerp(leg.from, leg.to, k / FRAMES), range: leg.range(k / FRAMES), fence: leg.fence });
  }
  return out;
}

// The still picture: rails and fences (ids fence-line-1…) along the whole path.
function belt(host, doc, box) {
  const W = doc.belt_width, pad = 2 * doc.cover_radius;
  const svg = el("svg", { class: "scene", role: "img", "aria-label": "the part carried along the belt through the fences",
    viewBox: `${box.x0} ${-(W + pad)} ${box.x1 - box.x0} ${W + 2 * pad}`, preserveAspectRatio: "xMidYMid meet" });
  const g = el("g", { transform: "scale(1,-1)" }, svg);
  for (const y of [0, W]) el("line", { x1: box.x0, y1: y, x2: box.x1, y2: y, stroke: "#888", "stroke-width": 2, "vector-effect": "non-scaling-stroke" }, g);
  doc.fences.forEach((f, i) => {
    const w = wall(doc, f);
    el("line", { id: `fence-line-${i + 1}`, x1: w.root[0], y1: w.root[1], x2: w.tip[0], y2: w.tip[1], stroke: "#c00",
      "stroke-width": 4, "vector-effect": "non-scaling-stroke" }, g);
  });
  if (doc.exit) {
    el("line", { id: "fence-exit-line", x1: doc.exit.start[0], y1: doc.exit.start[1], x2: doc.exit.end[0], y2: doc.exit.end[1],
      stroke: "#c00", "stroke-width": 3, "stroke-dasharray": "8 4", "vector-effect": "non-scaling-stroke" }, g);
  }
  host.replaceChildren(svg);
  return g;
}

// The view follows the part: a window 1.6 belt widths (at least 16 covering radii) long
// around it, within the whole path.
function follow_(svg, doc, box, x) {
  const W = doc.belt_width, pad = 2 * doc.cover_radius;
  const span = Math.min(box.x1 - box.x0, Math.max(1.6 * W, 16 * doc.cover_radius));
  const x0 = Math.min(Math.max(x - 0.5 * span, box.x0), box.x1 - span);
  svg.setAttribute("viewBox", `${x0} ${-(W + pad)} ${span} ${W + 2 * pad}`);
}

function outlineAt(geometry, phi, at) {
  return rotate(geometry.outline, phi, geometry.center_of_mass, at).map((p) => p.join(",")).join(" ");
}

// Plays the part from φ₀; #fence-final then holds the final orientation (data-final-deg,
// data-final-range, data-claimed) as the Plan page's #anim-final does.
export function playFences(state, phi0) {
  const doc = state.fences.doc, g = state.analysis.geometry, out = document.getElementById("fence-final");
  if (!hasImages(doc)) { out.textContent = "this fence document carries no trace (follow_deg): design again to animate it"; return; }
  const plan = fencePlan(doc);
  const phases = followFences(doc, phi0);
  const seq = frames(doc, phases);
  const xs = seq.map((f) => f.at[0]);
  const box = { x0: Math.min(...xs) - 2 * doc.cover_radius, x1: Math.max(...xs) + 2 * doc.cover_radius };
  const layer = belt(document.getElementById("fence-anim"), doc, box);
  const ghosts = [0, 1].map(() => el("polygon", { fill: "none", stroke: "#e65100", "stroke-dasharray": "5 3", "stroke-width": 1.5, "vector-effect": "non-scaling-stroke" }, layer));
  const part = el("polygon", { class: "part" }, layer);
  out.textContent = "playing…";
  for (const k of ["finalDeg", "finalRange", "claimed"]) delete out.dataset[k];
  const token = (state.fenceAnimation = (state.fenceAnimation || 0) + 1);
  let k = 0;
  const step = () => {
    if (state.fenceAnimation !== token) return; // a new design or another play took over
    const f = seq[k];
    follow_(layer.ownerSVGElement, doc, box, f.at[0]);
    part.setAttribute("points", outlineAt(g, middle(f.range), f.at));
    const spread = f.range[1] - f.range[0] > 1e-6;
    ghosts.forEach((e, j) => { e.setAttribute("points", spread ? outlineAt(g, f.range[j], f.at) : ""); });
    document.querySelectorAll("#fence-anim line[id]").forEach((e, i) => e.setAttribute("stroke", i === f.fence ? "#ff6f00" : "#c00"));
    k += 1;
    if (k < seq.length) requestAnimationFrame(step);
    else finish(plan, phases, out);
  };
  requestAnimationFrame(step);
}

function finish(plan, phases, out) {
  const last = phases[phases.length - 1].after;
  const { final, claimed } = markFinal(out, plan, last);
  const spread = last[1] - last[0] > 1e-6 ? ` (within ±${(0.5 * (last[1] - last[0])).toFixed(2)}°)` : "";
  const where = plan.exit ? "leaves the exit guide" : "leaves the last fence";
  out.textContent = `${where} at φ = ${final.toFixed(2)}°${spread} — ${claimSaid(claimed)}`;
}
