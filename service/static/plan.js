// Plan page: POST /v1/plans with the chosen options, the actions, final orientations and
// their uncertainty, the limits, the intervals Θᵢ on the transfer function, and a
// kinematic animation of the plan from a start orientation the user drags, driven by the
// plan's own images (motion.js) with the uncertainty wedge of each action.

import { api, begin } from "./api.js";
import { mod } from "./geom.js";
import { claimSaid, follow, hasImages, markFinal, middle } from "./motion.js";
import { drawScene, frameOf, sceneExtent, turningView, unionBox } from "./scene.js";
import { describePhysics, limitsWanted, physicsRequest } from "./physics.js";
import { clearPlot, linePlot } from "./plots.js";

export function planRequest(state, extra = {}) {
  const gripper = document.getElementById("gripper").value.trim();
  let profile = null;
  if (gripper) {
    try { profile = JSON.parse(gripper); } catch { throw new Error("gripper profile: not valid JSON"); }
  }
  return {
    part: state.part, action: document.getElementById("action").value,
    min_margin_deg: Number(document.getElementById("min-margin").value),
    exact: document.getElementById("model").value === "exact",
    physics: physicsRequest(), limits: limitsWanted(),
    optimise: document.getElementById("optimise").checked || Boolean(profile), gripper: profile, ...extra,
  };
}

// The animation needs the analysis of the same part and model as the plan.
export async function ensureAnalysis(state, exact) {
  if (!state.analysis || state.analysisOf !== state.part || Boolean(state.analysisExact) !== exact) {
    state.analysis = await api(`/v1/analyses?samples=720&exact=${exact}`, { json: state.part });
    state.analysisOf = state.part;
    state.analysisExact = exact;
  }
}

export async function makePlan(state) {
  const current = begin("plan");
  clearPlan(state); // a failed plan leaves no old plan under its error
  const body = planRequest(state);
  await ensureAnalysis(state, body.exact);
  current();
  const plan = await api("/v1/plans", { json: body });
  current(document.getElementById("plan-out"));
  state.plan = plan;
  showPlan(state);
}

// The Plan page shows nothing of a previous plan: no summary, steps, figure or animation end.
export function clearPlan(state) {
  state.plan = null;
  state.animation = (state.animation || 0) + 1; // a running animation stops at its next frame
  const out = document.getElementById("plan-out");
  out.hidden = true;
  delete out.dataset.stale;
  const summary = document.getElementById("plan-summary");
  summary.textContent = "";
  delete summary.dataset.steps;
  for (const id of ["plan-physics", "plan-limits"]) document.getElementById(id).textContent = "";
  document.querySelector("#plan-steps tbody").replaceChildren();
  clearPlot(document.getElementById("plot-intervals"));
  clearEnd();
}

function clearEnd() {
  const out = document.getElementById("anim-final");
  out.textContent = "";
  delete out.dataset.finalDeg;
  delete out.dataset.finalRange;
  delete out.dataset.claimed;
}

// The shown plan no longer matches the form (or the part): said, until the next Plan.
export function markPlanStale(state) {
  if (!state.plan) return;
  const out = document.getElementById("plan-out");
  out.dataset.stale = "true";
  document.getElementById("plan-stale").textContent = "the inputs changed since this plan: press Plan for a new one";
}

const fmt = (x, d = 2) => (x === null || x === undefined ? "—" : Number(x).toFixed(d));

export function showPlan(state) {
  const p = state.plan, units = state.analysis.part.units;
  const planOut = document.getElementById("plan-out");
  planOut.hidden = false;
  delete planOut.dataset.stale;
  document.getElementById("plan-stale").textContent = "";
  state.animation = (state.animation || 0) + 1;
  clearEnd();
  const finals = p.final_orientations_deg.map((f) => `${fmt(f)}°`).join(", ");
  const summary = document.getElementById("plan-summary");
  summary.textContent = `${p.steps.length}-step ${p.action.replace("_", "-")} plan (${p.model} model, ` +
    `${p.verified ? "verified" : "NOT verified"}): final orientation${p.final_orientations_deg.length > 1 ? "s" : ""} ` +
    `${finals} ± ${fmt(p.final_uncertainty_deg, 4)}°` + (p.cycle_time_s ? `; cycle time ${fmt(p.cycle_time_s)} s` : "");
  if (p.run_id) summary.append("; run ", Object.assign(document.createElement("span"), { className: "run-id", textContent: p.run_id }));
  summary.dataset.steps = p.steps.length;
  document.getElementById("plan-physics").textContent = p.dead_band ? `physics: ${describePhysics(p.dead_band)}` : "";
  showLimits(p.limits);
  const tbody = document.querySelector("#plan-steps tbody");
  tbody.replaceChildren(...p.steps.map((s, i) => {
    const tr = document.createElement("tr");
    const push = s.push_distance === null || s.push_distance === undefined ? "—" : `${fmt(s.push_distance, 3)} ${units}`;
    for (const v of [i + 1, fmt(s.gripper_angle_deg), s.margin_deg === null ? "— (first)" : fmt(s.margin_deg), push, fmt(s.duration_s)]) {
      tr.append(Object.assign(document.createElement("td"), { textContent: v }));
    }
    return tr;
  }));
  drawIntervals(state);
  showStart(state);
}

const LIMIT_NAMES = {
  jaw_friction_max: "largest jaw friction μ", support_friction_min: "smallest support friction μ",
  support_friction_max: "largest support friction μ", mass_min: "smallest part mass (kg)",
  mass_max: "largest part mass (kg)", profile_tolerance_max: "largest profile tolerance",
};

// The limits the plan carries (conventions §8): one row per range searched, and the advice.
function showLimits(limits) {
  const host = document.getElementById("plan-limits");
  host.replaceChildren();
  if (!limits) return;
  const rows = Object.entries(limits).filter(([, v]) => v && typeof v === "object" && "value" in v);
  if (rows.length) {
    const table = document.createElement("table");
    table.id = "plan-limits-table";
    table.append(Object.assign(document.createElement("caption"), { textContent: "Limits: how far each range may go with a plan still existing" }));
    for (const [name, v] of rows) {
      const tr = document.createElement("tr");
      tr.dataset.limit = name;
      const value = v.value === null ? "none found" : `${fmt(v.value, 3)}${v.bounded ? "" : " (the search's end: no limit below it)"}`;
      tr.append(Object.assign(document.createElement("th"), { scope: "row", textContent: LIMIT_NAMES[name] || name }),
        Object.assign(document.createElement("td"), { textContent: value }));
      table.append(tr);
    }
    host.append(table);
  }
  if (limits.advice) host.append(Object.assign(document.createElement("p"), { textContent: `limits: ${limits.advice}` }));
}

// The Θᵢ of Algorithm A′ as labelled bars, one row each under the transfer function the
// plan uses (an interval past the period wraps to 0: two pieces, one label).
function drawIntervals(state) {
  const p = state.plan, a = state.analysis;
  const name = p.action === "squeeze" ? "squeeze" : "push_grasp";
  const P = a[name].period_deg, c = a.curves;
  const n = Math.round((c.theta_deg.length * P) / 360);
  const lanes = p.intervals_deg.map(([lo, hi], i) => ({ x0: lo, x1: hi, label: `Θ${i + 1}`, cls: "bar-interval" }));
  linePlot(document.getElementById("plot-intervals"), {
    title: `${name === "squeeze" ? "Γ" : "Γ∘p"} and the intervals Θᵢ of Algorithm A′ (bars below)`,
    xLabel: "θ before (deg)", yLabel: "θ after (deg)", xDomain: [0, P], period: P,
    series: [{ xs: [0, P], ys: [0, P], cls: "identity" }, { xs: c.theta_deg.slice(0, n), ys: c[`${name}_deg`].slice(0, n), cls: "alt", breakJumps: 1 }],
    lanes,
  });
}

function showStart(state) {
  const phi0 = Number(document.getElementById("start-deg").value);
  document.getElementById("start-out").textContent = `${phi0}°`;
  drawScene(document.getElementById("anim-view"), state.analysis.geometry, { phi: phi0 }, null,
    { view: turningView(state.analysis.geometry), caption: `start φ₀ = ${phi0}° (drag to turn)`, label: "the part at its start orientation" });
}

// Drag on the view turns the part: the pointer's angle about the centre sets φ₀.
export function enableDrag(state) {
  const host = document.getElementById("anim-view");
  const input = document.getElementById("start-deg");
  let dragging = false;
  const angle = (ev) => {
    const r = host.getBoundingClientRect();
    return (Math.atan2(-(ev.clientY - (r.top + r.height / 2)), ev.clientX - (r.left + r.width / 2)) * 180) / Math.PI;
  };
  let start = 0, phiAtStart = 0;
  host.addEventListener("pointerdown", (ev) => {
    if (!state.plan) return;
    dragging = true;
    start = angle(ev);
    phiAtStart = Number(input.value);
    host.setPointerCapture(ev.pointerId);
  });
  host.addEventListener("pointermove", (ev) => {
    if (!dragging) return;
    input.value = Math.round(mod(phiAtStart + angle(ev) - start, 360)) % 360;
    showStart(state);
  });
  host.addEventListener("pointerup", () => { dragging = false; });
  input.addEventListener("input", () => state.plan && showStart(state));
}

// Frames of one action: turn the gripper, (push,) close, open. The part's orientation and
// its wedge ease from the interval before the action to the one after (the plan's images).
function frames(state, phases) {
  const R = sceneExtent(state.analysis.geometry), open = 1.15 * R, out = [];
  const ease = (u) => 0.5 - 0.5 * Math.cos(Math.PI * u);
  const between = (a, b, u) => [a[0] + (b[0] - a[0]) * ease(u), a[1] + (b[1] - a[1]) * ease(u)];
  const push = state.plan.action === "push_grasp";
  phases.forEach((ph, n) => {
    const N = 24, at = (w, f) => ({ ...f, phi: middle(w), wedge: { range: w, all: n ? phases[n - 1].all : null }, n });
    for (let i = 0; i <= N; i++) out.push(at(ph.before, { alpha: ph.alpha, lower: -open, higher: open }));
    if (push) for (let i = 0; i <= N; i++) out.push(at(ph.before, { alpha: ph.alpha, lower: null, higher: open * (1 - 0.1 * ease(i / N)) }));
    for (let i = 0; i <= N; i++) out.push(at(between(ph.before, ph.after, i / N), { alpha: ph.alpha, lower: null, higher: null }));
    for (let i = 0; i <= N / 2; i++) out.push({ ...at(ph.after, { alpha: ph.alpha, lower: -open, higher: open }), wedge: { range: ph.after, all: ph.all }, done: true });
  });
  return out;
}

export function play(state, { host = "anim-view", phi0, onEnd } = {}) {
  const start = phi0 ?? Number(document.getElementById("start-deg").value);
  if (!hasImages(state.plan)) {
    document.getElementById("anim-final").textContent = "this plan document carries no images: plan again to animate it";
    return;
  }
  const phases = follow(state.plan, start);
  const seq = frames(state, phases);
  const g = state.analysis.geometry;
  const jawsOf = (f) => ({ alpha: f.alpha, lower: f.lower ?? undefined, higher: f.higher ?? undefined });
  const view = unionBox(seq.map((f) => frameOf(g, { phi: f.phi }, jawsOf(f)))); // still, and everything in it
  const out = document.getElementById("anim-final");
  out.textContent = "playing…";
  delete out.dataset.finalDeg;
  let k = 0;
  const token = (state.animation = (state.animation || 0) + 1);
  const step = () => {
    if (state.animation !== token) return; // a new plan (or another play) took over the view
    const f = seq[k];
    const [lo, hi] = f.wedge.range;
    const spread = hi - lo > 1e-9 ? ` ± ${(0.5 * (hi - lo)).toFixed(2)}°` : "";
    drawScene(document.getElementById(host), g, { phi: f.phi }, jawsOf(f),
      { view, wedge: { ...f.wedge, step: f.n + 1, done: Boolean(f.done) },
        caption: `action ${f.n + 1}/${phases.length}: α = ${f.alpha.toFixed(1)}°, φ = ${mod(f.phi, 360).toFixed(1)}°${spread}` });
    k += 1;
    if (k < seq.length) requestAnimationFrame(step);
    else finish(state, phases, out, onEnd);
  };
  requestAnimationFrame(step);
}

function finish(state, phases, out, onEnd) {
  const last = phases[phases.length - 1].after;
  const { final, claimed } = markFinal(out, state.plan, last);
  const spread = last[1] - last[0] > 1e-9 ? ` (within [${mod(last[0], 360).toFixed(2)}°, ${(mod(last[0], 360) + last[1] - last[0]).toFixed(2)}°])` : "";
  out.textContent = `ends at φ = ${final.toFixed(2)}°${spread} — ${claimSaid(claimed)}`;
  if (onEnd) onEnd(final);
}
