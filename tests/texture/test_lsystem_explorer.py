"""WWW L-System Explorer's commands (seed 003 §5.9 Table 3) and the lilac bush (§4.8 ex. 7)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.texture import presets
from sylva.texture.lsystem_texture import (
    LSYSTEM_EXAMPLES,
    LSystemTextureError,
    rewrite,
    turtle,
)


def _lengths(segs):
    return np.linalg.norm(segs.end - segs.start, axis=1)


def test_nesting_scales_step_and_angle_and_brackets_restore_them():
    s = turtle("F<F<F>F>F", 90, step_scale=0.5)
    np.testing.assert_allclose(_lengths(s), [1, 0.5, 0.25, 0.5, 1])
    s = turtle("<+F", 90, angle_scale=0.5)  # the turn is 45 degrees one level down
    np.testing.assert_allclose(s.end[0], [math.cos(math.radians(135)), math.sin(math.radians(135))])
    s = turtle("[<F]F", 90, step_scale=0.5)
    np.testing.assert_allclose(_lengths(s), [0.5, 1.0])


def test_random_steps_stay_in_range_and_follow_the_seed():
    word = "R" * 400
    a = turtle(word, 30, step=2.0, random_step=(0.5, 1.5), seed=3)
    b = turtle(word, 30, step=2.0, random_step=(0.5, 1.5), seed=3)
    c = turtle(word, 30, step=2.0, random_step=(0.5, 1.5), seed=4)
    la = _lengths(a)
    assert la.min() >= 1.0 and la.max() <= 3.0 and la.std() > 0.2
    np.testing.assert_array_equal(la, _lengths(b))
    assert not np.array_equal(la, _lengths(c))
    with pytest.raises(LSystemTextureError):
        turtle("R", 30, random_step=(2.0, 1.0))


def test_dots_are_discs_in_their_colour_and_place_is_a_no_op():
    s = turtle("_F*", 90, dot="*", dot_size=3.0, width=2.0, dot_color=5)
    assert len(s) == 2
    np.testing.assert_allclose(s.start[1], [0.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(s.end[1], s.start[1])  # zero length: a round dot
    assert s.width[1] == pytest.approx(6.0) and s.color[1] == 5


def test_lilac_bush_counts():
    ex = LSYSTEM_EXAMPLES["lilac"]
    assert ex["axiom"] == "_*" and ex["rules"] == {"*": "[+RR<*>][RRRR<*>][-RR<*>]"}
    word, _ = rewrite(ex["axiom"], ex["rules"], ex["iterations"])
    # every * of step k becomes three of step k + 1 and eight R steps
    assert word.count("*") == 3**7
    assert word.count("R") == 8 * (3**7 - 1) // 2
    assert word.count("<") == word.count(">") == 3 * (3**7 - 1) // 2


def test_lilac_steps_shrink_by_delta_step_per_level():
    ex = LSYSTEM_EXAMPLES["lilac"]
    word, gen = rewrite(ex["axiom"], ex["rules"], 4)
    segs = turtle(word, ex["angle"], generation=gen, step=30.0, step_scale=ex["step_scale"],
                  angle_scale=ex["angle_scale"], dot="*", random_step=(0.5, 1.5), seed=1)
    # the nesting level of every R, counted independently of the turtle
    level, levels = 0, []
    for ch in word:
        level += (ch == "<") - (ch == ">")
        if ch == "R":
            levels.append(level)
    lengths = _lengths(segs)
    drawn = lengths[lengths > 0]  # the rest are the dots
    assert drawn.size == len(levels) and (lengths == 0).sum() == 3**4
    ratio = drawn / (30.0 * 0.7 ** np.array(levels))
    assert ratio.min() >= 0.5 - 1e-9 and ratio.max() <= 1.5 + 1e-9
    assert len(set(levels)) == 4  # R steps on every level 0 .. 3


def test_lilac_preset_renders_blossoms_in_the_dot_colour():
    img = presets.render({"kind": "lsystem", "example": "lilac", "size": [160, 160]})
    lilac = np.array([0xB5, 0x7E, 0xDC])
    close = np.abs(img.astype(int) - lilac).sum(axis=2) < 12
    assert close.sum() > 200  # the leftover * symbols are the blossoms
