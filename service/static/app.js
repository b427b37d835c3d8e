// The workbench: pages, the API key, messages, and the wiring between pages.

import { api, hasKey, setKey } from "./api.js";
import { listRuns, showRun } from "./runs.js";
import { setupEditor } from "./editor.js";
import { setupFences } from "./fences.js";
import { cancelJob, lastJob, listJobs, setupJobForm, showJob, startJob } from "./jobs.js";
import { analyse, drawAnalysis, importFile, loadExamples, setTheta, showThumbnails, showWarnings } from "./part.js";
import { clearPlan, enableDrag, ensureAnalysis, makePlan, markPlanStale, play, showPlan } from "./plan.js";
import { clearValidation, markValidationStale, playBack, runValidation, showValidation } from "./validate.js";

const state = {};
const $ = (id) => document.getElementById(id);

function say(text, error = false) {
  const m = $("message");
  m.textContent = text;
  m.className = error ? "error" : "";
}

// Every user action: busy message, then its error shown (never thrown to the console).
function action(label, fn) {
  return async (ev) => {
    if (ev && ev.preventDefault) ev.preventDefault();
    say(`${label}…`);
    try {
      await fn(ev);
      say(`${label}: done`);
    } catch (e) {
      if (e.name === "Superseded") return; // a later action of the same panel owns the message
      say(`${label} failed: ${e.message}`, true);
      if (e.status === 401 || e.status === 403) $("key-form").hidden = false;
    }
  };
}

const PAGES = ["part", "plan", "validation", "fences", "catalogue", "runs"];

function show(page) {
  if (!PAGES.includes(page)) page = "part";
  document.querySelectorAll(".page").forEach((s) => { s.hidden = s.id !== `page-${page}`; });
  document.querySelectorAll(".tab").forEach((t) => {
    if (t.dataset.page === page) t.setAttribute("aria-current", "page");
    else t.removeAttribute("aria-current");
  });
  if (location.hash !== `#${page}`) history.replaceState(null, "", `#${page}`);
  if (page === "runs") action("loading runs", () => listRuns(state, selectRun))();
  if (page === "catalogue") {
    action("loading jobs", async () => {
      await listJobs(state);
      const last = lastJob();
      if (last && !state.job && $("jobs-table").querySelector(`tr[data-job="${last}"]`)) state.jobActions.onShow(last);
    })();
  }
}

state.jobActions = {
  onShow: (id) => action("showing the job", () => showJob(state, id))(),
  onCancel: (id) => action("cancelling the job", () => cancelJob(state, id))(),
};

// A new part: every panel computed from the previous one is cleared.
async function usePart(doc) {
  state.part = doc;
  clearPlan(state);
  clearValidation(state);
  await analyse(state);
}

const selectRun = (runId) => action(`opening run ${runId}`, () => showRun(state, runId, openRun))();

// A recorded run opened from the Runs page: its part, plan and playback in the other pages.
const openRun = (runId) => action(`opening run ${runId}`, async () => {
  const pb = await api(`/v1/runs/${runId}/playback?points=400`);
  state.part = pb.part;
  clearPlan(state);
  clearValidation(state);
  await ensureAnalysis(state, Boolean(pb.options.exact));
  // the Part page shows the run's part too, not the one chosen before
  $("example").value = "";
  $("file").value = "";
  $("thumbs").replaceChildren();
  $("warnings").replaceChildren();
  $("exact").checked = Boolean(pb.options.exact);
  drawAnalysis(state);
  state.plan = { ...pb.plan, run_id: pb.plan.run_id ?? pb.run_id };
  state.playback = pb;
  showPlan(state);
  if (pb.validation) {
    showValidation(state);
    show("validation");
  } else show("plan");
})();

// A document saved as a file through a blob URL.
function saveJson(doc, filename) {
  const url = URL.createObjectURL(new Blob([JSON.stringify(doc, null, 2)], { type: "application/json" }));
  const a = Object.assign(document.createElement("a"), { href: url, download: filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

function wire() {
  document.querySelectorAll(".tab").forEach((t) => t.addEventListener("click", () => show(t.dataset.page)));
  // A key is tried at once (the examples need it): a wrong one is said, and not kept.
  $("key-form").addEventListener("submit", action("checking the key", async () => {
    const key = $("apikey").value.trim();
    if (!key) throw new Error("enter a key first");
    setKey(key);
    try {
      await loadExamples(state);
    } catch (e) {
      if (e.status === 401 || e.status === 403) setKey(null);
      throw e;
    }
    $("key-form").dataset.accepted = "true";
  }));
  $("example").addEventListener("change", action("analysing the example", async () => {
    $("thumbs").replaceChildren();
    $("warnings").replaceChildren();
    $("file").value = "";
    if ($("example").value) await usePart(state.examples[$("example").value]);
  }));
  const importChosen = action("importing the file", async () => {
    const file = $("file").files[0];
    if (!file) return;
    $("example").value = "";
    const sheet = await importFile(state, file);
    showWarnings(sheet);
    showThumbnails(sheet.parts, action("analysing the part", (doc) => usePart(doc)));
    await usePart(sheet.parts[0]);
    if (sheet.parts.length > 1) $("thumbs").querySelector(".thumb").setAttribute("aria-pressed", "true");
  });
  $("file").addEventListener("change", importChosen);
  $("units").addEventListener("change", () => $("file").files[0] && importChosen());
  $("engrave-colours").addEventListener("change", () => $("file").files[0] && importChosen());
  setupEditor({
    use: async (doc) => {
      $("example").value = "";
      $("file").value = "";
      $("thumbs").replaceChildren();
      $("warnings").replaceChildren();
      await usePart(doc);
    },
    save: (doc) => saveJson(doc, `${doc.name.replace(/[^\w.-]+/g, "-")}.json`),
    run: action,
  });
  $("exact").addEventListener("change", action("analysing", async () => { if (state.part) await analyse(state); }));
  $("theta").addEventListener("input", () => state.analysis && setTheta(state, Number($("theta").value)));
  $("plan-form").addEventListener("submit", action("planning", async () => {
    if (!state.part) throw new Error("choose a part first (Part & analysis)");
    await makePlan(state);
  }));
  for (const ev of ["input", "change"]) {
    $("plan-form").addEventListener(ev, () => { markPlanStale(state); markValidationStale(state); });
    $("validate-form").addEventListener(ev, () => markValidationStale(state));
  }
  enableDrag(state);
  $("anim-play").addEventListener("click", () => state.plan && play(state));
  $("validate-form").addEventListener("submit", action("validating in Drake", async () => {
    if (!state.part) throw new Error("choose a part first (Part & analysis)");
    await runValidation(state);
  }));
  $("playback-play").addEventListener("click", () => state.playback && playBack(state));
  setupJobForm();
  $("job-form").addEventListener("submit", action("running the catalogue job", () => startJob(state)));
  $("jobs-refresh").addEventListener("click", action("loading jobs", () => listJobs(state)));
  $("job-cancel").addEventListener("click", () => state.job && state.jobActions.onCancel(state.job));
  $("runs-refresh").addEventListener("click", action("loading runs", () => listRuns(state, selectRun)));
  setupFences(state, action);
}

async function main() {
  wire();
  const health = await api("/healthz");
  $("key-form").hidden = !health.auth_required;
  show((location.hash || "#part").slice(1));
  if (!health.auth_required || hasKey()) await loadExamples(state);
  else say("this service needs an API key: enter it above");
  document.body.dataset.ready = "true";
}

main().catch((e) => say(`the workbench could not start: ${e.message}`, true));
