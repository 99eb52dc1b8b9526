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
INF = _F(1e30)  # "no distance yet": finite, as fast-math assumes no infinities
LANES = 16  # samples per vector step of a run (padded)


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
def _run9(sq, manhattan, needk, cx, cyz, g, xr, n, f1, f2, f3):
    """Offer candidates ``9 g .. 9 g + 8`` of the run's window (``cx``: x of the feature
    point from the cell corner; ``cyz``: its y/z part of the distance) to the samples at
    ``xr[:n]`` (from the cell corner), updating ``f1..f3[:n]``.  The loops go by 16 lanes
    exactly (the buffers are padded): one AVX-512 vector, two AVX2 ones, no remainder."""
    e = 9 * g
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = (cx[e], cx[e + 1], cx[e + 2], cx[e + 3], cx[e + 4],
                                          cx[e + 5], cx[e + 6], cx[e + 7], cx[e + 8])
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = (cyz[e], cyz[e + 1], cyz[e + 2], cyz[e + 3],
                                          cyz[e + 4], cyz[e + 5], cyz[e + 6], cyz[e + 7],
                                          cyz[e + 8])
    for q0 in range(0, n, LANES):
        u0 = uint64(q0)
        if needk == 1:
            for q in range(LANES):
                p = u0 + uint64(q)
                x = xr[p]
                m0 = min(_d(sq, manhattan, a0 - x, b0), _d(sq, manhattan, a1 - x, b1))
                m1 = min(_d(sq, manhattan, a2 - x, b2), _d(sq, manhattan, a3 - x, b3))
                m2 = min(_d(sq, manhattan, a4 - x, b4), _d(sq, manhattan, a5 - x, b5))
                m3 = min(_d(sq, manhattan, a6 - x, b6), _d(sq, manhattan, a7 - x, b7))
                m4 = min(_d(sq, manhattan, a8 - x, b8), f1[p])
                f1[p] = min(min(min(m0, m1), min(m2, m3)), m4)
        else:
            for q in range(LANES):
                p = u0 + uint64(q)
                x = xr[p]
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
def _columns(hs, ndim, c0, ncol, y, z, icy, icz, px, py, pz, jitter, sq, manhattan, colx,
             colyz):
    """The candidate feature points of lattice columns ``c0 .. c0 + ncol - 1`` of a row:
    ``colx[e, c]`` (absolute x) and ``colyz[e, c]`` (the y/z part of the distance) for the
    3 (2D) or 9 (3D) cells ``e`` of the column, in (dz, dy) order."""
    if px == 0 and py == 0 and pz == 0:  # no periods: literal zeros, no modulo
        _colfill(hs, ndim, c0, ncol, y, z, icy, icz, 0, 0, 0, jitter, sq, manhattan, colx,
                 colyz)
    else:
        _colfill(hs, ndim, c0, ncol, y, z, icy, icz, px, py, pz, jitter, sq, manhattan, colx,
                 colyz)


@njit(inline="always", **_OPTS)
def _colfill(hs, ndim, c0, ncol, y, z, icy, icz, px, py, pz, jitter, sq, manhattan, colx,
             colyz):
    # one (dz, dy) cell row at a time, the columns in the inner loop: the integer hashes
    # vectorise across columns (64-bit lanes)
    rz = 1 if ndim >= 3 else 0
    e = 0
    for dz in range(-rz, rz + 1):
        for dy in range(-1, 2):
            iy = icy + dy
            iz = icz + dz
            for c in range(ncol):
                _, fpx, fpy, fpz = ck._feature(hs, ndim, c0 + c, iy, iz, px, py, pz, jitter)
                ddy = abs(fpy - y)
                ddz = abs(fpz - z) if ndim >= 3 else 0.0
                colx[e, c] = fpx
                l2 = ddy * ddy + ddz * ddz
                l1 = ddy + ddz
                li = max(ddy, ddz)
                colyz[e, c] = l2 if sq else (l1 if manhattan else li)
            e += 1


@njit(inline="always", **_OPTS)
def _lanes9(sq, manhattan, needk, c, xr, r1, r2, r3):
    """Offer nine candidates ``c`` (x parts, then y/z parts) to :data:`LANES` samples."""
    a0, a1, a2, a3, a4, a5, a6, a7, a8, b0, b1, b2, b3, b4, b5, b6, b7, b8 = c
    if needk == 1:
        for q in range(LANES):
            x = xr[q]
            m0 = min(_d(sq, manhattan, a0 - x, b0), _d(sq, manhattan, a1 - x, b1))
            m1 = min(_d(sq, manhattan, a2 - x, b2), _d(sq, manhattan, a3 - x, b3))
            m2 = min(_d(sq, manhattan, a4 - x, b4), _d(sq, manhattan, a5 - x, b5))
            m3 = min(_d(sq, manhattan, a6 - x, b6), _d(sq, manhattan, a7 - x, b7))
            m4 = min(_d(sq, manhattan, a8 - x, b8), r1[q])
            r1[q] = min(min(min(m0, m1), min(m2, m3)), m4)
    else:
        for q in range(LANES):
            x = xr[q]
            o1, o2, o3 = _keep(_d(sq, manhattan, a0 - x, b0), r1[q], r2[q], r3[q])
            o1, o2, o3 = _keep(_d(sq, manhattan, a1 - x, b1), o1, o2, o3)
            o1, o2, o3 = _keep(_d(sq, manhattan, a2 - x, b2), o1, o2, o3)
            o1, o2, o3 = _keep(_d(sq, manhattan, a3 - x, b3), o1, o2, o3)
            o1, o2, o3 = _keep(_d(sq, manhattan, a4 - x, b4), o1, o2, o3)
            o1, o2, o3 = _keep(_d(sq, manhattan, a5 - x, b5), o1, o2, o3)
            o1, o2, o3 = _keep(_d(sq, manhattan, a6 - x, b6), o1, o2, o3)
            o1, o2, o3 = _keep(_d(sq, manhattan, a7 - x, b7), o1, o2, o3)
            o1, o2, o3 = _keep(_d(sq, manhattan, a8 - x, b8), o1, o2, o3)
            r1[q] = o1
            r2[q] = o2
            r3[q] = o3


@njit(**_OPTS)
def _block(sq, manhattan, needk, ng, colx, colyz, k0, k1, lo, xr, r1, r2, r3):
    """Offer the candidates of columns ``k0 .. k1`` (indices into ``colx``) to the
    :data:`LANES` samples at ``xr`` (from ``lo``): nine candidates (three columns of a
    (dz, dy) group) per fixed 16-lane loop, then the columns beyond the third."""
    for q in range(LANES):
        r1[q] = INF
        r2[q] = INF
        r3[q] = INF
    for g in range(ng):
        e = 3 * g
        for kc in range(k0, k1 + 1, 3):
            ka = kc
            kb = min(kc + 1, k1)  # a repeated candidate changes no F1..F3 ... but F2, F3:
            kd = min(kc + 2, k1)  # so repeats are pushed out to infinity below
            wb = ZERO if kb > ka else INF
            wd = ZERO if kd > kb else INF
            a0 = _F(colx[e, ka] - lo)
            a1 = _F(colx[e + 1, ka] - lo)
            a2 = _F(colx[e + 2, ka] - lo)
            a3 = _F(colx[e, kb] - lo)
            a4 = _F(colx[e + 1, kb] - lo)
            a5 = _F(colx[e + 2, kb] - lo)
            a6 = _F(colx[e, kd] - lo)
            a7 = _F(colx[e + 1, kd] - lo)
            a8 = _F(colx[e + 2, kd] - lo)
            b0 = _F(colyz[e, ka])
            b1 = _F(colyz[e + 1, ka])
            b2 = _F(colyz[e + 2, ka])
            b3 = _F(colyz[e, kb]) + wb
            b4 = _F(colyz[e + 1, kb]) + wb
            b5 = _F(colyz[e + 2, kb]) + wb
            b6 = _F(colyz[e, kd]) + wd
            b7 = _F(colyz[e + 1, kd]) + wd
            b8 = _F(colyz[e + 2, kd]) + wd
            c = (a0, a1, a2, a3, a4, a5, a6, a7, a8, b0, b1, b2, b3, b4, b5, b6, b7, b8)
            # literal metric flags: each inlined copy is a loop without a metric branch
            if sq:
                _lanes9(True, False, needk, c, xr, r1, r2, r3)
            elif manhattan:
                _lanes9(False, True, needk, c, xr, r1, r2, r3)
            else:
                _lanes9(False, False, needk, c, xr, r1, r2, r3)


@njit(**_OPTS)
def _row_blocks(hs, ndim, nx, xb, y, z, icy, icz, px, py, pz, jitter, sq, manhattan, needk,
                xr, r1, r2, r3, f1, f2, f3):
    """F1..F3 (of at least the 3^d neighbourhood) of a row whose cells span many samples:
    blocks of :data:`LANES` samples, each against the candidates of every column from one
    left of its first sample's cell to one right of its last's (a superset of each
    sample's own 3^d cells, so the gap test keeps its meaning)."""
    c0 = math.floor(xb[0]) - 1
    ncol = int(math.floor(xb[nx - 1]) - c0) + 2
    ne = 9 if ndim >= 3 else 3
    colx = np.empty((ne, ncol))
    colyz = np.empty((ne, ncol))
    _columns(hs, ndim, int(c0), ncol, y, z, icy, icz, px, py, pz, jitter, sq, manhattan, colx,
             colyz)
    for base in range(0, nx, LANES):
        cnt = min(LANES, nx - base)
        ub = uint64(base)
        lo = math.floor(xb[ub])
        hi = math.floor(xb[ub + uint64(cnt - 1)])
        last = uint64(nx - 1)
        for q in range(LANES):  # fixed trip counts (lanes past the row repeat its end)
            xr[q] = _F(xb[min(ub + uint64(q), last)] - lo)
        k0 = int(lo - c0) - 1
        k1 = int(hi - c0) + 1
        _block(sq, manhattan, needk, ne // 3, colx, colyz, k0, k1, lo, xr, r1, r2, r3)
        for q in range(LANES):  # f1..f3 have LANES spare entries
            p = ub + uint64(q)
            f1[p] = r1[q]
            f2[p] = r2[q]
            f3[p] = r3[q]


@njit(**_OPTS)
def worley_row32(ndim, xs, fx, ox, y, z, px, py, pz, metric, jitter, seed, combo, c1, c2, c3,
                 work, nb):
    """Worley output ``combo`` (not the cell id) along one grid row into ``nb`` (float32):
    the samples ``x = xs[i] * fx + ox`` at fixed ``y`` (and ``z`` when ``ndim == 3``);
    ``work``: :func:`row_work`'s buffers."""
    xb, f1, f2, f3, xr, r1, r2, r3, win, cx, cyz, slot, bad = work
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
    a = 0
    if nx > 1 and (xb[nx - 1] - xb[0]) * 2.0 <= nx - 1:  # 2+ samples per cell: blocks
        _row_blocks(hs, ndim, nx, xb, y, z, icy, icz, px, py, pz, jitter, sq, manhattan, needk,
                    xr, r1, r2, r3, f1, f2, f3)
        a = nx
    for s in range(3):
        slot[s] = math.floor(xb[0]) + 5
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
        n16 = (n + LANES - 1) // LANES * LANES
        ua = uint64(a)
        for q in range(n):
            xr[q] = _F(xb[ua + uint64(q)] - icx)
        for q in range(n, n16):
            xr[q] = ZERO
        for q in range(n16):
            r1[q] = INF
            r2[q] = INF
            r3[q] = INF
        for g in range(ng):
            _run9(sq, manhattan, needk, cx, cyz, g, xr, n16, r1, r2, r3)
        for q in range(n):
            p = ua + uint64(q)
            f1[p] = r1[q]
            f2[p] = r2[q]
            f3[p] = r3[q]
        a = b
    if metric == ck.EUCLIDEAN:
        for i in range(nx):
            f1[i] = math.sqrt(f1[i])
        if needk > 1:
            for i in range(nx):
                f2[i] = math.sqrt(f2[i])
                f3[i] = math.sqrt(f3[i])
    # F1..F3 of the 3^d neighbourhood are final where the k-th distance is within the gap
    # to the unexamined cells (as in worley()); elsewhere the full search
    g2 = metric == ck.EUCLIDEAN_SQ
    fk = f1 if needk <= 1 else (f2 if needk == 2 else f3)
    nbad = 0
    for i in range(nx):
        x = xb[i]
        t = x - math.floor(x)
        gap = min(min(t + 1.0, 2.0 - t), gyz)
        gap = gap * gap if g2 else gap
        bad[i] = fk[i] > gap
        nbad += bad[i]
    if combo == ck.W_F1:
        nb[:] = f1[:nx]
    elif combo == ck.W_F2:
        nb[:] = f2[:nx]
    elif combo == ck.W_F2_F1:
        for i in range(nx):
            nb[i] = f2[i] - f1[i]
    else:
        for i in range(nx):
            nb[i] = ck.combine(combo, f1[i], f2[i], f3[i], ZERO, c1, c2, c3)
    if nbad:
        pw = px - px  # no period along w (not a literal 0: worley would compile again)
        for i in range(nx):
            if bad[i]:
                r1_, r2_, r3_, cid = ck.worley(ndim, xb[i], y, z, 0.0, px, py, pz, pw, metric,
                                               jitter, seed, needk)
                nb[i] = ck.combine(combo, r1_, r2_, r3_, cid, c1, c2, c3)


@njit(**_OPTS)
def row_work(nx):
    """Row buffers of :func:`worley_row32` for rows of ``nx`` samples."""
    return (
        np.empty(nx),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty((2, 3, 9)),
        np.empty(27, np.float32),
        np.empty(27, np.float32),
        np.empty(3, np.int64),
        np.empty(nx, np.uint8),
    )


@njit(**_OPTS)
def row_worley32(ndim, mode, xs, ys, zs, j, m, row, weight, freqs, amps, offs, pers, wpar,
                 gain, work, nb):
    """Row ``(m, j)`` of 2D or 3D Worley noise, every octave summed into ``row`` (float32;
    ridged sums are left unnormalised); ``work``: :func:`row_work`, ``nb`` a float32 row
    buffer (also the texture graph's row routine)."""
    metric = int(wpar[0])
    combo = int(wpar[1])
    seed = int(wpar[3])
    row[:] = ZERO
    weight[:] = ONE
    for o in range(freqs.shape[0]):
        worley_row32(ndim, xs, freqs[o, 0], offs[o, 0], ys[j] * freqs[o, 1] + offs[o, 1],
                     zs[m] * freqs[o, 2] + offs[o, 2], int(pers[o, 0]), int(pers[o, 1]),
                     int(pers[o, 2]), metric, wpar[2], seed, combo, wpar[4], wpar[5], wpar[6],
                     work, nb)
        _combine_block(mode, row, weight, 0, row.shape[0], nb, amps[o], gain)


def supported(wpar) -> bool:
    """Whether the float32 road covers the Worley set-up ``wpar`` (not the cell id, not the
    Poisson process)."""
    return not (wpar[7] > 0.0 or int(wpar[1]) == ck.W_CELL)


@njit(parallel=True, **_OPTS)
def worley_grid32(ndim, mode, xs, ys, zs, out, freqs, amps, offs, pers, wpar, norm, gain):
    """Fill ``out`` (float32, shape (nz, ny, nx)) with 2D or 3D Worley noise (jittered
    grid, any output but the cell id), every octave summed per row; arguments as for
    :func:`._gridkernels.worley_grid` (``amps`` already carry ``norm`` unless ridged)."""
    nz, ny, nx = out.shape
    nrows = ny * nz
    for c in prange((nrows + ROWS - 1) // ROWS):
        weight = np.empty(nx, np.float32)
        nb = np.empty(nx, np.float32)
        work = row_work(nx)
        for r in range(c * ROWS, min(nrows, (c + 1) * ROWS)):
            j = r % ny
            m = r // ny
            row = out[m, j]
            row_worley32(ndim, mode, xs, ys, zs, j, m, row, weight, freqs, amps, offs, pers,
                         wpar, gain, work, nb)
            _finish(mode, row, norm)
