"""Binary STL: one facet per triangle with its unit normal (no colours or materials).

STL is read by slicers and 3D-printing tools, for which +Z is up: the default ``up="z"``
rotates sylva's Y-up frame (``(x, y, z) -> (x, -z, y)``, a proper rotation, so facets keep
their winding); ``up="y"`` writes it unchanged.

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> buf = io.BytesIO(); write_stl(m, buf)
>>> len(buf.getvalue())   # 80 + 4 + 50 per triangle
134
"""

from __future__ import annotations

import numpy as np

from ._common import PathOrFile, as_scene, open_target, oriented

__all__ = ["write_stl"]

_FACET = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])


def write_stl(scene, target: PathOrFile, *, up: str = "z") -> None:
    """Write the scene, merged, as binary STL (``up``: ``"z"`` or ``"y"``)."""
    mesh = oriented(as_scene(scene).merged(), up)
    tri = mesh.vertices[mesh.indices].astype(np.float64)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ln = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.divide(n, ln, out=np.zeros_like(n), where=ln > 0)
    rec = np.zeros(mesh.n_triangles, _FACET)
    rec["n"] = n
    rec["v"] = tri
    header = b"sylva binary STL".ljust(80, b" ")
    with open_target(target, binary=True) as fh:
        fh.write(header)
        fh.write(np.uint32(mesh.n_triangles).tobytes())
        fh.write(rec.tobytes())
