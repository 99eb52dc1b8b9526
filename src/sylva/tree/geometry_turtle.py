"""The generic geometry interface components draw through (seed 002 §5.5: ``Turtle``).

:class:`TreeTurtle` keeps the current transform (set by :func:`~sylva.tree.components.traverse`)
and the current :class:`~sylva.tree.components.Context`; components call
:meth:`TreeTurtle.stem_points` and :meth:`TreeTurtle.leaves` with *local* coordinates and the
turtle stores them in plant coordinates.  Every stem point becomes a skeleton *joint*
(position + frame), which wind and glTF skinning use.  The result is a :class:`TreeGeometry`
of plain arrays; :mod:`sylva.tree.meshing` turns it into a :class:`~sylva.geometry.mesh.Mesh`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._kernels import turn_frames
from .components import Context
from .stem import Stem

__all__ = ["TreeGeometry", "TreeTurtle"]


@dataclass
class TreeGeometry:
    """What a traversal of the tree produced (plant coordinates, +Y up, metres).

    Attributes
    ----------
    stems : list of Stem
    joint_matrix : float64[j, 4, 4]
        Rest frame of each joint (stem point): columns x, tangent y, z and position.
    joint_parent : int64[j]
        Parent joint (-1 for the root).
    joint_level : int32[j]
    joint_radius : float64[j]
    joint_component : int64[j]
        Id of the component that emitted the point.
    leaf_pos : float64[k, 3]
    leaf_frame : float64[k, 3, 3]
        Columns: across the blade (x), along the blade (y), the blade normal (z).
    leaf_size : float64[k]
        Blade length (0 for leaves not yet out).
    leaf_width : float64[k]
        Blade width relative to its length.
    leaf_material : list of str
    leaf_joint : int64[k]
    leaf_group : int64[k]
        The leaf-bearing component (index into the growth skeleton's leaf joints).
    """

    stems: list
    joint_matrix: np.ndarray
    joint_parent: np.ndarray
    joint_level: np.ndarray
    joint_radius: np.ndarray
    joint_component: np.ndarray
    leaf_pos: np.ndarray
    leaf_frame: np.ndarray
    leaf_size: np.ndarray
    leaf_width: np.ndarray
    leaf_material: list
    leaf_joint: np.ndarray
    leaf_group: np.ndarray

    @property
    def n_joints(self) -> int:
        return int(self.joint_parent.shape[0])

    @property
    def n_leaves(self) -> int:
        return int(self.leaf_size.shape[0])

    def bounds(self) -> np.ndarray:
        """``float64[2, 3]`` box of the joints and leaf bases (a quick extent)."""
        pts = [self.joint_matrix[:, :3, 3], self.leaf_pos]
        p = np.concatenate([x for x in pts if len(x)]) if any(len(x) for x in pts) else np.zeros(
            (1, 3))
        return np.stack([p.min(0), p.max(0)])


class TreeTurtle:
    """Collects stems, leaves and joints during a traversal (the OpenGL-side Turtle of Rose
    becomes a NumPy one here; the POV-Ray side is the geometry team's ``write_pov``)."""

    def __init__(self, default_material: str = "bark") -> None:
        self.matrix = np.eye(4)
        self.context = Context(default_material)
        self.component = None
        self.stems: list[Stem] = []
        self._jm: list[tuple[np.ndarray, np.ndarray]] = []  # (frames, positions) per call
        self._jp: list[np.ndarray] = []
        self._jl: list[int] = []  # the stem level of each stem_points call
        self._jr: list[np.ndarray] = []
        self._jc: list[int] = []  # the component id of each call
        self._jn: list[int] = []  # joints added by each call
        self._nj = 0
        self._leaves: list[tuple] = []
        self._leaf_groups = 0

    def begin(self, component) -> None:
        self.component = component

    def new_stem(self, *, sides: int, material: str, lobes: int = 0, lobe_depth: float = 0.0,
                 level: int = 0) -> Stem:
        """Start a stem and make it the context's current stem."""
        s = Stem(material, sides, lobes, lobe_depth, level)
        self.stems.append(s)
        self.context.stem = s
        return s

    def stem_points(self, positions, frames, radii, *, parent_joint: int = -1,
                    skip_first: bool = False) -> np.ndarray:
        """Add points (local coordinates) to the current stem; returns their joint ids.

        ``positions`` float[n, 3], ``frames`` float[n, 3, 3] (columns x, tangent, z),
        ``radii`` float[n].  Joints are chained: the first one's parent is ``parent_joint``.
        With ``skip_first`` the first point is not added to the stem (it repeats the last one
        of the stem so far) but still gets a joint id (the ``parent_joint``).
        """
        stem = self.context.stem
        if stem is None:
            raise RuntimeError("stem_points: no current stem (call new_stem first)")
        m = self.matrix
        p = np.asarray(positions, np.float64)
        f = np.asarray(frames, np.float64)
        r = np.asarray(radii, np.float64)
        wp = p @ m[:3, :3].T + m[:3, 3]
        start = 1 if skip_first else 0
        wf = turn_frames(m, f, start)  # einsum("ij,njk->nik", m[:3, :3], f)[start:]'s numbers
        n = len(p) - start
        ids = np.empty(len(p), np.int64)
        if skip_first:
            ids[0] = parent_joint
        new = np.arange(self._nj, self._nj + n)
        ids[start:] = new
        if n:  # the joints are chained: each one's parent is the one before
            parents = new - 1
            parents[0] = parent_joint
        else:  # what np.concatenate([[parent_joint], new[:-1]]) gave
            parents = np.array([parent_joint], np.int64)
        # the joint matrices, levels and components are assembled once, in finish()
        self._jm.append((wf, wp[start:]))
        self._jp.append(parents)
        self._jl.append(stem.level)
        self._jr.append(r[start:])
        self._jc.append(getattr(self.component, "id", -1))
        self._jn.append(n)
        self._nj += n
        stem.add_points(wp[start:], wf, r[start:], new)
        return ids

    def leaves(self, positions, frames, sizes, width: float, material, joints) -> int:
        """Add leaves (local coordinates); returns their group id (one per call).

        ``material`` is one name for all of them, or a list of one name per leaf (an autumn
        tree's turned and green leaves)."""
        m = self.matrix
        p = np.asarray(positions, np.float64).reshape(-1, 3)
        wp = p @ m[:3, :3].T + m[:3, 3]
        wf = turn_frames(m, np.asarray(frames, np.float64).reshape(-1, 3, 3), 0)  # einsum's numbers
        g = self._leaf_groups
        self._leaf_groups += 1
        self._leaves.append((wp, wf, np.asarray(sizes, np.float64), width, material,
                             np.asarray(joints, np.int64), g))
        return g

    def _joint_matrices(self) -> np.ndarray:
        """``float64[j, 4, 4]``: every joint's frame and position as one matrix."""
        jm = np.zeros((self._nj, 4, 4))
        if self._jm:
            jm[:, :3, :3] = np.concatenate([f for f, _ in self._jm])
            jm[:, :3, 3] = np.concatenate([p for _, p in self._jm])
        jm[:, 3, 3] = 1.0
        return jm

    def finish(self) -> TreeGeometry:
        def cat(xs, shape, dtype):
            return np.concatenate(xs).astype(dtype) if xs else np.zeros(shape, dtype)

        lv = self._leaves
        k = sum(len(x[0]) for x in lv)
        return TreeGeometry(
            stems=self.stems,
            joint_matrix=self._joint_matrices(),
            joint_parent=cat(self._jp, (0,), np.int64),
            joint_level=np.repeat(np.array(self._jl, np.int32), self._jn),
            joint_radius=cat(self._jr, (0,), np.float64),
            joint_component=np.repeat(np.array(self._jc, np.int64), self._jn),
            leaf_pos=cat([x[0] for x in lv], (0, 3), np.float64),
            leaf_frame=cat([x[1] for x in lv], (0, 3, 3), np.float64),
            leaf_size=cat([x[2] for x in lv], (0,), np.float64),
            leaf_width=np.concatenate([np.full(len(x[0]), x[3]) for x in lv]) if k else np.zeros(0),
            leaf_material=[m for x in lv for m in (
                [x[4]] * len(x[0]) if isinstance(x[4], str) else x[4])],
            leaf_joint=cat([x[5] for x in lv], (0,), np.int64),
            leaf_group=np.concatenate([np.full(len(x[0]), x[6], np.int64) for x in lv])
            if k else np.zeros(0, np.int64),
        )
