"""cpfg's generalised cylinders (``@Gs @Gc @Ge @Gt``) as the Hermite curves of the CPFG
manual (§6.7.3) and cpfg's ``interpolate_connection``: between control points P0 and P1,
``d = |P1 - P0|`` apart, p(t) = h00 P0 + h10 T0 + h01 P1 + h11 T1 with T0 = b0·d·H0 and
T1 = a1·d·H1 (``@Gt(a, b)``, default 1.2), drawn as n strips through p(k/n)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.lsystem import Derivation
from sylva.lsystem.dialects import cpfg
from sylva.turtle import interpret, trace


def _geometry(axiom):
    p = cpfg.parse(f"Lsystem: 0\nAxiom: {axiom}\nendlsystem\n", view=False)
    return interpret(Derivation(p).word, p)


def _hermite(p0, t0, p1, t1, t):
    h00, h10 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t
    h01, h11 = -2 * t**3 + 3 * t**2, t**3 - t**2
    return h00 * p0 + h10 * t0 + h01 * p1 + h11 * t1


def test_a_quarter_turn_is_the_hermite_curve_of_the_headings():
    # @Gs at the origin heading +y; -(45) f(2) -(45): P1 = (√2, √2), the heading +x
    g = _geometry("#(0.4)@Gs-(45)f(2)-(45)@Ge(8)")
    p0, h0 = np.zeros(3), np.array([0.0, 1.0, 0.0])
    s = math.sqrt(0.5) * 2
    p1, h1 = np.array([s, s, 0.0]), np.array([1.0, 0.0, 0.0])
    d = 2.0
    want = np.array([_hermite(p0, 1.2 * d * h0, p1, 1.2 * d * h1, k / 8) for k in range(9)])
    assert g.n_segments == 8
    assert np.abs(g.seg_start[0] - p0).max() < 1e-12
    assert np.abs(g.seg_end - want[1:]).max() < 1e-12
    mid = g.seg_end[3]  # t = 1/2: (P0 + P1)/2 + (T0 - T1)/8
    assert np.allclose(mid, (p0 + p1) / 2 + 1.2 * d * (h0 - h1) / 8, atol=1e-12)
    assert np.array_equal(g.seg_parent, [-1, 0, 1, 2, 3, 4, 5, 6])  # one tube
    assert np.allclose(g.seg_radius, 0.2)


def test_gt_sets_the_leaving_and_arriving_coefficients():
    # @Gt(a, b): b for the tangent leaving a point, a for the one arriving (cpfg >= 3.4)
    g = _geometry("@Gt(0.5,3)@Gs-(45)f(2)-(45)@Ge(2)")
    s = math.sqrt(0.5) * 2
    p1 = np.array([s, s, 0.0])
    t0, t1 = 3 * 2 * np.array([0.0, 1.0, 0.0]), 0.5 * 2 * np.array([1.0, 0.0, 0.0])
    assert np.allclose(g.seg_end[0], _hermite(np.zeros(3), t0, p1, t1, 0.5), atol=1e-12)
    one = _geometry("@Gt(2)@Gs-(45)f(2)-(45)@Ge(2)")
    t0, t1 = 2 * 2 * np.array([0.0, 1.0, 0.0]), 2 * 2 * np.array([1.0, 0.0, 0.0])
    assert np.allclose(one.seg_end[0], _hermite(np.zeros(3), t0, p1, t1, 0.5), atol=1e-12)


def test_the_radius_goes_linearly_from_point_to_point_and_f_draws_nothing():
    g = _geometry("#(0.2)@Gsf(1)f(1)#(1.0)@Gc(4)f(1)@Ge")
    assert g.n_segments == 8  # 4 strips each (@Ge without a number: cpfg's 4)
    assert np.allclose(g.seg_radius[:4], [[0.1, 0.2], [0.2, 0.3], [0.3, 0.4], [0.4, 0.5]])
    assert np.allclose(g.seg_radius[4:], 0.5)
    ends = g.seg_end[[3, 7]]
    assert np.allclose(ends, [[0, 2, 0], [0, 3, 0]], atol=1e-12)


def test_coinciding_points_draw_nothing_and_the_trace_is_the_plain_walks():
    g = _geometry("@Gs@Gc(5)f(1)@Ge(3)")  # @Gs and @Gc at one point: no strips there
    assert g.n_segments == 3
    p = cpfg.parse("Lsystem: 0\nAxiom: @Gs+(90)f(1)@Ge(3)F\nendlsystem\n", view=False)
    t = trace(Derivation(p).word, p)
    assert len(t.positions) == len(Derivation(p).word)
    assert np.allclose(t.positions[-1], [-2, 0, 0], atol=1e-12)
    assert np.allclose(t.frames[-1, 0], [-1, 0, 0], atol=1e-12)


@pytest.mark.parametrize("axiom", ["@Gc(3)f(1)@Ge(3)", "f(1)@Ge(3)"])
def test_a_control_point_without_gs_starts_a_cylinder(axiom):
    # cpfg's continue_spline / finish_spline start one when none is open
    g = _geometry(axiom)
    assert g.n_segments == (3 if axiom.startswith("@Gc") else 0)
