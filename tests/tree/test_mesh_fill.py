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
"""

import numpy as np
import pytest

from sylva import _jit
from sylva.tree import Tree


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
