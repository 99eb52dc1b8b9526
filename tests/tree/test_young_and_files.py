"""Young trees carry leaves; growth is continuous; species files are checked."""

import numpy as np
import pytest

from sylva.errors import SylvaError
from sylva.tree import Tree
from sylva.tree._config import parse_blocks
from sylva.tree._schema import KEYS, check_species
from sylva.tree.parameters import ParameterManager
from sylva.tree.species import example_text, load_species, species_text


@pytest.mark.parametrize("age", [2.0, 6.0])
def test_a_young_aspen_is_a_leafy_sapling(age):
    t = Tree("quaking_aspen", seed=7).grow(age)
    s = t.stats()
    # a leaf at least every 15 cm of its height, not a bare pole
    assert s["leaves"] >= s["height"] / 0.15, s


def test_growth_is_continuous_and_the_mature_tree_is_unchanged():
    t = Tree("quaking_aspen", seed=5, quality=0.3)
    area, height = [], []
    ages = np.arange(0.5, 30.01, 0.5)
    for a in ages:
        g = t.grow(a).geometry()
        area.append(float(np.sum(g.leaf_size ** 2)))
        height.append(float(g.joint_matrix[:, 1, 3].max()))
    area, height = np.array(area), np.array(height)
    assert np.all(np.diff(height) >= -1e-9)  # never shrinks
    # no pops: leaves fall gradually (juvenile leaves fade over a year, shed branches retract
    # over two): half a year never loses more than a fifth of the foliage
    loss = area[:-1] - area[1:]
    assert np.all(loss <= 0.2 * area[:-1] + 1e-12), loss / np.maximum(area[:-1], 1e-12)
    # and the foliage arrives by unfolding (LeafUnfold): a tenth of a year adds little
    a0 = t.grow(12.0).geometry().leaf_size
    a1 = t.grow(12.1).geometry().leaf_size
    assert 0 < np.sum(a1 ** 2) - np.sum(a0 ** 2) < 0.2 * np.sum(a0 ** 2)
    # at the species' Age the juvenile branches and leaves are gone: the same tree as one
    # grown without them
    text, _ = species_text("quaking_aspen")
    plain = text.replace("[level 0]", "JuvenileBranches = 0\nJuvenileLeafLife = 0\n[level 0]")
    a = Tree("quaking_aspen", seed=5, quality=0.3).grow(30.0).geometry()
    b = Tree(ParameterManager.from_text(plain, seed=5), quality=0.3).grow(30.0).geometry()
    assert np.array_equal(a.joint_matrix, b.joint_matrix)
    assert np.array_equal(a.leaf_pos, b.leaf_pos)


def test_the_annotated_example_sets_every_key_and_grows():
    text = example_text()
    check_species(text, "example.txt")
    names = {e.name for b in parse_blocks(text) for e in b.entries}
    assert set(KEYS) <= names
    assert Tree(ParameterManager.from_text(text, seed=1)).grow(5.0).stats()["leaves"] > 0


BASE = "[global]\nLevels = 2\nShape = 3\n[level 0]\nLength = 1\n[level 1]\nBranches = 5\n"


@pytest.mark.parametrize(("change", "line", "col", "words"), [
    (("Shape = 3", "Shap = 3"), 3, 1, "unknown key 'Shap'"),
    (("Shape = 3", "Shape = 9"), 3, 9, "[0, 8]"),
    (("Branches = 5", "Branches = -5"), 7, 12, "[0, 10000]"),
    (("Length = 1", "Length = 1\nTaper = 3.5"), 6, 9, "[0, 3]"),
    (("[level 1]\nBranches = 5\n", ""), 2, 10, "missing [level 1]"),
    (("Levels = 2", "Levels = 2\nScale = 10 ± 12"), 3, 9, "deviation below 10"),
    (("Length = 1", "Length = 1\nCurve = 10 ± -5"), 6, 9, "helix"),
    (("Branches = 5", "Branches = 5\nDownAngle = 30\n[level 4]\nRotate = 3"), 9, 1,
     "beyond Levels = 2"),
    (("Shape = 3", 'Shape = 3\nLeafShape = "fern"'), 4, 13, "needles"),
])
def test_bad_species_files_name_file_line_column_and_range(tmp_path, change, line, col, words):
    path = tmp_path / "bad.txt"
    path.write_text(BASE.replace(*change), encoding="utf-8")
    with pytest.raises(SylvaError) as e:
        Tree(str(path))
    msg = str(e.value)
    assert words in msg and f"bad.txt:{line}:{col}" in msg, msg


def test_user_species_are_listed_and_found(tmp_path, monkeypatch, capsys):
    from sylva.cli import main

    (tmp_path / "my_elm.txt").write_text(example_text().replace('"my aspen"', '"my elm"'))
    monkeypatch.setenv("SYLVA_SPECIES_PATH", str(tmp_path))
    assert load_species("my_elm").text("Name") == "my elm"
    assert main(["tree", "--list"]) == 0
    out = capsys.readouterr().out
    assert "my_elm" in out and "[user:" in out and "quaking_aspen" in out
    assert main(["tree", "--example"]) == 0
    assert "JuvenileTrunkLeaves" in capsys.readouterr().out


def test_autumn_and_winter_are_a_parameter_away():
    summer = Tree("quaking_aspen", seed=2, quality=0.3).grow(12.0)
    autumn = Tree("quaking_aspen", seed=2, quality=0.3, season="autumn").grow(12.0)
    winter = Tree("quaking_aspen", seed=2, quality=0.3, season="winter").grow(12.0)
    n = summer.stats()["leaves"]
    assert n > 100 and autumn.stats()["leaves"] == n and winter.stats()["leaves"] == 0
    names = [m.name for m in autumn.mesh().mesh.materials]
    assert "leaf.autumn" in names and "leaf.aspen" not in names
    # the wood is the same tree in every season
    assert np.array_equal(summer.geometry().joint_matrix, winter.geometry().joint_matrix)
    # an evergreen keeps its needles
    pine = Tree("scots_pine", seed=2, quality=0.3, season="winter").grow(20.0)
    assert pine.stats()["leaves"] > 100
    with pytest.raises(ValueError, match="season"):
        Tree("quaking_aspen", season="monsoon")


def test_leaves_of_a_level_take_their_own_parameters():
    """The leaves on stems of level n read LeafScale, LeafMaterial… from [level n+1]: here
    the young trunk's shoots (level 1's leaves) get another material and size than the
    crown's (level 3's)."""
    text, _ = species_text("quaking_aspen")
    own = '[level 1]\nLeafMaterial = "leaf.birch"\nLeafScale = 0.3\n'
    mine = text.replace("[level 1]\n", own, 1)
    check_species(mine, "mine.txt")
    young = Tree(ParameterManager.from_text(mine, seed=4)).grow(3.0)
    geo = young.geometry()
    assert set(geo.leaf_material) == {"leaf.birch"}  # only the trunk's shoots have leaves
    assert geo.leaf_size.max() > 0.25
    old = Tree(ParameterManager.from_text(mine, seed=4), quality=0.3).grow(30.0).geometry()
    assert set(old.leaf_material) == {"leaf.aspen"}  # the crown's, at maturity
