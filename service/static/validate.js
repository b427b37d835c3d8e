// Validation page: POST /v1/plans with `validate` (Drake), then GET /v1/runs/{id}/playback
// to play each sample's simulated trajectory beside the predicted motion (dashed), with
// the per-sample table.

import { api } from "./api.js";
import { mod, predict } from "./geom.js";
import { ensureAnalysis, planRequest } from "./plan.js";
import { drawScene } from "./scene.js";

export async function runValidation(state) {
  const samples = Number(document.getElementById("samples").value);
  const cells = document.getElementById("sim-physics").value;
  const seed = Number(document.getElementById("val-seed").value) || 0;
  const progress = document.getElementById("validation-progress");
  const elapsed = document.getElementById("validation-elapsed");
  const t0 = performance.now();
  progress.hidden = false;
  const timer = setInterval(() => { elapsed.textContent = `simulating ${samples} samples… ${((performance.now() - t0) / 1000).toFixed(0)} s`; }, 250);
  try {
    const body = planRequest(state, { validate: { samples, seed, sim_physics: cells } });
    await ensureAnalysis(state, body.exact);
    state.plan = await api("/v1/plans", { json: body });
    state.playback = await api(`/v1/runs/${state.plan.run_id}/playback?points=400`);
  } finally {
    clearInterval(timer);
    progress.hidden = true;
  }
  elapsed.textContent = `done in ${((performance.now() - t0) / 1000).toFixed(1)} s`;
  showValidation(state);
}

export function showValidation(state) {
  const v = state.playback.validation;
  document.getElementById("validation-out").hidden = false;
  document.getElementById("validation-summary").textContent = v
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
  const select = document.getElementById("playback-sample");
  select.replaceChildren(...state.playback.trajectories.map((t) => new Option(`sample ${t.sample + 1}`, t.sample)));
  if (state.playback.trajectories.length) drawFrame(state, state.playback.trajectories[0], 0);
}

// The action a simulated state belongs to: the first plan step whose angle matches the
// gripper's, searched from the current one on (the gripper only moves forward through the plan).
function actionIndex(steps, alphaDeg, from) {
  for (let k = from; k < steps.length; k++) {
    if (Math.abs(mod(steps[k].gripper_angle_deg - alphaDeg + 180, 360) - 180) < 0.5) return k;
  }
  return from;
}

function drawFrame(state, tr, i, k = 0, phases = null) {
  const phi = tr.phi_deg[i];
  const ghost = phases ? { phi: phases[k].after, x: tr.x[i], y: tr.y[i] } : null;
  drawScene(document.getElementById("playback-view"), state.analysis.geometry, { phi, x: tr.x[i], y: tr.y[i] },
    { alpha: tr.gripper_angle_deg[i], lower: tr.lower_jaw[i], higher: tr.higher_jaw[i] },
    { ghost, zoom: 1.6, caption: `t = ${tr.t_s[i].toFixed(2)} s, φ = ${mod(phi, 360).toFixed(1)}°, α = ${tr.gripper_angle_deg[i].toFixed(1)}°`,
      label: "simulated part and jaws" });
}

export function playBack(state) {
  const sample = Number(document.getElementById("playback-sample").value);
  const tr = state.playback.trajectories.find((t) => t.sample === sample);
  const v = state.playback.validation.samples[sample];
  const plan = state.playback.plan;
  const phases = predict(state.analysis, plan, v.initial_deg);
  const status = document.getElementById("playback-status");
  status.dataset.ended = "false";
  status.textContent = "playing…";
  let i = 0, k = 0;
  const stride = Math.max(1, Math.round(tr.t_s.length / 240)); // about 4 s at 60 frames/s
  const step = () => {
    k = actionIndex(plan.steps, tr.gripper_angle_deg[i], k);
    drawFrame(state, tr, i, k, phases);
    i += stride;
    if (i < tr.t_s.length) requestAnimationFrame(step);
    else {
      drawFrame(state, tr, tr.t_s.length - 1, phases.length - 1, phases);
      status.dataset.ended = "true";
      status.textContent = `ended: simulated ${mod(v.simulated_deg, 360).toFixed(2)}°, predicted ${mod(v.predicted_deg, 360).toFixed(2)}° — ${v.agrees ? "agrees" : "DISAGREES"}`;
    }
  };
  requestAnimationFrame(step);
}
