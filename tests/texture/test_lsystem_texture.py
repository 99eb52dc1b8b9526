"""The texture module's own 2D L-system: derivation counts from seed 003, the turtle, and
tileable rasterising."""

import math

import numpy as np
import pytest

from sylva.errors import GrowthLimitError
from sylva.texture import (
    LSYSTEM_EXAMPLES,
    LSystemTextureError,
    Segments,
    _raster,
    draw_segments,
    lsystem_texture,
    rewrite,
    turtle,
)

EX = LSYSTEM_EXAMPLES


@pytest.mark.parametrize("n,length,count_f", [(1, 20, 8), (2, 172, 64), (3, 1388, 512),
                                              (4, 11116, 4096)])
def test_bourke_bush_counts(n, length, count_f):
    # seed 003 §4.8, test vectors: total length / number of F
    word, gen = rewrite("F", EX["bush"]["rules"], n)
    assert len(word) == length and word.count("F") == count_f
    assert len(gen) == len(word)


def test_lindenmayer_system_generator_plant_counts():
    rules = EX["alga"]["rules"]
    assert [len(rewrite("F", rules, n)[0]) for n in (1, 2, 4)] == [39, 533, 164731]
    word = rewrite("F", rules, 3)[0]
    assert (len(word), word.count("F"), word.count("G"), word.count("A")) == (11325, 1497,
                                                                              2540, 1270)


def test_lsystems_explorer_plant_counts():
    rules = EX["lse-bush"]["rules"]
    assert [len(rewrite("F", rules, n)[0]) for n in (1, 2, 3, 4)] == [40, 576, 12275, 190391]


def test_generations_mark_branches_by_iteration():
    word, gen = rewrite("F", {"F": "F[+F]F"}, 2)
    assert word == "F[+F]F[+F[+F]F]F[+F]F"
    # trunk symbols keep generation 0; the branches of step 1 are 1, of step 2 are 2
    assert gen[0] == 0 and gen[word.index("[+F]") + 2] == 2
    assert gen.tolist()[:6] == [0, 2, 2, 2, 2, 0]
    assert max(gen) == 2


def test_stochastic_rules_are_seeded():
    rules = EX["stochastic"]["rules"]
    a = rewrite("F", rules, 4, seed=1)[0]
    b = rewrite("F", rules, 4, seed=1)[0]
    c = rewrite("F", rules, 4, seed=2)[0]
    assert a == b and a != c
    # both alternatives are used roughly in proportion 0.3 : 0.7
    w = rewrite("F", {"F": [(0.3, "a"), (0.7, "b")]}, 1, seed=0)[0]
    big = rewrite("FFFFFFFFFF" * 200, {"F": [(0.3, "a"), (0.7, "b")]}, 1, seed=0)[0]
    assert w in ("a", "b") and 0.25 < big.count("a") / len(big) < 0.35
    with pytest.raises(LSystemTextureError, match="sum"):
        rewrite("F", {"F": [(0.3, "a"), (0.3, "b")]}, 1)


def test_turtle_geometry():
    s = turtle("F+F-F", 90.0)
    np.testing.assert_allclose(s.end, [[0, 1], [-1, 1], [-1, 2]], atol=1e-12)
    s = turtle("F[+F]F", 90.0)
    np.testing.assert_allclose(s.start[2], [0, 1], atol=1e-12)  # popped back
    s = turtle("3+F", 30.0, start_angle=0.0)
    np.testing.assert_allclose(s.end[0], [0, 1], atol=1e-12)
    s = turtle("FfF", 90.0)
    assert len(s) == 2 and s.start[1, 1] == pytest.approx(2.0)
    s = turtle("F#F!!F;F", 90, width=2.0, width_increment=1.0, color_start=1)
    assert s.width.tolist() == [2.0, 3.0, 1.0, 1.0] and s.color.tolist() == [1, 1, 1, 2]
    with pytest.raises(LSystemTextureError, match="unbalanced"):
        turtle("F]", 90)


def test_koch_snowflake_is_closed_with_the_right_perimeter():
    ex = EX["koch"]
    for n in range(4):
        word, gen = rewrite(ex["axiom"], ex["rules"], n)
        s = turtle(word, ex["angle"], start_angle=0.0)
        assert len(s) == 3 * 4**n
        assert s.total_length() == pytest.approx(3 * 4**n)
        np.testing.assert_allclose(s.end[-1], [0, 0], atol=1e-9)


def test_per_generation_colour_and_width():
    word, gen = rewrite("F", {"F": "F[+F]F"}, 2)
    s = turtle(word, 30, generation=gen, width=4.0, width_factor=0.5, color_start=2,
               color_increment=1)
    assert set(s.color.tolist()) == {2, 3, 4}
    assert set(s.width.tolist()) == {4.0, 2.0, 1.0}


def test_wrapping_rasteriser_is_seamless():
    rgb = np.zeros((16, 16, 3))
    cov = np.zeros((16, 16))
    _raster.draw_segments(rgb, cov, np.array([-5.0]), np.array([8.0]), np.array([5.0]),
                          np.array([8.0]), np.array([1.0]), np.ones((1, 3)), True)
    row = cov[8]
    assert row[0] == 1.0 and row[4] == 1.0 and row[12] == 1.0 and row[15] == 1.0
    assert row[8] == 0.0  # the middle of the tile is not covered


def test_textures_render_and_tile():
    img = lsystem_texture((64, 64), "F", EX["bush"]["rules"], 3, 22.5, tileable=True, count=5,
                          size=0.7, seed=3)
    assert img.shape == (64, 64, 3) and img.dtype == np.uint8 and img.any()
    again = lsystem_texture((64, 64), "F", EX["bush"]["rules"], 3, 22.5, tileable=True,
                            count=5, size=0.7, seed=3)
    np.testing.assert_array_equal(img, again)
    fit = lsystem_texture((40, 30), "F", EX["bush"]["rules"], 2, 22.5, alpha=True)
    assert fit.shape == (40, 30, 4)
    empty = Segments(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0), np.zeros(0, np.int32),
                     np.zeros(0, np.int16))
    assert draw_segments((8, 8), empty, background="#102030")[0, 0].tolist() == [16, 32, 48]


def test_growth_limit():
    with pytest.raises(GrowthLimitError):
        rewrite("F", {"F": "FF"}, 30, max_length=1000)
    with pytest.raises(LSystemTextureError):
        rewrite("F", {"FF": "F"}, 1)
    with pytest.raises(LSystemTextureError, match="unbalanced"):
        rewrite("F", {"F": "F[+F"}, 1)


def test_fig33_string_draws_17_segments():
    ex = EX["bracketed"]
    word, _ = rewrite(ex["axiom"], ex["rules"], 0)
    assert len(turtle(word, 25)) == 17
    assert math.isclose(turtle(word, 25).total_length(), 17.0)
