"""A polygon extruded into a closed triangle mesh and written as a binary STL (float32
coordinates, as every STL exporter writes them). Test helper: shapely triangulates, trimesh
writes; nothing of algrasp is used."""

from __future__ import annotations

import numpy as np
import shapely
import trimesh


def extrude_stl(poly: shapely.Polygon, height: float) -> bytes:
    verts: list[tuple[float, float, float]] = []
    index: dict[tuple[float, float, float], int] = {}

    def vid(x: float, y: float, z: float) -> int:
        key = (round(x, 12), round(y, 12), z)
        if key not in index:
            index[key] = len(verts)
            verts.append((x, y, z))
        return index[key]

    faces = []
    for tri in shapely.constrained_delaunay_triangles(poly).geoms:
        a, b, c = (tuple(p) for p in np.asarray(tri.exterior.coords)[:3])
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0:
            b, c = c, b
        faces += [[vid(*a, height), vid(*b, height), vid(*c, height)], [vid(*a, 0.0), vid(*c, 0.0), vid(*b, 0.0)]]
    for ring in [poly.exterior, *poly.interiors]:
        pts = np.asarray(ring.coords)
        for p, q in zip(pts[:-1], pts[1:]):
            faces += [[vid(*p, 0.0), vid(*q, 0.0), vid(*q, height)], [vid(*p, 0.0), vid(*q, height), vid(*p, height)]]
    mesh = trimesh.Trimesh(np.array(verts), np.array(faces), process=True)
    mesh.fix_normals()
    return bytes(trimesh.exchange.stl.export_stl(mesh))
