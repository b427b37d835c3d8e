// Catalogue jobs: POST /v1/jobs (archive), poll GET /v1/jobs/{id}, show per-part results
// and the gripper specification (GET /v1/jobs/{id}/gripper), download the results zip.

import { api, download } from "./api.js";
import { physicsRequest } from "./physics.js";

const POLL_MS = 700;

export async function startJob(state) {
  const file = document.getElementById("job-archive").files[0];
  if (!file) throw new Error("choose a catalogue archive (zip or tar) first");
  const gripper = document.getElementById("job-gripper").value.trim();
  const options = { min_margin_deg: Number(document.getElementById("job-margin").value) };
  const physics = physicsRequest();  // the Plan page's cell physics apply to the job too
  if (physics) options.physics = physics;
  if (gripper) {
    try { options.gripper = JSON.parse(gripper); } catch { throw new Error("gripper profile: not valid JSON"); }
  }
  const form = new FormData();
  form.append("archive", file);
  form.append("options", JSON.stringify(options));
  const job = await api("/v1/jobs", { form });
  state.job = job.id;
  document.getElementById("job-out").hidden = false;
  await poll(state, job.id);
}

// Per-part results (JSON lines): fetched on every poll for small jobs, at the end for big ones.
const LIVE_RESULTS_MAX = 500;

async function results(id) {
  const r = await api(`/v1/jobs/${id}/results`, { raw: true });
  const out = {};
  for (const line of (await r.text()).split("\n")) {
    if (line.trim()) {
      const row = JSON.parse(line);
      out[row.index] = row;
    }
  }
  return out;
}

async function poll(state, id) {
  for (;;) {
    const job = await api(`/v1/jobs/${id}`);
    if (state.job !== id) return; // another job was started meanwhile
    const running = ["queued", "running"].includes(job.state);
    showJob(job, running && job.total > LIVE_RESULTS_MAX ? {} : await results(id));
    if (!running) break;
    await new Promise((r) => setTimeout(r, POLL_MS));
  }
  showSpec(await api(`/v1/jobs/${id}/gripper`));
}

function cell(tr, text) {
  tr.append(Object.assign(document.createElement("td"), { textContent: text ?? "—" }));
}

function showJob(job, byIndex) {
  const bar = document.getElementById("job-progress");
  bar.max = job.progress.total || 1;
  bar.value = job.progress.finished;
  document.getElementById("job-state").textContent = `${job.state}: ${job.progress.finished}/${job.progress.total} parts ` +
    `(${job.done} done, ${job.failed} failed, ${job.cancelled} cancelled)`;
  const zip = document.getElementById("job-zip");
  zip.onclick = (ev) => { ev.preventDefault(); download(`/v1/jobs/${job.id}/results?format=zip`, `job-${job.id}.zip`); };
  const rows = job.parts.map((p) => {
    const tr = document.createElement("tr");
    const res = (byIndex[p.index] && byIndex[p.index].result) || {};
    const why = p.error ? p.error.message : res.orientable === false ? Object.values(res.reasons || {}).join("; ") : "";
    if (p.status === "failed" || res.orientable === false) tr.className = "bad";
    [p.index + 1, p.name, p.status, res.action, res.plan ? res.plan.steps.length : null, why].forEach((v) => cell(tr, v));
    return tr;
  });
  document.querySelector("#job-parts tbody").replaceChildren(...rows);
}

function showSpec(spec) {
  const rows = [
    ["parts oriented", `${spec.oriented} of ${spec.parts}`],
    ["jaw opening (mm)", spec.jaw_opening_mm?.toFixed(2)],
    ["jaw length (mm)", spec.jaw_length_mm?.toFixed(2)],
    ["push stroke (mm)", spec.push_stroke_mm?.toFixed(2)],
    ["max cycle time (s)", spec.max_cycle_time_s?.toFixed(2)],
    ["mean cycle time (s)", spec.mean_cycle_time_s?.toFixed(2)],
    ["jaw friction limit", spec.jaw_advice ?? "—"],
    ["actions", Object.entries(spec.actions).map(([a, n]) => `${a}: ${n}`).join(", ")],
    ["not oriented", spec.not_oriented.map((f) => `${f.name} (${f.why})`).join("; ") || "none"],
  ].map(([k, v]) => {
    const tr = document.createElement("tr");
    tr.append(Object.assign(document.createElement("th"), { textContent: k, scope: "row" }));
    cell(tr, v);
    return tr;
  });
  const table = document.getElementById("gripper-spec");
  table.dataset.loaded = "true";
  table.querySelector("tbody").replaceChildren(...rows);
}
