"""Parameter spaces, the lookup order, fixed random values and the configuration format."""

import pytest

from sylva.errors import LSystemSyntaxError
from sylva.tree.components import Component
from sylva.tree.parameters import (
    FloatParameter,
    IntParameter,
    ParameterError,
    ParameterManager,
    ParameterSpace,
)

CONFIG = """\
# a comment
[global]
Levels = 3            # int
Scale = 13.0 ± 3.0    # float with deviation
Ratio = 0.015
BarkMaterial = "bark.aspen"
1Branches = 50        # Weber-Penn style: level 1
ScaleV = 2.5          # the deviation of Scale (paper style)

[level 1]
DownAngle = 60 +- -50
Length = 0.3

[level 2]
Length = 0.6 ± 0.1
"""


def test_types_values_and_weber_penn_name_mapping():
    pm = ParameterManager.from_text(CONFIG, seed=1)
    g = pm.global_space
    assert g.get("Levels").kind == "int" and g.value("Levels") == 3
    scale = g.get("Scale")
    assert scale.kind == "float" and scale.value == 13.0 and scale.deviation == 2.5
    assert g.get("BarkMaterial").kind == "text" and g.value("BarkMaterial") == "bark.aspen"
    assert "ScaleV" not in g
    assert pm.level(1).value("Branches") == 50 and "1Branches" not in g
    down = pm.level(1).get("DownAngle")
    assert down.deviation == -50.0  # a negative deviation is kept (special modes)
    assert pm.levels == [1, 2]


def test_lookup_order_slot_then_level_then_global():
    pm = ParameterManager(seed=0)
    pm.global_space.set_float("Length", 1.0)
    pm.level(1).set_float("Length", 2.0)
    root, mid, leaf = Component(), Component(), Component()
    root.attach(mid, root.add_slot())
    mid.attach(leaf, mid.primary)
    assert leaf.level == 1
    assert pm.float("Length", leaf).value == 2.0  # level space
    assert pm.float("Length", root).value == 1.0  # level 0 has none: global
    root.slots[2].space().set_float("Length", 3.0)
    assert pm.float("Length", leaf).value == 3.0  # a slot on the way to the root wins
    mid.primary.space().set_float("Length", 4.0)
    assert pm.float("Length", leaf).value == 4.0  # the nearest slot wins
    assert pm.resolve("Missing", leaf) is None
    with pytest.raises(ParameterError, match="Missing"):
        pm.float("Missing", leaf)
    assert pm.float("Missing", leaf, default=5.0).value == 5.0
    mid.primary.space().update("Length", 6.5)  # readers see updates at once
    assert pm.float("Length", leaf).value == 6.5


def test_fixed_random_value_drawn_once_per_space_and_seed():
    a = ParameterManager.from_text(CONFIG, seed=11)
    b = ParameterManager.from_text(CONFIG, seed=11)
    c = ParameterManager.from_text(CONFIG, seed=12)
    fa = a.global_space.get("Scale").fixed
    assert 10.5 <= fa <= 15.5
    assert fa == b.global_space.get("Scale").fixed  # same seed, same value
    assert fa != c.global_space.get("Scale").fixed  # another seed, another value
    assert a.global_space.get("Scale").fixed == fa  # asking again does not redraw
    p = a.global_space.get("Scale")
    a.global_space.update("Scale", 20.0)
    assert p.value == 20.0 and p.fixed == fa  # updates keep the fixed value
    # the same parameter in two spaces gets two draws
    s1, s2 = ParameterSpace((1, 1), 5), ParameterSpace((1, 2), 5)
    x1 = s1.register(FloatParameter("L", 1.0, 0.5)).fixed
    x2 = s2.register(FloatParameter("L", 1.0, 0.5)).fixed
    assert x1 != x2
    # the draw does not depend on the order of registration
    s3 = ParameterSpace((1, 1), 5)
    s3.register(FloatParameter("Other", 0.0, 1.0))
    assert s3.register(FloatParameter("L", 1.0, 0.5)).fixed == x1
    # no deviation: the fixed value is the value
    assert ParameterSpace().register(FloatParameter("x", 2.0)).fixed == 2.0
    # sampling uses the caller's generator and stays in range
    import numpy as np

    rng = np.random.default_rng(0)
    assert all(0.5 <= p.sample(rng) <= 1.5 for p in [FloatParameter("y", 1.0, -0.5)] * 50)


def test_integers_are_32_bit():
    IntParameter("n", 2**31 - 1)
    with pytest.raises(ParameterError):
        IntParameter("n", 2**31)


def test_dumps_round_trips():
    pm = ParameterManager.from_text(CONFIG, seed=3)
    again = ParameterManager.from_text(pm.dumps(), seed=3)
    for space, other in [(pm.global_space, again.global_space), (pm.level(1), again.level(1)),
                         (pm.level(2), again.level(2))]:
        for p in space:
            q = other.get(p.name)
            assert q is not None and q.kind == p.kind and q.value == p.value
            if p.kind == "float":
                assert q.deviation == p.deviation and q.fixed == p.fixed


@pytest.mark.parametrize(
    ("text", "line", "column", "words"),
    [
        ("Levels = 3\n", 1, 1, "before any block"),
        ("[global]\nScale = 1 ± x\n", 2, 9, "cannot read value"),
        ("[global]\nName = \"open\n", 2, 8, "unterminated"),
        ("[global]\n= 3\n", 2, 1, "name = value"),
        ("[level x]\nA = 1\n", 1, 1, "level number"),
        ("[branch]\nA = 1\n", 1, 1, "unknown block"),
        ("[global]\nColor = 1 2 3\n", 2, 9, "expected one number"),
        ("[global]\nA = 1\nAV = \"no\"\n", 3, 6, "deviation must be a number"),
    ],
)
def test_configuration_errors_point_at_the_text(text, line, column, words):
    with pytest.raises(LSystemSyntaxError) as info:
        ParameterManager.from_text(text, filename="tree.txt")
    err = info.value
    assert words in str(err)
    assert (err.line, err.column, err.filename) == (line, column, "tree.txt")
