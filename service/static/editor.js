// A part editor on the Part page (conventions §5, mm). Loops of vertices: the outline and
// any holes ("Add hole" starts one; the active loop takes the clicks). Click to add a
// vertex, drag one to move it, or type x, y and the bulge of the edge leaving it (tan of
// a quarter of its arc's sweep: 0 a line, 1 a half circle, negative bulging the other
// way). A centre of mass may be given (else the area centroid). "Use this part" analyses
// it; an error the API names (boundary[3], holes[0][2], center_of_mass) is marked on the
// drawing. "Save" downloads the part document.

import { el, path } from "./svg.js";

const SIZE = 60; // mm: the drawing area is SIZE × SIZE, a 5 mm grid, points snap to 0.5 mm
const SNAP = 0.5;
const RAD = Math.PI / 180;
const $ = (id) => document.getElementById(id);

export function polygonArea(points) {
  let a = 0;
  points.forEach(([x, y], i) => {
    const [u, v] = points[(i + 1) % points.length];
    a += x * v - u * y;
  });
  return a / 2;
}

// The arc of an edge a → b with bulge β: centre, radius, start and end angles (deg),
// sweeping 4·atan β (positive: counter-clockwise).
export function bulgeArc(a, b, bulge) {
  const sweep = 4 * Math.atan(bulge);
  const dx = b[0] - a[0], dy = b[1] - a[1], c = Math.hypot(dx, dy);
  const r = c / (2 * Math.sin(Math.abs(sweep) / 2));
  const h = r * Math.cos(sweep / 2) * Math.sign(sweep); // centre's offset from the chord's middle, to the left
  const center = [(a[0] + b[0]) / 2 - (h * dy) / c, (a[1] + b[1]) / 2 + (h * dx) / c];
  const start = Math.atan2(a[1] - center[1], a[0] - center[0]) / RAD;
  return { center, radius: r, start_deg: start, end_deg: start + sweep / RAD };
}

// Points along a loop (its arcs as chords of at most 6°), for drawing and the area.
export function loopPoints(loop) {
  const out = [];
  loop.forEach((v, i) => {
    const w = loop[(i + 1) % loop.length];
    out.push([v.x, v.y]);
    if (!v.bulge) return;
    const arc = bulgeArc([v.x, v.y], [w.x, w.y], v.bulge);
    const n = Math.max(2, Math.ceil(Math.abs(arc.end_deg - arc.start_deg) / 6));
    for (let k = 1; k < n; k++) {
      const t = (arc.start_deg + ((arc.end_deg - arc.start_deg) * k) / n) * RAD;
      out.push([arc.center[0] + arc.radius * Math.cos(t), arc.center[1] + arc.radius * Math.sin(t)]);
    }
  });
  return out;
}

// The points of edge k alone (vertex k to the next, along its arc).
function edgePoints(loop, k) {
  const v = loop[k], w = loop[(k + 1) % loop.length];
  return loopPoints([v, { ...w, bulge: 0 }]); // v, its arc's chords, w (the way back is not drawn)
}

const round = (x) => Math.round(x * 1e9) / 1e9;

// One loop as the document writes it: [x, y] vertices when every edge is a line, else
// segments (line, arc), edge k from vertex k — so the API's index k names that edge.
function loopDocument(loop) {
  if (loop.every((v) => !v.bulge)) return loop.map((v) => [v.x, v.y]);
  return loop.map((v, i) => {
    const w = loop[(i + 1) % loop.length];
    if (!v.bulge) return { type: "line", start: [v.x, v.y], end: [w.x, w.y] };
    const a = bulgeArc([v.x, v.y], [w.x, w.y], v.bulge);
    return { type: "arc", center: a.center.map(round), radius: round(a.radius), start_deg: round(a.start_deg), end_deg: round(a.end_deg) };
  });
}

// The part document of the drawing: `polygon` when it is one loop of lines, else `boundary`.
export function editorDocument(model) {
  const [outer, ...holes] = model.loops;
  const doc = { name: $("editor-name").value.trim() || "drawn part", units: "mm" };
  const body = loopDocument(outer);
  if (Array.isArray(body[0])) doc.polygon = body;
  else doc.boundary = body;
  const drawn = holes.filter((h) => h.length);
  if (drawn.length) doc.holes = drawn.map(loopDocument);
  if (model.com) doc.center_of_mass = [...model.com];
  doc.source = { format: "workbench editor" };
  return doc;
}

// Where an API field points on the drawing: {loop, edge} (edge null: the whole loop), or
// {com: true}; null when it names nothing drawn.
export function fieldTarget(field) {
  if (!field) return null;
  if (field.startsWith("center_of_mass")) return { com: true };
  let m = /^(?:polygon|boundary)(?:\[(\d+)\])?/.exec(field);
  if (m) return { loop: 0, edge: m[1] === undefined ? null : Number(m[1]) };
  m = /^holes(?:\[(\d+)\](?:\[(\d+)\])?)?/.exec(field);
  if (m) return { loop: m[1] === undefined ? null : 1 + Number(m[1]), edge: m[2] === undefined ? null : Number(m[2]) };
  return null;
}

export function setupEditor({ use, save, run }) {
  const model = { loops: [[]], active: 0, com: null, error: null };
  const svg = $("editor-canvas");
  const snap = (v) => Math.min(SIZE, Math.max(0, Math.round(v / SNAP) * SNAP));
  const world = (ev) => {
    const p = new DOMPoint(ev.clientX, ev.clientY).matrixTransform(svg.getScreenCTM().inverse());
    return [snap(p.x), snap(-p.y)];
  };
  const flip = (pts) => pts.map(([x, y]) => [x, -y]);
  let dragging = null;
  const changed = () => { model.error = null; draw(); };

  const drawLoop = (loop, li) => {
    const out = [];
    const cls = li === 0 ? "part" : "hole editor-hole";
    if (loop.length > 2) out.push(path(flip(loopPoints(loop)), { class: cls, "data-loop": li }, true));
    else out.push(path(flip(loop.map((v) => [v.x, v.y])), { class: "editor-open", "data-loop": li }));
    const t = model.error && model.error.target;
    if (t && !t.com && (t.loop === li || (t.loop === null && li > 0))) {
      const k = t.edge;
      const pts = k !== null && loop[k] ? edgePoints(loop, k) : loopPoints(loop);
      const mark = path(flip(pts), { class: "editor-error" }, k === null);
      mark.dataset.errorField = model.error.field;
      out.push(mark);
    }
    loop.forEach((v, i) => out.push(el("circle", { cx: v.x, cy: -v.y, r: 1.1, class: "editor-vertex", "data-loop": li, "data-index": i })));
    return out;
  };

  const draw = () => {
    const grid = [];
    for (let v = 0; v <= SIZE; v += 5) {
      grid.push(path([[v, 0], [v, -SIZE]], { class: "editor-grid" }), path([[0, -v], [SIZE, -v]], { class: "editor-grid" }));
    }
    const com = [];
    if (model.com) {
      const c = el("circle", { cx: model.com[0], cy: -model.com[1], r: 1.3, class: "com editor-com" });
      if (model.error && model.error.target && model.error.target.com) c.dataset.errorField = model.error.field;
      com.push(c);
    }
    svg.replaceChildren(...grid, ...model.loops.flatMap(drawLoop), ...com);
    $("editor-vertices").replaceChildren(...model.loops.flatMap((loop, li) => loop.map((v, i) => vertexRow(v, li, i))));
    const [outer, ...holes] = model.loops;
    const area = outer.length > 2 ? Math.abs(polygonArea(loopPoints(outer))) - holes.filter((h) => h.length > 2)
      .reduce((s, h) => s + Math.abs(polygonArea(loopPoints(h))), 0) : 0;
    $("editor-facts").textContent = `${outer.length} vertices${holes.length ? `, ${holes.length} hole${holes.length > 1 ? "s" : ""}` : ""}; area ${area.toFixed(2)} mm²` +
      (model.active ? ` — drawing hole ${model.active}` : "");
    $("editor-error").textContent = model.error ? `${model.error.field}: ${model.error.message}` : "";
    $("editor-use").disabled = outer.length < 3;
    $("editor-save").disabled = outer.length < 3;
  };

  const number = (value, label, onChange, step = "0.1") => {
    const input = Object.assign(document.createElement("input"), { type: "number", step, value, size: 6 });
    input.setAttribute("aria-label", label);
    input.addEventListener("change", () => { onChange(Number(input.value)); changed(); });
    return input;
  };
  const vertexRow = (v, li, i) => {
    const li_ = document.createElement("li");
    const where = li === 0 ? `vertex ${i + 1}` : `hole ${li} vertex ${i + 1}`;
    li_.dataset.loop = li;
    li_.append(li === 0 ? "" : `hole ${li}: `, "x ", number(v.x, `${where} x (mm)`, (x) => { v.x = x; }), " y ",
      number(v.y, `${where} y (mm)`, (y) => { v.y = y; }), " bulge ",
      number(v.bulge, `${where} bulge of the edge to the next vertex`, (b) => { v.bulge = b; }, "0.05"));
    return li_;
  };

  svg.addEventListener("pointerdown", (ev) => {
    const d = ev.target.dataset || {};
    if (d.index !== undefined) {
      dragging = { loop: Number(d.loop), index: Number(d.index) };
      svg.setPointerCapture(ev.pointerId);
    } else if ($("editor-com-mode").checked) {
      model.com = world(ev);
      $("editor-com-mode").checked = false;
      changed();
    } else {
      const [x, y] = world(ev);
      model.loops[model.active].push({ x, y, bulge: 0 });
      changed();
    }
  });
  svg.addEventListener("pointermove", (ev) => {
    if (!dragging) return;
    const [x, y] = world(ev);
    Object.assign(model.loops[dragging.loop][dragging.index], { x, y });
    changed();
  });
  svg.addEventListener("pointerup", () => { dragging = null; });
  $("editor-undo").addEventListener("click", () => {
    const loop = model.loops[model.active];
    if (loop.length) loop.pop();
    else if (model.active > 0) { model.loops.pop(); model.active = model.loops.length - 1; }
    changed();
  });
  $("editor-clear").addEventListener("click", () => { Object.assign(model, { loops: [[]], active: 0, com: null }); changed(); });
  $("editor-hole").addEventListener("click", () => {
    if (model.loops[model.active].length < 3) return; // finish this loop first
    model.loops.push([]);
    model.active = model.loops.length - 1;
    changed();
  });
  $("editor-com-clear").addEventListener("click", () => { model.com = null; changed(); });
  $("editor-use").addEventListener("click", run("analysing the drawn part", async () => {
    try {
      await use(editorDocument(model));
    } catch (e) {
      if (e.field) model.error = { field: e.field, message: e.message, target: fieldTarget(e.field) };
      draw();
      throw e;
    }
  }));
  $("editor-save").addEventListener("click", () => save(editorDocument(model)));
  $("editor-open").addEventListener("click", () => { $("editor").hidden = !$("editor").hidden; draw(); });
  draw();
}
