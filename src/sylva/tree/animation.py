"""Wind and growth as glTF skeletal animation (and as mesh sequences for the renderer).

Wind: the skeleton is the tree's stem points; joints follow :meth:`Wind.joint_matrices`,
leaves flutter through three morph targets (leaves dealt round-robin into three groups,
whose weights are the mean flutter of their group, so neighbouring leaves move out of step).

Growth: the bind pose is the tree at the end age; at each keyframe a joint sits where its
stem point is at that time (points beyond the growing tip gather at the tip), scaled across
the stem by the current/final radius, or to nothing before its stem is born.  Leaves hang on
one extra joint per leaf-bearing run, scaled by how far its leaves have unfolded (an
approximation: the blades unfold about the run's base, not each about its own petiole; the
rendered growth, :func:`growth_meshes`, is exact).

Examples
--------
>>> from sylva.tree.model import Tree
>>> a = growth_animation(Tree("hazel_shrub", seed=1), 0.5, 3.0, seconds=1.0, fps=4)
>>> a.translation.shape[0], bool(a.scale.min() < 0.01)
(5, True)
"""

from __future__ import annotations

import numpy as np

from ..geometry.exchange.gltf_animation import SkinnedAnimation
from ..geometry.mesh import Mesh
from .meshing import TreeMesh
from .wind import Wind, quaternions

__all__ = ["growth_animation", "growth_meshes", "wind_animation", "wind_meshes"]


def _trs(m: np.ndarray):
    """Translation, rotation quaternion and scale of matrices m[..., 4, 4] = T · R · S."""
    t = m[..., :3, 3]
    cols = m[..., :3, :3]
    s = np.linalg.norm(cols, axis=-2)
    r = cols / np.where(s > 1e-12, s, 1.0)[..., None, :]
    return t, quaternions(r), s


def wind_animation(tm: TreeMesh, wind: Wind, seconds: float = 4.0, fps: float = 24.0,
                   name: str = "wind") -> SkinnedAnimation:
    """Keyframes of ``wind`` on the tree mesh ``tm`` over ``seconds`` (sampled at ``fps``)."""
    geo = tm.geometry
    k = max(2, int(round(seconds * fps)) + 1)
    times = np.linspace(0.0, seconds, k)
    mats = np.stack([wind.joint_matrices(geo, t) for t in times])
    tr, q, _ = _trs(mats)
    targets, weights = [], None
    leaf = tm.vertex_leaf >= 0
    if np.any(leaf) and wind.flutter > 0:
        group = np.where(leaf, tm.vertex_leaf % 3, -1)
        for g in range(3):
            disp = np.where((group == g)[:, None], tm.flutter, 0.0).astype(np.float32)
            targets.append(disp)
        # per-leaf phases would average out over a group: each group gets its own oscillation
        f = np.array([3.3, 4.1, 5.2])
        gust = wind.gust(times)
        phase = 2 * np.pi * f[None] * times[:, None] + np.array([0.0, 2.1, 4.2])
        weights = wind.flutter * (0.35 + gust)[:, None] * np.sin(phase)
        weights *= min(1.0, 0.3 + 0.7 * wind.strength)
    return SkinnedAnimation(
        tm.mesh, np.maximum(tm.vertex_joint, 0), geo.joint_matrix, times, tr, q, None,
        targets, weights, [f"joint{i}_L{lv}" for i, lv in enumerate(geo.joint_level)], name,
    )


def wind_meshes(tm: TreeMesh, wind: Wind, seconds: float = 4.0, fps: float = 24.0):
    """Meshes of the tree in the wind, one per frame (a generator)."""
    k = max(1, int(round(seconds * fps)))
    for i in range(k):
        yield wind.mesh_at(tm, i / fps)


def growth_meshes(tree, start: float, end: float, frames: int, **mesh_options):
    """Exact meshes of ``tree`` at ``frames`` ages from ``start`` to ``end`` (a generator)."""
    for age in np.linspace(start, end, max(frames, 1)):
        yield tree.grow(float(age)).mesh(**mesh_options).mesh


def growth_animation(tree, start: float, end: float, seconds: float = 6.0, fps: float = 12.0,
                     name: str = "growth") -> SkinnedAnimation:
    """Keyframes of the tree growing from age ``start`` to ``end`` in ``seconds``."""
    tree.grow(end)
    tm = tree.mesh()
    geo = tm.geometry
    J = geo.n_joints
    branches = [b for b in tree.branches() if b._joints is not None]
    groups = int(geo.leaf_group.max()) + 1 if geo.n_leaves else 0
    # one leaf joint per leaf group: groups are made in traversal order, one per leafy run
    leafy = [b for b in branches if len(b.leaf_arc) and np.any(b.leaf_sizes_at(end) > 0)]
    if len(leafy) != groups:
        raise RuntimeError("leaf groups and leaf-bearing runs disagree")
    k = max(2, int(round(seconds * fps)) + 1)
    ages = np.linspace(start, end, k)
    times = np.linspace(0.0, seconds, k)
    bind = np.concatenate([geo.joint_matrix, np.zeros((groups, 4, 4))])
    # the mesh is drawn with the tree's ZScale applied to heights; world matrices are not
    zs = np.array([1.0, getattr(tree, "zscale", 1.0), 1.0])
    for gi, b in enumerate(leafy):
        bind[J + gi] = b.world_matrix()
        bind[J + gi, :3, 3] *= zs
    trans = np.zeros((k, J + groups, 3))
    rot = np.zeros((k, J + groups, 4))
    scale = np.full((k, J + groups, 3), 1e-4)
    q_bind = quaternions(bind[:, :3, :3])
    rot[:] = q_bind[None]
    trans[:] = bind[None, :, :3, 3]
    final_r = geo.joint_radius
    alive = np.zeros((k, J), bool)
    for b in branches:
        W = b.world_matrix()
        first = 1 if b._skip_first else 0
        ids = b._joints[first:]
        _, _, _, arc_final, _ = b.grown_points(end)
        arc_final = arc_final[first:]
        for ki, age in enumerate(ages):
            if age < b.birth_time - 1e-12:
                continue
            P, _, _, A, _ = b.grown_points(age)
            if len(A) == 0:
                continue
            a = np.minimum(arc_final, A[-1])
            pos = np.stack([np.interp(a, A, P[:, c]) for c in range(3)], 1)
            plan = b.plan
            cur = max(plan.length_at(age), 1e-9)
            r = plan.radius * plan.thickness_at(age) * plan.profile(arc_final, cur)
            r = np.where(arc_final <= A[-1] + 1e-9, r, 0.0)
            s = np.maximum(r / np.maximum(final_r[ids], 1e-9), 1e-4)
            trans[ki, ids] = (pos @ W[:3, :3].T + W[:3, 3]) * zs
            scale[ki, ids] = np.stack([s, np.ones_like(s), s], 1)
            alive[ki, ids] = True
    # joints not yet grown wait, collapsed, at their nearest grown ancestor (parents first)
    waiting = ~alive
    scale[:, :J][waiting] = 1e-4
    parent = geo.joint_parent
    for j in range(J):
        p = parent[j]
        if p >= 0:
            w = waiting[:, j]
            if np.any(w):
                trans[w, j] = trans[w, p]
    for gi, b in enumerate(leafy):
        base_joint = b._joints[1 if b._skip_first else 0]
        # the bind pose holds the leaves as they are at the end: scale relative to that
        unfold = np.clip((ages[:, None] - b.leaf_birth[None, :]) / max(tree.leaf_unfold, 1e-6),
                         0.0, 1.0).mean(1)
        scale[:, J + gi] = np.maximum(unfold / max(unfold[-1], 1e-9), 1e-4)[:, None]
        none_out = unfold <= 0
        trans[none_out, J + gi] = trans[none_out, base_joint]
    vj = tm.vertex_joint.copy()
    leaf = tm.vertex_leaf >= 0
    vj[leaf] = J + geo.leaf_group[tm.vertex_leaf[leaf]]
    names = [f"joint{i}_L{lv}" for i, lv in enumerate(geo.joint_level)] + [
        f"leaves{g}" for g in range(groups)]
    mesh = Mesh(tm.mesh.vertices, tm.mesh.indices, normals=tm.mesh.normals, uvs=tm.mesh.uvs,
                colors=tm.mesh.colors, material_ids=tm.mesh.material_ids,
                materials=tm.mesh.materials, name=tm.mesh.name, attributes=tm.mesh.attributes)
    return SkinnedAnimation(mesh, np.maximum(vj, 0), bind, times, trans, rot, scale, [], None,
                            names, name)

