"""The voxel world as an open L-system's environment: roots and branches stop at the
terrain and at rocks (sylva.world.environment)."""

from __future__ import annotations

import numpy as np

from sylva.lsystem import Derivation, loads
from sylva.plant import grow, turtle_locate
from sylva.world import Block, WorldConfig
from sylva.world.environment import WorldEnvironment

# a root: down from the plant's foot one unit a step while the block a unit ahead is soil
# (not air or water, 0 and 1; not stone, 2)
ROOT = """
axiom = &(180) ?E(1, 0) R
?E(d, b) < R : b > 2 -> F(1) ?E(1, 0) R
"""
# a branch: down from 5 units above the foot while the block a unit ahead is air
FALL = """
axiom = f(5) &(180) ?E(1, 0) R
?E(d, b) < R : b == 0 -> F(1) ?E(1, 0) R
"""


def _tip(program, env, steps):
    d = Derivation(program, environment=env, locate=turtle_locate(program))
    d.advance(steps)
    return grow(program, steps, environment=env).geometry.seg_end, d.word


def test_a_root_grows_through_the_soil_and_stops_at_the_stone():
    env = WorldEnvironment(WorldConfig(seed=3), size=8)
    c = 8 // 2
    column = env.blocks[c, :, c]
    top = int(env.height[c, c])  # the surface block; the foot stands on it
    assert column[top + 1] == Block.AIR and column[top] > Block.STONE
    stone = max(j for j in range(top) if column[j] == Block.STONE)  # first stone below
    ends, word = _tip(loads(ROOT), env, 20)
    # by hand: the root goes down a block a step through the soil layers top..stone+1
    assert len(ends) == top - stone
    np.testing.assert_allclose(ends[-1], [0, -(top - stone), 0], atol=1e-9)
    # and the last probe, a unit below the tip, saw stone
    assert [v for s, v in word if s == "?E"][-1][1] == Block.STONE


def test_a_falling_branch_stops_at_the_ground():
    env = WorldEnvironment(WorldConfig(seed=3), size=8)
    ends, _ = _tip(loads(FALL), env, 20)
    # from y = 5 down to y = 0, the top of the surface block: the point a unit ahead is
    # then in the block
    assert len(ends) == 5
    np.testing.assert_allclose(ends[-1], [0, 0, 0], atol=1e-9)


def test_a_rock_is_stone_and_the_probe_answers_height_and_biome():
    env = WorldEnvironment(WorldConfig(seed=3), size=8, scale=2.0, rocks=[(-4, 1, 0, 2.5)])
    out = env.probe(np.array([[-4, 1, 0], [-4, 4, 0], [0, 4, 0], [0, -1, 0]]))
    assert out[:, 0].tolist()[:3] == [Block.STONE, Block.AIR, Block.AIR]
    # heights are in turtle units (2 per block), from the top of the column's surface block
    assert out[2, 1] == 4.0 and out[3, 1] == -1.0
    c = 8 // 2
    assert out[2, 2] == env.biome[c, c]
    # a branch growing along -X (+ turns H toward L = -X) into the rock stops at it
    p = loads("axiom = f(1) +(90) ?E(0.5, 0) R\n?E(d, b) < R : b == 0 -> F(0.5) ?E(0.5, 0) R\n")
    ends, word = _tip(p, env, 20)
    assert len(ends) >= 2 and ends[-1][0] > -4  # it grew, and stopped short of the centre
    assert [v for s, v in word if s == "?E"][-1][1] == Block.STONE  # with the rock ahead
    assert (env.probe(ends)[:, 0] == Block.AIR).all()  # nothing of it is in the stone


def test_the_rock_example_grows_around_the_boulder_and_not_into_it():
    from sylva.data import find
    from sylva.environments import resolve_environment

    p = loads(find("42-sylva-world-rock").path.read_text(), filename="42.lsys")
    env = resolve_environment(None, p)
    assert isinstance(env, WorldEnvironment)
    plant = grow(p)
    out = env.probe(plant.geometry.seg_end)
    above = out[:, 1] > 0
    assert above.sum() > 50 and (out[above, 0] == Block.AIR).all()  # no shoot in the rock
    # shoots met it and turned (the +(20) of a blocked apex), and some climbed past its top
    assert sum(1 for s, v in plant.word if s == "+" and v == (20.0,)) >= 3
    assert plant.geometry.seg_end[:, 1].max() > 0.8 + 1.3
