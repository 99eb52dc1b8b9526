"""Leaves as components (seed 002 §4.7–4.10; issue 18 item 4): the leaves of a stem are a
component on its base slot, of level + 1, with the parameters of that level; their count,
size, colour and fall follow the documented parameters (sylva.tree.leaves)."""

import json
import math

import numpy as np
import pytest

from sylva.errors import SylvaError
from sylva.tree import Branch, Leaves, Tree, shape_ratio
from sylva.tree._schema import check_species
from sylva.tree.parameters import ParameterManager
from sylva.tree.species import species_text

ASPEN, _ = species_text("quaking_aspen")
AGE = 12.0


def _aspen(extra_global: str = "", levels: dict | None = None, **kw) -> Tree:
    """The quaking aspen (seed 2, quality 0.3) with lines added to [global] / [level N]."""
    text = ASPEN.replace("[level 0]", extra_global + "\n[level 0]", 1)
    for lv, lines in (levels or {}).items():
        head = f"[level {lv}]"
        text = text.replace(head, head + "\n" + lines, 1) if head in text else \
            text + f"\n{head}\n{lines}\n"
    check_species(text, "aspen.txt")
    return Tree(ParameterManager.from_text(text, seed=2), quality=0.3, **kw)


@pytest.fixture(scope="module")
def summer():
    t = _aspen().grow(AGE)
    return t, t.geometry()


def _rows(geo) -> set:
    return {tuple(np.round(p, 9)) for p in geo.leaf_pos}


def test_leaves_are_components_on_their_stems_base_slot(summer):
    tree, geo = summer
    comps = tree.leaf_components()
    assert len(comps) > 50
    for leaves in comps:
        stem = leaves.parent
        assert isinstance(stem, Branch) and stem.foliage is leaves
        assert leaves.parent_slot is stem.base  # the identity slot: the stem's own frame
        assert np.array_equal(stem.base.matrix, np.eye(4))
        assert leaves.level == stem.level + 1 == leaves.leaf_level  # not primary: level + 1
        assert leaves.simulation is tree.simulation
    # crown leaves on the twigs are level 3; a young tree's shoots carry levels 1 and 2
    assert {c.level for c in comps} == {1, 2, 3}
    # traversal draws each component's leaves as one group, right after its stem
    out = [c for c in comps if np.any(c.sizes_at(AGE) > 0)]
    assert int(geo.leaf_group.max()) + 1 == len(out)
    assert sum(int(np.count_nonzero(c.sizes_at(AGE) > 0)) for c in out) == geo.n_leaves
    assert tree.stats()["leaves"] == geo.n_leaves


def test_leaf_count_per_slot_is_weber_and_penns(summer):
    """Each twig hangs on its own slot of its parent, whose space holds the offset and the
    parent's length (seed 002 §4.10); its leaves number Leaves · ShapeRatio(4, offset /
    parent length) · LeafDensity (÷ quality), error-diffused: within one of that."""
    tree, _ = summer
    twigs = [b for b in tree.branches() if b.level == 2 and b.k0 == 0]
    assert len(twigs) > 100
    for b in twigs:
        space = b.parent_slot.params
        offset, parent = space.get("Offset").value, space.get("ParentLength").value
        want = 25 * shape_ratio(4, offset / parent) * 1.0 / 0.3
        n = len(b.foliage) if b.foliage is not None else 0
        assert math.floor(want) <= n <= math.floor(want) + 1, (want, n)


def test_leaf_density_per_level(summer):
    tree, _ = summer
    half = _aspen(levels={3: "LeafDensity = 0.5"}).grow(AGE)
    double = _aspen(levels={1: "LeafDensity = 2"}).grow(AGE)

    def count(t, level):
        return sum(len(c) for c in t.leaf_components() if c.level == level)

    # [level 3] halves the crown's leaves and leaves the young shoots' alone …
    assert abs(count(half, 3) / count(tree, 3) - 0.5) < 0.03
    assert count(half, 1) == count(tree, 1) and count(half, 2) == count(tree, 2)
    # … [level 1] doubles the leaves of the young trunk's shoots only
    assert 1.9 <= count(double, 1) / count(tree, 1) <= 2.1
    assert count(double, 3) == count(tree, 3)
    # and the stems are the same tree
    assert np.array_equal(half.geometry().joint_matrix, tree.geometry().joint_matrix)


def test_leaf_size_follows_its_parameter_space_over_age(summer):
    tree, _ = summer
    young = _aspen("LeafScaleYoung = 2\nLeafAdultAge = 10").grow(AGE)
    a, b = tree.leaf_components(), young.leaf_components()
    assert len(a) == len(b)
    for ca, cb in zip(a, b, strict=True):  # the same leaves, born at the same times
        assert np.array_equal(ca.birth, cb.birth)
        expect = ca.size * (2.0 - np.minimum(ca.birth / 10.0, 1.0))
        np.testing.assert_allclose(cb.size, expect, rtol=1e-12)
    # a leaf unfolds over LeafUnfold (0.3 years): (age / LeafUnfold)^0.7 of its size
    c = max(a, key=len)
    t = float(c.birth[0]) + 0.15
    half = c.sizes_at(t)[0]
    assert half == pytest.approx(c.size[0] * 0.5 ** 0.7, rel=1e-12)
    # a per-level value reaches that level's leaves only
    own = _aspen(levels={1: "LeafScaleYoung = 3"}).grow(AGE)
    for ca, co in zip(a, own.leaf_components(), strict=True):
        if co.level == 1:
            assert np.all(co.size >= ca.size) and np.any(co.size > 2 * ca.size)
        else:
            assert np.array_equal(co.size, ca.size)


def test_autumn_turns_then_drops_the_leaves(summer):
    tree, geo = summer
    n = geo.n_leaves
    all_turned = _aspen(season="autumn").grow(AGE).geometry()
    assert all_turned.n_leaves == n and set(all_turned.leaf_material) == {"leaf.autumn"}
    # LeafTurn: that fraction of the leaves in AutumnMaterial, the rest still green
    half = _aspen(season="autumn", leaf_turn=0.5).grow(AGE).geometry()
    mats = np.array(half.leaf_material)
    assert half.n_leaves == n and set(mats) == {"leaf.autumn", "leaf.aspen"}
    assert abs(np.mean(mats == "leaf.autumn") - 0.5) < 0.03
    # LeafFall: that fraction on the ground, the others still on the tree where they were
    fall = _aspen(season="autumn", leaf_fall=0.3).grow(AGE).geometry()
    assert abs(fall.n_leaves / n - 0.7) < 0.03
    assert _rows(fall) <= _rows(geo)
    more = _aspen(season="autumn", leaf_fall=0.6).grow(AGE).geometry()
    assert _rows(more) < _rows(fall)  # falling goes on: the same leaves and then some
    # the first to turn fall first: 50 % turned, 30 % down → 2/7 of those left are turned
    both = _aspen(season="autumn", leaf_turn=0.5, leaf_fall=0.3).grow(AGE).geometry()
    assert _rows(both) == _rows(fall)
    assert abs(np.mean(np.array(both.leaf_material) == "leaf.autumn") - 2 / 7) < 0.03
    # the same from the species file
    from_file = _aspen('Season = "autumn"\nLeafFall = 0.3').grow(AGE).geometry()
    assert np.array_equal(from_file.leaf_pos, fall.leaf_pos)


def test_bare_winter_tree_has_the_same_stems_and_no_leaves(summer):
    tree, geo = summer
    bare = [_aspen(season="winter").grow(AGE), _aspen(season="autumn", leaf_fall=1).grow(AGE)]
    bark = tree.mesh(leaves=False).mesh
    for t in bare:
        g = t.geometry()
        assert g.n_leaves == 0 and t.stats()["leaves"] == 0
        assert np.array_equal(g.joint_matrix, geo.joint_matrix)
        m = t.mesh().mesh
        assert m.n_triangles == bark.n_triangles and np.array_equal(m.vertices, bark.vertices)
    # a level's own LeafFall: the crown (level 3) bare, the young shoots' leaves stay
    crown_down = _aspen('Season = "autumn"', levels={3: "LeafFall = 1"}).grow(AGE)
    shoots = sum(int(np.count_nonzero(c.sizes_at(AGE) > 0))
                 for c in tree.leaf_components() if c.level < 3)
    assert shoots > 0 and crown_down.stats()["leaves"] == shoots
    # an evergreen keeps its needles whatever autumn says
    pine = Tree("scots_pine", seed=2, quality=0.3, season="autumn", leaf_fall=1).grow(20.0)
    assert pine.stats()["leaves"] > 100
    with pytest.raises(SylvaError, match=r"\[0, 1\]"):
        Tree("quaking_aspen", leaf_fall=1.5)


BASE = "[global]\nLevels = 2\nShape = 3\n[level 0]\nLength = 1\n[level 1]\nBranches = 5\n"


@pytest.mark.parametrize(("change", "line", "col", "words"), [
    (("Shape = 3", "Shape = 3\nLeafFall = 1.5"), 4, 12, "LeafFall = 1.5 is out of range: "
                                                        "expected [0, 1]"),
    (("Branches = 5", "Branches = 5\nLeafTurn = -0.2"), 8, 12, "expected [0, 1]"),
    (("Shape = 3", "Shape = 3\nLeafScaleYoung = 0"), 4, 18, "expected (0, 10]"),
    (("Shape = 3", "Shape = 3\nLeafAdultAge = 2000"), 4, 16, "expected (0, 1000]"),
    (("Shape = 3", "Shape = 3\nSpringLeafScale = 2"), 4, 19, "expected [0, 1]"),
    (("Shape = 3", "Shape = 3\nLeafFal = 0.2"), 4, 1, "unknown key 'LeafFal'"),
    (("Shape = 3", "Shape = 3\nleafturn = 0.2"), 4, 1, "did you mean 'LeafTurn'"),
    (("Shape = 3", "Shape = 3\nLeafFall = 0.2 ± 0.1"), 4, 12, "takes no deviation"),
])
def test_bad_leaf_keys_name_file_line_column_and_range(tmp_path, change, line, col, words):
    path = tmp_path / "bad.txt"
    path.write_text(BASE.replace(*change), encoding="utf-8")
    with pytest.raises(SylvaError) as e:
        Tree(str(path))
    msg = str(e.value)
    assert words in msg and f"bad.txt:{line}:{col}" in msg, msg


def test_cli_autumn_and_bare(tmp_path, capsys):
    from sylva.cli import main

    glb = tmp_path / "a.glb"
    assert main(["tree", "quaking_aspen", "--age", "4", "--season", "autumn", "--leaf-turn",
                 "0.5", "-o", str(glb)]) == 0
    data = glb.read_bytes()
    n = int(np.frombuffer(data[12:16], np.uint32)[0])
    names = {m["name"] for m in json.loads(data[20:20 + n])["materials"]}
    assert {"leaf.autumn", "leaf.aspen"} <= names
    capsys.readouterr()
    assert main(["tree", "quaking_aspen", "--age", "4", "--season", "autumn", "--leaf-fall",
                 "1", "-o", str(tmp_path / "b.glb")]) == 0
    assert " 0 leaves" in capsys.readouterr().out
    assert main(["tree", "quaking_aspen", "--leaf-fall", "2", "-o", str(tmp_path / "c.glb")]) \
        != 0


def test_leaves_is_exported():
    assert Leaves.__module__ == "sylva.tree.leaves"
