"""cpfg's tropisms and torques (view lines ``tropism:`` / ``torque:``, ``@Ts(k, e)``) and its
old tropism (``tropism direction:`` with ``_``), against a reference turtle written out here
from the formulas of the CPFG manual (§6.8, §8.1.8) and cpfg's ``movements.c`` / ``bend``.

The reference keeps the frame as a 3×3 matrix of columns H, L, U and applies each rule
with numpy: before each ``F`` the tropisms' V = Σ e cos γ T + Σ e sin γ T × (H × T)/|H × T|
turns the frame about H × V by min(|H × V|, 1); the torques roll U toward D's part across H
by min(|U × P|, 1); after each ``F`` the old tropism turns H toward U by asin(e T·U), then
toward L by asin(e T·L).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from sylva.errors import LSystemSyntaxError, SylvaWarning
from sylva.lsystem import Derivation
from sylva.lsystem.dialects import cpfg
from sylva.lsystem.dialects._cpfg_view import read_view
from sylva.turtle import interpret, trace


def _rot(axis, angle):
    x, y, z = axis / np.linalg.norm(axis)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def _frame():
    return np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # cols H, L, U


def _movements(frame, moves):
    """One application of the movements ``(kind, T, gamma_deg, e)``."""
    h = frame[:, 0]
    v = np.zeros(3)
    d = np.zeros(3)
    for kind, t, gamma, e in moves:
        t = np.asarray(t, float)
        if kind == "torque":
            d += e * t
            continue
        g = math.radians(gamma)
        v += e * math.cos(g) * t
        hxt = np.cross(h, t)
        v += e * math.sin(g) * np.cross(t, hxt) / np.linalg.norm(hxt)
    r = np.cross(h, v)
    if np.linalg.norm(r) > 1e-6:
        frame = _rot(r, min(np.linalg.norm(r), 1.0)) @ frame
    if np.any(d):
        h, u = frame[:, 0], frame[:, 2]
        dh = d / np.linalg.norm(d)
        p = (dh - (dh @ h) * h) * np.linalg.norm(d)
        a = np.cross(u, p)
        if np.linalg.norm(a) > 1e-7:
            frame = _rot(a, min(np.linalg.norm(a), 1.0)) @ frame
    return frame


def _program(tmp_path, axiom, view):
    (tmp_path / "m.l").write_text(f"Lsystem: 0\nderivation length: 0\nAxiom: {axiom}\n"
                                  "endlsystem\n")  # fmt: skip
    (tmp_path / "m.v").write_text(view)
    return cpfg.parse((tmp_path / "m.l").read_text(), str(tmp_path / "m.l"))


def _ends(p):
    return np.asarray(interpret(Derivation(p).word, p).seg_end)


def test_the_view_reads_tropism_and_torque_lines_as_cpfg_scales_them():
    s = read_view("tropism: T: 0 1 0\ntropism: T: 0.0 2.0 0.0 A:90 E: 0.3 S: 0.1\n"
                  "torque: T: 0 1 0 I: 0.5\ntropism: T: 0 0 3 I: 6\n")  # fmt: skip
    assert s["tropisms"] == (
        ("tropism", (0.0, 1.0, 0.0), 0.0, 0.0, 0.0),
        ("tropism", (0.0, 1.0, 0.0), 90.0, 0.3, 0.1),  # normalised
        ("torque", (0.0, 0.5, 0.0), 0.0, 0.0, 0.0),  # times the intensity
        ("tropism", (0.0, 0.0, 3.0), 0.0, 0.0, 0.0),  # I/|T| = 2 is clipped to 1
    )


@pytest.mark.parametrize(
    ("line", "column", "match"),
    [
        ("tropism: T: 0 1 0 Q: 2", 19, "unknown subcommand 'Q:'"),
        ("tropism: A: 90", 15, "expected the vector"),
        ("torque: T: 0 0 0", 9, "zero vector"),
        ("tropism: T: 0 x 0", 15, "T: expected 3 numbers"),
        ("tropism: I: 2 T: 0 1 0", 10, "intensity 0 \\(or before T:\\)"),
    ],
)
def test_a_bad_tropism_line_names_file_line_and_column(line, column, match):
    with pytest.raises(LSystemSyntaxError, match=match) as info:
        read_view(f"angle factor: 8\n{line}\n", "plant.v")
    assert (info.value.filename, info.value.line, info.value.column) == ("plant.v", 2, column)


def test_two_tropisms_bend_the_heading_as_the_manual_formula(tmp_path):
    # an orthotropism toward +x and a diatropism (A: 90) about +y, both switched on by @Ts
    # (the elasticities are module parameters: cpfg keeps them as 32-bit floats)
    e1, e2 = float(np.float32(0.15)), float(np.float32(0.2))
    moves = [("tropism", (1.0, 0.0, 0.0), 0.0, e1), ("tropism", (0.0, 1.0, 0.0), 90.0, e2)]
    view = "tropism: T: 2 0 0\ntropism: T: 0 1 0 A: 90\n"
    p = _program(tmp_path, "&(30)@Ts(1,0.15)@Ts(2,0.2)F(1)F(1)F(1)F(1)F(1)", view)
    frame = _rot(np.array([-1.0, 0.0, 0.0]), math.radians(30)) @ _frame()  # &(30): about L
    pos, ends = np.zeros(3), []
    for _ in range(5):
        frame = _movements(frame, moves)  # before the step, as cpfg's movement_adjust
        pos = pos + frame[:, 0]
        ends.append(pos)
    got = _ends(p)
    assert np.abs(got - np.array(ends)).max() < 1e-12
    t = trace(Derivation(p).word, p)
    assert np.allclose(t.frames[-1], frame.T, atol=1e-12)  # rows H, L, U
    # each tropism alone bends otherwise: both count
    one = _program(tmp_path, "&(30)@Ts(1,0.15)F(1)F(1)F(1)F(1)F(1)", view)
    assert np.abs(_ends(one) - got).max() > 0.1


def test_the_bend_is_clipped_at_one_radian(tmp_path):
    p = _program(tmp_path, "@Ts(1,3)F(1)", "tropism: T: 1 0 0\n")
    h = trace(Derivation(p).word, p).frames[-1, 0]
    assert math.acos(h[1]) == pytest.approx(1.0, abs=1e-12)  # not 3 radians
    assert h[0] > 0  # toward T


def test_a_torque_rolls_about_the_heading_without_turning_it(tmp_path):
    moves = [("torque", (1.0, 0.0, 0.0), 0.0, 0.4)]
    p = _program(tmp_path, "/(10)@Ts(1,0.4)F(1)F(1)", "torque: T: 1 0 0 E: 0.0\n")
    frame = _rot(np.array([0.0, 1.0, 0.0]), math.radians(-10)) @ _frame()  # /: about H
    for _ in range(2):
        frame = _movements(frame, moves)
    t = trace(Derivation(p).word, p)
    assert np.allclose(t.frames[-1], frame.T, atol=1e-12)
    assert np.allclose(t.frames[-1, 0], [0.0, 1.0, 0.0], atol=1e-12)  # H stays


def test_elasticities_step_and_belong_to_the_branch(tmp_path):
    view = "tropism: T: 1 0 0 E: 0.1 S: 0.05\ntropism: T: 0 0 1 E: 0 S: 0.02\n"
    # @Ti(1) adds S: 0.05 inside the branch only; after ] the trunk bends with E: 0.1 again
    p = _program(tmp_path, "F(1)[@Ti(1)@Ti(2)@Td(2,0.01)F(1)]F(1)", view)
    got = _ends(p)
    moves = [("tropism", (1.0, 0.0, 0.0), 0.0, 0.1), ("tropism", (0.0, 0.0, 1.0), 0.0, 0.0)]
    trunk = _movements(_frame(), moves)
    first = trunk[:, 0]
    branch = _movements(trunk, [("tropism", (1.0, 0.0, 0.0), 0.0, 0.15),
                                ("tropism", (0.0, 0.0, 1.0), 0.0, 0.01)])  # fmt: skip
    rest = _movements(trunk, moves)
    assert np.allclose(got, [first, first + branch[:, 0], first + rest[:, 0]], atol=1e-12)


def test_an_index_without_a_tropism_line_is_ignored_with_a_warning(tmp_path):
    p = _program(tmp_path, "@Ts(3,0.5)F(1)", "tropism: T: 1 0 0\n")
    with pytest.warns(SylvaWarning, match=r"names tropism 3, but the view file defines 1"):
        got = _ends(p)
    assert np.allclose(got, [[0.0, 1.0, 0.0]])  # as cpfg: 'Movement index out of range'
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        zero = _program(tmp_path, "@Ts(1,0)F(1)", "tropism: T: 1 0 0\n")
        assert np.allclose(_ends(zero), [[0.0, 1.0, 0.0]])


def test_the_old_tropism_bends_after_the_step_and_underscore_steps_it(tmp_path):
    # WeepingBirch's construct: tropism direction with initial elasticity and increment,
    # '_' adds the increment (here it turns the bend from up to down) and _(e) sets it
    view = "tropism direction: 0,1,0\ninitial elasticity: 0.04\nelasticity increment: -0.1\n"
    p = _program(tmp_path, "+(60)F(1)_F(1)_(0.3)F(1)F(1)", view)
    frame = _rot(np.array([0.0, 0.0, 1.0]), math.radians(60)) @ _frame()
    t = np.array([0.0, 1.0, 0.0])
    pos, ends = np.zeros(3), []
    e3 = float(np.float32(0.3))  # _(0.3): a module parameter, a 32-bit float in cpfg
    for e in (0.04, -0.06, e3, e3):
        pos = pos + frame[:, 0]
        ends.append(pos)
        for side in (2, 1):  # toward U, then toward L: sin = e T.side
            h, v = frame[:, 0].copy(), frame[:, side].copy()
            c = e * (t @ v)
            s = math.sqrt(1.0 - c * c)
            frame[:, 0], frame[:, side] = s * h + c * v, s * v - c * h
    assert np.abs(_ends(p) - np.array(ends)).max() < 1e-12
    # the second segment's elasticity is negative: it bends down, away from T
    assert ends[2][1] - ends[1][1] < ends[1][1] - ends[0][1]


def test_underscore_means_nothing_outside_cpfg():
    a = interpret("+(60)F_F_F", dialect="abop", elasticity=0.2, elasticity_step=0.5)
    b = interpret("+(60)FFF", dialect="abop", elasticity=0.2, elasticity_step=0.5)
    assert np.array_equal(a.seg_end, b.seg_end)


def test_more_movements_than_sylva_draws_is_an_error_naming_the_line():
    text = "".join(f"tropism: T: 0 1 0 E: 0.{k}\n" for k in range(4)) + "torque: T: 1 0 0\n"
    with pytest.raises(LSystemSyntaxError, match="more than 4 tropism and torque") as info:
        read_view(text, "plant.v")
    assert (info.value.line, info.value.column) == (5, 8)  # its value
