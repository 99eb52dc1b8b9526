"""Numba kernel for Worley cellular noise (private; see :mod:`sylva.texture.noise`).

One feature point per unit cell (a jittered grid), placed by a 32-bit integer hash of the
cell coordinates and the seed, so the texture is identical on every machine.  The search
starts with the 3^d neighbourhood and widens ring by ring until the k-th distance is
provably final (no unexamined cell can hold a closer point), so F1, F2 and F3 are exact.

:func:`worley_poisson` is Worley's own point process (Worley 1996): each cell holds a
Poisson-distributed number of feature points (mean ``density``, at most
:data:`POISSON_MAX_POINTS`), each uniform in the cell, so the points form a Poisson process
with no grid regularity.  Cells can be empty, so its search widens up to
:data:`POISSON_MAX_RING` rings.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, uint64

MASK = 0xFFFFFFFF
INV32 = 1.0 / 4294967296.0

EUCLIDEAN, MANHATTAN, CHEBYSHEV, EUCLIDEAN_SQ = 0, 1, 2, 3
MAX_RING = 4
# Poisson process (worley_poisson): points per cell at most (P(N > 32) < 1e-10 for a
# density up to 8) and the widest search ring (exact with overwhelming probability for a
# density of at least 0.01: the disc of radius 64 then holds about 100 points on average)
POISSON_MAX_POINTS = 32
POISSON_MAX_RING = 64
_COUNT_SALT = 0x5851F42D  # the hashed uniform that draws a cell's point count
_POINT_SALT = 0x9E3779B9  # point i of a cell hashes (i + 1) * _POINT_SALT


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


@njit(cache=True, inline="always")
def _cell_hash(hs, ndim, ix, iy, iz, iw, px, py, pz, pw):
    """The hash of cell ``(ix, iy[, iz[, iw]])`` (wrapped by the periods) as in :func:`worley`."""
    h = hash32(hs ^ (_pmod(ix, px) & MASK))
    h = hash32(h ^ (_pmod(iy, py) & MASK))
    if ndim >= 3:
        h = hash32(h ^ (_pmod(iz, pz) & MASK))
    if ndim >= 4:
        h = hash32(h ^ (_pmod(iw, pw) & MASK))
    return h


@njit(cache=True, inline="always")
def _distance4(metric, ddx, ddy, ddz, ddw):
    """The ``metric`` distance of the offset (ddx, ddy, ddz, ddw) (squared for EUCLIDEAN_SQ)."""
    if metric == MANHATTAN:
        return abs(ddx) + abs(ddy) + abs(ddz) + abs(ddw)
    if metric == CHEBYSHEV:
        return max(max(abs(ddx), abs(ddy)), max(abs(ddz), abs(ddw)))
    d = ddx * ddx + ddy * ddy + ddz * ddz + ddw * ddw
    return math.sqrt(d) if metric == EUCLIDEAN else d


@njit(cache=True, inline="always")
def _offer(d, h, f1, f2, f3, best):
    """F1 <= F2 <= F3 and the nearest point's hash after offering distance ``d`` of ``h``."""
    if d < f1:
        return d, f1, f2, h
    if d < f2:
        return f1, d, f2, best
    if d < f3:
        return f1, f2, d, best
    return f1, f2, f3, best


@njit(cache=True, inline="always")
def _ring_gap(ndim, metric, r, fx, fy, fz, fw):
    """The least distance from the point (at ``fx, fy …`` in its cell) to any cell outside
    the rings searched up to ``r``: every unexamined cell lies at least this far away along
    some axis (squared for EUCLIDEAN_SQ)."""
    gap = min(min(fx + r, r + 1 - fx), min(fy + r, r + 1 - fy))
    if ndim >= 3:
        gap = min(gap, min(fz + r, r + 1 - fz))
    if ndim >= 4:
        gap = min(gap, min(fw + r, r + 1 - fw))
    return gap * gap if metric == EUCLIDEAN_SQ else gap


@njit(cache=True, fastmath=False)
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
                        h = _cell_hash(hs, ndim, ix, iy, iz, iw, px, py, pz, pw)
                        ddx = ix + 0.5 + jitter * (hash32(h ^ 0x68E31DA4) * INV32 - 0.5) - x
                        ddy = iy + 0.5 + jitter * (hash32(h ^ 0xB5297A4D) * INV32 - 0.5) - y
                        ddz = 0.0
                        ddw = 0.0
                        if ndim >= 3:
                            ddz = iz + 0.5 + jitter * (hash32(h ^ 0x1B56C4E9) * INV32 - 0.5) - z
                        if ndim >= 4:
                            ddw = iw + 0.5 + jitter * (hash32(h ^ 0x7F4A7C15) * INV32 - 0.5) - w
                        d = _distance4(metric, ddx, ddy, ddz, ddw)
                        f1, f2, f3, best = _offer(d, h, f1, f2, f3, best)
        fk = f1 if needk <= 1 else (f2 if needk == 2 else f3)
        if fk <= _ring_gap(ndim, metric, r, x - cx, y - cy, z - cz, w - cw) or r >= MAX_RING:
            break
        r += 1
    return f1, f2, f3, hash32(best ^ 0x2545F491) * INV32


@njit(cache=True, inline="always")
def poisson_count(h, density):
    """The number of feature points of the cell with hash ``h``: Poisson(``density``) by the
    inverse CDF against a hashed uniform (terms computed on the fly), capped at
    :data:`POISSON_MAX_POINTS`."""
    u = hash32(h ^ _COUNT_SALT) * INV32
    p = math.exp(-density)
    cdf = p
    n = 0
    while u >= cdf and n < POISSON_MAX_POINTS:
        n += 1
        p *= density / n
        cdf += p
    return n


@njit(cache=True, inline="always")
def _point_hash(h, i):
    return hash32(h ^ (((i + 1) * _POINT_SALT) & MASK))


@njit(cache=True, fastmath=False)
def worley_poisson(ndim, x, y, z, w, px, py, pz, pw, metric, density, seed, needk):
    """:func:`worley` for a Poisson process of ``density`` points per unit cell.

    Cell ``c`` holds :func:`poisson_count` points; point ``i`` is at ``c + u`` with ``u``
    uniform in [0, 1)^d from the hash of the point (the cell hash, wrapped by the periods,
    and ``i``), so a periodic point set repeats exactly.  The search widens ring by ring
    until the k-th distance is provably final or :data:`POISSON_MAX_RING` is reached.  With
    a period on every axis the tile may hold no point at all; the distances are then
    infinite (the search stops once the window holds a whole tile).
    Returns ``(f1, f2, f3, cell_id)``; ``cell_id`` is a hash of the nearest point in [0, 1).
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
    # the largest period when every axis has one (a tile can hold no point at all)
    maxp = max(px, py) if min(px, py) > 0 else POISSON_MAX_RING * 4
    if ndim >= 3:
        maxp = max(maxp, pz) if pz > 0 else POISSON_MAX_RING * 4
    if ndim >= 4:
        maxp = max(maxp, pw) if pw > 0 else POISSON_MAX_RING * 4
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
                        h = _cell_hash(hs, ndim, ix, iy, iz, iw, px, py, pz, pw)
                        for i in range(poisson_count(h, density)):
                            hp = _point_hash(h, i)
                            ddx = ix + hash32(hp ^ 0x68E31DA4) * INV32 - x
                            ddy = iy + hash32(hp ^ 0xB5297A4D) * INV32 - y
                            ddz = 0.0
                            ddw = 0.0
                            if ndim >= 3:
                                ddz = iz + hash32(hp ^ 0x1B56C4E9) * INV32 - z
                            if ndim >= 4:
                                ddw = iw + hash32(hp ^ 0x7F4A7C15) * INV32 - w
                            d = _distance4(metric, ddx, ddy, ddz, ddw)
                            f1, f2, f3, best = _offer(d, hp, f1, f2, f3, best)
        fk = f1 if needk <= 1 else (f2 if needk == 2 else f3)
        gap = _ring_gap(ndim, metric, r, x - cx, y - cy, z - cz, w - cw)
        if fk <= gap or r >= POISSON_MAX_RING:
            break
        if f1 == math.inf and 2 * r + 1 >= maxp:
            break  # every axis periodic and the searched window holds a whole empty tile
        r += 1
    return f1, f2, f3, hash32(best ^ 0x2545F491) * INV32


@njit(cache=True, fastmath=False)
def poisson_cell_points(ndim, ix, iy, iz, iw, px, py, pz, pw, density, seed):
    """The feature points of one cell of :func:`worley_poisson` (for tests and debugging):
    ``(points, hashes)``, ``points`` of shape (n, ndim) and the points' hashes."""
    h = _cell_hash(hash32(seed), ndim, ix, iy, iz, iw, px, py, pz, pw)
    n = poisson_count(h, density)
    pts = np.empty((n, ndim))
    hashes = np.empty(n, np.int64)
    for i in range(n):
        hp = _point_hash(h, i)
        hashes[i] = hp
        pts[i, 0] = ix + hash32(hp ^ 0x68E31DA4) * INV32
        pts[i, 1] = iy + hash32(hp ^ 0xB5297A4D) * INV32
        if ndim >= 3:
            pts[i, 2] = iz + hash32(hp ^ 0x1B56C4E9) * INV32
        if ndim >= 4:
            pts[i, 3] = iw + hash32(hp ^ 0x7F4A7C15) * INV32
    return pts, hashes


# Worley combinations (``wpar[1]``)
W_F1, W_F2, W_F3, W_F2_F1, W_F1_F2SUM, W_F1F2, W_SQRT_F1F2, W_SQRT_F2_F1 = range(8)
W_INV_F1, W_INV_F2, W_CELL, W_LINEAR = 8, 9, 10, 11
NEEDK = (1, 2, 3, 2, 2, 2, 2, 2, 1, 2, 1, 3)


@njit(cache=True, inline="always")
def combine(combo, f1, f2, f3, cid, c1, c2, c3):
    """The Worley output ``combo`` from F1..F3 and the cell id (``c*``: linear weights)."""
    if combo == W_F1:
        return f1
    if combo == W_F2:
        return f2
    if combo == W_F3:
        return f3
    if combo == W_F2_F1:
        return f2 - f1
    if combo == W_F1_F2SUM:
        return f1 + f2
    if combo == W_F1F2:
        return f1 * f2
    if combo == W_SQRT_F1F2:
        return math.sqrt(f1 * f2)
    if combo == W_SQRT_F2_F1:
        return math.sqrt(f2 - f1)
    if combo == W_INV_F1:
        return 1.0 - f1
    if combo == W_INV_F2:
        return 1.0 - f2
    if combo == W_CELL:
        return cid
    return c1 * f1 + c2 * f2 + c3 * f3


# ----------------------------------------------------------------------------- grids
# On a grid row (fixed y and z) the samples that share a lattice cell form a run, and every
# sample of a run has the same 3^d candidate feature points.  Each run takes its candidates
# from a window of three lattice columns (each column hashed once per row) and updates
# F1..F3 for all its samples in branch-free loops that vectorise.  The distances use the
# operations of :func:`worley`, so F1..F3 are the same (they do not depend on the order in
# which the candidates come); for the nearest cell's id, where the order decides ties, the
# candidates are visited in the order of :func:`worley`.  A sample whose k-th distance is
# not provably final after the 3^d neighbourhood is handed to :func:`worley` itself.


@njit(cache=True, inline="always")
def _feature(hs, ndim, ix, iy, iz, px, py, pz, jitter):
    """Hash and feature point of cell ``(ix, iy[, iz])`` exactly as in :func:`worley`."""
    h = hash32(hs ^ (_pmod(ix, px) & MASK))
    h = hash32(h ^ (_pmod(iy, py) & MASK))
    if ndim >= 3:
        h = hash32(h ^ (_pmod(iz, pz) & MASK))
    fx = ix + 0.5 + jitter * (hash32(h ^ 0x68E31DA4) * INV32 - 0.5)
    fy = iy + 0.5 + jitter * (hash32(h ^ 0xB5297A4D) * INV32 - 0.5)
    fz = 0.0
    if ndim >= 3:
        fz = iz + 0.5 + jitter * (hash32(h ^ 0x1B56C4E9) * INV32 - 0.5)
    return h, fx, fy, fz


@njit(cache=True, inline="always")
def _dist(metric, ddx, cy2, cz2, cy, cz):
    """The distance of :func:`worley` from the x offset and the precomputed y/z parts
    (squared ``cy2, cz2`` or absolute ``cy, cz``; zero in 2D, where adding them changes
    nothing)."""
    if metric == MANHATTAN:
        return abs(ddx) + cy + cz
    if metric == CHEBYSHEV:
        return max(max(abs(ddx), cy), cz)
    d = ddx * ddx + cy2 + cz2
    return math.sqrt(d) if metric == EUCLIDEAN else d


@njit(cache=True, inline="always")
def _keep(d, o1, o2, o3):
    """F1 <= F2 <= F3 after offering distance ``d``: the branches of :func:`worley` as
    selects (equal values in every case, ties included)."""
    return min(d, o1), o1 if d < o1 else min(d, o2), o2 if d < o2 else min(d, o3)


@njit(cache=True, inline="always")
def _dist_sel(metric, ddx, cy2, cz2, cy, cz):
    """:func:`_dist` for the metrics without a square root, all three computed and one
    selected: no branch in the loop, so it vectorises without a copy per metric."""
    a = abs(ddx)
    l1 = a + cy + cz
    li = max(max(a, cy), cz)
    sq = ddx * ddx + cy2 + cz2
    return l1 if metric == MANHATTAN else (li if metric == CHEBYSHEV else sq)


@njit(cache=True, fastmath=False)
def worley_row(
    ndim,
    xs,
    fx,
    ox,
    y,
    z,
    px,
    py,
    pz,
    metric,
    jitter,
    seed,
    combo,
    c1,
    c2,
    c3,
    xb,
    f1,
    f2,
    f3,
    best,
    nb,
    win,
    winh,
    slot,
):
    """Worley output ``combo`` along one grid row into ``nb[:nx]``: the samples
    ``x = xs[i] * fx + ox`` at fixed ``y`` (and ``z`` when ``ndim == 3``).

    ``win`` (5, 3, 9), ``winh`` (3, 9) and ``slot`` (3,) are work space: a window of three
    lattice columns (column ``c`` in slot ``c % 3``) holding their candidate feature points
    (x, squared and absolute y and z offsets, hash), so neighbouring runs share them.
    """
    nx = xs.shape[0]
    hs = hash32(seed)
    needk = NEEDK[combo]
    # only the cell id needs the nearest point's hash; without it Euclidean distances are
    # compared squared and rooted at the end (sqrt is monotonic, so the k-th smallest root
    # is the root of the k-th smallest square: F1..F3 come out the same)
    track = combo == W_CELL
    dmetric = EUCLIDEAN_SQ if metric == EUCLIDEAN and not track else metric
    cyf = math.floor(y)
    icy = int(cyf)
    czf = math.floor(z) if ndim >= 3 else 0.0
    icz = int(czf)
    rz = 1 if ndim >= 3 else 0
    n3 = 3 if ndim >= 3 else 1  # groups of three candidates per column
    # the y and z parts of the gap to unexamined cells are the same for the whole row
    gyz = min(y - cyf + 1, 2 - (y - cyf))
    if ndim >= 3:
        gyz = min(gyz, min(z - czf + 1, 2 - (z - czf)))
    for i in range(nx):
        xb[i] = xs[i] * fx + ox
        f1[i] = math.inf
        f2[i] = math.inf
        f3[i] = math.inf
        best[i] = 0
    for s in range(3):  # an empty window: a column the first run cannot ask for
        slot[s] = math.floor(xb[0]) + 5
    a = 0
    while a < nx:
        icx = math.floor(xb[a])
        b = a + 1
        while b < nx and math.floor(xb[b]) == icx:
            b += 1
        for dx in range(-1, 2):
            ic = icx + dx
            s = ic % 3
            if slot[s] != ic:
                slot[s] = ic
                e = 0
                for dz in range(-rz, rz + 1):
                    for dy in range(-1, 2):
                        h, fpx, fpy, fpz = _feature(
                            hs, ndim, ic, icy + dy, icz + dz, px, py, pz, jitter
                        )
                        ddy = fpy - y
                        ddz = fpz - z if ndim >= 3 else 0.0
                        win[0, s, e] = fpx
                        win[1, s, e] = ddy * ddy
                        win[2, s, e] = ddz * ddz
                        win[3, s, e] = abs(ddy)
                        win[4, s, e] = abs(ddz)
                        winh[s, e] = h
                        e += 1
        n = b - a
        ua = uint64(a)  # unsigned indices: no negative-index wrap-around, the loops vectorise
        if track:  # F1 and the nearest hash; the order of worley() decides ties
            for e in range(3 * n3):  # dz, dy outer
                for dx in range(-1, 2):  # dx inner
                    s = (icx + dx) % 3
                    cx = win[0, s, e]
                    cy2 = win[1, s, e]
                    cz2 = win[2, s, e]
                    cy = win[3, s, e]
                    cz = win[4, s, e]
                    ch = winh[s, e]
                    for q in range(n):
                        p = ua + uint64(q)
                        d = _dist(dmetric, cx - xb[p], cy2, cz2, cy, cz)
                        o1 = f1[p]
                        f1[p] = min(d, o1)
                        best[p] = ch if d < o1 else best[p]
            a = b
            continue
        # F1..F3 do not depend on the order of the candidates: three at a time
        for dx in range(-1, 2):
            s = (icx + dx) % 3
            for g in range(n3):
                e = 3 * g
                cx0 = win[0, s, e]
                cx1 = win[0, s, e + 1]
                cx2 = win[0, s, e + 2]
                cy20 = win[1, s, e]
                cy21 = win[1, s, e + 1]
                cy22 = win[1, s, e + 2]
                cz20 = win[2, s, e]
                cz21 = win[2, s, e + 1]
                cz22 = win[2, s, e + 2]
                cy0 = win[3, s, e]
                cy1 = win[3, s, e + 1]
                cy2 = win[3, s, e + 2]
                cz0 = win[4, s, e]
                cz1 = win[4, s, e + 1]
                cz2 = win[4, s, e + 2]
                if needk == 1:
                    for q in range(n):
                        p = ua + uint64(q)
                        x = xb[p]
                        d0 = _dist_sel(dmetric, cx0 - x, cy20, cz20, cy0, cz0)
                        d1 = _dist_sel(dmetric, cx1 - x, cy21, cz21, cy1, cz1)
                        d2 = _dist_sel(dmetric, cx2 - x, cy22, cz22, cy2, cz2)
                        f1[p] = min(d2, min(d1, min(d0, f1[p])))
                else:  # F1..F3 (F3 is not needed for needk 2, but costs little)
                    for q in range(n):
                        p = ua + uint64(q)
                        x = xb[p]
                        o1, o2, o3 = _keep(
                            _dist_sel(dmetric, cx0 - x, cy20, cz20, cy0, cz0), f1[p], f2[p], f3[p]
                        )
                        o1, o2, o3 = _keep(
                            _dist_sel(dmetric, cx1 - x, cy21, cz21, cy1, cz1), o1, o2, o3
                        )
                        o1, o2, o3 = _keep(
                            _dist_sel(dmetric, cx2 - x, cy22, cz22, cy2, cz2), o1, o2, o3
                        )
                        f1[p] = o1
                        f2[p] = o2
                        f3[p] = o3
        a = b
    if dmetric != metric:
        for i in range(nx):
            f1[i] = math.sqrt(f1[i])
            f2[i] = math.sqrt(f2[i])
            f3[i] = math.sqrt(f3[i])
    # F1..F3 of the 3^d neighbourhood are final where the k-th distance is within the gap
    # to the unexamined cells (as in worley()); elsewhere (flag 1 in nb) the full search
    for i in range(nx):
        x = xb[i]
        cxf = math.floor(x)
        gap = min(min(x - cxf + 1, 2 - (x - cxf)), gyz)
        if metric == EUCLIDEAN_SQ:
            gap = gap * gap
        fk = f1[i] if needk <= 1 else (f2[i] if needk == 2 else f3[i])
        nb[i] = 0.0 if fk <= gap else 1.0
    if combo == W_CELL:
        for i in range(nx):
            f1[i] = hash32(best[i] ^ 0x2545F491) * INV32
    pw = px - px  # no period along w; not a literal 0, which would compile worley again
    for i in range(nx):
        if nb[i] != 0.0:
            r1, r2, r3, cid = worley(
                ndim, xb[i], y, z, 0.0, px, py, pz, pw, metric, jitter, seed, needk
            )
            nb[i] = combine(combo, r1, r2, r3, cid, c1, c2, c3)
        else:
            nb[i] = combine(combo, f1[i], f2[i], f3[i], f1[i], c1, c2, c3)


@njit(cache=True, fastmath=False)
def worley_poisson_row(
    ndim, xs, fx, ox, y, z, px, py, pz, metric, density, seed, combo, c1, c2, c3, nb
):
    """:func:`worley_row` for the Poisson process of :func:`worley_poisson`: output
    ``combo`` at ``x = xs[i] * fx + ox`` into ``nb[:nx]``, one full search per sample."""
    needk = NEEDK[combo]
    pw = px - px  # no period along w; not a literal 0, which would compile worley_poisson again
    for i in range(xs.shape[0]):
        r1, r2, r3, cid = worley_poisson(
            ndim, xs[i] * fx + ox, y, z, 0.0, px, py, pz, pw, metric, density, seed, needk
        )
        nb[i] = combine(combo, r1, r2, r3, cid, c1, c2, c3)
