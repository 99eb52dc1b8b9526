"""OpenSCAD source: a coloured ``polyhedron`` per mesh and material (seed 001's export).

Seed 001 names an OpenSCAD export without describing it.  We write one ``polyhedron`` per
(mesh, material) with the material colour, inside a ``union()``, so the plant can be
rendered, combined with other solids and exported to STL for printing.  OpenSCAD is Z-up
and wants faces clockwise seen from outside: points are rotated from sylva's Y-up
(``(x, y, z) -> (x, -z, y)``, a proper rotation) and faces are reversed.  ``scale``
multiplies all coordinates (OpenSCAD works in millimetres).

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> out = io.StringIO(); write_scad(m, out)
>>> "faces=[[2,1,0]]" in out.getvalue()
True
"""

from __future__ import annotations

import numpy as np

from ._common import PathOrFile, as_scene, material_groups, material_of, open_target

__all__ = ["write_scad"]


def _list(fmt: str, arr: np.ndarray) -> str:
    if arr.shape[0] == 0:
        return "[]"
    item = "[" + ",".join([fmt] * arr.shape[1]) + "]"
    return "[" + ",".join([item] * arr.shape[0]) % tuple(arr.reshape(-1).tolist()) + "]"


def write_scad(scene, target: PathOrFile, *, scale: float = 1.0, convexity: int = 10) -> None:
    """Write an OpenSCAD file to a path or a text file object."""
    scene = as_scene(scene)
    with open_target(target, binary=False) as fh:
        fh.write(f"// sylva: {scene.name}\n// Z up; {scene.n_triangles} triangles\nunion() {{\n")
        for mesh in scene.meshes:
            for mid, tris in material_groups(mesh):
                idx = mesh.indices[tris]
                used, inv = np.unique(idx, return_inverse=True)
                faces = inv.reshape(-1, 3)[:, ::-1]
                p = mesh.vertices[used].astype(np.float64) * scale
                pts = np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)
                mat = material_of(mesh, mid)
                r, g, b, a = (float(x) for x in mat.color)
                fh.write(f"  // {mesh.name} / {mat.name}\n")
                fh.write(f"  color([{r:.4g},{g:.4g},{b:.4g},{a:.4g}]) polyhedron(\n")
                fh.write("    points=" + _list("%.6g", pts) + ",\n")
                fh.write("    faces=" + _list("%d", faces) + f",\n    convexity={convexity});\n")
        fh.write("}\n")
