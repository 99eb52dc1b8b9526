"""Numba kernel for Worley cellular noise (private; see :mod:`sylva.texture.noise`).

One feature point per unit cell (a jittered grid), placed by a 32-bit integer hash of the
cell coordinates and the seed, so the texture is identical on every machine.  The search
starts with the 3^d neighbourhood and widens ring by ring until the k-th distance is
provably final (no unexamined cell can hold a closer point), so F1, F2 and F3 are exact.
"""

from __future__ import annotations

import math

from numba import njit

MASK = 0xFFFFFFFF
INV32 = 1.0 / 4294967296.0

EUCLIDEAN, MANHATTAN, CHEBYSHEV, EUCLIDEAN_SQ = 0, 1, 2, 3
MAX_RING = 4


@njit(cache=True, inline="always")
def hash32(a):
    """A 32-bit integer finaliser (Chris Wellons' lowbias32); ``a`` is masked to 32 bits."""
    a &= MASK
    a = ((a ^ (a >> 16)) * 0x7FEB352D) & MASK
    a = ((a ^ (a >> 15)) * 0x846CA68B) & MASK
    return a ^ (a >> 16)


@njit(cache=True, inline="always")
def _pmod(i, period):
    return i % period if period > 0 else i


@njit(cache=True)
def worley(ndim, x, y, z, w, px, py, pz, pw, metric, jitter, seed, needk):
    """Distances to the 1st, 2nd and 3rd nearest feature points and the nearest cell's id.

    Returns ``(f1, f2, f3, cell_id)``; ``cell_id`` is a hash in [0, 1).
    """
    cx = math.floor(x)
    cy = math.floor(y)
    cz = math.floor(z) if ndim >= 3 else 0.0
    cw = math.floor(w) if ndim >= 4 else 0.0
    icx = int(cx)
    icy = int(cy)
    icz = int(cz)
    icw = int(cw)
    f1 = math.inf
    f2 = math.inf
    f3 = math.inf
    best = 0
    hs = hash32(seed)
    r = 1
    while True:
        rz = r if ndim >= 3 else 0
        rw = r if ndim >= 4 else 0
        for dw in range(-rw, rw + 1):
            for dz in range(-rz, rz + 1):
                for dy in range(-r, r + 1):
                    for dx in range(-r, r + 1):
                        if r > 1 and max(max(abs(dx), abs(dy)), max(abs(dz), abs(dw))) < r:
                            continue
                        ix = icx + dx
                        iy = icy + dy
                        iz = icz + dz
                        iw = icw + dw
                        h = hash32(hs ^ (_pmod(ix, px) & MASK))
                        h = hash32(h ^ (_pmod(iy, py) & MASK))
                        if ndim >= 3:
                            h = hash32(h ^ (_pmod(iz, pz) & MASK))
                        if ndim >= 4:
                            h = hash32(h ^ (_pmod(iw, pw) & MASK))
                        ddx = ix + 0.5 + jitter * (hash32(h ^ 0x68E31DA4) * INV32 - 0.5) - x
                        ddy = iy + 0.5 + jitter * (hash32(h ^ 0xB5297A4D) * INV32 - 0.5) - y
                        ddz = 0.0
                        ddw = 0.0
                        if ndim >= 3:
                            ddz = iz + 0.5 + jitter * (hash32(h ^ 0x1B56C4E9) * INV32 - 0.5) - z
                        if ndim >= 4:
                            ddw = iw + 0.5 + jitter * (hash32(h ^ 0x7F4A7C15) * INV32 - 0.5) - w
                        if metric == MANHATTAN:
                            d = abs(ddx) + abs(ddy) + abs(ddz) + abs(ddw)
                        elif metric == CHEBYSHEV:
                            d = max(max(abs(ddx), abs(ddy)), max(abs(ddz), abs(ddw)))
                        else:
                            d = ddx * ddx + ddy * ddy + ddz * ddz + ddw * ddw
                            if metric == EUCLIDEAN:
                                d = math.sqrt(d)
                        if d < f1:
                            f3 = f2
                            f2 = f1
                            f1 = d
                            best = h
                        elif d < f2:
                            f3 = f2
                            f2 = d
                        elif d < f3:
                            f3 = d
        # every unexamined cell lies at least `gap` away along some axis
        gap = min(x - cx + r, r + 1 - (x - cx))
        gap = min(gap, min(y - cy + r, r + 1 - (y - cy)))
        if ndim >= 3:
            gap = min(gap, min(z - cz + r, r + 1 - (z - cz)))
        if ndim >= 4:
            gap = min(gap, min(w - cw + r, r + 1 - (w - cw)))
        if metric == EUCLIDEAN_SQ:
            gap = gap * gap
        fk = f1 if needk <= 1 else (f2 if needk == 2 else f3)
        if fk <= gap or r >= MAX_RING:
            break
        r += 1
    return f1, f2, f3, hash32(best ^ 0x2545F491) * INV32
