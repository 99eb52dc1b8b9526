"""Turtle geometry against published results (seed 000, ABOP, seed 004 §4.2)."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

from sylva.turtle import interpret

from .words import expand

HILBERT = {
    "A": "B-F+CFC+F-D&F^D-F+&&CFC+F+B//",
    "B": "A&F^CFB^F^D^^-F-D^|F^B|FC^F^A//",
    "C": "|D^|F^B-F+C^F^A&&FA&F^C+F+B^F^D//",
    "D": "|CFB-F+B|FA&F^A&&FB-F+B|FC//",
}


@pytest.mark.parametrize(
    "n, length, segments, side", [(1, 29, 7, 2), (2, 271, 63, 4), (3, 2155, 511, 8)]
)
def test_hilbert_3d_visits_every_grid_point_once(n, length, segments, side):
    # seed 000 §3.2: n = 2 gives 63 unit segments through the 64 points of a 4x4x4 lattice
    word = expand("A", HILBERT, n)
    assert len(word) == length
    g = interpret(word, dialect="classic", rot=90)
    assert g.n_segments == segments
    np.testing.assert_allclose(np.linalg.norm(g.seg_end - g.seg_start, axis=1), 1.0, atol=1e-9)
    path = np.concatenate([g.seg_start[:1], g.seg_end])
    np.testing.assert_allclose(g.seg_start[1:], g.seg_end[:-1], atol=1e-9)  # one stroke
    lattice = np.rint(path - path.min(axis=0)).astype(int)
    np.testing.assert_allclose(path - path.min(axis=0), lattice, atol=1e-9)
    assert len({tuple(p) for p in lattice}) == segments + 1  # no point visited twice
    assert (lattice.max(axis=0) == side - 1).all() and (lattice.min(axis=0) == 0).all()


@pytest.mark.parametrize("n", [1, 2, 3])
def test_quadratic_koch_island_bounding_box(n):
    # seed 004 §4.2 / ABOP Fig. 1.7a.  Each side of length 4^n grows bumps of
    # (4^n - 1)/3 on both sides (the generator is point-symmetric), so the box side is
    # 4^n + 2(4^n - 1)/3: 6, 26, 106.
    g = interpret(expand("F-F-F-F", {"F": "F-F+F+FF-F-F+F"}, n), dialect="abop", rot=90)
    assert g.n_segments == 4 * 8**n
    size = np.ptp(g.bounds(), axis=0)
    expected = 4**n + 2 * (4**n - 1) / 3
    np.testing.assert_allclose(size, [expected, expected, 0], atol=1e-9)
    assert g.is_planar()


@pytest.mark.parametrize("n", [1, 3])
def test_koch_snowflake_fills_its_hexagon(n):
    # ABOP Fig. 1.9 snowflake: the convex hull of the curve is the regular hexagon of
    # circumradius s/sqrt(3) (s = 3^n unit steps), vertices on the x axis here.
    g = interpret(expand("F--F--F", {"F": "F+F--F+F"}, n), dialect="abop", rot=60)
    np.testing.assert_allclose(
        np.ptp(g.bounds(), axis=0)[:2], [2 * 3**n / math.sqrt(3), 3**n], atol=1e-9
    )


def test_dragon_curve_tends_to_its_one_and_a_half_by_one_box():
    # Heighway dragon (ABOP Fig. 1.10a): relative to its chord the limit set spans
    # [-1/3, 7/6] along it and 1 across it (1/3 on one side, 2/3 on the other).
    n = 16
    g = interpret(expand("FX", {"X": "X+YF+", "Y": "-FX-Y"}, n), dialect="abop", rot=90)
    assert g.n_segments == 2**n
    p = np.concatenate([g.seg_start[:1], g.seg_end])[:, :2]
    chord = p[-1] - p[0]
    d = np.linalg.norm(chord)
    assert d == pytest.approx(2 ** (n / 2))
    e = chord / d
    along = (p - p[0]) @ e / d
    across = (p - p[0]) @ np.array([-e[1], e[0]]) / d
    tol = 0.01
    assert along.min() == pytest.approx(-1 / 3, abs=tol)
    assert along.max() == pytest.approx(7 / 6, abs=tol)
    assert sorted([across.max(), -across.min()]) == pytest.approx([1 / 3, 2 / 3], abs=tol)


def _reference_2d(word: str, delta: float) -> np.ndarray:
    """An independent 2D turtle on complex numbers (start up, '+' counter-clockwise)."""
    pos, head, stack, pts = 0j, 1j, [], [0j]
    turn = cmath.exp(1j * math.radians(delta))
    for c in word:
        if c == "F":
            pos += head
            pts.append(pos)
        elif c == "+":
            head *= turn
        elif c == "-":
            head /= turn
        elif c == "[":
            stack.append((pos, head))
        elif c == "]":
            pos, head = stack.pop()
    z = np.array(pts)
    return np.array([[z.real.min(), z.imag.min()], [z.real.max(), z.imag.max()]])


@pytest.mark.parametrize(
    "axiom, rules, n, delta, count",
    [
        ("F", {"F": "F[+F]F[-F]F"}, 5, 25.7, 5**5),  # ABOP Fig. 1.24a
        ("X", {"X": "F[+X][-X]FX", "F": "FF"}, 7, 25.7, 4118),  # seed 000 §3.3 (F = 4118)
        ("X", {"X": "F-[[X]+X]+F[+FX]-X", "F": "FF"}, 5, 22.5, None),  # ABOP Fig. 1.24f
    ],
)
def test_abop_plants_bounding_box_and_counts(axiom, rules, n, delta, count):
    word = expand(axiom, rules, n)
    g = interpret(word, dialect="abop", rot=delta)
    if count is not None:
        assert g.n_segments == count
    assert g.n_segments == word.count("F")
    np.testing.assert_allclose(g.bounds()[:, :2], _reference_2d(word, delta), atol=1e-9)
    assert g.bounds()[1, 1] > 0 and g.is_planar()


def test_seed_000_bush_with_leaves_counts():
    # seed 000 §3.7 (Table 5.2) at n = 7: F = 3891, L = 1284; radii taper by 0.95 per F
    rules = {"A": "[&FXA]/////[&FXA]////////[&FXA]", "F": "S/////F", "S": "FX", "X": "[^^L]"}
    word = expand("A", rules, 7)
    assert len(word) == 49915
    g = interpret(word, dialect="classic", rot=22.5, reduction=0.95, radius=0.3)
    assert g.n_segments == 3891 and g.n_leaves == 1284
    assert np.all(g.leaf_size == 1.0)  # leaves do not taper
    ratio = g.seg_radius[:, 1] / g.seg_radius[:, 0]
    np.testing.assert_allclose(ratio, 0.95, rtol=1e-6)
    assert g.seg_radius[0, 0] == pytest.approx(0.3)
