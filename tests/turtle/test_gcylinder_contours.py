"""cpfg's contours as the sections of generalised cylinders (cpfg's ``make_contour``): at a
control point in contour ``@#(id)`` the ring is ``P + r·(x·U − y·L)`` for the contour's
points stepped at equal arc lengths (8 by default) from its start, turned onto +x; between
two contours the points mix linearly along the piece; ``F`` and round pieces stay tubes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.errors import SylvaWarning
from sylva.lsystem import Derivation, load
from sylva.lsystem.dialects._cpfg_contour import Contour
from sylva.turtle import interpret, trace
from sylva.turtle._gcylinder import contour_ring

# a square with its corners on the axes, each corner thrice: the B-spline is the square
SQUARE = """cver 1 2
name: square
points: 4 12
type: cr
1 0 0 3
0 1 0 3
-1 0 0 3
0 -1 0 3
"""
CORNERS = np.array([[1.0, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]])


def _program(tmp_path, axiom, view="contour: 3 sq.con\n"):
    (tmp_path / "sq.con").write_text(SQUARE)
    (tmp_path / "p.l").write_text(f"Lsystem: 1\nderivation length: 0\nAxiom: {axiom}\n"
                                  "endlsystem\n")  # fmt: skip
    (tmp_path / "p.v").write_text(view)
    return load(tmp_path / "p.l")


def _rings(g):
    """The quads' rings: ``(pieces·strips, 8, 4, 3)``."""
    v = g.poly_vertices.reshape(-1, 4, 3)
    return v.reshape(-1, 8, 4, 3)


def test_the_contour_is_stepped_by_arc_length_from_its_start():
    ring = contour_ring(Contour(tuple(tuple(c) for c in CORNERS for _ in range(3)), True), 8)
    assert np.abs(ring[0:8:2] - CORNERS).max() < 1e-9
    mid = (CORNERS + np.roll(CORNERS, -1, axis=0)) / 2  # the edges' midpoints
    assert np.abs(ring[1:8:2] - mid).max() < 1e-3
    assert np.array_equal(ring[8], ring[0])
    # a closed contour starting off the x axis is turned onto it (cpfg's MakeContour)
    turned = contour_ring(Contour(tuple(tuple(c) for c in CORNERS[[1, 2, 3, 0]]
                                         for _ in range(3)), True), 8)  # fmt: skip
    assert np.abs(turned[0:8:2] - CORNERS).max() < 1e-9
    circle = contour_ring(None, 8)
    assert np.allclose(circle[2], [0.0, 1.0, 0.0]) and np.allclose(circle[0], [1, 0, 0])


def test_a_square_contour_puts_the_ring_on_the_corners_in_the_turtle_frame(tmp_path):
    axiom = "#(0.5)@#(3)/(20)&(10)@Gs-(30)f(2)+(10)@Ge(4)"
    p = _program(tmp_path, axiom)
    word = Derivation(p).word
    g = interpret(word, p)
    assert g.n_segments == 0 and g.n_polygons == 4 * 8  # 4 strips of 8 quads
    tr = trace(word, p)
    start = 7  # the @ of @Gs: its pose is the ring's frame
    pos, (h, left, up) = tr.positions[start], tr.frames[start]
    r = 0.25
    want = pos + r * (CORNERS[:, :1] * up - CORNERS[:, 1:2] * left)
    first = g.poly_vertices.reshape(-1, 4, 3)[:8, 0]  # ring 0: each quad's first corner
    assert np.abs(first[0:8:2] - want).max() < 1e-9
    assert np.allclose(first @ h, pos @ h)  # the ring lies in the plane normal to H
    # the last ring: the end point, its frame the start's turned onto the end's heading
    end = g.poly_vertices.reshape(4, 8, 4, 3)[3, :, 3]
    pe, he = tr.positions[11], tr.frames[11][0]  # the @ of @Ge
    assert np.allclose(end @ he, pe @ he, atol=1e-9)
    assert np.allclose(np.linalg.norm(end[0:8:2] - pe, axis=1), r, atol=1e-9)


def test_between_two_contours_the_points_mix_along_the_piece(tmp_path):
    # square at the start, the circle (@#(0)) at the end: the middle ring is their mean
    p = _program(tmp_path, "#(2)@#(3)@Gsf(2)@#(0)@Ge(2)")
    g = interpret(Derivation(p).word, p)
    v = g.poly_vertices.reshape(2, 8, 4, 3)
    ring0, ring1, ring2 = v[0, :, 0], v[1, :, 0], v[1, :, 3]
    # the turtle heads +y with U = +z... whatever the frame, radii from the axis tell
    axis = np.array([0.0, 1.0, 0.0])

    def radial(ring):
        off = ring - np.outer(ring @ axis, axis)
        return np.linalg.norm(off, axis=1)

    assert np.allclose(radial(ring0), [1, math.sqrt(0.5)] * 4, atol=1e-3)  # square
    assert np.allclose(radial(ring2), 1.0)  # circle
    assert np.allclose(radial(ring1), [1, (1 + math.sqrt(0.5)) / 2] * 4, atol=1e-3)
    # the branch restores the contour: after ] the circle again, so tubes
    q = _program(tmp_path, "#(2)@Gs[@#(3)f(1)@Gc(2)]f(2)@Ge(2)")
    gq = interpret(Derivation(q).word, q)
    assert gq.n_polygons == 2 * 8 and gq.n_segments == 2


def test_f_cylinders_and_round_pieces_are_unchanged(tmp_path):
    p = _program(tmp_path, "#(0.4)@#(3)F(1)@#(0)@Gs-(45)f(2)-(45)@Ge(8)")
    g = interpret(Derivation(p).word, p)
    assert g.n_polygons == 0 and g.n_segments == 1 + 8  # F stays a round segment


def test_an_unknown_contour_id_draws_the_circle_with_a_warning(tmp_path):
    p = _program(tmp_path, "#(0.4)@#(7)@Gsf(1)@Ge(2)")
    with pytest.warns(
        SylvaWarning,
        match=r"module 3 of the word: .* contour 7, which the "
        r"view file does not define \(its contour: ids: 3\)",
    ):
        g = interpret(Derivation(p).word, p)
    assert g.n_polygons == 0 and g.n_segments == 2


def test_contour_sides_sets_the_points_of_a_ring(tmp_path):
    p = _program(tmp_path, "#(2)@#(3)@Gsf(2)@Ge(1)", "contour: 3 sq.con\ncontour sides: 4\n")
    assert p.settings["contour_sides"] == 4
    g = interpret(Derivation(p).word, p)
    ring = g.poly_vertices.reshape(-1, 4, 3)[:, 0]
    assert g.n_polygons == 4  # one strip of 4 quads, from the 4 corners
    assert np.allclose(np.linalg.norm(ring - [0.0, 0.0, 0.0], axis=1), 1.0)


@pytest.mark.parametrize("twist", [False, True])
def test_a_roll_between_control_points_and_the_twist_of_cylinders(tmp_path, twist):
    # cpfg: twist off carries the frame from @Gs (the roll is not seen); on, each point's
    # ring is in the turtle's own frame there, turned about the heading in between
    view = "contour: 3 sq.con\n" + ("twist of cylinders: on\n" if twist else "")
    axiom = "#(2)@#(3)@Gsf(1)/(60)@Gc(2)f(1)@Ge(2)"
    p = _program(tmp_path, axiom, view)
    word = Derivation(p).word
    g = interpret(word, p)
    q = g.poly_vertices.reshape(2, 2, 8, 4, 3)
    end0, start1 = q[0, 1, :, 3], q[1, 0, :, 0]
    assert np.allclose(end0, start1, atol=1e-9)  # one ring at the shared point
    tr = trace(word, p)
    at = 10  # the @ of @Gc, after the roll
    pos, (_, left, up) = tr.positions[at], tr.frames[at]
    own = pos + 1.0 * (CORNERS[:, :1] * up - CORNERS[:, 1:2] * left)
    assert np.allclose(start1[0:8:2], own, atol=1e-9) == twist
    if not twist:  # the frame of @Gs, where the roll has not happened
        _, left0, up0 = tr.frames[4]
        carried = pos + 1.0 * (CORNERS[:, :1] * up0 - CORNERS[:, 1:2] * left0)
        assert np.allclose(start1[0:8:2], carried, atol=1e-9)
