// A polygon part editor on the Part page: click to add a vertex, drag a vertex to move it,
// type its coordinates; "Use this part" analyses it, "Save" downloads the part document
// (conventions §5: `polygon` in mm, centre of mass the area centroid). Lines only: arcs,
// holes and a given centre of mass are for part documents and drawings.

import { el, path } from "./svg.js";

const SIZE = 60; // mm: the drawing area is SIZE × SIZE, a 5 mm grid, points snap to 0.5 mm
const SNAP = 0.5;
const $ = (id) => document.getElementById(id);

export function polygonArea(points) {
  let a = 0;
  points.forEach(([x, y], i) => {
    const [u, v] = points[(i + 1) % points.length];
    a += x * v - u * y;
  });
  return a / 2;
}

// The part document of the drawn points (counter-clockwise, as the importer writes them).
export function editorDocument(points) {
  const pts = polygonArea(points) < 0 ? [...points].reverse() : points;
  return { name: $("editor-name").value.trim() || "drawn part", units: "mm", polygon: pts.map((p) => [...p]),
    source: { format: "workbench editor" } };
}

export function setupEditor(onUse, onSave) {
  const points = [];
  const svg = $("editor-canvas");
  const snap = (v) => Math.min(SIZE, Math.max(0, Math.round(v / SNAP) * SNAP));
  const world = (ev) => {
    const p = new DOMPoint(ev.clientX, ev.clientY).matrixTransform(svg.getScreenCTM().inverse());
    return [snap(p.x), snap(-p.y)];
  };
  let dragging = -1;
  const draw = () => {
    const grid = [];
    for (let v = 0; v <= SIZE; v += 5) {
      grid.push(path([[v, 0], [v, -SIZE]], { class: "editor-grid" }), path([[0, -v], [SIZE, -v]], { class: "editor-grid" }));
    }
    const flip = points.map(([x, y]) => [x, -y]);
    const shape = points.length > 2 ? [path(flip, { class: "part" }, true)] : [path(flip, { class: "editor-open" })];
    const handles = flip.map(([x, y], i) => el("circle", { cx: x, cy: y, r: 1.1, class: "editor-vertex", "data-index": i }));
    svg.replaceChildren(...grid, ...shape, ...handles);
    $("editor-vertices").replaceChildren(...points.map((p, i) => vertexRow(p, i)));
    const area = points.length > 2 ? Math.abs(polygonArea(points)) : 0;
    $("editor-facts").textContent = `${points.length} vertices; area ${area.toFixed(2)} mm²`;
    $("editor-use").disabled = points.length < 3;
    $("editor-save").disabled = points.length < 3;
  };
  const vertexRow = (p, i) => {
    const li = document.createElement("li");
    ["x", "y"].forEach((axis, k) => {
      const input = Object.assign(document.createElement("input"), { type: "number", step: "0.1", value: p[k], size: 6 });
      input.setAttribute("aria-label", `vertex ${i + 1} ${axis} (mm)`);
      input.addEventListener("change", () => { points[i][k] = Number(input.value); draw(); });
      li.append(`${axis} `, input, " ");
    });
    return li;
  };
  svg.addEventListener("pointerdown", (ev) => {
    const i = ev.target.dataset ? Number(ev.target.dataset.index ?? -1) : -1;
    if (i >= 0) {
      dragging = i;
      svg.setPointerCapture(ev.pointerId);
    } else {
      points.push(world(ev));
      draw();
    }
  });
  svg.addEventListener("pointermove", (ev) => {
    if (dragging < 0) return;
    points[dragging] = world(ev);
    draw();
  });
  svg.addEventListener("pointerup", () => { dragging = -1; });
  $("editor-undo").addEventListener("click", () => { points.pop(); draw(); });
  $("editor-clear").addEventListener("click", () => { points.length = 0; draw(); });
  $("editor-use").addEventListener("click", () => onUse(editorDocument(points)));
  $("editor-save").addEventListener("click", () => onSave(editorDocument(points)));
  $("editor-open").addEventListener("click", () => { $("editor").hidden = !$("editor").hidden; draw(); });
  draw();
}
