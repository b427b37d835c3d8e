// Part & analysis page: pick or upload a part, analyse it (POST /v1/analyses?samples=720),
// and show the outline, d(θ), r(θ) and the transfer functions; hovering θ anywhere shows
// the part at that orientation between the jaws.

import { api, begin } from "./api.js";
import { bounds, documentPolylines, mod } from "./geom.js";
import { drawScene, turningView } from "./scene.js";
import { linePlot } from "./plots.js";
import { el, path } from "./svg.js";

const SAMPLES = 720;
let cursors = [];

export async function loadExamples(state) {
  const { examples } = await api("/v1/examples");
  const select = document.getElementById("example");
  select.replaceChildren(new Option("— choose —", ""), ...examples.map((ex) => new Option(ex.name, ex.name)));
  state.examples = Object.fromEntries(examples.map((e) => [e.name, e.part]));
  showGallery(examples);
}

const MAX_THUMBNAILS = 24;

function importForm(file, fields) {
  const form = new FormData();
  form.append("file", file);
  for (const [k, v] of Object.entries(fields)) form.append(k, v);
  return form;
}

// A file: a part document (JSON) is used as it is; a drawing goes once through
// /v1/imports: the sheet's listing with the documents of its first MAX_THUMBNAILS parts.
// The page's "drawing units" choice (empty: the drawing's header) and "engrave colours"
// (empty: judged from the drawing) go with it.
export async function importFile(state, file) {
  const current = begin("import");
  if (file.name.toLowerCase().endsWith(".json")) {
    return { parts: [JSON.parse(await file.text())], warnings: [], ignored: [] };
  }
  const units = document.getElementById("units").value;
  const engrave = document.getElementById("engrave-colours").value.trim();
  const fields = { list: "true", documents: String(MAX_THUMBNAILS), ...(units ? { units } : {}),
                   ...(engrave ? { engrave_colours: engrave } : {}) };
  const sheet = await api("/v1/imports", { form: importForm(file, fields) });
  current(document.getElementById("thumbs"));
  const warnings = [...sheet.warnings];
  if (sheet.parts.length > MAX_THUMBNAILS) warnings.push(`${sheet.parts.length} parts: only the first ${MAX_THUMBNAILS} are shown`);
  return { parts: sheet.documents, warnings, ignored: sheet.ignored };
}

// The importer speaks to the command line ("use --units in"); the page's control is "drawing units".
function forThePage(w) {
  return w.replace(/use --units (\w+)/g, "choose $1 under “drawing units” above")
    .replace(/use --units/g, "choose the unit under “drawing units” above");
}

// Each warning once: the sheet's, then any a part has of its own.
export function showWarnings(sheet) {
  const ul = document.getElementById("warnings");
  const items = [...(sheet.warnings || []), ...(sheet.ignored || []).map((s) => `ignored: ${s}`)];
  const seen = new Set([...(sheet.warnings || []), ...(sheet.ignored || [])]);
  for (const p of sheet.parts) {
    for (const w of (p.source && p.source.warnings) || []) {
      if (!seen.has(w)) items.push(`${p.name}: ${w}`);
      seen.add(w);
    }
  }
  ul.replaceChildren(...items.map((w) => Object.assign(document.createElement("li"), { textContent: forThePage(w) })));
}

// Several parts on a sheet: thumbnails to choose from (drawn from the documents themselves).
// A button showing a part document's outline and its name (the #K index never cut short).
function thumbnail(doc, full, onPick, host) {
  const { outline, holes } = documentPolylines(doc);
  const b = bounds(outline);
  const w = Math.max(b.x1 - b.x0, b.y1 - b.y0) * 1.1 || 1;
  const svg = el("svg", { viewBox: `${b.x0 - w * 0.05} ${-b.y1 - w * 0.05} ${w} ${w}`, "aria-hidden": "true" });
  const flip = (pts) => pts.map(([x, y]) => [x, -y]);
  svg.append(path(flip(outline), { class: "part" }, true), ...holes.map((h) => path(flip(h), { class: "hole" }, true)));
  const button = document.createElement("button");
  button.type = "button";
  button.className = "thumb";
  button.setAttribute("aria-pressed", "false");
  const m = /^(.*?)(#\d+)$/.exec(full);
  const label = Object.assign(document.createElement("span"), { className: "thumb-label", title: full });
  label.append(Object.assign(document.createElement("span"), { className: "thumb-name", textContent: m ? m[1] : full }));
  if (m) label.append(Object.assign(document.createElement("span"), { className: "thumb-index", textContent: m[2] }));
  button.title = full;
  button.append(svg, label);
  button.addEventListener("click", () => {
    host.querySelectorAll(".thumb").forEach((t) => t.setAttribute("aria-pressed", "false"));
    button.setAttribute("aria-pressed", "true");
    onPick(doc);
  });
  return button;
}

export function showThumbnails(parts, onPick) {
  const host = document.getElementById("thumbs");
  host.replaceChildren();
  if (parts.length < 2) return;
  parts.forEach((doc, i) => host.append(thumbnail(doc, doc.name || `part ${i + 1}`, onPick, host)));
}

// The gallery: every bundled example (the paper's parts and real drawings'); a click
// chooses it as the example list would.
function showGallery(examples) {
  const host = document.getElementById("gallery");
  const select = document.getElementById("example");
  host.replaceChildren(...examples.map((ex) => {
    const button = thumbnail(ex.part, ex.name, () => {
      select.value = ex.name;
      select.dispatchEvent(new Event("change"));
    }, host);
    button.dataset.example = ex.name;
    const licence = ex.part.source && ex.part.source.licence;
    button.title = `${ex.name}: ${ex.kind === "real" ? `a real drawing's part (${licence || "see its source"})` : "a part of the paper"}`;
    button.append(Object.assign(document.createElement("span"), { className: "thumb-kind", textContent: ex.kind === "real" ? "real drawing" : "paper" }));
    return button;
  }));
}

// The analysis of the current part; while it is computed the old plots are marked stale,
// and an answer for a part (or model) chosen before the current one is dropped.
export async function analyse(state) {
  const current = begin("analysis");
  const exact = document.getElementById("exact").checked;
  const host = document.getElementById("analysis");
  host.dataset.stale = "true";
  const part = state.part;
  const analysis = await api(`/v1/analyses?samples=${SAMPLES}&exact=${exact}`, { json: part });
  current(host);
  delete host.dataset.stale;
  Object.assign(state, { analysis, analysisOf: part, analysisExact: exact });
  drawAnalysis(state);
}

function dead(state, name) {
  const r = state.analysis.robust;
  const zones = (r && r[name] && r[name].dead_zones_deg) || [];
  return zones.map(([a, b]) => ({ x0: a, x1: b, cls: "band-dead" }));
}

function ramps(tf) {
  return tf.ramps.map((r) => ({ x0: r.start_deg, x1: r.end_deg, cls: "band-ramp" }));
}

function extrema(f) {
  return f.extrema.map((e) => ({ x: e.theta_deg, y: e.value, cls: e.kind === "max" ? "mk-max" : "mk-min",
    label: `${e.kind} ${e.value.toPrecision(5)} at ${e.theta_deg.toFixed(2)}° (${e.equilibrium})` }));
}

// The set images of the robust model: θ in [start, end) ends in [lower, upper] (null: θ
// itself), over one symmetry period T. Values come wrapped into [0, P); each is lifted next
// to its interval; the plot draws every copy shifted by k·T (a piece past P wraps to 0).
function imagePolys(state, name, P) {
  const r = state.analysis.robust;
  const images = (r && r[name] && r[name].images) || [];
  const T = (r && r[name] && r[name].symmetry_period_deg) || P;
  return images.map((im) => {
    const [a, b] = [im.start_deg, im.end_deg < im.start_deg ? im.end_deg + T : im.end_deg];
    const mid = (a + b) / 2;
    const lift = (v) => v + P * Math.round((mid - v) / P);
    const lo = (x) => (im.lower_deg === null ? x : lift(im.lower_deg));
    const hi = (x) => (im.upper_deg === null ? x : lift(im.upper_deg));
    return { points: [[a, lo(a)], [b, lo(b)], [b, hi(b)], [a, hi(a)]], cls: "band-image", period: T };
  });
}

function functionPlot(state, hostId, name, key, period, label) {
  const a = state.analysis, c = a.curves, units = a.part.units;
  const n = Math.round((c.theta_deg.length * period) / 360);
  return linePlot(document.getElementById(hostId), {
    title: `${label}: ● red max, ● green min; grey dead zones, orange constant`,
    xLabel: "θ, part orientation relative to the gripper (deg)", yLabel: `${key === "diameter" ? "d" : "r"}(θ) (${units})`,
    xDomain: [0, period], period, series: [{ xs: c.theta_deg.slice(0, n + 1), ys: c[key].slice(0, n + 1) }],
    bands: [...dead(state, name), ...a[key].constant_intervals_deg.map(([x0, x1]) => ({ x0, x1, cls: "band-ramp" }))],
    markers: extrema(a[key]), onHover: (t) => setTheta(state, t),
  });
}

function transferPlot(state, name, label) {
  const a = state.analysis, c = a.curves, tf = a[name];
  const P = tf.period_deg;
  const n = Math.round((c.theta_deg.length * P) / 360);
  const xs = c.theta_deg.slice(0, n), ys = c[`${name}_deg`].slice(0, n);
  return linePlot(document.getElementById(`plot-${name}`), {
    title: `${label}: steps, ramps (orange), robust set images (blue)`,
    xLabel: "θ before (deg)", yLabel: "θ after (deg, lifted)", xDomain: [0, P],
    series: [{ xs: [0, P], ys: [0, P], cls: "identity" }, { xs, ys, cls: "alt", breakJumps: 1 }],
    period: P, bands: ramps(tf), polys: imagePolys(state, name, P),
    markers: tf.steps.map((s) => ({ x: mod(s.fixed_point_deg, P), y: mod(s.fixed_point_deg, P), cls: "mk-fixed",
      label: `fixed point ${s.fixed_point_deg.toFixed(2)}° of step [${s.start_deg.toFixed(2)}, ${s.end_deg.toFixed(2)})` })),
    onHover: (t) => setTheta(state, t),
  });
}

export function drawAnalysis(state) {
  const a = state.analysis;
  document.getElementById("analysis").hidden = false;
  cursors = [
    functionPlot(state, "plot-d", "squeeze", "diameter", 180, "diameter d(θ)"),
    functionPlot(state, "plot-r", "push", "radius", 360, "radius r(θ)"),
    transferPlot(state, "squeeze", "squeeze Γ"),
    transferPlot(state, "push", "push p"),
    transferPlot(state, "push_grasp", "push-grasp Γ∘p"),
  ];
  const p = a.part;
  document.getElementById("part-facts").textContent =
    `${p.name || "part"}: area ${p.area.toPrecision(5)} ${p.units}², hull perimeter ${p.hull_perimeter.toPrecision(5)} ${p.units}; ` +
    `squeeze ${a.squeeze.orientable ? "orientable" : "not orientable"}, push-grasp ${a.push_grasp.orientable ? "orientable" : "not orientable"}`;
  setTheta(state, Number(document.getElementById("theta").value));
}

// θ relative to the gripper; the view shows the gripper at α = 0, so φ = θ.
export function setTheta(state, theta) {
  const t = mod(theta, 360);
  const input = document.getElementById("theta");
  input.value = t;
  document.getElementById("theta-out").textContent = `${t.toFixed(1)}°`;
  drawScene(document.getElementById("part-view"), state.analysis.geometry, { phi: t }, { alpha: 0 },
    { view: turningView(state.analysis.geometry), caption: `θ = ${t.toFixed(1)}°: jaws touching`, label: `the part at θ = ${t.toFixed(1)} degrees between the jaws` });
  cursors.forEach((c, i) => c.setCursor(i === 0 || i === 2 ? mod(t, 180) : t));
}
