// The workbench: pages, the API key, messages, and the wiring between pages.

import { api, hasKey, setKey } from "./api.js";
import { listRuns } from "./runs.js";
import { startJob } from "./jobs.js";
import { analyse, importFile, loadExamples, setTheta, showThumbnails, showWarnings } from "./part.js";
import { enableDrag, ensureAnalysis, makePlan, play, showPlan } from "./plan.js";
import { playBack, runValidation, showValidation } from "./validate.js";

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
      say(`${label} failed: ${e.message}`, true);
      if (e.status === 401) $("key-form").hidden = false;
    }
  };
}

const PAGES = ["part", "plan", "validation", "catalogue", "runs"];

function show(page) {
  if (!PAGES.includes(page)) page = "part";
  document.querySelectorAll(".page").forEach((s) => { s.hidden = s.id !== `page-${page}`; });
  document.querySelectorAll(".tab").forEach((t) => {
    if (t.dataset.page === page) t.setAttribute("aria-current", "page");
    else t.removeAttribute("aria-current");
  });
  if (location.hash !== `#${page}`) history.replaceState(null, "", `#${page}`);
  if (page === "runs") action("loading runs", () => listRuns(state, openRun))();
}

async function usePart(doc) {
  state.part = doc;
  state.plan = null;
  $("plan-out").hidden = true;
  $("validation-out").hidden = true;
  await analyse(state);
}

// A recorded run opened from the Runs page: its part, plan and playback in the other pages.
async function openRun(pb) {
  state.part = pb.part;
  await ensureAnalysis(state, Boolean(pb.options.exact));
  state.plan = pb.plan;
  state.playback = pb;
  showPlan(state);
  if (pb.validation) {
    showValidation(state);
    show("validation");
  } else show("plan");
}

function wire() {
  document.querySelectorAll(".tab").forEach((t) => t.addEventListener("click", () => show(t.dataset.page)));
  $("key-form").addEventListener("submit", action("saving the key", async () => {
    setKey($("apikey").value.trim());
    if (!state.examples) await loadExamples(state);
  }));
  $("example").addEventListener("change", action("analysing the example", async () => {
    $("thumbs").replaceChildren();
    $("warnings").replaceChildren();
    if ($("example").value) await usePart(state.examples[$("example").value]);
  }));
  $("file").addEventListener("change", action("importing the file", async () => {
    const file = $("file").files[0];
    if (!file) return;
    const sheet = await importFile(state, file);
    showWarnings(sheet);
    showThumbnails(sheet.parts, action("analysing the part", (doc) => usePart(doc)));
    await usePart(sheet.parts[0]);
    if (sheet.parts.length > 1) $("thumbs").querySelector(".thumb").setAttribute("aria-pressed", "true");
  }));
  $("exact").addEventListener("change", action("analysing", async () => { if (state.part) await analyse(state); }));
  $("theta").addEventListener("input", () => state.analysis && setTheta(state, Number($("theta").value)));
  $("plan-form").addEventListener("submit", action("planning", async () => {
    if (!state.part) throw new Error("choose a part first (Part & analysis)");
    await makePlan(state);
  }));
  enableDrag(state);
  $("anim-play").addEventListener("click", () => state.plan && play(state));
  $("validate-form").addEventListener("submit", action("validating in Drake", async () => {
    if (!state.part) throw new Error("choose a part first (Part & analysis)");
    await runValidation(state);
  }));
  $("playback-play").addEventListener("click", () => state.playback && playBack(state));
  $("job-form").addEventListener("submit", action("running the catalogue job", () => startJob(state)));
  $("runs-refresh").addEventListener("click", action("loading runs", () => listRuns(state, openRun)));
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
