"""Stanford PLY, binary little-endian.

Vertices: ``x y z nx ny nz s t`` (float) and ``red green blue alpha`` (uchar: the colour
the vertex is drawn with, its tint times its material colour); faces: ``vertex_indices`` (a
uchar-counted int list) and the material table is written as comments (``comment material
<i> <name>``): PLY has no standard per-face property for it that common readers accept.
PLY files go to scanners' tools, slicers and Blender, which take +Z as up: the default
``up="z"`` rotates sylva's Y-up frame (``(x, y, z) -> (x, -z, y)``); ``up="y"`` writes it
unchanged.

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> buf = io.BytesIO(); write_ply(m, buf)
>>> buf.getvalue().split(b"\\n")[1]
b'format binary_little_endian 1.0'
"""

from __future__ import annotations

import numpy as np

from ._common import PathOrFile, as_scene, open_target, oriented, safe_name, shaded_colors

__all__ = ["write_ply"]


def write_ply(scene, target: PathOrFile, *, up: str = "z") -> None:
    """Write the scene, merged into one mesh, as binary PLY (``up``: ``"z"`` or ``"y"``)."""
    mesh = oriented(as_scene(scene).merged(), up)
    n, m = mesh.n_vertices, mesh.n_triangles
    vdt = np.dtype([("p", "<f4", 3), ("n", "<f4", 3), ("uv", "<f4", 2), ("c", "u1", 4)])
    v = np.empty(n, vdt)
    v["p"] = mesh.vertices
    v["n"] = mesh.normals
    v["uv"] = mesh.uvs if mesh.uvs is not None else 0.0
    col = shaded_colors(mesh)
    v["c"] = np.clip(np.rint(col * 255.0), 0, 255).astype(np.uint8)
    fdt = np.dtype([("k", "u1"), ("i", "<i4", 3)])
    f = np.empty(m, fdt)
    f["k"] = 3
    f["i"] = mesh.indices.astype(np.int32)
    header = ["ply", "format binary_little_endian 1.0", "comment sylva"]
    header += [
        f"comment material {i} {safe_name(mat.name)}" for i, mat in enumerate(mesh.materials)
    ]
    header += [
        f"element vertex {n}",
        "property float x", "property float y", "property float z",
        "property float nx", "property float ny", "property float nz",
        "property float s", "property float t",
        "property uchar red", "property uchar green", "property uchar blue",
        "property uchar alpha",
        f"element face {m}",
        "property list uchar int vertex_indices",
        "end_header",
    ]  # fmt: skip
    with open_target(target, binary=True) as fh:
        fh.write(("\n".join(header) + "\n").encode("ascii"))
        fh.write(v.tobytes())
        fh.write(f.tobytes())
