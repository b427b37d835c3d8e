// A plan's motion from a start orientation, read off the plan document's own images (the
// API's `images` and each step's `image_deg`): no planner here. Per action, the interval of
// world orientations the part can be in (robust bounds: an uncertainty wedge; the exact
// model: a point) and the arcs it can be in from any start. Degrees, lifted.

import { mod } from "./geom.js";

// The map's value at θ (gripper frame): pieces [start, end, lower, upper] over one period,
// repeating with it; null lower/upper is θ itself. which: 2 lower, 3 upper.
export function valueAt(images, theta, which) {
  const P = images.period_deg, pieces = images.pieces;
  const base = pieces[0][0];
  const k = Math.floor((theta - base) / P);
  const x = theta - k * P;
  let piece = pieces[0];
  for (const p of pieces) if (p[0] <= x) piece = p;
  const v = piece[which];
  return v === null ? theta : v + k * P;
}

// Whether the plan document carries what the animation needs (older records may not).
export function hasImages(plan) {
  return Boolean(plan.images && plan.images.pieces && plan.images.pieces.length && plan.steps.every((s) => s.image_deg));
}

// Per action {alpha, before: [lo, hi], after: [lo, hi], all: image_deg} from φ₀.
export function follow(plan, phi0) {
  let lo = phi0, hi = phi0;
  return plan.steps.map((step) => {
    const alpha = step.gripper_angle_deg;
    const before = [lo, hi];
    lo = valueAt(plan.images, lo - alpha, 2) + alpha;
    hi = valueAt(plan.images, hi - alpha, 3) + alpha;
    return { alpha, before, after: [lo, hi], all: step.image_deg };
  });
}

export const middle = ([lo, hi]) => 0.5 * (lo + hi);

// Whether the interval [lo, hi] lies within the uncertainty of a claimed final orientation.
export function withinClaim(plan, [lo, hi], slackDeg = 1e-6) {
  const tol = (plan.final_uncertainty_deg || 0) + slackDeg;
  return plan.final_orientations_deg.some((f) => {
    const c = f + 360 * Math.round((middle([lo, hi]) - f) / 360);
    return lo >= c - tol && hi <= c + tol;
  });
}

export const wrapDeg = (x) => mod(x, 360);

// Marks `out` with a played plan's final interval [lo, hi] (data-final-deg, the middle in
// [0, 360); data-final-range; data-claimed) and returns {final, claimed}.
export function markFinal(out, plan, last) {
  const final = mod(middle(last), 360), claimed = withinClaim(plan, last);
  out.dataset.finalDeg = final.toFixed(6);
  out.dataset.finalRange = JSON.stringify(last);
  out.dataset.claimed = String(claimed);
  return { final, claimed };
}

export const claimSaid = (claimed) => (claimed ? "a claimed final orientation" : "NOT a claimed final orientation");
