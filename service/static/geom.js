// Geometry of the workbench, computed in the page from the API's documents (conventions
// §2–§3): part outlines for thumbnails, rotations and supports. A plan's motion is not
// predicted here: motion.js reads it off the plan's own images. Degrees here, as in every
// document the API sends.

const RAD = Math.PI / 180;

export function mod(x, p) {
  return ((x % p) + p) % p;
}

// Points along one part-document segment (without its end point).
function segmentPoints(seg, n) {
  const out = [];
  const at = {
    line: (t) => [seg.start[0] + t * (seg.end[0] - seg.start[0]), seg.start[1] + t * (seg.end[1] - seg.start[1])],
    arc: (t) => {
      const a = (seg.start_deg + t * (seg.end_deg - seg.start_deg)) * RAD;
      return [seg.center[0] + seg.radius * Math.cos(a), seg.center[1] + seg.radius * Math.sin(a)];
    },
    ellipse_arc: (t) => {
      const a = (seg.start_deg + t * (seg.end_deg - seg.start_deg)) * RAD;
      const r = (seg.rotation_deg || 0) * RAD;
      const x = seg.rx * Math.cos(a), y = seg.ry * Math.sin(a);
      return [seg.center[0] + x * Math.cos(r) - y * Math.sin(r), seg.center[1] + x * Math.sin(r) + y * Math.cos(r)];
    },
    bezier: (t) => bezierPoint(seg.points, seg.weights, t),
  }[seg.type];
  if (!at) return out;
  const k = seg.type === "line" ? 1 : n;
  for (let i = 0; i < k; i++) out.push(at(i / k));
  return out;
}

// De Casteljau in homogeneous coordinates: exact for rational Beziers.
function bezierPoint(points, weights, t) {
  let q = points.map((p, i) => {
    const w = weights ? weights[i] : 1;
    return [p[0] * w, p[1] * w, w];
  });
  while (q.length > 1) {
    q = q.slice(1).map((b, i) => [0, 1, 2].map((j) => (1 - t) * q[i][j] + t * b[j]));
  }
  return [q[0][0] / q[0][2], q[0][1] / q[0][2]];
}

// A part document → {outline, holes} as closed polylines (for thumbnails).
export function documentPolylines(doc, n = 24) {
  const loop = (segs) => segs.flatMap((s) => segmentPoints(s, n));
  const outline = doc.polygon ? doc.polygon : loop(doc.boundary || []);
  const holes = (doc.holes || []).map((h) => (Array.isArray(h[0]) ? h : loop(h)));
  return { outline, holes };
}

export function bounds(points) {
  const xs = points.map((p) => p[0]), ys = points.map((p) => p[1]);
  return { x0: Math.min(...xs), x1: Math.max(...xs), y0: Math.min(...ys), y1: Math.max(...ys) };
}

export function rotate(points, deg, about = [0, 0], to = [0, 0]) {
  const c = Math.cos(deg * RAD), s = Math.sin(deg * RAD);
  return points.map(([x, y]) => {
    const dx = x - about[0], dy = y - about[1];
    return [to[0] + c * dx - s * dy, to[1] + s * dx + c * dy];
  });
}

// Least and greatest projection of points on the closing normal n = (−sin α, cos α).
export function support(points, alphaDeg) {
  const nx = -Math.sin(alphaDeg * RAD), ny = Math.cos(alphaDeg * RAD);
  let lo = Infinity, hi = -Infinity;
  for (const [x, y] of points) {
    const p = x * nx + y * ny;
    lo = Math.min(lo, p);
    hi = Math.max(hi, p);
  }
  return [lo, hi];
}
