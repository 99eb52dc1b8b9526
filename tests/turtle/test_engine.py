"""Seed 004's block turtle and executor (§4.4–4.9, Appendix A)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.lsystem.ast import Module, Pattern, Program, Rule
from sylva.turtle import generate, hash01, hash1d, interpret, trace
from sylva.turtle.engine import limited


def moved(text, **kw):
    t = trace(text, dialect="engine", **kw)
    start = trace("A", dialect="engine", **kw).positions[0]
    return t, t.positions[-1] - start


def test_start_yaw_is_minus_90_degrees():
    t, _ = moved("A")
    h, l, u = t.frames[0]
    np.testing.assert_allclose(h, [0, 0, -1], atol=1e-12)  # Front
    np.testing.assert_allclose(-l, [1, 0, 0], atol=1e-12)  # Right
    np.testing.assert_allclose(u, [0, 1, 0], atol=1e-12)  # Up


@pytest.mark.parametrize(
    "text, settings, expected",
    [
        ("-F", {"yaw": 90}, (1, 0, 0)),  # yaw +90 then forward 1
        ("^F", {"pitch": 90}, (0, 1, 0)),  # pitch +90 then forward 1
        ("-F", {"yaw": 45, "scale": math.sqrt(2)}, (1, 0, -1)),  # yaw +45, forward sqrt 2
    ],
)
def test_seed_004_turtle_vectors(text, settings, expected):
    _, d = moved(text, **settings)
    np.testing.assert_allclose(d, expected, atol=1e-3)  # the engine's epsilon


def test_plus_turns_left_and_minus_right():
    _, d = moved("+F", yaw=90)
    np.testing.assert_allclose(d, [-1, 0, 0], atol=1e-12)


def test_pitch_guard_keeps_the_frame_finite_and_orthonormal():
    t, _ = moved("^^", pitch=45)
    f = t.frames[-1]
    assert np.isfinite(f).all()
    np.testing.assert_allclose(f @ f.T, np.eye(3), atol=1e-9)
    np.testing.assert_allclose(f[0], [0, 1, 0], atol=1e-3)


def test_block_rule_emits_floor_base_over_scale_blocks():
    assert interpret("F", dialect="engine").n_blocks == 1
    assert interpret("xF", dialect="engine", shrink=0.5).n_blocks == 2
    assert interpret("xxF", dialect="engine", shrink=0.5).n_blocks == 4
    assert interpret("xF", dialect="engine", shrink=0.8).n_blocks == 1
    g = interpret("xxU", dialect="engine", shrink=0.5)
    np.testing.assert_allclose(np.diff(g.block_center[:, 1]), 0.25)
    np.testing.assert_allclose(g.block_size, 0.25)


def test_shrinking_moves_back_so_blocks_touch():
    g = interpret("UxU", dialect="engine", shrink=0.5)
    c, s = g.block_center[:, 1], g.block_size
    np.testing.assert_allclose(c, [0.0, 0.75, 1.25])
    assert c[0] + s[0] / 2 == pytest.approx(c[1] - s[1] / 2)  # no gap, no overlap
    g = interpret("UxUXU", dialect="engine", shrink=0.5)
    top = g.block_center[2, 1] + g.block_size[2] / 2
    assert g.block_center[3, 1] - g.block_size[3] / 2 == pytest.approx(top)


def test_first_block_is_anchored_to_the_ground():
    g = interpret("U", dialect="engine", scale=0.5)
    assert g.block_center[0, 1] - g.block_size[0] / 2 == pytest.approx(-0.5)


def test_output_buffers_switch_and_are_restored_by_brackets():
    g = interpret("F1F[2F]F0F", dialect="engine")
    assert g.block_buffer.tolist() == [0, 1, 2, 1, 0]
    assert g.block_module.tolist() == [0, 2, 5, 7, 9]


def _squirrel_reference(x: int, seed: int) -> int:
    """Seed 004 A.2 pseudo-code on Python ints, written out independently."""
    m = ((x & 0xFFFFFFFF) * 0x68E31DA4) & 0xFFFFFFFF
    m = (m + seed) & 0xFFFFFFFF
    m ^= m >> 8
    m = (m + 0xB5297A4D) & 0xFFFFFFFF
    m ^= (m << 8) & 0xFFFFFFFF
    m = (m * 0x1B56C4E9) & 0xFFFFFFFF
    m ^= m >> 8
    return m


@pytest.mark.parametrize("x, seed", [(0, 0), (1, 0), (-1, 0), (123456789, 42), (2**31, 2**32 - 1)])
def test_squirrel3_follows_the_published_steps(x, seed):
    assert hash1d(x, seed) == _squirrel_reference(x, seed)


def test_squirrel3_hash_is_a_uint32_stream():
    xs = [hash1d(i) for i in range(2000)]
    assert all(0 <= x < 2**32 for x in xs) and len(set(xs)) == 2000
    assert hash1d(5, seed=1) != hash1d(5, seed=2)
    u = np.array([hash01(i) for i in range(2000)])
    assert 0.45 < u.mean() < 0.55 and u.min() >= 0 and u.max() <= 1
    assert all(0 <= limited(i, 3) < 3 for i in range(500))


def test_random_angle_is_within_angle_var_and_follows_the_salt():
    def yaw_after(seed):
        t = trace("+" * 50, dialect="engine", yaw=10, angle_var=0.2, seed=seed)
        h = t.frames[:, 0]
        yaw = np.degrees(np.unwrap(np.arctan2(h[:, 2], h[:, 0])))
        return np.diff(np.concatenate([[-90.0], yaw]))

    d = yaw_after(7)
    assert np.all(d <= -8.0 + 1e-9) and np.all(d >= -12.0 - 1e-9)  # -(1 -/+ 0.2) * 10
    assert np.std(d) > 0.3
    np.testing.assert_array_equal(d, yaw_after(7))  # same salt, same plant
    assert not np.allclose(d, yaw_after(8))
    np.testing.assert_allclose(
        trace("+", dialect="engine", yaw=10).frames[0, 0],
        [-math.sin(math.radians(10)), 0, -math.cos(math.radians(10))],
    )


def _acacia() -> Program:
    def mods(s):
        return tuple(Module(c) for c in s)

    rules = [("U", "uU"), ("A", "+uuE"), ("A", "-uE"), ("A", "+uE"), ("A", "-E"), ("A", "uuE"),
             ("A", "uE"), ("E", "x[++++UE1S&F+F+F+F]+UE"), ("E", "x[++++++UE1S&F+F+F+F]++UE"),
             ("E", "x[++UE1S&F+F+F+F]-UE")]  # fmt: skip
    return Program(
        axiom=mods("^uA1S&F+F+F+F"),
        rules=tuple(Rule(Pattern(a), mods(b)) for a, b in rules),
        settings={"turtle": "engine", "yaw": 45.0, "pitch": 45.0, "shrink": 0.8},
        dialect="engine",
    )


def test_executor_is_deterministic_per_salt_and_splits_buffers():
    p = _acacia()
    a = generate(p, salt=11, derivations=4, angle_var=0.15)
    b = generate(p, salt=11, derivations=4, angle_var=0.15)
    c = generate(p, salt=12, derivations=4, angle_var=0.15)
    np.testing.assert_array_equal(a.block_center, b.block_center)
    assert a.n_blocks != c.n_blocks or not np.allclose(a.block_center, c.block_center)
    assert set(np.unique(a.block_buffer).tolist()) == {0, 1}  # trunk and leaves


def test_executor_scale_grows_with_the_derivation_count():
    p = _acacia()
    for salt in range(6):
        k = limited(salt, 3)
        g = generate(p, salt=salt, derivations=2, derivation_var=3, min_scale=0.7, max_scale=1.0)
        assert g.block_size.max() == pytest.approx(0.7 + 0.15 * k)
