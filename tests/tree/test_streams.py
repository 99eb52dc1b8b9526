"""The components' random streams made from the compiled seed hash are NumPy's own."""

import copy

import numpy as np
import pytest

from sylva import _jit
from sylva.tree import _streams
from sylva.tree._kernels import seed_state


def test_seed_hash_is_numpys_seed_sequence():
    rs = np.random.default_rng(0)
    for trial in range(300):
        words = [int(x) for x in rs.integers(0, 2**32 if trial % 3 else 20,
                                             int(rs.integers(1, 12)))]
        if trial % 7 == 0:
            words[0] = 0
        ref = np.random.SeedSequence(words).generate_state(4, np.uint64)
        assert np.array_equal(seed_state(np.array(words, np.int64)), ref), words


@pytest.mark.parametrize("words", [(0,), (7, 0, 1, 3, 1, 5, 2, 0), (2**32 - 1, 4, 9, 7),
                                   (5, 2**40)])  # the last: past a word, NumPy's road
def test_a_stream_is_default_rngs(words):
    with _jit.compiled():  # the compiled hash, whatever the cache holds
        g = _streams.stream(*words)
    ref = np.random.default_rng(list(words))
    assert np.array_equal(g.uniform(size=50), ref.uniform(size=50))
    assert g.integers(0, 1000) == ref.integers(0, 1000)
    twin = copy.deepcopy(g)  # components are duplicated with their streams
    assert twin.uniform() == g.uniform()


def test_uniform_is_generator_uniform_bit_for_bit():
    """``_streams.uniform`` (and the ``rng.random()`` the stems draw for ``rng.uniform()``)
    takes the same step of the stream and gives the same double as ``Generator.uniform``,
    over the bounds the stems use and random ones."""
    rs = np.random.default_rng(3)
    lows = rs.normal(0.0, 100.0, 2000)
    bounds = [(0.0, 2 * np.pi), (-1, 1), (0.2, 0.8), (0.25, 0.75), (0, 360), (-0.04, 0.04),
              (-8, 8), (-30.0, 30.0), (0.0, 1.0)]
    bounds += list(zip(lows.tolist(), (lows + np.abs(rs.normal(0.0, 100.0, 2000))).tolist()))
    a, b = np.random.default_rng([7, 1, 2]), np.random.default_rng([7, 1, 2])
    for lo, hi in bounds:
        for _ in range(10):
            assert np.float64(a.uniform(lo, hi)).tobytes() == np.float64(
                _streams.uniform(b, lo, hi)).tobytes()
        assert a.uniform() == b.random()
        d = abs(hi - lo)
        assert a.uniform(-d, d) == -d + (d + d) * b.random()  # FloatParameter.sample's form
