"""The built-in environments of open L-systems: Palubicki's light grid, obstacle shapes."""

from __future__ import annotations

import numpy as np
import pytest

import sylva
from sylva.environments import Light, Obstacle, resolve_environment
from sylva.errors import SylvaError
from sylva.lsystem import Derivation, loads
from sylva.lsystem.environment import Communication
from sylva.plant import grow, turtle_locate


def test_the_shadow_grid_of_four_buds_by_hand():
    # Palubicki et al. 2009 §4.2: a bud in voxel (I, J, K) adds a·b^-q to (I±p, J-q, K±p),
    # 0 <= p <= q <= q_max; a bud's light is max(C - s + a, 0) (here divided by C).
    # a = 1, b = 2, q_max = 2, C = 2, unit voxels; buds at voxels B1 (0,2,0), B5 (1,1,0),
    # B2 (0,0,0), B4 (3,0,0).
    light = Light(voxel=1, shadow=1, falloff=2, depth=2, full=2)
    pos = np.array([[0, 2, 0], [1, 1, 0], [0, 0, 0], [3, 0, 0]]) + 0.5
    grid, cells = light.grid(pos)
    s = {tuple(c): grid[tuple(c)] for c in cells}
    # B1: alone on top, its own a = 1
    # B5: own 1 + B1 one layer up (q = 1, |dx| = 1 <= 1): 1/2
    # B2: own 1 + B1 (q = 2, dx = 0): 1/4 + B5 (q = 1, |dx| = 1): 1/2
    # B4: own 1 (B1 at |dx| = 3 > 2, B5 at |dx| = 2 > 1)
    assert [s[tuple(c)] for c in cells] == [1.0, 1.5, 1.75, 1.0]
    np.testing.assert_allclose(light.light(pos), [(2 - 1 + 1) / 2, (2 - 1.5 + 1) / 2,
                                                  (2 - 1.75 + 1) / 2, 1.0])  # fmt: skip
    # an empty voxel under B1, beside B5: B1's q = 1 only
    lo = cells[2] - np.array([0, 0, 0])  # B2's voxel in grid indices
    assert grid[lo[0], lo[1] + 1, lo[2]] == 0.5
    # every bud's shadow sums to a·Σ_q (2q+1)²·b^-q when nothing is cut off
    one = Light(depth=3).grid(np.array([[0.5, 9.5, 0.5]]))[0]
    assert one.sum() == pytest.approx(sum((2 * q + 1) ** 2 * 2.0**-q for q in range(4)))


def test_a_bud_turns_away_from_the_shade():
    # bud A at voxel (0,0,0) heading +Y, an occluder at (1,2,0): its q = 1 layer (y = 1)
    # covers x in 0..2, so of A's neighbours ahead within 45° only (-1,1,0) is unshaded.
    light = Light(shadow=1, falloff=2, depth=2, full=1, cone=45)
    pos = np.array([[0.5, 0.5, 0.5], [1.5, 2.5, 0.5]])
    out = light.answer(pos, np.array([[0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]))
    np.testing.assert_allclose(out[0, 1:], [-2**-0.5, 2**-0.5, 0.0])
    assert out[0, 0] == pytest.approx(0.75)  # own 1 + 1/4 from the occluder two layers up
    np.testing.assert_allclose(out[1], [1.0, 0.0, 1.0, 0.0])  # in full light: straight on


def test_the_light_environment_answers_q_and_the_direction_in_the_modules():
    p = loads("axiom = F(1) ?E(0,0,0,0) [ F(2) ?E(0,0,0,0) ]")
    d = Derivation(p, environment=Light(shadow=1, falloff=2, depth=3), locate=turtle_locate(p))
    vals = [v for s, v in d.word if s == "?E"]
    # the lower bud sits in voxel y=1, two layers under the upper (y=3): 1/4 shade
    assert vals[0][0] == pytest.approx(0.75) and vals[1][0] == pytest.approx(1.0)
    assert vals[1][1:] == (0.0, 1.0, 0.0)



def test_a_leaf_above_a_bud_takes_its_light():
    # the bud at voxel y = 0; a leaf of size 1 drawn from (0.5, 1.9, 0.5) up +Y has its
    # centre at y = 2.4, voxel 2: two layers above the bud, 1/4 of a bud's shadow
    light = Light(shadow=1, falloff=2, depth=3)
    bud = np.array([[0.5, 0.5, 0.5]])
    assert light.light(bud) == pytest.approx([1.0])
    assert light.light(bud, np.array([[0.5, 2.4, 0.5]]), np.array([0])) == pytest.approx([0.75])
    # weights: a leaf as half a bud; segments cast nothing unless asked
    half = Light(shadow=1, falloff=2, depth=3, leaves=0.5, segments=0.0)
    both = np.array([[0.5, 2.4, 0.5], [0.5, 1.4, 0.5]])
    assert half.light(bud, both, np.array([0, 1])) == pytest.approx([1 - 0.5 / 4])
    seg = Light(shadow=1, falloff=2, depth=3, leaves=0.0, segments=1.0)
    assert seg.light(bud, both, np.array([0, 1])) == pytest.approx([0.5])
    # in a derivation: the same bud under a leaf drawn above it, and without the leaf
    p = loads("turtle = abop\naxiom = ?E(0) [ f(1.9) ~(1) ]")
    env, locate = sylva.plant.environment_for(
        p.replace(settings={**p.settings, "environment": "light(depth = 3)"}))
    assert env.wants_organs
    d = Derivation(p, environment=env, locate=locate)
    assert [v for s, v in d.word if s == "?E"] == [(0.75,)]
    bare = loads("turtle = abop\naxiom = ?E(0) [ f(1.9) ]")
    d = Derivation(bare, environment=env, locate=locate)
    assert [v for s, v in d.word if s == "?E"] == [(1.0,)]
    with pytest.raises(SylvaError, match="'leaves' must be a number >= 0"):
        Light(leaves=-1)

HEDGE = """
environment = obstacle(shape = box, y = 1.5, sx = 1.2, sy = 1.5, sz = 1.2)
rot = 35
axiom = F(0.5) ?E(0) A
?E(d) < A : d < 0 -> F(0.5) [ +?E(0) A ] [ -?E(0) A ] [ &?E(0) A ] ?E(0) A
?E(d) < A : d >= 0 ->
"""


def test_obstacle_pruning_keeps_a_hedge_inside_its_box():
    box = Obstacle("box", y=1.5, sx=1.2, sy=1.5, sz=1.2)
    p = loads(HEDGE)
    plant = grow(p, 7)
    pts = plant.geometry.seg_end
    # a tip is tested after its segment is drawn: at most one segment (0.5) outside
    assert box.distance(pts).max() <= 0.5 + 1e-9
    assert box.distance(pts).max() > 0  # it did reach the walls
    # the same bush in open space passes them by far
    free = grow(p, 7, environment=lambda c: np.full(c.params.shape, -1.0))
    far = free.geometry.seg_end
    assert box.distance(far).max() >= 1.0  # the trunk alone: 8 × 0.5 up, 1 over the top
    assert len(plant.word) < len(free.word)


def test_the_signed_distance_of_each_shape():
    pts = np.array([[0.0, 0, 0], [3, 0, 0], [0, 5, 0]])
    np.testing.assert_allclose(Obstacle("sphere", r=2).distance(pts), [-2, 1, 3])
    np.testing.assert_allclose(Obstacle("box", sx=1, sy=2, sz=1).distance(pts), [-1, 2, 3])
    np.testing.assert_allclose(Obstacle("cylinder", r=1, sy=2).distance(pts), [-1, 2, 3])
    np.testing.assert_allclose(Obstacle("ellipsoid", sx=1, sy=4, sz=1).distance(pts),
                               [-1, 2, 0.25])  # fmt: skip


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("fog", r"unknown environment 'fog'; expected light, obstacle, density, world"),
        ("light(voxel = -1)", r"light: 'voxel' must be a positive number"),
        ("obstacle(shape = cone)", r"unknown shape 'cone'"),
        (3, r"expected a name .* or a function of a Communication, got int"),
    ],
)
def test_a_bad_environment_name_or_option_is_an_error(spec, message):
    with pytest.raises(SylvaError, match=message):
        resolve_environment(spec)


def test_grow_and_derive_take_the_environment_from_the_program_or_the_call():
    p = loads("environment = obstacle(shape = sphere, r = 3.5)\naxiom = F(2)?E(0)\n"
              "?E(d) : d < 0 -> F(1)?E(0)")  # fmt: skip
    assert str(sylva.derive(p, 4)) == 'F(2)F(1)F(1)"?E"(0.5)'
    assert str(sylva.derive(p, 4, environment="obstacle(r = 5.5)")) == (
        'F(2)F(1)F(1)F(1)F(1)"?E"(0.5)'
    )
    seen: list[Communication] = []
    mine = sylva.grow(p, 2, environment=lambda c: seen.append(c) or c.params - 1)
    assert len(seen) == 3 and mine.stats["modules"] == 4


def test_the_command_line_takes_an_environment(tmp_path, capsys):
    from sylva.cli import main

    f = tmp_path / "open.lsys"
    f.write_text("axiom = F(2)?E(0)\n?E(d) : d < 0 -> F(1)?E(0)\n")
    assert main(["derive", str(f), "-n", "4", "--environment", "obstacle(r = 3.5)"]) == 0
    assert capsys.readouterr().out.strip() == 'F(2)F(1)F(1)"?E"(0.5)'
    assert main(["derive", str(f), "-n", "1"]) == 2
    assert "expected an environment" in capsys.readouterr().err


def test_the_light_example_two_trees_shade_each_other_and_lean_apart():
    import dataclasses

    from sylva.data import find

    p = sylva.load(find("41-sylva-light-competition").path)
    cut = [m.symbol for m in p.axiom].index("@")  # the axiom: [tree 1] @M(2.6,0,0) [tree 2]
    lone = grow(dataclasses.replace(p, axiom=p.axiom[:cut]), 12).geometry.seg_end
    both = grow(p, 12)
    syms = [s for s, _ in both.word]
    n1 = syms[: syms.index("M")].count("F")  # tree 1's segments come first
    ends = both.geometry.seg_end
    one, two = ends[:n1], ends[n1:] - [2.6, 0, 0]
    # alone, the tree is what the second tree would be; together each crown turns away
    # from the other's shade (tree 2 stands at +x), and tree 1 loses shoots to it
    assert one[:, 0].mean() < lone[:, 0].mean() - 0.15
    assert two[:, 0].mean() > lone[:, 0].mean() + 0.15
    assert len(one) < len(lone)
