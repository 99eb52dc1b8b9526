"""The Stem object (seed 002 §5.6): points with position, orientation and radius → rings.

Components add points in their local frame through the turtle, which stores them in the
stem's (plant) frame; one stem may receive points from several components, which is how a
branch made of several components becomes one continuous tube.  On conversion every point
becomes a ring of ``sides + 1`` vertices (the seam is duplicated so that ``u`` runs 0 → 1),
rings are stitched with two triangles per side, ``u`` runs around and ``v`` along the
accumulated length divided by the circumference at the base (square bark texels).

Orientations are ``float64[3, 3]`` frames whose *columns* are the ring's x axis, the
tangent (y) and z.  A stem built without orientations gets parallel-transport frames
(:func:`sylva.tree._kernels.parallel_transport`).  All stems of a tree are meshed in one
vectorised pass (:func:`stems_to_arrays`).

Examples
--------
>>> import numpy as np
>>> s = Stem(sides=6)
>>> s.add_points(np.array([[0, 0, 0], [0, 1, 0], [0, 2, 0.]]), None, np.array([.2, .1, .05]))
>>> v, n, uv, tri, joint, tri_stem = stems_to_arrays([s])
>>> v.shape, tri.shape
((21, 3), (24, 3))
>>> bool(np.allclose(np.linalg.norm(v[:7, [0, 2]], axis=1), 0.2))
True
"""

from __future__ import annotations

import numpy as np

from ._kernels import parallel_transport

__all__ = ["Stem", "stems_to_arrays"]


class Stem:
    """A sequence of points (position, orientation, radius) forming one tube.

    Parameters
    ----------
    material : str
        Material name (looked up in the material database when meshing).
    sides : int
        Ring resolution (≥ 3).
    lobes : int
        Lobes of the cross-section (Weber–Penn ``Lobes``; 0 for a circle).
    lobe_depth : float
        Relative depth of the lobes; they fade out along the stem's first 30 %.
    level : int
        Branching level (kept for statistics and wind).
    """

    def __init__(self, material: str = "bark", sides: int = 8, lobes: int = 0,
                 lobe_depth: float = 0.0, level: int = 0) -> None:
        if sides < 3:
            raise ValueError(f"a stem needs at least 3 sides, got {sides}")
        self.material = material
        self.sides = int(sides)
        self.lobes = int(lobes)
        self.lobe_depth = float(lobe_depth)
        self.level = int(level)
        self._pos: list[np.ndarray] = []
        self._frame: list[np.ndarray | None] = []
        self._rad: list[np.ndarray] = []
        self._joint: list[np.ndarray] = []

    def add_point(self, position, orientation, radius: float, joint: int = -1) -> None:
        """Append one point (plant frame): ``position`` (3,), ``orientation`` (3, 3) or None."""
        self.add_points(np.asarray(position, np.float64).reshape(1, 3),
                        None if orientation is None else np.asarray(orientation).reshape(1, 3, 3),
                        np.array([radius], np.float64), np.array([joint]))

    def add_points(self, positions, orientations, radii, joints=None) -> None:
        """Append points: ``positions`` float[n, 3], ``orientations`` float[n, 3, 3] or None,
        ``radii`` float[n], ``joints`` int[n] (skeleton joint of each point, -1 none)."""
        p = np.asarray(positions, np.float64).reshape(-1, 3)
        n = p.shape[0]
        self._pos.append(p)
        self._frame.append(None if orientations is None
                           else np.asarray(orientations, np.float64).reshape(n, 3, 3))
        r = np.asarray(radii, np.float64)
        # np.broadcast_to's Python-level checks only where a shape needs them
        self._rad.append(r.copy() if r.shape == (n,) else np.broadcast_to(r, (n,)).copy())
        if joints is None:
            self._joint.append(np.full(n, -1, np.int64))
        else:
            j = np.asarray(joints, np.int64)
            self._joint.append(j.copy() if j.shape == (n,) else np.broadcast_to(j, (n,)).copy())

    @property
    def n_points(self) -> int:
        return int(sum(len(p) for p in self._pos))

    @property
    def positions(self) -> np.ndarray:
        return np.concatenate(self._pos) if self._pos else np.zeros((0, 3))

    @property
    def radii(self) -> np.ndarray:
        return np.concatenate(self._rad) if self._rad else np.zeros(0)

    @property
    def joints(self) -> np.ndarray:
        return np.concatenate(self._joint) if self._joint else np.zeros(0, np.int64)

    def frames(self) -> np.ndarray:
        """``float64[n, 3, 3]``: given orientations, parallel transport where none was given."""
        n = self.n_points
        if n == 0:
            return np.zeros((0, 3, 3))
        if all(f is not None for f in self._frame):
            return np.concatenate(self._frame)
        pos = self.positions
        ref = np.array([[1.0, 0.0, 0.0]])
        first = next((f for f in self._frame if f is not None), None)
        if first is not None:
            ref = first[0, :, 0].reshape(1, 3)
        return parallel_transport(pos, np.array([0]), np.array([n]), ref)


def _ring_table(sides: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    theta = np.linspace(0.0, 2.0 * np.pi, sides + 1)
    return np.cos(theta), np.sin(theta), theta / (2.0 * np.pi)


def stems_to_arrays(stems: list[Stem]):
    """Mesh all ``stems`` in one vectorised pass.

    Returns
    -------
    vertices : float32[v, 3]
    normals : float32[v, 3]
    uvs : float32[v, 2]
    triangles : uint32[t, 3]
        Counter-clockwise seen from outside.
    joints : int64[v]
        The joint of the point each vertex's ring belongs to.
    tri_stem : int64[t]
        Index into ``stems`` of the stem each triangle belongs to.
    """
    out_v, out_n, out_uv, out_t, out_j, out_s = [], [], [], [], [], []
    base = 0
    by_sides: dict[int, list[int]] = {}
    n_points = [s.n_points for s in stems]
    for i, s in enumerate(stems):
        if n_points[i] >= 2:
            by_sides.setdefault(s.sides, []).append(i)
    for sides, members in sorted(by_sides.items()):
        group = [stems[i] for i in members]
        # the stems' pieces concatenated at once (the same rows as each stem's own arrays)
        pos = np.concatenate([p for s in group for p in s._pos])
        rad = np.concatenate([r for s in group for r in s._rad])
        jnt = np.concatenate([j for s in group for j in s._joint])
        frm = np.concatenate([f for s in group for f in (
            s._frame if all(x is not None for x in s._frame) else [s.frames()])])
        counts = np.array([n_points[i] for i in members])
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        n = pos.shape[0]
        # arc length along each stem, restarted at each stem's start
        seg = np.linalg.norm(np.diff(pos, axis=0), axis=1)
        seg = np.concatenate([[0.0], seg])
        seg[starts] = 0.0
        arc = np.cumsum(seg)
        arc -= np.repeat(arc[starts], counts)
        stem_len = np.repeat(arc[starts + counts - 1], counts)
        base_r = np.repeat(np.maximum(rad[starts], 1e-6), counts)
        v = arc / (2.0 * np.pi * base_r)
        # lobed cross-sections (fading over the first 30 % of the stem)
        lobes = np.repeat(np.array([s.lobes for s in group]), counts)
        depth = np.repeat(np.array([s.lobe_depth for s in group]), counts)
        frac = np.where(stem_len > 0, arc / np.maximum(stem_len, 1e-12), 0.0)
        depth = depth * np.clip(1.0 - frac / 0.3, 0.0, 1.0)
        c, s_, u = _ring_table(sides)
        theta = u * 2.0 * np.pi
        lobe = 1.0 + depth[:, None] * np.sin(lobes[:, None] * theta[None, :])
        r = rad[:, None] * lobe  # (n, sides+1)
        xa = frm[:, :, 0]
        za = frm[:, :, 2]
        radial = c[None, :, None] * xa[:, None, :] + s_[None, :, None] * za[:, None, :]
        verts = pos[:, None, :] + r[:, :, None] * radial
        normals = radial  # lobes bend normals slightly; the radial direction is close enough
        uvs = np.stack(np.broadcast_arrays(u[None, :], v[:, None]), axis=-1)
        # triangles between ring i and i+1 of the same stem
        valid = np.ones(n, bool)
        valid[starts + counts - 1] = False
        rows = np.nonzero(valid)[0]
        k = np.arange(sides)
        a = (rows[:, None] * (sides + 1) + k[None, :]).ravel()
        b = a + 1
        a2 = a + (sides + 1)
        b2 = b + (sides + 1)
        # ring x-axis, tangent y, z: increasing theta turns x → z, which is clockwise seen
        # along +y; with y the direction of growth, (a, a2, b) faces outward
        tri = np.concatenate([np.stack([a, a2, b], 1), np.stack([b, a2, b2], 1)])
        row_stem = np.repeat(np.asarray(members), counts)[rows]
        out_s.append(np.tile(np.repeat(row_stem, sides), 2))
        out_v.append(verts.reshape(-1, 3))
        out_n.append(normals.reshape(-1, 3))
        out_uv.append(uvs.reshape(-1, 2))
        out_t.append(tri + base)
        out_j.append(np.repeat(jnt, sides + 1))
        base += n * (sides + 1)
    if not out_v:
        return (np.zeros((0, 3), np.float32), np.zeros((0, 3), np.float32),
                np.zeros((0, 2), np.float32), np.zeros((0, 3), np.uint32), np.zeros(0, np.int64),
                np.zeros(0, np.int64))
    return (np.concatenate(out_v).astype(np.float32), np.concatenate(out_n).astype(np.float32),
            np.concatenate(out_uv).astype(np.float32),
            np.concatenate(out_t).astype(np.uint32), np.concatenate(out_j),
            np.concatenate(out_s))
