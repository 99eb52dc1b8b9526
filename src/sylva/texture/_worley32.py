"""The float32 road of Worley noise on regular grids (private; see :mod:`._gridkernels32`).

The same feature points as the float64 road (:func:`._cellkernels.worley_row`: one
jittered point per cell, placed by the 32-bit integer hash of the cell and the seed, the
hash computed once per lattice column of a row) and the same runs of samples sharing a
cell, but the distances in float32 and all 3^d candidates of a run in one branch-free loop
(2D: the nine candidates; 3D: three loops of nine), which LLVM vectorises to 16 float32
lanes with AVX-512.  Each run's samples are measured from their cell's corner, so the
float32 offsets carry no large coordinates.  Samples whose k-th distance is not provably
final after the 3^d neighbourhood get the float64 road's full search
(:func:`._cellkernels.worley`), as there.

The values differ from the float64 road by float32 rounding (below
``_gridkernels32.TOLERANCE``); the cell-id output (``"cell"``) and Worley's Poisson
process stay on the float64 road (the id is a hash of the nearest cell, which rounding
could change at ties).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange, uint64

from . import _cellkernels as ck
from ._gridkernels import ROWS
from ._gridkernels32 import _OPTS, ONE, ZERO, _combine_block, _finish

_F = np.float32
INF = _F(np.inf)


@njit(inline="always", **_OPTS)
def _d(sq, manhattan, dx, cyz):
    """Distance from the x offset and the candidate's y/z part (squared sum, sum of
    absolutes or maximum, as the metric)."""
    if sq:
        return dx * dx + cyz
    a = abs(dx)
    return a + cyz if manhattan else max(a, cyz)


@njit(inline="always", **_OPTS)
def _keep(d, o1, o2, o3):
    """F1 <= F2 <= F3 after offering ``d`` (selects, as :func:`._cellkernels._keep`)."""
    return min(d, o1), o1 if d < o1 else min(d, o2), o2 if d < o2 else min(d, o3)


@njit(**_OPTS)
def _run9(sq, manhattan, needk, cx, cyz, g, xr, ua, n, f1, f2, f3):
    """Offer candidates ``9 g .. 9 g + 8`` of the run's window (``cx``: x of the feature
    point from the cell corner; ``cyz``: its y/z part of the distance) to the ``n`` samples
    at ``xr[:n]`` (from the cell corner), updating ``f1..f3[ua:ua + n]``."""
    e = 9 * g
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = (cx[e], cx[e + 1], cx[e + 2], cx[e + 3], cx[e + 4],
                                          cx[e + 5], cx[e + 6], cx[e + 7], cx[e + 8])
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = (cyz[e], cyz[e + 1], cyz[e + 2], cyz[e + 3],
                                          cyz[e + 4], cyz[e + 5], cyz[e + 6], cyz[e + 7],
                                          cyz[e + 8])
    if needk == 1:
        for q in range(n):
            p = ua + uint64(q)
            x = xr[q]
            m0 = min(_d(sq, manhattan, a0 - x, b0), _d(sq, manhattan, a1 - x, b1))
            m1 = min(_d(sq, manhattan, a2 - x, b2), _d(sq, manhattan, a3 - x, b3))
            m2 = min(_d(sq, manhattan, a4 - x, b4), _d(sq, manhattan, a5 - x, b5))
            m3 = min(_d(sq, manhattan, a6 - x, b6), _d(sq, manhattan, a7 - x, b7))
            m4 = min(_d(sq, manhattan, a8 - x, b8), f1[p])
            f1[p] = min(min(min(m0, m1), min(m2, m3)), m4)
        return
    for q in range(n):
        p = ua + uint64(q)
        x = xr[q]
        o1, o2, o3 = _keep(_d(sq, manhattan, a0 - x, b0), f1[p], f2[p], f3[p])
        o1, o2, o3 = _keep(_d(sq, manhattan, a1 - x, b1), o1, o2, o3)
        o1, o2, o3 = _keep(_d(sq, manhattan, a2 - x, b2), o1, o2, o3)
        o1, o2, o3 = _keep(_d(sq, manhattan, a3 - x, b3), o1, o2, o3)
        o1, o2, o3 = _keep(_d(sq, manhattan, a4 - x, b4), o1, o2, o3)
        o1, o2, o3 = _keep(_d(sq, manhattan, a5 - x, b5), o1, o2, o3)
        o1, o2, o3 = _keep(_d(sq, manhattan, a6 - x, b6), o1, o2, o3)
        o1, o2, o3 = _keep(_d(sq, manhattan, a7 - x, b7), o1, o2, o3)
        o1, o2, o3 = _keep(_d(sq, manhattan, a8 - x, b8), o1, o2, o3)
        f1[p] = o1
        f2[p] = o2
        f3[p] = o3


@njit(**_OPTS)
def worley_row32(ndim, xs, fx, ox, y, z, px, py, pz, metric, jitter, seed, combo, c1, c2, c3,
                 work, nb):
    """Worley output ``combo`` (not the cell id) along one grid row into ``nb`` (float32):
    the samples ``x = xs[i] * fx + ox`` at fixed ``y`` (and ``z`` when ``ndim == 3``);
    ``work``: :func:`row_work`'s buffers."""
    xb, f1, f2, f3, xr, win, cx, cyz, slot = work
    nx = xs.shape[0]
    hs = ck.hash32(seed)
    needk = ck.NEEDK[combo]
    sq = (metric == ck.EUCLIDEAN) | (metric == ck.EUCLIDEAN_SQ)
    manhattan = metric == ck.MANHATTAN
    cyf = math.floor(y)
    icy = int(cyf)
    czf = math.floor(z) if ndim >= 3 else 0.0
    icz = int(czf)
    rz = 1 if ndim >= 3 else 0
    ng = 3 if ndim >= 3 else 1  # groups of nine candidates
    gyz = min(y - cyf + 1, 2 - (y - cyf))
    if ndim >= 3:
        gyz = min(gyz, min(z - czf + 1, 2 - (z - czf)))
    for i in range(nx):
        xb[i] = xs[i] * fx + ox
        f1[i] = INF
        f2[i] = INF
        f3[i] = INF
    for s in range(3):
        slot[s] = math.floor(xb[0]) + 5
    a = 0
    while a < nx:
        icx = math.floor(xb[a])
        b = a + 1
        while b < nx and math.floor(xb[b]) == icx:
            b += 1
        for dx in range(-1, 2):  # the window: three columns of candidates, x absolute
            ic = icx + dx
            s = ic % 3
            if slot[s] != ic:
                slot[s] = ic
                e = 0
                for dz in range(-rz, rz + 1):
                    for dy in range(-1, 2):
                        _, fpx, fpy, fpz = ck._feature(hs, ndim, ic, icy + dy, icz + dz, px, py,
                                                       pz, jitter)
                        ddy = abs(fpy - y)
                        ddz = abs(fpz - z) if ndim >= 3 else 0.0
                        win[0, s, e] = fpx
                        if sq:
                            win[1, s, e] = ddy * ddy + ddz * ddz
                        elif manhattan:
                            win[1, s, e] = ddy + ddz
                        else:
                            win[1, s, e] = max(ddy, ddz)
                        e += 1
        # the run's 3^d candidates, 9 per group (dz, dy, dx order), from the cell corner
        for e in range(3 * ng):
            for dx in range(3):
                s = (icx + dx - 1) % 3
                cx[3 * e + dx] = _F(win[0, s, e] - icx)
                cyz[3 * e + dx] = _F(win[1, s, e])
        n = b - a
        ua = uint64(a)
        for q in range(n):
            xr[q] = _F(xb[ua + uint64(q)] - icx)
        for g in range(ng):
            _run9(sq, manhattan, needk, cx, cyz, g, xr, ua, n, f1, f2, f3)
        a = b
    if metric == ck.EUCLIDEAN:
        for i in range(nx):
            f1[i] = math.sqrt(f1[i])
            f2[i] = math.sqrt(f2[i])
            f3[i] = math.sqrt(f3[i])
    pw = px - px  # no period along w (not a literal 0: worley would compile again)
    for i in range(nx):
        x = xb[i]
        cxf = math.floor(x)
        gap = min(min(x - cxf + 1, 2 - (x - cxf)), gyz)
        if metric == ck.EUCLIDEAN_SQ:
            gap = gap * gap
        fk = f1[i] if needk <= 1 else (f2[i] if needk == 2 else f3[i])
        if fk <= gap:
            nb[i] = ck.combine(combo, f1[i], f2[i], f3[i], ZERO, c1, c2, c3)
        else:
            r1, r2, r3, cid = ck.worley(ndim, x, y, z, 0.0, px, py, pz, pw, metric, jitter,
                                        seed, needk)
            nb[i] = ck.combine(combo, r1, r2, r3, cid, c1, c2, c3)


@njit(**_OPTS)
def row_work(nx):
    """Row buffers of :func:`worley_row32` for rows of ``nx`` samples."""
    return (
        np.empty(nx),
        np.empty(nx, np.float32),
        np.empty(nx, np.float32),
        np.empty(nx, np.float32),
        np.empty(nx, np.float32),
        np.empty((2, 3, 9)),
        np.empty(27, np.float32),
        np.empty(27, np.float32),
        np.empty(3, np.int64),
    )


@njit(parallel=True, **_OPTS)
def worley_grid32(ndim, mode, xs, ys, zs, out, freqs, amps, offs, pers, wpar, norm, gain):
    """Fill ``out`` (float32, shape (nz, ny, nx)) with 2D or 3D Worley noise (jittered
    grid, any output but the cell id), every octave summed per row; arguments as for
    :func:`._gridkernels.worley_grid` (``amps`` already carry ``norm`` unless ridged)."""
    nz, ny, nx = out.shape
    nrows = ny * nz
    metric = int(wpar[0])
    combo = int(wpar[1])
    jitter = wpar[2]
    seed = int(wpar[3])
    c1 = wpar[4]
    c2 = wpar[5]
    c3 = wpar[6]
    for c in prange((nrows + ROWS - 1) // ROWS):
        weight = np.empty(nx, np.float32)
        nb = np.empty(nx, np.float32)
        work = row_work(nx)
        for r in range(c * ROWS, min(nrows, (c + 1) * ROWS)):
            j = r % ny
            m = r // ny
            row = out[m, j]
            row[:] = ZERO
            weight[:] = ONE
            for o in range(freqs.shape[0]):
                worley_row32(ndim, xs, freqs[o, 0], offs[o, 0], ys[j] * freqs[o, 1] + offs[o, 1],
                             zs[m] * freqs[o, 2] + offs[o, 2], int(pers[o, 0]), int(pers[o, 1]),
                             int(pers[o, 2]), metric, jitter, seed, combo, c1, c2, c3, work, nb)
                _combine_block(mode, row, weight, 0, nx, nb, amps[o], gain)
            _finish(mode, row, norm)
