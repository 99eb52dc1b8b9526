"""What a turtle draws: segments, leaves, polygons and blocks, as NumPy arrays.

A :class:`Geometry` is the plain-data result of interpreting a word (see
:func:`sylva.turtle.interpret`).  It lives in :mod:`sylva.geometry` so that mesh builders and
exporters can read it without importing the turtle.  Every record keeps the index of the
module that drew it (``module``), so a tool can show which module (and rule) made a branch.

Examples
--------
>>> g = Geometry.empty()
>>> g.n_segments, g.n_leaves, g.n_polygons, g.n_blocks
(0, 0, 0, 0)
>>> g.bounds().tolist()
[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .mesh import Material, Mesh

__all__ = ["Geometry"]


def _f64(a, cols: int | None = 3) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a.reshape(-1, cols) if cols else a.ravel()


@dataclass
class Geometry:
    """Records drawn by a turtle.

    Segments (``n`` of them)
        ``seg_start``, ``seg_end`` : float64[n, 3]
            Where each segment starts and ends.
        ``seg_radius`` : float32[n, 2]
            Radius at the start and at the end (tapering).
        ``seg_color`` : float32[n, 3]
            Linear RGB colour.
        ``seg_material`` : int32[n]
            Index into :attr:`materials` (the colour index of ABOP, the output buffer of
            seed 004, 0 otherwise).
        ``seg_module`` : int64[n]
            Index of the module of the word that drew the segment.
        ``seg_parent`` : int64[n]
            The segment this one grows from (ends where this one starts), -1 for none.
        ``seg_depth`` : int32[n]
            Bracket depth of the drawing module (0 on the main axis).
        ``seg_ref`` : float32[n, 3]
            A unit vector normal to the segment, parallel-transported from the parent's,
            used as the reference direction (u = 0) of tube rings.
    Leaves (``k``)
        ``leaf_pos`` : float64[k, 3]; ``leaf_frame`` : float64[k, 3, 3] (rows H, L, U);
        ``leaf_size`` : float32[k]; ``leaf_color`` : float32[k, 3]; ``leaf_material`` :
        int32[k]; ``leaf_module`` : int64[k].
    Polygons (``p``, with ``v`` vertices in all)
        ``poly_vertices`` : float64[v, 3]; ``poly_offsets`` : int64[p + 1] (polygon ``i``
        is ``poly_vertices[poly_offsets[i]:poly_offsets[i+1]]``); ``poly_color`` :
        float32[p, 3]; ``poly_material`` : int32[p]; ``poly_module`` : int64[p].
    Blocks (``b``; seed 004's voxels, axis-aligned cubes)
        ``block_center`` : float64[b, 3]; ``block_size`` : float32[b]; ``block_buffer`` :
        int32[b]; ``block_module`` : int64[b].
    materials : list of Material
        The material table the ``*_material`` indices refer to.
    dialect : str
        The command table used (``"lsys"``, ``"abop"``, ``"classic"``, ``"engine"``).
    background : tuple of 3 float or None
        The background colour the program asks for (``bg``), if any.
    detail : int or None
        The number of sides the program asks for (``detail``), if any.
    vertex_colors : bool
        True when colours vary per record within a material (seed 001's RGB turtle colour):
        meshes then carry vertex colours and the materials are white.
    leaf_surface : int32[k] or None
        The template of each leaf: an index into :attr:`surfaces`, or -1 for sylva's default
        leaf (:func:`~sylva.geometry.build.leaf_template`); ``None``: -1 for all.
    leaf_stretch : float32[k, 3] or None
        Per leaf, the scale of its template's x, y, z relative to :attr:`leaf_size` (cpfg's
        ``~X(sx, sy, sz)``: ``(1, sy/sx, sz/sx)``); ``None``: uniform.
    surfaces : tuple
        The leaf templates of predefined surfaces (cpfg's ``~X``; see
        :mod:`sylva.geometry.surfaces`): ``(name, vertices, uvs, tris)`` each, in the frame of
        :func:`~sylva.geometry.build.leaf_template`.
    scenery : Mesh or None
        Objects drawn around the plant: a cpfg view file's ``background scene``
        (:mod:`sylva.geometry.scenery`); :func:`~sylva.geometry.build.build_mesh` adds it
        to the scene as the mesh ``background``.
    """

    seg_start: np.ndarray
    seg_end: np.ndarray
    seg_radius: np.ndarray
    seg_color: np.ndarray
    seg_material: np.ndarray
    seg_module: np.ndarray
    seg_parent: np.ndarray
    seg_depth: np.ndarray
    seg_ref: np.ndarray
    leaf_pos: np.ndarray
    leaf_frame: np.ndarray
    leaf_size: np.ndarray
    leaf_color: np.ndarray
    leaf_material: np.ndarray
    leaf_module: np.ndarray
    poly_vertices: np.ndarray
    poly_offsets: np.ndarray
    poly_color: np.ndarray
    poly_material: np.ndarray
    poly_module: np.ndarray
    block_center: np.ndarray
    block_size: np.ndarray
    block_buffer: np.ndarray
    block_module: np.ndarray
    materials: list[Material] = field(default_factory=lambda: [Material("bark")])
    dialect: str = "lsys"
    background: tuple[float, float, float] | None = None
    detail: int | None = None
    vertex_colors: bool = False
    leaf_surface: np.ndarray | None = None
    surfaces: tuple = ()
    leaf_stretch: np.ndarray | None = None
    scenery: Mesh | None = None

    def __post_init__(self) -> None:
        self.seg_start = _f64(self.seg_start)
        self.seg_end = _f64(self.seg_end)
        n = self.seg_start.shape[0]
        self.seg_radius = np.ascontiguousarray(self.seg_radius, np.float32).reshape(n, 2)
        self.seg_color = np.ascontiguousarray(self.seg_color, np.float32).reshape(n, 3)
        self.seg_material = np.ascontiguousarray(self.seg_material, np.int32).reshape(n)
        self.seg_module = np.ascontiguousarray(self.seg_module, np.int64).reshape(n)
        self.seg_parent = np.ascontiguousarray(self.seg_parent, np.int64).reshape(n)
        self.seg_depth = np.ascontiguousarray(self.seg_depth, np.int32).reshape(n)
        self.seg_ref = np.ascontiguousarray(self.seg_ref, np.float32).reshape(n, 3)
        self.leaf_pos = _f64(self.leaf_pos)
        k = self.leaf_pos.shape[0]
        self.leaf_frame = np.ascontiguousarray(self.leaf_frame, np.float64).reshape(k, 3, 3)
        self.leaf_size = np.ascontiguousarray(self.leaf_size, np.float32).reshape(k)
        self.leaf_color = np.ascontiguousarray(self.leaf_color, np.float32).reshape(k, 3)
        self.leaf_material = np.ascontiguousarray(self.leaf_material, np.int32).reshape(k)
        self.leaf_module = np.ascontiguousarray(self.leaf_module, np.int64).reshape(k)
        if self.leaf_surface is None:
            self.leaf_surface = np.full(k, -1, np.int32)
        self.leaf_surface = np.ascontiguousarray(self.leaf_surface, np.int32).reshape(k)
        self.surfaces = tuple(self.surfaces)
        if self.leaf_stretch is not None:
            self.leaf_stretch = np.ascontiguousarray(self.leaf_stretch,
                                                     np.float32).reshape(k, 3)  # fmt: skip
        self.poly_vertices = _f64(self.poly_vertices)
        self.poly_offsets = np.ascontiguousarray(self.poly_offsets, np.int64).ravel()
        p = self.poly_offsets.shape[0] - 1
        if p < 0:
            raise ValueError("poly_offsets needs at least one entry")
        self.poly_color = np.ascontiguousarray(self.poly_color, np.float32).reshape(p, 3)
        self.poly_material = np.ascontiguousarray(self.poly_material, np.int32).reshape(p)
        self.poly_module = np.ascontiguousarray(self.poly_module, np.int64).reshape(p)
        self.block_center = _f64(self.block_center)
        b = self.block_center.shape[0]
        self.block_size = np.ascontiguousarray(self.block_size, np.float32).reshape(b)
        self.block_buffer = np.ascontiguousarray(self.block_buffer, np.int32).reshape(b)
        self.block_module = np.ascontiguousarray(self.block_module, np.int64).reshape(b)
        if not self.materials:
            self.materials = [Material("bark")]

    # ------------------------------------------------------------------ construction
    @classmethod
    def empty(cls, **kw) -> Geometry:
        """A geometry with no records."""
        z3 = np.zeros((0, 3))
        zi = np.zeros(0, np.int64)
        zf = np.zeros(0, np.float32)
        return cls(
            z3, z3, np.zeros((0, 2)), z3, zi, zi, zi, zi, z3,
            z3, np.zeros((0, 3, 3)), zf, z3, zi, zi,
            z3, np.zeros(1, np.int64), z3, zi, zi,
            z3, zf, zi, zi, **kw,
        )  # fmt: skip

    # ------------------------------------------------------------------ views
    @property
    def n_segments(self) -> int:
        return int(self.seg_start.shape[0])

    @property
    def n_leaves(self) -> int:
        return int(self.leaf_pos.shape[0])

    @property
    def n_polygons(self) -> int:
        return int(self.poly_offsets.shape[0] - 1)

    @property
    def n_blocks(self) -> int:
        return int(self.block_center.shape[0])

    def polygon(self, i: int) -> np.ndarray:
        """``float64[k, 3]``: the vertices of polygon ``i`` in drawing order."""
        return self.poly_vertices[self.poly_offsets[i] : self.poly_offsets[i + 1]]

    def points(self) -> np.ndarray:
        """``float64[m, 3]``: every point the records touch (segment ends, leaf bases,
        polygon vertices, block centres)."""
        return np.concatenate(
            [self.seg_start, self.seg_end, self.leaf_pos, self.poly_vertices, self.block_center]
        )

    def bounds(self) -> np.ndarray:
        """``float64[2, 3]``: the box around :meth:`points` (zeros when empty).

        Radii, leaf blades and block extents are not included: this is the box of the
        turtle's path, the quantity published for Koch curves and plants.
        """
        p = self.points()
        if p.shape[0] == 0:
            return np.zeros((2, 3))
        return np.stack([p.min(axis=0), p.max(axis=0)])

    def is_planar(self, axis: int = 2, tol: float = 1e-9) -> bool:
        """True when every point has the same coordinate ``axis`` (a 2D system)."""
        p = self.points()
        return bool(p.shape[0] == 0 or np.ptp(p[:, axis]) <= tol)

    def __repr__(self) -> str:
        return (
            f"Geometry(dialect={self.dialect!r}, segments={self.n_segments}, "
            f"leaves={self.n_leaves}, polygons={self.n_polygons}, blocks={self.n_blocks})"
        )
