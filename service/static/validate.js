// Validation page: POST /v1/plans with `validate` (Drake), then GET /v1/runs/{id}/playback
// to play each sample's simulated trajectory beside the predicted motion (dashed), with
// the per-sample table. The page says what it validated (part, action, model, cells,
// placement, seed); the view is framed on the part and the jaws over the whole playback.

import { api, begin } from "./api.js";
import { mod } from "./geom.js";
import { follow, hasImages, middle } from "./motion.js";
import { ensureAnalysis, planRequest, showPlan } from "./plan.js";
import { drawScene, frameOf, unionBox } from "./scene.js";

const $ = (id) => document.getElementById(id);

export function validateOptions() {
  const out = {
    samples: Number($("samples").value),
    seed: Math.max(0, Math.floor(Number($("val-seed").value) || 0)),
    sim_physics: $("sim-physics").value,
  };
  if (out.sim_physics === "cell") {
    out.sim_physics = $("sim-cell").value.trim();
    if (!out.sim_physics) throw new Error("enter the cell to simulate (KEY=VALUE,…), e.g. support_friction=0.05");
  }
  if ($("val-placement").value) out.placement = $("val-placement").value;
  return out;
}

export async function runValidation(state) {
  const current = begin("validation");
  clearValidation(state); // a failed validation leaves no old one under its error
  const validate = validateOptions();
  const progress = $("validation-progress");
  const elapsed = $("validation-elapsed");
  const t0 = performance.now();
  progress.hidden = false;
  const timer = setInterval(() => { elapsed.textContent = `simulating ${validate.samples} samples… ${((performance.now() - t0) / 1000).toFixed(0)} s`; }, 250);
  let plan, playback;
  try {
    const body = planRequest(state, { validate });
    await ensureAnalysis(state, body.exact);
    plan = await api("/v1/plans", { json: body });
    current();
    playback = await api(`/v1/runs/${plan.run_id}/playback?points=400`);
    current($("validation-out"));
  } finally {
    clearInterval(timer);
    progress.hidden = true;
  }
  elapsed.textContent = `done in ${((performance.now() - t0) / 1000).toFixed(1)} s`;
  state.plan = plan;
  state.playback = playback;
  showPlan(state); // the Plan page shows the plan that was validated
  showValidation(state);
}

// Nothing of an earlier validation stays on the page.
export function clearValidation(state) {
  state.playback = null;
  state.playing = (state.playing || 0) + 1;
  const out = $("validation-out");
  out.hidden = true;
  delete out.dataset.stale;
  $("validation-summary").textContent = "";
  $("validation-what").textContent = "";
  $("validation-stale").textContent = "";
  $("validation-elapsed").textContent = "";
  document.querySelector("#validation-table tbody").replaceChildren();
  $("playback-sample").replaceChildren();
  $("playback-view").replaceChildren();
  const status = $("playback-status");
  status.textContent = "";
  delete status.dataset.ended;
}

export function markValidationStale(state) {
  if (!state.playback) return;
  $("validation-out").dataset.stale = "true";
  $("validation-stale").textContent = "the inputs changed since this validation: validate again for results that match them";
}

// What the run record says was validated: "validated: 3-step squeeze plan (robust model) of
// pie-20; cells simulated nominal, placement random, seed 0, 4 samples".
function describeValidated(state) {
  const pb = state.playback, p = pb.plan || state.plan, v = pb.validation || {}, o = pb.options || {};
  const part = (pb.part && pb.part.name) || "part";
  const placement = v.placement || o.placement || (p.dead_band && p.dead_band.placement) || "as the cell says";
  const samples = v.samples ? v.samples.length : o.samples;
  return `validated: ${p.steps.length}-step ${p.action.replace("_", "-")} plan (${p.model} model) of ${part}; ` +
    `cells simulated ${o.sim_physics || "nominal"}, placement ${placement}, seed ${o.seed ?? 0}, ${samples} samples`;
}

export function showValidation(state) {
  const v = state.playback.validation;
  const out = $("validation-out");
  out.hidden = false;
  delete out.dataset.stale;
  $("validation-stale").textContent = "";
  $("validation-what").textContent = describeValidated(state);
  $("validation-summary").textContent = v
    ? `agreement ${(100 * v.agreement).toFixed(1)} % of ${v.samples.length} samples within ${v.tolerance_deg}° ` +
      `(clear of unstable equilibria: ${(100 * v.agreement_clear).toFixed(1)} %); ${v.sim_seconds.toFixed(1)} s simulated in ${v.wall_seconds.toFixed(1)} s; run ${state.playback.run_id}` +
      (v.cells && v.cells.length > 1 ? "; per cell: " + v.cells.map((c) => `${c.label} ${(100 * c.agreement).toFixed(0)} %`).join("; ") : "")
    : "this run has no validation";
  const rows = (v ? v.samples : []).map((s, i) => {
    const tr = document.createElement("tr");
    if (!s.agrees) tr.className = "bad";
    for (const x of [i + 1, s.initial_deg.toFixed(2), s.predicted_deg.toFixed(2), s.simulated_deg.toFixed(2), s.agrees ? "yes" : "no"]) {
      tr.append(Object.assign(document.createElement("td"), { textContent: x }));
    }
    return tr;
  });
  document.querySelector("#validation-table tbody").replaceChildren(...rows);
  const select = $("playback-sample");
  select.replaceChildren(...state.playback.trajectories.map((t) => new Option(`sample ${t.sample + 1}`, t.sample)));
  if (state.playback.trajectories.length) drawFrame(state, state.playback.trajectories[0], 0, playbackView(state, state.playback.trajectories[0]));
}

// The action a simulated state belongs to: the first plan step whose angle matches the
// gripper's, searched from the current one on (the gripper only moves forward through the plan).
function actionIndex(steps, alphaDeg, from) {
  for (let k = from; k < steps.length; k++) {
    if (Math.abs(mod(steps[k].gripper_angle_deg - alphaDeg + 180, 360) - 180) < 0.5) return k;
  }
  return from;
}

function pose(tr, i) {
  return [{ phi: tr.phi_deg[i], x: tr.x[i], y: tr.y[i] },
    { alpha: tr.gripper_angle_deg[i], lower: tr.lower_jaw[i], higher: tr.higher_jaw[i] }];
}

// One view for the whole trajectory: the box around the part and both jaws at every frame.
function playbackView(state, tr) {
  const g = state.analysis.geometry;
  return unionBox(tr.t_s.map((_, i) => frameOf(g, ...pose(tr, i))));
}

function drawFrame(state, tr, i, view, k = 0, phases = null) {
  const [p, jaws] = pose(tr, i);
  const ghost = phases ? { phi: middle(phases[k].after), x: tr.x[i], y: tr.y[i] } : null;
  drawScene($("playback-view"), state.analysis.geometry, p, jaws,
    { ghost, view, caption: `t = ${tr.t_s[i].toFixed(2)} s, φ = ${mod(p.phi, 360).toFixed(1)}°, α = ${jaws.alpha.toFixed(1)}°`,
      label: "simulated part and jaws" });
}

export function playBack(state) {
  const sample = Number($("playback-sample").value);
  const tr = state.playback.trajectories.find((t) => t.sample === sample);
  const v = state.playback.validation.samples[sample];
  const plan = state.playback.plan;
  const phases = hasImages(plan) ? follow(plan, v.initial_deg) : null; // the plan's own images
  const view = playbackView(state, tr);
  const status = $("playback-status");
  status.dataset.ended = "false";
  status.textContent = "playing…";
  const token = (state.playing = (state.playing || 0) + 1);
  let i = 0, k = 0;
  const stride = Math.max(1, Math.round(tr.t_s.length / 240)); // about 4 s at 60 frames/s
  const step = () => {
    if (state.playing !== token) return; // cleared or another playback started
    k = actionIndex(plan.steps, tr.gripper_angle_deg[i], k);
    drawFrame(state, tr, i, view, k, phases);
    i += stride;
    if (i < tr.t_s.length) requestAnimationFrame(step);
    else {
      drawFrame(state, tr, tr.t_s.length - 1, view, phases ? phases.length - 1 : 0, phases);
      status.dataset.ended = "true";
      status.textContent = `ended: simulated ${mod(v.simulated_deg, 360).toFixed(2)}°, predicted ${mod(v.predicted_deg, 360).toFixed(2)}° — ${v.agrees ? "agrees" : "DISAGREES"}`;
    }
  };
  requestAnimationFrame(step);
}
