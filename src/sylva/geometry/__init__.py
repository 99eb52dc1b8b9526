"""Geometry: meshes and scenes, turtle records, mesh builders and exporters.

* :mod:`sylva.geometry.mesh` — :class:`Mesh`, :class:`Material`, :class:`Scene` (plain data);
* :mod:`sylva.geometry.records` — :class:`Geometry`, what a turtle draws;
* :mod:`sylva.geometry.build` — :func:`~sylva.geometry.build.build_mesh` and friends
  (continuous tubes, prisms, cones, leaves, polygons, voxel blocks);
* :mod:`sylva.geometry.exchange` — :func:`~sylva.geometry.exchange.write` and one module per
  file format;
* :mod:`sylva.geometry.buffers` — the pool that lends the memory of dropped turtle records
  and meshes to the next build.

Only the plain-data classes are imported here, so importing this package stays cheap; the
builders (numba kernels) load when :mod:`sylva.geometry.build` is imported.

Examples
--------
>>> from sylva.geometry import Geometry, Mesh
>>> Geometry.empty().n_segments
0
"""

from .mesh import Material, Mesh, Scene
from .records import Geometry

__all__ = ["Geometry", "Material", "Mesh", "Scene"]
