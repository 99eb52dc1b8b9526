"""Numba kernel for Worley F1..Fn of any order n (private; see :mod:`sylva.texture.noise`).

The same feature points as :mod:`._cellkernels` (the jittered grid of ``worley`` or the
Poisson process of ``worley_poisson``, from the same hashes, so F1..F3 agree), but the ``n``
nearest distances are kept in a sorted array, and the ring-by-ring search widens until the
n-th distance is provably final (no unexamined cell can hold a closer point).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._cellkernels import (
    INV32,
    POISSON_MAX_RING,
    _cell_hash,
    _distance4,
    _point_hash,
    _ring_gap,
    hash32,
    poisson_count,
)

# the widest search ring: exact for any order up to (2 * MAX_RING - 1)^2 points in 2D
MAX_RING = POISSON_MAX_RING


@njit(cache=True, fastmath=False)
def worley_n(ndim, x, y, z, w, px, py, pz, pw, metric, jitter, density, seed, d, ids):
    """The ``len(d)`` nearest feature-point distances at ``(x, y[, z[, w]])``, ascending,
    into ``d`` (and the points' hashes into ``ids``).  ``density > 0``: the Poisson process
    of ``worley_poisson``; otherwise the jittered grid of ``worley`` (``jitter``)."""
    n = d.shape[0]
    for i in range(n):
        d[i] = math.inf
        ids[i] = 0
    cx = math.floor(x)
    cy = math.floor(y)
    cz = math.floor(z) if ndim >= 3 else 0.0
    cw = math.floor(w) if ndim >= 4 else 0.0
    icx = int(cx)
    icy = int(cy)
    icz = int(cz)
    icw = int(cw)
    hs = hash32(seed)
    # every axis periodic: once the window holds a whole tile, an empty tile stays empty
    maxp = max(px, py) if min(px, py) > 0 else MAX_RING * 4
    if ndim >= 3:
        maxp = max(maxp, pz) if pz > 0 else MAX_RING * 4
    if ndim >= 4:
        maxp = max(maxp, pw) if pw > 0 else MAX_RING * 4
    r = 0
    while True:
        rz = r if ndim >= 3 else 0
        rw = r if ndim >= 4 else 0
        for dw in range(-rw, rw + 1):
            for dz in range(-rz, rz + 1):
                for dy in range(-r, r + 1):
                    for dx in range(-r, r + 1):
                        if max(max(abs(dx), abs(dy)), max(abs(dz), abs(dw))) < r:
                            continue
                        ix = icx + dx
                        iy = icy + dy
                        iz = icz + dz
                        iw = icw + dw
                        h = _cell_hash(hs, ndim, ix, iy, iz, iw, px, py, pz, pw)
                        count = poisson_count(h, density) if density > 0.0 else 1
                        for j in range(count):
                            if density > 0.0:
                                hp = _point_hash(h, j)
                                ddx = ix + hash32(hp ^ 0x68E31DA4) * INV32 - x
                                ddy = iy + hash32(hp ^ 0xB5297A4D) * INV32 - y
                                ddz = 0.0
                                ddw = 0.0
                                if ndim >= 3:
                                    ddz = iz + hash32(hp ^ 0x1B56C4E9) * INV32 - z
                                if ndim >= 4:
                                    ddw = iw + hash32(hp ^ 0x7F4A7C15) * INV32 - w
                            else:
                                hp = h
                                ux = hash32(h ^ 0x68E31DA4) * INV32 - 0.5
                                uy = hash32(h ^ 0xB5297A4D) * INV32 - 0.5
                                ddx = ix + 0.5 + jitter * ux - x
                                ddy = iy + 0.5 + jitter * uy - y
                                ddz = 0.0
                                ddw = 0.0
                                if ndim >= 3:
                                    uz = hash32(h ^ 0x1B56C4E9) * INV32 - 0.5
                                    ddz = iz + 0.5 + jitter * uz - z
                                if ndim >= 4:
                                    uw = hash32(h ^ 0x7F4A7C15) * INV32 - 0.5
                                    ddw = iw + 0.5 + jitter * uw - w
                            dist = _distance4(metric, ddx, ddy, ddz, ddw)
                            if dist < d[n - 1]:  # insertion into the sorted n nearest
                                k = n - 1
                                while k > 0 and d[k - 1] > dist:
                                    d[k] = d[k - 1]
                                    ids[k] = ids[k - 1]
                                    k -= 1
                                d[k] = dist
                                ids[k] = hp
        if r >= 1:
            gap = _ring_gap(ndim, metric, r, x - cx, y - cy, z - cz, w - cw)
            if d[n - 1] <= gap or r >= MAX_RING or (d[0] == math.inf and 2 * r + 1 >= maxp):
                break
        r += 1


@njit(cache=True, fastmath=False, parallel=True)
def worley_n_points(ndim, xs, ys, zs, ws, px, py, pz, pw, metric, jitter, density, seed, n):
    """:func:`worley_n` at every point: ``(F, cell)``, ``F`` of shape (len(xs), n) (F1..Fn)
    and ``cell`` the nearest point's id in [0, 1)."""
    m = xs.shape[0]
    out = np.empty((m, n))
    cell = np.empty(m)
    for i in prange(m):
        d = np.empty(n)
        ids = np.empty(n, np.int64)
        worley_n(ndim, xs[i], ys[i], zs[i], ws[i], px, py, pz, pw, metric, jitter, density,
                 seed, d, ids)
        for k in range(n):
            out[i, k] = d[k]
        cell[i] = hash32(ids[0] ^ 0x2545F491) * INV32
    return out, cell
