// Runs: GET /v1/runs, a run's summary, its figure, its MCAP, and opening its plan and
// validation playback in the other pages (GET /v1/runs/{id}/playback).

import { api, download } from "./api.js";

export async function listRuns(state, onOpen) {
  const { runs } = await api("/v1/runs?limit=100");
  const rows = runs.map((r) => {
    const tr = document.createElement("tr");
    tr.tabIndex = 0;
    const cells = [r.run_id, r.command, r.part_name, r.action, r.steps, r.agreement === null ? null : `${(100 * r.agreement).toFixed(0)} %`, r.status];
    for (const v of cells) tr.append(Object.assign(document.createElement("td"), { textContent: v ?? "—" }));
    const open = () => showRun(state, r.run_id, onOpen);
    tr.addEventListener("click", open);
    tr.addEventListener("keydown", (ev) => { if (ev.key === "Enter" || ev.key === " ") { ev.preventDefault(); open(); } });
    return tr;
  });
  document.querySelector("#runs-table tbody").replaceChildren(...rows);
}

async function showRun(state, runId, onOpen) {
  const run = await api(`/v1/runs/${runId}`);
  document.getElementById("run-detail").hidden = false;
  document.getElementById("run-title").textContent = `Run ${runId}: ${run.command} ${run.part_name || ""} (${run.status})`;
  document.getElementById("run-json").textContent = JSON.stringify(run, null, 2);
  document.getElementById("run-download").onclick = () => download(`/v1/runs/${runId}/record`, `${runId}.mcap`);
  const open = document.getElementById("run-open");
  open.disabled = !run.steps;
  open.onclick = async () => onOpen(await api(`/v1/runs/${runId}/playback?points=400`));
  const host = document.getElementById("run-figure");
  host.replaceChildren();
  if (run.steps) {
    // the figure is behind the key: fetched, then shown from a blob URL
    const r = await api(`/v1/runs/${runId}/figure.svg`, { raw: true });
    const img = Object.assign(document.createElement("img"), { alt: `plan figure of run ${runId}`, src: URL.createObjectURL(await r.blob()) });
    host.append(img);
  }
}
