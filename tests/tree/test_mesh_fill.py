"""The compiled leaf fill of the tree mesher is the NumPy road: the same mesh bit for bit.

:func:`sylva.tree.meshing.build_tree_mesh` writes the leaf blades straight into the mesh's
float32 arrays with :func:`sylva.tree._kernels.leaf_fill` (a mature tree has a million leaf
vertices, and the NumPy road made several float64 copies of them before the cast).  The
NumPy road is kept unchanged as the reference: it is what runs while the kernel is not
compiled (and under ``SYLVA_JIT=never``).  Here the same grown trees are meshed both ways
and every array of the result — vertices, normals, uvs, colours, triangles, material ids,
joints, leaves, flutter and the ``WIND`` attribute — must be equal byte for byte, on
species of four leaf shapes (blade, ovate, ellipse, needles), a disc, and an autumn tree
whose leaves carry two materials.

The traversal's turtle assembles the joint matrices, levels and components once, at the
end, rather than per stem: a copy of the per-call turtle as it was is kept here as the
slow reference, and the joints of both must be equal byte for byte.
"""

import numpy as np
import pytest

from sylva import _jit
from sylva.tree import Tree
from sylva.tree.components import traverse
from sylva.tree.geometry_turtle import TreeTurtle


def _arrays(tm) -> dict:
    m = tm.mesh
    out = {"vertices": m.vertices, "indices": m.indices, "normals": m.normals, "uvs": m.uvs,
           "colors": m.colors, "material_ids": m.material_ids, "joint": tm.vertex_joint,
           "leaf": tm.vertex_leaf, "flutter": tm.flutter,
           "n_bark": np.array(tm.n_bark_vertices)}
    out.update({f"attr {k}": v for k, v in (m.attributes or {}).items()})
    out["materials"] = np.array([mat.name for mat in m.materials])
    return out


def _both_roads(tree, monkeypatch, **options):
    monkeypatch.setenv("SYLVA_JIT", "never")
    ref = _arrays(tree.mesh(**options))
    monkeypatch.delenv("SYLVA_JIT")
    with _jit.compiled():
        new = _arrays(tree.mesh(**options))
    return ref, new


@pytest.mark.parametrize("name,age,options", [
    ("weeping_willow", 5, {}),
    ("silver_birch", 6, {}),
    ("sphere_tree", 5, {}),
    ("sphere_tree", 5, {"leaf_shape": "disc"}),
    ("douglas_fir", 10, {}),
])
def test_the_filled_mesh_is_the_numpy_mesh_bit_for_bit(name, age, options, monkeypatch):
    tree = Tree(name, seed=3).grow(age)
    ref, new = _both_roads(tree, monkeypatch, **options)
    assert int(np.sum(ref["leaf"] >= 0)) > 100  # the tree has leaves to fill
    assert ref.keys() == new.keys()
    for key in ref:
        assert ref[key].dtype == new[key].dtype, key
        assert ref[key].shape == new[key].shape, key
        assert ref[key].tobytes() == new[key].tobytes(), key


def test_leaves_of_two_materials_keep_their_ids(monkeypatch):
    tree = Tree("silver_birch", seed=3, season="autumn", leaf_turn=0.5).grow(6)
    ref, new = _both_roads(tree, monkeypatch)
    assert len(np.unique(ref["material_ids"])) >= 3  # bark and two leaf materials
    for key in ref:
        assert ref[key].tobytes() == new[key].tobytes(), key


class _OldTurtle(TreeTurtle):
    """The joints of :meth:`TreeTurtle.stem_points` as they were built before the joint
    matrices were assembled once in ``finish`` (a slow reference: one 4×4 stack, one level
    and one component array per call)."""

    def stem_points(self, positions, frames, radii, *, parent_joint=-1, skip_first=False):
        stem = self.context.stem
        m = self.matrix
        p = np.asarray(positions, np.float64)
        f = np.asarray(frames, np.float64)
        r = np.asarray(radii, np.float64)
        wp = p @ m[:3, :3].T + m[:3, 3]
        wf = np.einsum("ij,njk->nik", m[:3, :3], f)
        start = 1 if skip_first else 0
        n = len(p) - start
        ids = np.empty(len(p), np.int64)
        if skip_first:
            ids[0] = parent_joint
        new = np.arange(self._nj, self._nj + n)
        ids[start:] = new
        jm = np.zeros((n, 4, 4))
        jm[:, :3, :3] = wf[start:]
        jm[:, :3, 3] = wp[start:]
        jm[:, 3, 3] = 1.0
        self._old.append((jm, np.full(n, stem.level, np.int32),
                          np.full(n, getattr(self.component, "id", -1), np.int64)))
        self._jp.append(np.concatenate([[parent_joint], new[:-1]]))
        self._jr.append(r[start:])
        self._nj += n
        stem.add_points(wp[start:], wf[start:], r[start:], new)
        return ids

    def finish(self):
        geo = super().finish()
        geo.joint_matrix = np.concatenate([x[0] for x in self._old])
        geo.joint_level = np.concatenate([x[1] for x in self._old])
        geo.joint_component = np.concatenate([x[2] for x in self._old])
        return geo


@pytest.mark.parametrize("name,age", [("black_tupelo", 10), ("weeping_willow", 5)])
def test_the_joints_are_those_of_the_per_call_turtle(name, age):
    tree = Tree(name, seed=3).grow(age)
    new = tree.geometry()
    old_turtle = _OldTurtle(tree.bark_material)
    old_turtle._old = []
    traverse(tree.root, old_turtle)
    old = old_turtle.finish()
    assert len(new.joint_matrix) > 100
    for key in ("joint_matrix", "joint_parent", "joint_level", "joint_radius",
                "joint_component", "leaf_pos", "leaf_frame", "leaf_joint"):
        a, b = getattr(old, key), getattr(new, key)
        assert a.dtype == b.dtype and a.shape == b.shape, key
        assert a.tobytes() == b.tobytes(), key
