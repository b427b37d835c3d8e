// Fences page (conventions §9): POST /v1/fences designs the part's conveyor fences; the
// page shows the API's own SVG drawing and the fence table, plays the part along the belt
// (fence_anim.js, from the document's images), validates on the belt in Drake (the same
// endpoint with `validate`) and downloads the DXF/SVG drawings. The part is the Part page's.

import { api, begin, clearFieldErrors, markFieldError } from "./api.js";
import { hasImages, playFences } from "./fence_anim.js";

const $ = (id) => document.getElementById(id);
const fmt = (x, d = 4) => Number(x.toPrecision(d)).toString();

// The body of POST /v1/fences the form describes (a bad value is the API's 422, said by field).
function request(state) {
  if (!state.part) throw new Error("choose a part first (Part & analysis)");
  const body = {
    part: state.part,
    exact: $("fence-model").value === "exact",
    fence_friction: [Number($("fence-mu-lo").value), Number($("fence-mu-hi").value)],
    min_margin_deg: Number($("fence-margin").value),
    exit_turns: $("fence-tip-turns").checked,
    same_rail: $("fence-same-rail").checked,
  };
  const w = $("belt-width").value.trim();
  if (w) body.belt_width = Number(w);
  const e = $("fence-exit-steepness").value.trim();
  if (e) body.exit_steepness_deg = Number(e);
  return body;
}

// The form's controls, by the name a 422's field ends with.
const FIELDS = {
  fence_friction: "fence-mu-lo", min_margin_deg: "fence-margin", belt_width: "belt-width",
  exit_steepness_deg: "fence-exit-steepness", exit_turns: "fence-tip-turns", same_rail: "fence-same-rail",
};

async function design(state) {
  const current = begin("fences");
  const body = request(state);
  clearFieldErrors($("fence-form"));
  let doc, svg;
  try {
    doc = await api("/v1/fences", { json: body });
    svg = await (await api("/v1/fences", { json: { ...body, drawing: "svg" }, raw: true })).text();
  } catch (err) {
    markFieldError(err, FIELDS);
    throw err;
  }
  current($("fence-out"));
  show(state, body, doc, svg);
  $("fence-validation").hidden = true;
}

function show(state, body, doc, svg) {
  state.fences = { body, doc, part: state.part };
  const u = doc.units, n = doc.fences.length;
  const finals = doc.final_orientations_deg.map((f) => `${fmt(f)}°`).join(", ");
  const s = $("fence-summary");
  s.textContent = `${n} fence${n > 1 ? "s" : ""} for ${state.part.name || "the part"} (${doc.model} model, fence friction `
    + `${doc.fence_friction[0]}–${doc.fence_friction[1]}: each fence at most ${fmt(doc.max_steepness_deg)}° to the belt); `
    + `belt width ${fmt(doc.belt_width)} ${u}, total fence length ${fmt(doc.total_length)} ${u}; `
    + (doc.exit ? `an exit guide at ${fmt(doc.exit.steepness_deg, 3)}° to the belt, ${fmt(doc.exit.length)} ${u} long; ` : "")
    + `the part leaves ${doc.exit ? "the guide" : "the layout"} at ${finals} ± ${fmt(doc.final_uncertainty_deg, 3)}° `
    + `(mod ${fmt(doc.symmetry_period_deg)}°)`
    + (doc.exit_turns === false ? "; in Berretty et al.'s model (no turn over the fences' tips)" : "");
  s.dataset.fences = String(n);
  const drawing = new DOMParser().parseFromString(svg, "image/svg+xml").documentElement;
  drawing.removeAttribute("width");
  drawing.removeAttribute("height");
  drawing.setAttribute("style", "width: 100%; height: auto; max-height: 320px; display: block");
  $("fence-drawing").replaceChildren(document.importNode(drawing, true));
  $("fence-table").tBodies[0].replaceChildren(...doc.fences.map((f, i) => row([i + 1, f.side, f.angle_deg.toFixed(2),
    f.steepness_deg.toFixed(2), `±${f.margin_deg.toFixed(2)}`, `${fmt(f.position)} ${u}`, `${fmt(f.length)} ${u}`])));
  $("fence-stale").textContent = "";
  $("fence-out").hidden = false;
  $("fence-final").textContent = hasImages(doc) ? "" : "this fence document carries no trace (follow_deg): design again to animate it";
  if (state.analysis) playFences(state, Number($("fence-start").value));
}

function row(cells) {
  const tr = document.createElement("tr");
  for (const c of cells) tr.append(Object.assign(document.createElement("td"), { textContent: String(c) }));
  return tr;
}

async function validate(state) {
  if (!state.fences) throw new Error("design the fences first");
  const current = begin("fence-validation");
  const samples = Math.max(1, Math.floor(Number($("fence-samples").value) || 1));
  const seed = Math.max(0, Math.floor(Number($("fence-seed").value) || 0));
  const body = { ...state.fences.body, validate: { samples, seed } };
  $("fence-progress").hidden = false;
  let out;
  try {
    out = await api("/v1/fences", { json: body });
  } finally {
    $("fence-progress").hidden = true;
  }
  current($("fence-validation"));
  showValidation(state, out);
}

// What was validated, the agreement, and a row per sample.
function showValidation(state, out) {
  const v = out.validation, n = v.samples.length, u = out.units;
  const agree = v.samples.filter((s) => s.agrees).length;
  const finals = v.final_orientations_deg.map((f) => `${fmt(f)}°`).join(", ");
  $("fence-validation-what").textContent = `Validated: the ${out.fences.length}-fence design above for `
    + `${state.fences.part.name || "the part"} (${out.model} model), simulated in Drake on a belt moving at `
    + `${fmt(v.belt_speed_m_s, 3)} m/s (support friction ${fmt(v.support_friction, 3)}, fence friction `
    + `${fmt(v.fence_friction, 3)}) from ${n} start${n > 1 ? "s" : ""} of seed ${v.seed}, each at a random orientation `
    + `and lateral position; a sample agrees when it leaves within ±${fmt(v.final_uncertainty_deg, 3)}° + `
    + `${v.tolerance_deg}° of ${finals} (mod ${fmt(v.symmetry_period_deg)}°).`;
  const s = $("fence-validation-summary");
  s.textContent = `agreement ${(100 * v.agreement).toFixed(0)}% (${agree}/${n}); on the last fence, before the part `
    + `comes off its end: ${(100 * v.agreement_on_last_fence).toFixed(0)}%; run ${out.run_id}`;
  s.dataset.agreement = String(v.agreement);
  s.dataset.samples = String(n);
  $("fence-validation-table").tBodies[0].replaceChildren(...v.samples.map((x, i) => {
    const tr = row([i + 1, `${x.initial_deg.toFixed(2)}°`, `${fmt(x.lateral)} ${u}`,
      x.on_last_fence_deg == null ? "—" : `${x.on_last_fence_deg.toFixed(2)}°`, `${x.simulated_deg.toFixed(2)}°`,
      `${x.error_deg.toFixed(2)}°`, x.agrees ? "yes" : "NO"]);
    if (!x.agrees) tr.className = "bad";
    return tr;
  }));
  $("fence-validation").hidden = false;
}

async function download(state, kind) {
  if (!state.fences) throw new Error("design the fences first");
  const r = await api("/v1/fences", { json: { ...state.fences.body, drawing: kind }, raw: true });
  const url = URL.createObjectURL(await r.blob());
  const name = `${(state.fences.part.name || "part").replace(/[^\w.-]+/g, "-")}-fences.${kind}`;
  const a = Object.assign(document.createElement("a"), { href: url, download: name });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

// A design made for another part, or under other options, is marked stale.
function markStale(state) {
  if (!state.fences) return;
  const other = state.fences.part !== state.part;
  let changed = false;
  try { changed = JSON.stringify({ ...request(state), part: null }) !== JSON.stringify({ ...state.fences.body, part: null }); } catch { changed = true; }
  $("fence-stale").textContent = other ? "the part changed since this design: design again"
    : changed ? "the options changed since this design: design again" : "";
}

export function setupFences(state, action) {
  $("fence-form").addEventListener("submit", action("designing fences", () => design(state)));
  $("fence-validate-form").addEventListener("submit", action("validating the fences on the belt in Drake", () => validate(state)));
  $("fence-dxf").addEventListener("click", action("downloading the DXF", () => download(state, "dxf")));
  $("fence-svg").addEventListener("click", action("downloading the SVG", () => download(state, "svg")));
  $("fence-start").addEventListener("input", () => { $("fence-start-out").textContent = `${$("fence-start").value}°`; });
  $("fence-play").addEventListener("click", () => state.fences && state.analysis && playFences(state, Number($("fence-start").value)));
  for (const ev of ["input", "change"]) $("fence-form").addEventListener(ev, () => markStale(state));
  document.querySelector("button[data-page=fences]").addEventListener("click", () => markStale(state));
}
