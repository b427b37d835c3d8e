// Catalogue jobs: POST /v1/jobs (archive); the list of jobs (GET /v1/jobs, polled while
// any runs) with state, progress and Cancel (DELETE /v1/jobs/{id}); one job shown (poll
// GET /v1/jobs/{id}) with per-part results, the gripper specification (GET
// /v1/jobs/{id}/gripper) and the results zip. The job shown last is remembered for a reload.

import { api, begin, clearFieldErrors, download, markFieldError } from "./api.js";
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
  Object.assign(options, fenceOptions());
  const form = new FormData();
  form.append("archive", file);
  form.append("options", JSON.stringify(options));
  clearFieldErrors(document.getElementById("job-form"));
  let job;
  try {
    job = await api("/v1/jobs", { form });
  } catch (e) {
    markFieldError(e, FIELDS);
    throw e;
  }
  state.jobIgnored = { ...state.jobIgnored, [job.id]: job.ignored || [] };
  listJobs(state).catch(() => {}); // the list shows it at once; its own errors come with its next refresh
  await showJob(state, job.id);
}

// The job options' controls, by the name a 422's field ends with.
const FIELDS = {
  min_margin_deg: "job-margin", gripper: "job-gripper", fences: "job-fences", fence_friction: "job-fence-mu-lo",
  fence_min_margin_deg: "job-fence-margin", belt_width: "job-belt-width", exit_steepness_deg: "job-exit-steepness",
  exit_turns: "job-fence-tip-turns", same_rail: "job-fence-same-rail",
};

// The fence options of POST /v1/jobs (the Fences page's, per part); none unless ticked.
function fenceOptions() {
  const $ = (id) => document.getElementById(id);
  if (!$("job-fences").checked) return {};
  const out = {
    fences: true,
    fence_friction: [Number($("job-fence-mu-lo").value), Number($("job-fence-mu-hi").value)],
    exit_turns: $("job-fence-tip-turns").checked,
    same_rail: $("job-fence-same-rail").checked,
  };
  for (const [key, id] of [["fence_min_margin_deg", "job-fence-margin"], ["belt_width", "job-belt-width"],
    ["exit_steepness_deg", "job-exit-steepness"]]) {
    const v = $(id).value.trim();
    if (v) out[key] = Number(v);
  }
  return out;
}

// The fence options are enabled while "design conveyor fences" is ticked.
export function setupJobForm() {
  const box = document.getElementById("job-fences");
  const sync = () => { document.getElementById("job-fence-options").disabled = !box.checked; };
  box.addEventListener("change", sync);
  sync();
}

// A part's fence result, compactly: the count (and the exit guide) or why refused.
function fenceCell(f) {
  if (!f) return null;
  if (f.orientable === false) return `refused: ${f.message || f.reason}`;
  const n = f.fences.length;
  return `${n} fence${n > 1 ? "s" : ""}` + (f.exit ? `, exit guide ${Number(f.exit.steepness_deg.toPrecision(3))}°` : "");
}

const RUNNING = ["queued", "running"];
const LAST_JOB = "algrasp-job";
let listTimer = null;

// The job shown below the list: polled until it ends (another job shown stops the poll).
export async function showJob(state, id) {
  state.job = id;
  sessionStorage.setItem(LAST_JOB, id);
  document.getElementById("job-out").hidden = false;
  document.getElementById("job-out").dataset.job = id;
  const spec = document.getElementById("gripper-spec");
  delete spec.dataset.loaded;
  spec.querySelector("tbody").replaceChildren();
  document.querySelector("#job-parts tbody").replaceChildren();
  document.getElementById("job-state").textContent = "loading…";
  const ignored = (state.jobIgnored || {})[id] || [];
  document.getElementById("job-ignored").replaceChildren(...ignored.map((w) =>
    Object.assign(document.createElement("li"), { textContent: `ignored: ${w}` })));
  document.querySelectorAll("#jobs-table tbody tr").forEach((tr) => tr.setAttribute("aria-selected", String(tr.dataset.job === id)));
  await poll(state, id);
}

export function lastJob() {
  return sessionStorage.getItem(LAST_JOB);
}

export async function cancelJob(state, id) {
  await api(`/v1/jobs/${id}`, { method: "DELETE" });
  await listJobs(state);
}

// The list of jobs, newest first; refreshed every POLL_MS while one runs and the page shows.
export async function listJobs(state, { onShow, onCancel } = state.jobActions || {}) {
  const current = begin("jobs");
  const { jobs } = await api("/v1/jobs?limit=20");
  const live = await Promise.all(jobs.map((j) => (RUNNING.includes(j.state) ? api(`/v1/jobs/${j.id}`) : null)));
  current();
  const rows = jobs.map((j, k) => {
    const tr = document.createElement("tr");
    tr.dataset.job = j.id;
    tr.dataset.state = j.state;
    tr.setAttribute("aria-selected", String(state.job === j.id));
    cell(tr, j.id.slice(0, 8));
    cell(tr, new Date(j.created_at * 1000).toLocaleString());
    cell(tr, j.state);
    const td = document.createElement("td");
    if (live[k]) {
      const { finished, total } = live[k].progress;
      const bar = Object.assign(document.createElement("progress"), { max: total || 1, value: finished });
      bar.setAttribute("aria-label", `job ${j.id.slice(0, 8)} progress`);
      td.append(bar, ` ${finished}/${total}`);
    } else td.textContent = `${j.total} parts`;
    tr.append(td);
    const actions = document.createElement("td");
    const show = Object.assign(document.createElement("button"), { type: "button", textContent: "Show", className: "job-show" });
    show.addEventListener("click", () => onShow && onShow(j.id));
    actions.append(show);
    if (RUNNING.includes(j.state)) {
      const cancel = Object.assign(document.createElement("button"), { type: "button", textContent: "Cancel", className: "job-cancel" });
      cancel.addEventListener("click", () => onCancel && onCancel(j.id));
      actions.append(" ", cancel);
    }
    tr.append(actions);
    return tr;
  });
  document.querySelector("#jobs-table tbody").replaceChildren(...rows);
  document.getElementById("jobs-table").dataset.loaded = "true";
  clearTimeout(listTimer);
  const onPage = !document.getElementById("page-catalogue").hidden;
  if (onPage && jobs.some((j) => RUNNING.includes(j.state))) {
    listTimer = setTimeout(() => listJobs(state).catch(() => {}), POLL_MS);
  }
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
    const byIndex = running && job.total > LIVE_RESULTS_MAX ? {} : await results(id);
    if (state.job !== id) return;
    drawJob(job, byIndex);
    if (!running) break;
    await new Promise((r) => setTimeout(r, POLL_MS));
  }
  const spec = await api(`/v1/jobs/${id}/gripper`);
  if (state.job === id) showSpec(spec);
}

function cell(tr, text) {
  tr.append(Object.assign(document.createElement("td"), { textContent: text ?? "—" }));
}

function drawJob(job, byIndex) {
  const out = document.getElementById("job-out");
  out.dataset.state = job.state;
  document.getElementById("job-cancel").hidden = !RUNNING.includes(job.state);
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
    [p.index + 1, p.name, p.status, res.action, res.plan ? res.plan.steps.length : null, why, fenceCell(res.fences)]
      .forEach((v) => cell(tr, v));
    if (res.fences) tr.lastChild.dataset.fences = res.fences.orientable === false ? "refused" : String(res.fences.fences.length);
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
