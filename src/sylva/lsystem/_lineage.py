"""Lineage keys: the random stream of a module derived from its ancestry (issue 19 item 6).

Every module carries a ``uint64`` key, a hash of its parent's key and its index in the
parent's successor; the axiom's modules descend from the seed.  The engine draws a
stochastic module's rule from its key and the step (``Derivation(lineage=True)``), so an
edit to one branch's rules leaves every other branch's modules as they were.

Examples
--------
>>> import numpy as np
>>> k = axiom_keys(7, 2)
>>> bool(lineage_keys(k[:1], np.array([0]))[0] == lineage_keys(k[:1], np.array([0]))[0])
True
"""

from __future__ import annotations

import numpy as np

__all__ = ["axiom_keys", "child_index", "decomposed_keys", "lineage_keys"]

MASK = (1 << 64) - 1


_GOLDEN = np.uint64(0x9E3779B97F4A7C15)


def _mix64(z: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser over a ``uint64`` array (wrapping arithmetic)."""
    z = z ^ (z >> np.uint64(30))
    z = z * np.uint64(0xBF58476D1CE4E5B9)
    z = z ^ (z >> np.uint64(27))
    z = z * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def lineage_keys(parents: np.ndarray, index: np.ndarray) -> np.ndarray:
    """The lineage keys of modules: a hash of their parent's key and their index in the
    parent's successor (``uint64``; the axiom's parent is the seed)."""
    return _mix64(parents + (index.astype(np.uint64) + np.uint64(1)) * _GOLDEN)


def axiom_keys(seed: int, n: int) -> np.ndarray:
    return lineage_keys(np.full(n, seed & MASK, np.uint64), np.arange(n))


def child_index(src: np.ndarray) -> np.ndarray:
    """For ``src`` (non-decreasing), each entry's index among the entries of its value."""
    m = src.shape[0]
    if m == 0:
        return np.zeros(0, np.int64)
    start = np.flatnonzero(np.r_[True, src[1:] != src[:-1]])
    return np.arange(m) - np.repeat(start, np.diff(np.r_[start, m]))


def decomposed_keys(keys: np.ndarray, src: np.ndarray) -> np.ndarray:
    """Lineage keys after decomposition passes (``src``: the module each came from); a
    module the passes left alone keeps its key."""
    alone = np.bincount(src, minlength=keys.shape[0])[src] == 1
    return np.where(alone, keys[src], lineage_keys(keys[src], child_index(src)))
