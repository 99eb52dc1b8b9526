"""Wind: branches sway by level, more at the tips and for thin branches; gusts; leaf flutter.

The thesis's wind formulas (§5.5) are not in the seed; this is our design, in the spirit of
the real-time tree animation of the time (hierarchical, per-branch rotations):

* The skeleton is the tree's stem points (:class:`~sylva.tree.geometry_turtle.TreeGeometry`
  joints).  Each joint turns about its own origin by a small angle, and the rotations
  compose from the root outwards, so a branch moves with its parent and its tip sweeps
  further than its base ("more at the tips").
* The angle at joint ``j`` is ``A_j · g(t − d_j) · (0.55 + 0.45 sin(2π f_j t + φ_s))``
  about the axis ``tangent × wind`` (bending downwind), plus ``0.3 A_j g sin(2π 1.3 f_j t +
  φ'_s)`` about the axis across it (a figure-eight sway).  ``A_j = strength ·
  level_sway[level] · clip(√(r̄_level / r_j), 0.5, 2)`` grows with the level and for
  branches thinner than their level's median ``r̄``; ``f_j`` rises with the level and
  thinness; the phase ``φ_s`` is shared by the joints of one stem.
* The gust ``g`` is 1-D fBm noise (:func:`sylva.texture.noise.fbm`) of time, mapped to
  ``[0.15, 1.35]``, delayed by ``d_j = (p_j · wind) / gust_speed`` so gusts travel through
  the crown.
* Leaves flutter: every blade bends about its base along its normal by
  ``flutter · (0.35 + g) · sin(2π f_l t + φ_l)`` with ``f_l`` in ``[3, 6]`` Hz.

Examples
--------
>>> from sylva.tree.model import Tree
>>> tm = Tree("hazel_shrub", seed=2).grow(4.0).mesh()
>>> w = Wind(strength=1.5, seed=1)
>>> v0 = w.deform(tm, 0.0)[0]; v1 = w.deform(tm, 0.7)[0]
>>> bool(abs(v1 - v0).max() > 0)
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..texture.noise import fbm
from ._kernels import compose_hierarchy
from .geometry_turtle import TreeGeometry

__all__ = ["Wind", "quaternions"]


def _rot_many(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """``float64[n, 3, 3]`` rotations about unit ``axis`` (n, 3) by ``angle`` (n,)."""
    x, y, z = axis[:, 0], axis[:, 1], axis[:, 2]
    c, s = np.cos(angle), np.sin(angle)
    C = 1.0 - c
    return np.stack([
        np.stack([c + x * x * C, x * y * C - z * s, x * z * C + y * s], -1),
        np.stack([y * x * C + z * s, c + y * y * C, y * z * C - x * s], -1),
        np.stack([z * x * C - y * s, z * y * C + x * s, c + z * z * C], -1),
    ], 1)


def quaternions(r: np.ndarray) -> np.ndarray:
    """Unit quaternions ``(x, y, z, w)`` float64[..., 4] of rotation matrices r[..., 3, 3]."""
    r = np.asarray(r, np.float64)
    shp = r.shape[:-2]
    m = r.reshape(-1, 3, 3)
    q = np.empty((len(m), 4))
    tr = m[:, 0, 0] + m[:, 1, 1] + m[:, 2, 2]
    cand = np.stack([tr, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], 1)
    k = np.argmax(cand, 1)
    for case in range(4):
        sel = k == case
        if not np.any(sel):
            continue
        a = m[sel]
        if case == 0:
            s = np.sqrt(np.maximum(tr[sel] + 1.0, 1e-300)) * 2
            q[sel] = np.stack([(a[:, 2, 1] - a[:, 1, 2]) / s, (a[:, 0, 2] - a[:, 2, 0]) / s,
                               (a[:, 1, 0] - a[:, 0, 1]) / s, 0.25 * s], 1)
        elif case == 1:
            s = np.sqrt(np.maximum(1.0 + a[:, 0, 0] - a[:, 1, 1] - a[:, 2, 2], 1e-300)) * 2
            q[sel] = np.stack([0.25 * s, (a[:, 0, 1] + a[:, 1, 0]) / s,
                               (a[:, 0, 2] + a[:, 2, 0]) / s, (a[:, 2, 1] - a[:, 1, 2]) / s], 1)
        elif case == 2:
            s = np.sqrt(np.maximum(1.0 + a[:, 1, 1] - a[:, 0, 0] - a[:, 2, 2], 1e-300)) * 2
            q[sel] = np.stack([(a[:, 0, 1] + a[:, 1, 0]) / s, 0.25 * s,
                               (a[:, 1, 2] + a[:, 2, 1]) / s, (a[:, 0, 2] - a[:, 2, 0]) / s], 1)
        else:
            s = np.sqrt(np.maximum(1.0 + a[:, 2, 2] - a[:, 0, 0] - a[:, 1, 1], 1e-300)) * 2
            q[sel] = np.stack([(a[:, 0, 2] + a[:, 2, 0]) / s, (a[:, 1, 2] + a[:, 2, 1]) / s,
                               0.25 * s, (a[:, 1, 0] - a[:, 0, 1]) / s], 1)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[q[:, 3] < 0] *= -1.0
    return q.reshape(*shp, 4)


@dataclass
class Wind:
    """A wind field acting on a tree skeleton.

    Parameters
    ----------
    strength : float
        0 calm, 1 a breeze, 2–3 a storm (scales every angle).
    direction : (float, float, float)
        Horizontal direction the wind blows toward (normalised; y is ignored).
    gust_frequency : float
        Hz of the gust noise.
    gust_speed : float
        m/s at which gusts travel through the crown.
    sway_frequency : float
        Hz of the trunk's sway; higher levels and thinner branches sway faster.
    level_sway : tuple of float
        Bend (radians per joint at strength 1) for levels 0, 1, 2, 3+.
    flutter : float
        Leaf flutter amplitude (1: the mesh's full flutter displacement).
    seed : int
    """

    strength: float = 1.0
    direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    gust_frequency: float = 0.3
    gust_speed: float = 8.0
    sway_frequency: float = 0.45
    level_sway: tuple[float, ...] = (0.006, 0.03, 0.05, 0.07)
    flutter: float = 1.0
    seed: int = 0

    def _dir(self) -> np.ndarray:
        d = np.array([self.direction[0], 0.0, self.direction[2]], np.float64)
        n = np.linalg.norm(d)
        return d / n if n > 1e-12 else np.array([1.0, 0.0, 0.0])

    def gust(self, t) -> np.ndarray:
        """Gust factor at times ``t`` (any shape), in about ``[0.15, 1.35]``."""
        t = np.asarray(t, np.float64)
        x = t.ravel() * self.gust_frequency
        n = fbm(x, np.full_like(x, 0.37), octaves=4, seed=self.seed % (2**31))
        return (0.75 + 1.2 * np.asarray(n, np.float64)).clip(0.15, 1.35).reshape(t.shape)

    # -- per-tree constants ------------------------------------------------------------------
    def _setup(self, geo: TreeGeometry) -> dict:
        cache = getattr(self, "_cache", None)
        if cache is not None and cache[0] is geo:
            return cache[1]
        J = geo.n_joints
        W0 = geo.joint_matrix
        parents = geo.joint_parent
        inv_parent = np.linalg.inv(W0[np.maximum(parents, 0)])
        local = np.where((parents >= 0)[:, None, None], inv_parent @ W0, W0)
        lv = np.minimum(geo.joint_level, len(self.level_sway) - 1)
        r = np.maximum(geo.joint_radius, 1e-5)
        med = np.ones(J)
        for level in np.unique(geo.joint_level):
            sel = geo.joint_level == level
            med[sel] = np.median(r[sel])
        thin = np.clip(np.sqrt(med / r), 0.5, 2.0)
        amp = np.asarray(self.level_sway)[lv] * thin
        freq = self.sway_frequency * (1.0 + 0.5 * geo.joint_level) * np.clip(thin, 0.8, 1.5)
        rng = np.random.default_rng([self.seed & 0xFFFFFFFF, 5])
        # one phase per stem: the first joint of each component chain
        _, first = np.unique(geo.joint_component, return_index=True)
        comp_first = dict(zip(geo.joint_component[first].tolist(), first.tolist(), strict=True))
        base = rng.uniform(0, 2 * np.pi, (J, 2))
        idx = np.array([comp_first[c] for c in geo.joint_component.tolist()], np.int64)
        phase = base[idx] if J else base
        d = self._dir()
        tangent = W0[:, :3, 1]
        bend = np.cross(tangent, d)
        nb = np.linalg.norm(bend, axis=1, keepdims=True)
        bend = np.where(nb > 1e-6, bend / np.maximum(nb, 1e-12), np.cross([0.0, 1.0, 0.0], d))
        across = np.cross(bend, tangent)
        na = np.linalg.norm(across, axis=1, keepdims=True)
        across = np.where(na > 1e-6, across / np.maximum(na, 1e-12), d)
        # axes in each joint's own frame (rotation about the joint origin, local side)
        rot0 = W0[:, :3, :3]
        bend_l = np.einsum("jik,ji->jk", rot0, bend)
        across_l = np.einsum("jik,ji->jk", rot0, across)
        delay = (W0[:, :3, 3] @ d) / max(self.gust_speed, 1e-6)
        k = geo.n_leaves
        lrng = np.random.default_rng([self.seed & 0xFFFFFFFF, 6])
        setup = {
            "local": local, "parents": parents.astype(np.int64), "amp": amp, "freq": freq,
            "phase": phase, "bend": bend_l, "across": across_l, "delay": delay,
            "leaf_f": lrng.uniform(3.0, 6.0, k), "leaf_p": lrng.uniform(0, 2 * np.pi, k),
            "leaf_delay": (geo.leaf_pos @ d) / max(self.gust_speed, 1e-6) if k else np.zeros(0),
        }
        self._cache = (geo, setup)
        return setup

    def joint_matrices(self, geo: TreeGeometry, t: float) -> np.ndarray:
        """World matrices ``float64[j, 4, 4]`` of every joint at time ``t`` (seconds)."""
        s = self._setup(geo)
        if geo.n_joints == 0:
            return np.zeros((0, 4, 4))
        g = self.gust(t - s["delay"])
        w = 2 * np.pi * s["freq"] * t
        a1 = self.strength * s["amp"] * g * (0.55 + 0.45 * np.sin(w + s["phase"][:, 0]))
        a2 = self.strength * s["amp"] * g * 0.3 * np.sin(1.3 * w + s["phase"][:, 1])
        r = _rot_many(s["bend"], a1) @ _rot_many(s["across"], a2)
        lm = s["local"].copy()
        lm[:, :3, :3] = lm[:, :3, :3] @ r
        return compose_hierarchy(s["parents"], lm)

    def leaf_weights(self, geo: TreeGeometry, t: float) -> np.ndarray:
        """Flutter of every leaf at ``t``: float64[k] in about ``[-1.7, 1.7]``."""
        s = self._setup(geo)
        if geo.n_leaves == 0:
            return np.zeros(0)
        g = self.gust(t - s["leaf_delay"])
        return self.flutter * (0.35 + g) * np.sin(2 * np.pi * s["leaf_f"] * t + s["leaf_p"]) \
            * min(1.0, 0.3 + 0.7 * self.strength)

    def deform(self, tm, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Vertices and normals (float32[n, 3]) of a :class:`~sylva.tree.meshing.TreeMesh`
        at time ``t``."""
        geo = tm.geometry
        W = self.joint_matrices(geo, t)
        skin = W @ np.linalg.inv(geo.joint_matrix) if len(W) else np.zeros((0, 4, 4))
        v = tm.mesh.vertices.astype(np.float64)
        leaf = tm.vertex_leaf >= 0
        if np.any(leaf):
            lw = self.leaf_weights(geo, t)
            v[leaf] += tm.flutter[leaf] * lw[tm.vertex_leaf[leaf]][:, None]
        j = np.maximum(tm.vertex_joint, 0)
        m = skin[j]
        out = np.einsum("nij,nj->ni", m[:, :3, :3], v) + m[:, :3, 3]
        nrm = np.einsum("nij,nj->ni", m[:, :3, :3], tm.mesh.normals.astype(np.float64))
        return out.astype(np.float32), nrm.astype(np.float32)

    def mesh_at(self, tm, t: float):
        """A copy of ``tm.mesh`` moved by the wind at ``t``."""
        from ..geometry.mesh import Mesh

        v, n = self.deform(tm, t)
        m = tm.mesh
        return Mesh(v, m.indices, normals=n, uvs=m.uvs, colors=m.colors,
                    material_ids=m.material_ids, materials=m.materials, name=m.name,
                    attributes=m.attributes)
