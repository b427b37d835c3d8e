// Runs: GET /v1/runs, a run's summary, its figure, its MCAP, and opening its plan and
// validation playback in the other pages (GET /v1/runs/{id}/playback). Only the run
// clicked last is shown: a slower answer for an earlier click is dropped.

import { api, begin, download } from "./api.js";

// onSelect(runId): the row's run is wanted (app.js shows it through its action wrapper).
export async function listRuns(state, onSelect) {
  const current = begin("runs");
  const { runs } = await api("/v1/runs?limit=100");
  current();
  const rows = runs.map((r) => {
    const tr = document.createElement("tr");
    tr.tabIndex = 0;
    const cells = [r.run_id, r.command, r.part_name, r.action, r.steps, r.agreement === null ? null : `${(100 * r.agreement).toFixed(0)} %`, r.status];
    for (const v of cells) tr.append(Object.assign(document.createElement("td"), { textContent: v ?? "—" }));
    tr.addEventListener("click", () => onSelect(r.run_id));
    tr.addEventListener("keydown", (ev) => { if (ev.key === "Enter" || ev.key === " ") { ev.preventDefault(); onSelect(r.run_id); } });
    return tr;
  });
  document.querySelector("#runs-table tbody").replaceChildren(...rows);
}

export async function showRun(state, runId, onOpen) {
  const current = begin("run-detail");
  const host = document.getElementById("run-figure");
  const detail = document.getElementById("run-detail");
  detail.dataset.run = runId;
  host.replaceChildren();
  if (host.dataset.url) URL.revokeObjectURL(host.dataset.url);
  delete host.dataset.url;
  document.getElementById("run-title").textContent = `Run ${runId}: loading…`;
  document.getElementById("run-json").textContent = "";
  const run = await api(`/v1/runs/${runId}`);
  current(host);
  detail.hidden = false;
  document.getElementById("run-title").textContent = `Run ${runId}: ${run.command} ${run.part_name || ""} (${run.status})`;
  document.getElementById("run-json").textContent = JSON.stringify(run, null, 2);
  document.getElementById("run-download").onclick = () => download(`/v1/runs/${runId}/record`, `${runId}.mcap`);
  const open = document.getElementById("run-open");
  open.disabled = !run.steps;
  open.onclick = () => onOpen(runId);
  if (run.steps) {
    // the figure is behind the key: fetched, then shown from a blob URL
    const r = await api(`/v1/runs/${runId}/figure.svg`, { raw: true });
    const blob = await r.blob();
    current(host);
    const url = URL.createObjectURL(blob);
    host.dataset.url = url;
    host.append(Object.assign(document.createElement("img"), { alt: `plan figure of run ${runId}`, src: url }));
  }
}
