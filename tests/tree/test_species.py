"""Every shipped species: it loads, grows to a plausible size with the expected branching,
has the traits that make it recognisable, meshes, and is the same tree for the same seed."""

import numpy as np
import pytest

from sylva.tree import Tree, load_species, species_info, species_names
from sylva.tree.species import SpeciesError

SPECIES = ["hazel_shrub", "quaking_aspen"]  # the others: test_likeness.py

# height range (m) and stems per level (min, max) at the species' default age, seed 7
EXPECT = {
    "quaking_aspen": ((10, 22), [(1, 1), (40, 60), (500, 1200)]),
    "hazel_shrub": ((2.5, 6), [(8, 30), (20, 80), (200, 700)]),
}


def test_the_species_list():
    names = species_names()
    assert set(SPECIES) <= set(names) and len(names) >= 18
    for name in names:
        info = species_info(name)
        assert info["Name"] and info["Source"] and info["Description"]
        assert any(w in info["Source"] for w in ("Weber & Penn 1995", "tree-gen", "Sapling",
                                                 "designed for sylva")), name
    paper = {n for n in names if "Weber & Penn 1995" in species_info(n)["Source"]}
    assert {"black_oak", "quaking_aspen", "weeping_willow", "palm", "sassafras"} <= paper
    with pytest.raises(SpeciesError, match="quaking_aspen"):
        load_species("no such tree")


@pytest.fixture(scope="module", params=SPECIES)
def grown(request):
    tree = Tree(request.param, seed=7).grow()
    return request.param, tree, tree.stats(), tree.geometry()


def test_height_and_branch_counts_per_level(grown):
    name, tree, stats, _ = grown
    (lo, hi), per_level = EXPECT[name]
    assert lo <= stats["height"] <= hi, stats
    assert len(stats["stems"]) == len(per_level)
    for level, ((a, b), n) in enumerate(zip(per_level, stats["stems"], strict=True)):
        assert a <= n <= b, (name, level, stats["stems"])
    assert stats["leaves"] > 500


def _traits(tree, stats, geo):
    h = stats["height"]
    ly = geo.leaf_pos[:, 1]
    first = [b for b in tree.branches() if b.level == 1]
    lowest = min(b.world_matrix()[1, 3] for b in first) / h
    radial = np.linalg.norm(geo.leaf_pos[:, [0, 2]] - geo.leaf_pos[:, [0, 2]].mean(0), axis=1)
    top = radial[ly > 0.8 * h]
    middle = radial[(ly > 0.4 * h) & (ly < 0.7 * h)]
    return {
        "conical": float(np.percentile(middle, 90) / np.percentile(top, 90))
        if len(top) and len(middle) else 0.0,
        "slender": h / stats["width"],
        "low_leaves": float(np.mean(ly < 0.5 * h)),
        "leaf_floor": float(ly.min() / h),
        "lowest_branch": lowest,
    }


def test_recognisable_traits(grown):
    name, tree, stats, geo = grown
    t = _traits(tree, stats, geo)
    if name == "quaking_aspen":  # narrow crown, bare lower trunk
        assert t["slender"] > 1.4 and t["lowest_branch"] > 0.3
    elif name == "hazel_shrub":  # many stems from the ground, about as wide as high
        assert stats["stems"][0] >= 8 and t["slender"] < 1.3


def test_mesh_has_bark_and_leaf_materials(grown):
    name, tree, stats, geo = grown
    tm = tree.mesh()
    mesh = tm.mesh
    names = [m.name for m in mesh.materials]
    assert names[0].startswith("bark") and any(n.startswith(("leaf", "needle")) for n in names)
    leaf_mats = [i for i, m in enumerate(mesh.materials) if m.double_sided]
    assert leaf_mats and np.isin(mesh.triangle_materials(), leaf_mats).sum() == 4 * stats["leaves"]
    assert mesh.uvs is not None and np.isfinite(mesh.vertices).all()
    assert mesh.bounds()[0, 1] > -0.5  # nothing far below the ground


def test_same_seed_same_tree_other_seed_other_tree():
    a = Tree("fan_palm", seed=11).grow()
    b = Tree("fan_palm", seed=11).grow()
    c = Tree("fan_palm", seed=12).grow()
    ga, gb, gc = a.geometry(), b.geometry(), c.geometry()
    assert np.array_equal(ga.joint_matrix, gb.joint_matrix)
    assert np.array_equal(ga.leaf_pos, gb.leaf_pos)
    assert ga.joint_matrix.shape != gc.joint_matrix.shape or not np.allclose(
        ga.joint_matrix, gc.joint_matrix)


def test_a_configuration_file(tmp_path):
    text = (load_species("fan_palm").dumps().replace("Branches = 27", "Branches = 5"))
    path = tmp_path / "mine.txt"
    path.write_text(text)
    tree = Tree(str(path), seed=1).grow()
    assert tree.stats()["stems"] == [1, 5]
