// Interaction for the SVG plots of svg.js: zoom (wheel, or the + / − buttons), pan (drag,
// or ← / →), a hover read-out of θ and the plotted value, Reset, and export to PNG (the
// plot as drawn, styles inlined) and CSV (every series' samples). A plot is redrawn on
// its new x range, so ticks, wrapped regions and labels stay exact at every zoom.

const STYLE_KEYS = ["fill", "fill-opacity", "stroke", "stroke-width", "stroke-dasharray", "opacity", "font-size",
  "font-family", "font-weight", "visibility"];

// The value of a series at x (linear between samples; null outside or across a gap).
export function valueAt(series, x) {
  const { xs, ys } = series;
  for (let i = 1; i < xs.length; i++) {
    if ((xs[i - 1] - x) * (xs[i] - x) <= 0 && xs[i] !== xs[i - 1]) {
      if (series.breakJumps && Math.abs(ys[i] - ys[i - 1]) > series.breakJumps) return x - xs[i - 1] < xs[i] - x ? ys[i - 1] : ys[i];
      return ys[i - 1] + ((x - xs[i - 1]) / (xs[i] - xs[i - 1])) * (ys[i] - ys[i - 1]);
    }
  }
  return null;
}

function save(blob, filename) {
  const url = URL.createObjectURL(blob);
  const a = Object.assign(document.createElement("a"), { href: url, download: filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

const slug = (s) => s.replace(/[^\w]+/g, "-").replace(/^-|-$/g, "").slice(0, 40) || "plot";

export function toCsv(spec) {
  const rows = ["series,x,y"];
  spec.series.forEach((s, k) => {
    const name = s.label || s.cls || `series ${k + 1}`;
    s.xs.forEach((x, i) => rows.push(`${JSON.stringify(name)},${x},${s.ys[i]}`));
  });
  return rows.join("\n") + "\n";
}

// The SVG as a standalone image: computed styles copied onto each element.
function standalone(svg) {
  const copy = svg.cloneNode(true);
  const src = [svg, ...svg.querySelectorAll("*")], dst = [copy, ...copy.querySelectorAll("*")];
  src.forEach((node, i) => {
    const cs = getComputedStyle(node);
    dst[i].setAttribute("style", STYLE_KEYS.map((k) => `${k}:${cs.getPropertyValue(k)}`).join(";"));
  });
  copy.setAttribute("xmlns", "http://www.w3.org/2000/svg");
  return new XMLSerializer().serializeToString(copy);
}

async function toPng(svg, scale = 2) {
  const [, , w, h] = svg.getAttribute("viewBox").split(" ").map(Number);
  const img = new Image();
  const url = URL.createObjectURL(new Blob([standalone(svg)], { type: "image/svg+xml" }));
  await new Promise((ok, fail) => { img.onload = ok; img.onerror = fail; img.src = url; });
  const canvas = Object.assign(document.createElement("canvas"), { width: w * scale, height: h * scale });
  const g = canvas.getContext("2d");
  g.fillStyle = "#fff";
  g.fillRect(0, 0, canvas.width, canvas.height);
  g.drawImage(img, 0, 0, canvas.width, canvas.height);
  URL.revokeObjectURL(url);
  return new Promise((ok) => canvas.toBlob(ok, "image/png"));
}

// Wire one plot into host. draw(domain) draws it on [x0, x1] and returns {svg,
// toData(clientX), readout(x), fit()}; full: the whole domain. Returns the drawn plot.
export function interact(host, spec, full, draw) {
  const view = { domain: [...full] };
  const minWidth = (full[1] - full[0]) / 200;
  const set = (a, b) => {
    const w = Math.min(full[1] - full[0], Math.max(minWidth, b - a));
    let lo = a;
    lo = Math.min(Math.max(lo, full[0]), full[1] - w);
    view.domain = [lo, lo + w];
    render();
  };
  const zoom = (factor, at) => {
    const [a, b] = view.domain;
    const c = at ?? (a + b) / 2;
    set(c - (c - a) * factor, c + (b - c) * factor);
  };
  const pan = (dx) => set(view.domain[0] + dx, view.domain[1] + dx);
  const button = (label, title, fn) => {
    const b = Object.assign(document.createElement("button"), { type: "button", textContent: label, title, className: "plot-btn" });
    b.setAttribute("aria-label", `${title}: ${spec.title}`);
    b.addEventListener("click", fn);
    return b;
  };
  let current = null;
  const bar = document.createElement("div");
  bar.className = "plot-tools";
  const out = Object.assign(document.createElement("output"), { className: "plot-readout" });
  bar.append(button("+", "zoom in", () => zoom(0.5)), button("−", "zoom out", () => zoom(2)),
    button("←", "pan left", () => pan(-(view.domain[1] - view.domain[0]) / 4)),
    button("→", "pan right", () => pan((view.domain[1] - view.domain[0]) / 4)),
    button("Reset", "reset zoom", () => set(...full)),
    button("PNG", "export PNG", async () => save(await toPng(current.svg), `${slug(spec.title)}.png`)),
    button("CSV", "export CSV", () => save(new Blob([toCsv(spec)], { type: "text/csv" }), `${slug(spec.title)}.csv`)), out);
  let drag = null;
  const render = () => {
    current = draw(view.domain);
    const svg = current.svg;
    svg.dataset.domain = JSON.stringify(view.domain);
    svg.addEventListener("wheel", (ev) => {
      ev.preventDefault();
      zoom(ev.deltaY < 0 ? 0.8 : 1.25, current.toData(ev.clientX));
    }, { passive: false });
    svg.addEventListener("pointerdown", (ev) => {
      drag = { x: current.toData(ev.clientX), domain: [...view.domain] };
      svg.setPointerCapture(ev.pointerId);
    });
    svg.addEventListener("pointermove", (ev) => {
      const x = current.toData(ev.clientX);
      if (drag) {
        const dx = drag.x - x;
        if (Math.abs(dx) > 0) { set(view.domain[0] + dx, view.domain[1] + dx); return; }
      }
      const r = current.readout(x);
      if (!r) return;
      out.textContent = r.text;
      out.dataset.x = String(r.x);
      out.dataset.y = r.y === null ? "" : String(r.y);
    });
    svg.addEventListener("pointerup", () => { drag = null; });
    host.replaceChildren(svg, bar);
    current.fit();
  };
  render();
  return current;
}
