"""Seed 004's discrete randomness: Squirrel3 integer noise (Appendix A.2).

All discrete choices of the world (biome jitter, grass, plant salts, cache indices) come
from these hashes, never from a global random state, so a world is a pure function of its
seed and of world coordinates: chunks agree wherever they are generated.

``hash2d(x, z) = hash1d(x + 198491317·z)`` and ``hash3d(x, y, z) = hash1d(x + 198491317·y
+ 6542989·z)``; ``hash01 = hash / (2³² − 1)``; ``limited(…, n) = uint(hash01·n)`` (clamped
to ``n − 1``).  Every function takes scalars or NumPy arrays (broadcast; int64 results).

Examples
--------
>>> hash1d(0), hash1d(1)
(2957163356, 2179289154)
>>> hash2d(3, 4, seed=7) == hash1d(3 + 198491317 * 4, seed=7)
True
>>> 0 <= limited(12345, 5) < 5
True
"""

from __future__ import annotations

import numpy as np

__all__ = ["UINT_MAX", "hash01", "hash1d", "hash2d", "hash3d", "limited"]

UINT_MAX = 4294967295
_M = np.uint64(0xFFFFFFFF)


def _u32(x) -> np.ndarray:
    return (np.asarray(x, dtype=np.int64).astype(np.uint64)) & _M


def _squirrel(x, seed) -> np.ndarray:
    with np.errstate(over="ignore"):
        m = (_u32(x) * np.uint64(0x68E31DA4)) & _M
        m = (m + _u32(seed)) & _M
        m ^= m >> np.uint64(8)
        m = (m + np.uint64(0xB5297A4D)) & _M
        m ^= (m << np.uint64(8)) & _M
        m = (m * np.uint64(0x1B56C4E9)) & _M
        m ^= m >> np.uint64(8)
    return m.astype(np.int64)


def _out(a: np.ndarray, *args):
    if all(np.ndim(v) == 0 for v in args):
        return int(a)
    return a


def hash1d(x, seed=0):
    """Squirrel3 of the integer ``x`` under ``seed``: a ``uint32`` value (int / int64 array).

    Parameters
    ----------
    x : int or int array
        Wrapped to 32 bits (float coordinates must be truncated by the caller).
    seed : int or int array

    Returns
    -------
    int or int64 ndarray, values in ``[0, 2³² − 1]``
    """
    return _out(_squirrel(x, seed), x, seed)


def _combine(*coords) -> np.ndarray:
    ks = (1, 198491317, 6542989)
    with np.errstate(over="ignore"):
        acc = np.zeros(np.broadcast(*coords).shape, np.int64)
        for k, c in zip(ks, coords, strict=False):
            acc = acc + np.asarray(c, np.int64) * np.int64(k)
    return acc


def hash2d(x, z, seed=0):
    """``hash1d(x + 198491317·z, seed)``: the 2D hash seed 004 uses for (x, z) positions."""
    return _out(_squirrel(_combine(x, z), seed), x, z, seed)


def hash3d(x, y, z, seed=0):
    """``hash1d(x + 198491317·y + 6542989·z, seed)``."""
    return _out(_squirrel(_combine(x, y, z), seed), x, y, z, seed)


def hash01(h):
    """A hash value scaled to [0, 1] (``h / (2³² − 1)``)."""
    if np.ndim(h) == 0:
        return int(h) / UINT_MAX
    return np.asarray(h, np.float64) / UINT_MAX


def limited(x, n: int, seed=0):
    """An index in ``[0, n)`` from ``hash1d(x, seed)``: ``uint(hash01·n)``, at most ``n − 1``."""
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    v = np.minimum((hash01(hash1d(x, seed)) * n).astype(np.int64) if np.ndim(x) else
                   int(hash01(hash1d(x, seed)) * n), n - 1)
    return int(v) if np.ndim(v) == 0 else v
