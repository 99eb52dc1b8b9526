"""The turtle's H, L, U frame, checked numerically after every command (ABOP signs)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.lsystem.lstring import ModuleString
from sylva.turtle import TurtleSettingsError, interpret, trace

H0 = np.array([0.0, 1.0, 0.0])
L0 = np.array([-1.0, 0.0, 0.0])
U0 = np.array([0.0, 0.0, 1.0])


def rot(axis, deg):
    """Right-handed rotation matrix about a unit axis (Rodrigues), independent of sylva."""
    a = np.asarray(axis, float)
    t = math.radians(deg)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * k @ k


def frame_after(text, **kw):
    kw.setdefault("dialect", "abop")
    return trace(ModuleString.from_text(text), **kw)


def test_initial_frame_faces_up_with_h_cross_l_equal_u():
    t = frame_after("A")
    h, l, u = t.frames[0]
    np.testing.assert_allclose(h, H0)
    np.testing.assert_allclose(l, L0)
    np.testing.assert_allclose(np.cross(h, l), u)


@pytest.mark.parametrize(
    "cmd, expected_h",
    [
        ("+(90)", -np.array([1.0, 0, 0])),  # turn left: H toward L
        ("-(90)", np.array([1.0, 0, 0])),  # turn right
        ("&(90)", -U0),  # pitch down: H toward -U
        ("^(90)", U0),  # pitch up
        ("|", -H0),  # turn around
    ],
)
def test_heading_after_each_turn(cmd, expected_h):
    t = frame_after(cmd)
    np.testing.assert_allclose(t.frames[0, 0], expected_h, atol=1e-12)


def test_roll_keeps_heading_and_turns_left_vector_toward_up():
    t = frame_after("\\(90)")
    h, l, u = t.frames[0]
    np.testing.assert_allclose(h, H0, atol=1e-12)
    np.testing.assert_allclose(l, U0, atol=1e-12)  # ABOP R_H(90): L' = U
    np.testing.assert_allclose(u, -L0, atol=1e-12)
    t = frame_after("/(90)")
    np.testing.assert_allclose(t.frames[0, 1], -U0, atol=1e-12)


@pytest.mark.parametrize("cmd, axis_row, sign", [
    ("+", 2, 1), ("-", 2, -1), ("&", 1, 1), ("^", 1, -1), ("\\", 0, 1), ("/", 0, -1),
])  # fmt: skip
def test_every_rotation_is_a_right_handed_turn_about_a_frame_axis(cmd, axis_row, sign):
    rng = np.random.default_rng(7)
    # a random prefix puts the turtle in a general pose
    prefix = "".join(f"{rng.choice(list('+-&^/'))}({rng.uniform(5, 80):.3f})" for _ in range(6))
    angle = 37.5
    t = frame_after(prefix + f"{cmd}({angle})")
    before, after = t.frames[-2], t.frames[-1]
    r = rot(before[axis_row], sign * angle)
    np.testing.assert_allclose(after, before @ r.T, atol=1e-12)


def test_default_angle_comes_from_rot_and_parameters_override_it():
    t = frame_after("+", rot=30)
    np.testing.assert_allclose(
        t.frames[0, 0], [-math.sin(math.radians(30)), math.cos(math.radians(30)), 0], atol=1e-12
    )
    g = interpret(ModuleString.from_text("F(2)+(90)F"), dialect="abop", rot=30, len=3)
    np.testing.assert_allclose(g.seg_end, [[0, 2, 0], [-3, 2, 0]], atol=1e-12)


def test_frame_stays_orthonormal_over_many_turns():
    rng = np.random.default_rng(3)
    text = "".join(
        f"{rng.choice(list('+-&^/|'))}({rng.uniform(-180, 180):.6f})F" for _ in range(3000)
    )
    t = frame_after(text)
    f = t.frames[-1]
    np.testing.assert_allclose(f @ f.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(np.cross(f[0], f[1]), f[2], atol=1e-12)


def test_level_makes_left_horizontal_and_up_point_upward():
    t = frame_after("&(30)\\(40)+(20)$")
    h, l, u = t.frames[-1]
    np.testing.assert_allclose(h, t.frames[-2, 0])  # heading unchanged
    assert abs(l[1]) < 1e-12  # L horizontal
    np.testing.assert_allclose(l, np.cross([0, 1, 0], h) / np.linalg.norm(np.cross([0, 1, 0], h)))
    assert u[1] > 0
    np.testing.assert_allclose(np.cross(h, l), u, atol=1e-12)


def test_brackets_restore_position_and_frame():
    t = frame_after("F[+F&F]F")
    np.testing.assert_allclose(t.positions[-1], [0, 2, 0], atol=1e-12)
    np.testing.assert_allclose(t.frames[-1], np.stack([H0, L0, U0]), atol=1e-12)


def test_segment_records_know_their_module_parent_and_depth():
    g = interpret("F[+F[-F]]F", dialect="abop", rot=90)
    assert g.seg_module.tolist() == [0, 3, 6, 9]
    assert g.seg_parent.tolist() == [-1, 0, 1, 0]
    assert g.seg_depth.tolist() == [0, 1, 2, 0]


def test_move_without_drawing_breaks_the_axis():
    g = interpret("FfF", dialect="abop")
    assert g.n_segments == 2 and g.seg_parent.tolist() == [-1, -1]
    np.testing.assert_allclose(g.seg_start[1], [0, 2, 0])


def test_cut_skips_the_rest_of_the_branch():
    g = interpret("F[+F%F+F]F", dialect="abop", rot=90)
    assert g.n_segments == 3
    np.testing.assert_allclose(g.seg_end[-1], [0, 2, 0], atol=1e-12)
    assert interpret("FF%FFF", dialect="abop").n_segments == 2


def test_unknown_dialect_and_setting_are_user_errors():
    with pytest.raises(TurtleSettingsError, match="unknown turtle dialect"):
        interpret("F", dialect="logo")
    with pytest.raises(TurtleSettingsError, match="unknown setting 'lenght'"):
        interpret("F", dialect="lsys", lenght=2)
    with pytest.raises(TurtleSettingsError, match="must be a number"):
        interpret("F", dialect="lsys", len="long")
