"""3-D meshes (trimesh: STL, OBJ, PLY, OFF, GLB) → polygonal part documents.

The part rests on the table in one of its stable poses (trimesh's quasi-static pose
probabilities); the outline the jaws see is the convex hull of the mesh projected on
the table, and the centre of mass is the solid's, projected. The result is marked
``approximate``: a mesh is already a tessellation of the real part.
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from algrasp.errors import PartDocumentError

MESH_TYPES = ("stl", "obj", "ply", "off", "glb")


def mesh_document(data: bytes, file_type: str, name: str, pose: int | None, units: str) -> dict[str, Any]:
    """The part document of stable pose ``pose`` (default: the most probable)."""
    import trimesh
    from scipy.spatial import ConvexHull

    try:
        mesh = trimesh.load(io.BytesIO(data), file_type=file_type, force="mesh")
    except Exception as exc:  # noqa: BLE001 - loaders raise many types
        raise PartDocumentError("mesh", f"not a readable {file_type.upper()} mesh: {exc}") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise PartDocumentError("mesh", "no triangles in the file")
    if not mesh.is_watertight:
        raise PartDocumentError("mesh", "the mesh is not watertight: its resting poses and centre of mass are undefined")
    transforms, probs = trimesh.poses.compute_stable_poses(mesh)
    order = np.argsort(-np.asarray(probs))
    k = 0 if pose is None else pose
    if not 0 <= k < len(order):
        raise PartDocumentError("pose", f"pose {k} does not exist: the mesh has {len(order)} stable poses (0 = most probable)")
    T = transforms[order[k]]
    pts = trimesh.transform_points(mesh.vertices, T)[:, :2]
    com = trimesh.transform_points(mesh.center_mass[None, :], T)[0, :2]
    hull = pts[ConvexHull(pts).vertices]
    return {"name": name, "units": units, "polygon": hull.tolist(), "center_of_mass": com.tolist(), "approximate": True,
            "source": {"format": file_type, "pose": k, "pose_probability": float(probs[order[k]]),
                       "pose_probabilities": [float(probs[i]) for i in order]}}
