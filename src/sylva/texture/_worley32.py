"""The float32 road of Worley noise on regular grids (private; see :mod:`._gridkernels32`).

The same feature points as the float64 road (:func:`._cellkernels.worley_row`: one
jittered point per cell, placed by the 32-bit integer hash of the cell and the seed), but
the distances in float32, 16 samples at a time in one branch-free loop that LLVM
vectorises to 16 float32 lanes with AVX-512 (two vectors with AVX2).

A row of samples (fixed y, z and w) goes by *blocks* of :data:`LANES` samples, each
against the candidates of every lattice column from one left of its first sample's cell to
one right of its last's: a superset of each sample's own 3^d cells, so the gap test keeps
its meaning.  2D takes the three cells of three columns per loop (nine candidates), 3D the
nine (dz, dy) cells of one column, 4D the 27 (dw, dz, dy) cells of one column in three
loops.  Each block's samples are measured from its first sample's cell corner, so the
float32 offsets carry no large coordinates.

The feature points of a row of cells (one ``(iy, iz, iw)``, every column the grid row
spans) are hashed once and kept in a small cache of such rows (:data:`NSLOT` slots,
direct-mapped on ``(iy mod 3, iz mod 3, iw mod 3)`` and, in 2D and 3D, the columns): the
grid rows of one row of cells share them
(16 grid rows of a cell 16 samples high hash them once), and the next row of cells shares
two thirds of its 3^d neighbours.  Per grid row only the y/z part of each candidate's
distance is recomputed (one vectorised pass over the columns).

Where the cells are small (fewer than :data:`MIN_SPC` samples per cell, the fine octaves of
a fractal sum) a block would span too many columns: the row goes run by run (the samples
sharing a cell), each run against its 3^d cells, the columns hashed as the window of three
slides along the row, through the same block kernel.

Samples whose k-th distance is not provably final after the 3^d neighbourhood get the
float64 road's full search (:func:`._cellkernels.worley`), as there.

The values differ from the float64 road by float32 rounding (below
``_gridkernels32.TOLERANCE``); the cell-id output (``"cell"``) and Worley's Poisson
process stay on the float64 road (the id is a hash of the nearest cell, which rounding
could change at ties).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, uint64

from . import _cellkernels as ck
from ._gridkernels32 import _OPTS, ONE, ZERO, _combine_block, _finish

_F = np.float32
INF = _F(1e30)  # "no distance yet": finite, as fast-math assumes no infinities
LANES = 16  # samples per block (buffers are padded by as many)
NSLOT = 36  # cached rows of cells: 2D and 3D the 9 (dy, dz) neighbours of a row, 4 ways;
#              4D the 27 (dy, dz, dw), one way
MIN_SPC = 0.5  # samples per cell from which a row goes by blocks (else run by run)
WROWS = 32  # grid rows per work item (rows of one row of cells share its cache)


# The small helpers of the lane loops are plain kernels, not inline="always": LLVM inlines
# them (and folds the literal metric flags) all the same, while numba's own inlining of
# their 140-odd call sites cost 15 CPU s of compiling.
@njit(**_OPTS)
def _d(sq, manhattan, dx, cyz):
    """Distance from the x offset and the candidate's y/z part (squared sum, sum of
    absolutes or maximum, as the metric)."""
    if sq:
        return dx * dx + cyz
    a = abs(dx)
    return a + cyz if manhattan else max(a, cyz)


@njit(**_OPTS)
def _yz(sq, manhattan, ddy, ddz, ddw):
    """The y/z/w part of a candidate's distance (``_d`` adds the x part; absolute offsets,
    zero past the grid's dimensions)."""
    if sq:
        return ddy * ddy + ddz * ddz + ddw * ddw
    return ddy + ddz + ddw if manhattan else max(max(ddy, ddz), ddw)


@njit(inline="always", **_OPTS)
def _ne(ndim):
    """The (dy[, dz[, dw]]) cells of a lattice column: 3, 9 or 27."""
    return 27 if ndim >= 4 else (9 if ndim >= 3 else 3)


@njit(inline="always", **_OPTS)
def _cell(ndim, e, icy, icz, icw):
    """Cell ``e`` of a column's :func:`_ne` (dy fastest, then dz, then dw)."""
    iz = icz + (e // 3) % 3 - 1 if ndim >= 3 else 0
    iw = icw + e // 9 - 1 if ndim >= 4 else 0
    return icy + e % 3 - 1, iz, iw


@njit(inline="always", **_OPTS)
def _feat(hs, ndim, ix, iy, iz, iw, px, py, pz, pw, jitter):
    """The feature point of cell ``(ix, iy[, iz[, iw]])`` exactly as
    :func:`._cellkernels.worley` places it (float64)."""
    if ndim < 4:
        _, fpx, fpy, fpz = ck._feature(hs, ndim, ix, iy, iz, px, py, pz, jitter)
        return fpx, fpy, fpz, 0.0
    h = ck._cell_hash(hs, ndim, ix, iy, iz, iw, px, py, pz, pw)
    return (ix + 0.5 + jitter * (ck.hash32(h ^ 0x68E31DA4) * ck.INV32 - 0.5),
            iy + 0.5 + jitter * (ck.hash32(h ^ 0xB5297A4D) * ck.INV32 - 0.5),
            iz + 0.5 + jitter * (ck.hash32(h ^ 0x1B56C4E9) * ck.INV32 - 0.5),
            iw + 0.5 + jitter * (ck.hash32(h ^ 0x7F4A7C15) * ck.INV32 - 0.5))


@njit(**_OPTS)
def _keep(d, o1, o2, o3):
    """F1 <= F2 <= F3 after offering ``d`` (selects, as :func:`._cellkernels._keep`)."""
    return min(d, o1), o1 if d < o1 else min(d, o2), o2 if d < o2 else min(d, o3)


@njit(inline="always", **_OPTS)
def _cands(ndim, colx, colyz, cb, kc, k1, lo, e0):
    """Nine candidates (x parts from ``lo``, then y/z parts) from column ``kc`` on (of
    cells ``cb + k``): 3D the nine (dz, dy) cells of column ``kc`` (4D the nine of rows
    ``e0 .. e0 + 8``), 2D the three dy cells of columns ``kc .. kc + 2`` (those past ``k1``
    repeat it, pushed out to infinity: a repeat changes no F1 but would F2 and F3)."""
    if ndim >= 3:
        f = _F(cb + kc - lo)
        return (f + colx[e0, kc], f + colx[e0 + 1, kc], f + colx[e0 + 2, kc],
                f + colx[e0 + 3, kc], f + colx[e0 + 4, kc], f + colx[e0 + 5, kc],
                f + colx[e0 + 6, kc], f + colx[e0 + 7, kc], f + colx[e0 + 8, kc],
                colyz[e0, kc], colyz[e0 + 1, kc], colyz[e0 + 2, kc], colyz[e0 + 3, kc],
                colyz[e0 + 4, kc], colyz[e0 + 5, kc], colyz[e0 + 6, kc], colyz[e0 + 7, kc],
                colyz[e0 + 8, kc])
    kb = min(kc + 1, k1)
    kd = min(kc + 2, k1)
    wb = ZERO if kb > kc else INF
    wd = ZERO if kd > kb else INF
    fa = _F(cb + kc - lo)
    fb = _F(cb + kb - lo)
    fd = _F(cb + kd - lo)
    return (fa + colx[0, kc], fa + colx[1, kc], fa + colx[2, kc], fb + colx[0, kb],
            fb + colx[1, kb], fb + colx[2, kb], fd + colx[0, kd], fd + colx[1, kd],
            fd + colx[2, kd], colyz[0, kc], colyz[1, kc], colyz[2, kc], colyz[0, kb] + wb,
            colyz[1, kb] + wb, colyz[2, kb] + wb, colyz[0, kd] + wd, colyz[1, kd] + wd,
            colyz[2, kd] + wd)


@njit(inline="always", **_OPTS)
def _blocks(sq, manhattan, needk, ndim, nblk, sched, slo, colx, colyz, xb, xr, f1, f2, f3):
    """F1..F3 of the blocks ``sched[:, :nblk]`` (first sample, columns ``k0 .. k1`` of
    cells ``cb + k``) into ``f1..f3``: each block's :data:`LANES` samples from ``xb`` (x
    measured from ``slo``, the first sample's cell) against its columns' candidates
    (``colx``: x of the feature point from its cell's corner, ``colyz``: the y/z part of
    the distance, rows the (dz, dy) cells), in order: each block writes all its lanes,
    later blocks overwrite the samples past its own."""
    # the lane count is a bound, not a literal: a literal 16 is unrolled to scalar code
    nl = min(LANES, xr.shape[0])
    step = 1 if ndim >= 3 else 3
    ng = 3 if ndim >= 4 else 1  # 4D: a column's 27 cells, nine at a time
    for s in range(nblk):
        ub = uint64(sched[0, s])
        k1 = sched[2, s]
        cb = sched[3, s]
        lo = slo[s]
        for q in range(nl):
            p = ub + uint64(q)
            xr[q] = _F(xb[p] - lo)
            f1[p] = INF
            f2[p] = INF
            f3[p] = INF
        for kc in range(sched[1, s], k1 + 1, step):
            for g in range(ng):
                a0, a1, a2, a3, a4, a5, a6, a7, a8, b0, b1, b2, b3, b4, b5, b6, b7, b8 = (
                    _cands(ndim, colx, colyz, cb, kc, k1, lo, 9 * g))
                if needk == 1:
                    for q in range(nl):
                        p = ub + uint64(q)
                        x = xr[q]
                        m0 = min(_d(sq, manhattan, a0 - x, b0), _d(sq, manhattan, a1 - x, b1))
                        m1 = min(_d(sq, manhattan, a2 - x, b2), _d(sq, manhattan, a3 - x, b3))
                        m2 = min(_d(sq, manhattan, a4 - x, b4), _d(sq, manhattan, a5 - x, b5))
                        m3 = min(_d(sq, manhattan, a6 - x, b6), _d(sq, manhattan, a7 - x, b7))
                        m4 = min(_d(sq, manhattan, a8 - x, b8), f1[p])
                        f1[p] = min(min(min(m0, m1), min(m2, m3)), m4)
                else:
                    for q in range(nl):
                        p = ub + uint64(q)
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


@njit(inline="always", **_OPTS)
def _fill(hs, ndim, c0, ncol, iy, iz, iw, px, py, pz, pw, jitter, s, cfx, cfy, cfz, cfw):
    # the columns in the inner loop: the integer hashes vectorise across columns
    for c in range(ncol):
        fpx, fpy, fpz, fpw = _feat(hs, ndim, c0 + c, iy, iz, iw, px, py, pz, pw, jitter)
        cfx[s, c] = _F(fpx - (c0 + c))
        cfy[s, c] = fpy
        cfz[s, c] = fpz
        if ndim >= 4:  # (a one-element row otherwise)
            cfw[s, c] = fpw


@njit(**_OPTS)
def _columns(hs, ndim, c0, ncol, y, z, w, icy, icz, icw, px, py, pz, pw, jitter, sq,
             manhattan, colx, colyz, cache):
    """The candidates of lattice columns ``c0 .. c0 + ncol - 1`` of a row at ``(y, z, w)``
    into ``colx, colyz[e, :ncol]`` for its 3 (2D), 9 (3D) or 27 (4D) (dw, dz, dy) cells
    ``e``, the rows of cells' feature points taken from ``cache`` (hashed on a miss)."""
    keys, cj, cfx, cfy, cfz, cfw = cache
    ne = _ne(ndim)
    way = 0 if ndim >= 4 else 9 * (ck.hash32(c0 ^ (ncol << 20) ^ hs) & 3)
    for e in range(ne):
        iy, iz, iw = _cell(ndim, e, icy, icz, icw)
        s = way + iy % 3 + 3 * (iz % 3) + 9 * (iw % 3)
        hit = (keys[s, 0] == 1 and keys[s, 1] == iy and keys[s, 2] == iz and keys[s, 3] == c0
               and keys[s, 4] == ncol and keys[s, 5] == hs and keys[s, 6] == px
               and keys[s, 7] == py and keys[s, 8] == pz and keys[s, 9] == iw
               and keys[s, 10] == pw and cj[s] == jitter)
        if not hit:
            if px == 0 and py == 0 and pz == 0 and pw == 0:  # no periods: no modulo
                _fill(hs, ndim, c0, ncol, iy, iz, iw, 0, 0, 0, 0, jitter, s, cfx, cfy, cfz,
                      cfw)
            else:
                _fill(hs, ndim, c0, ncol, iy, iz, iw, px, py, pz, pw, jitter, s, cfx, cfy,
                      cfz, cfw)
            keys[s, 0] = 1
            keys[s, 1] = iy
            keys[s, 2] = iz
            keys[s, 3] = c0
            keys[s, 4] = ncol
            keys[s, 5] = hs
            keys[s, 6] = px
            keys[s, 7] = py
            keys[s, 8] = pz
            keys[s, 9] = iw
            keys[s, 10] = pw
            cj[s] = jitter
        for c in range(ncol):
            ddy = abs(cfy[s, c] - y)
            ddz = abs(cfz[s, c] - z) if ndim >= 3 else 0.0
            ddw = abs(cfw[s, c] - w) if ndim >= 4 else 0.0
            colx[e, c] = cfx[s, c]
            colyz[e, c] = _F(_yz(sq, manhattan, ddy, ddz, ddw))


@njit(**_OPTS)
def _wincol(hs, ndim, ic, y, z, w, icy, icz, icw, px, py, pz, pw, jitter, sq, manhattan,
            colx, colyz, k):
    """The candidates of lattice column ``ic`` into column ``k`` of ``colx, colyz`` (the
    run-by-run road's window)."""
    for e in range(_ne(ndim)):
        iy, iz, iw = _cell(ndim, e, icy, icz, icw)
        fpx, fpy, fpz, fpw = _feat(hs, ndim, ic, iy, iz, iw, px, py, pz, pw, jitter)
        ddz = abs(fpz - z) if ndim >= 3 else 0.0
        ddw = abs(fpw - w) if ndim >= 4 else 0.0
        colx[e, k] = _F(fpx - ic)
        colyz[e, k] = _F(_yz(sq, manhattan, abs(fpy - y), ddz, ddw))


@njit(**_OPTS)
def _worley_rows(ndim, mode, xs, ys, zs, ws, out, r0, r1, jfix, mfix, nfix, weight, freqs,
                 amps, offs, pers, wpar, gain, work, nb, norm):
    """Rows ``r0 .. r1`` of ``out`` (shape (nw, nz, ny, nx)), every octave summed, in one
    call (a call per row and octave, its work buffers passed field by field, cost about
    0.6 µs, half a 256-sample 3D row's work); with ``jfix >= 0`` the one row
    ``out[0, 0, 0]`` at ``(nfix, mfix, jfix)``, left unnormalised (:func:`row_worley4`).
    An octave's row: Worley output ``combo`` (not the cell id) at the samples
    ``x = xs[i] * fx + ox`` of the row's ``y`` (and ``z``, ``w`` when ``ndim`` is 3 or 4)
    into ``nb``, then summed into the row."""
    xb, f1, f2, f3, xr, colx, colyz, cache, sched, slo = work
    metric = int(wpar[0])
    combo = int(wpar[1])
    seed = int(wpar[3])
    jitter = wpar[2]
    c1 = wpar[4]
    c2 = wpar[5]
    c3 = wpar[6]
    _, nzo, nyo, _ = out.shape
    for rr in range(r0, r1):
        if jfix >= 0:
            jj = jfix
            mm = mfix
            nn = nfix
            orow = out[0, 0, 0]
        else:
            jj = rr % nyo
            mm = (rr // nyo) % nzo
            nn = rr // (nyo * nzo)
            orow = out[nn, mm, jj]
        if amps.shape[0] == 0:  # no octave (the first octave sets the row)
            orow[:] = ZERO
        for oo in range(freqs.shape[0]):
            fx = freqs[oo, 0]
            ox = offs[oo, 0]
            y = ys[jj] * freqs[oo, 1] + offs[oo, 1]
            z = zs[mm] * freqs[oo, 2] + offs[oo, 2]
            w = ws[nn] * freqs[oo, 3] + offs[oo, 3]
            px = int(pers[oo, 0])
            py = int(pers[oo, 1])
            pz = int(pers[oo, 2])
            pw = int(pers[oo, 3])
            nx = xs.shape[0]
            hs = ck.hash32(seed)
            needk = ck.NEEDK[combo]
            sq = (metric == ck.EUCLIDEAN) | (metric == ck.EUCLIDEAN_SQ)
            manhattan = metric == ck.MANHATTAN
            cyf = math.floor(y)
            icy = int(cyf)
            czf = math.floor(z) if ndim >= 3 else 0.0
            icz = int(czf)
            cwf = math.floor(w) if ndim >= 4 else 0.0
            icw = int(cwf)
            gyz = min(y - cyf + 1, 2 - (y - cyf))
            if ndim >= 3:
                gyz = min(gyz, min(z - czf + 1, 2 - (z - czf)))
            if ndim >= 4:
                gyz = min(gyz, min(w - cwf + 1, 2 - (w - cwf)))
            for i in range(nx):
                xb[i] = xs[i] * fx + ox
            for i in range(nx, nx + LANES):  # blocks past the row repeat its end
                xb[i] = xb[nx - 1]
            span = xb[nx - 1] - xb[0]
            nblk = 0
            if span >= 0.0 and span * MIN_SPC <= nx - 1:  # by blocks against whole columns
                c0f = math.floor(xb[0]) - 1
                c0 = int(c0f)
                ncol = int(math.floor(xb[nx - 1]) - c0f) + 2
                _columns(hs, ndim, c0, ncol, y, z, w, icy, icz, icw, px, py, pz, pw, jitter, sq,
                         manhattan, colx, colyz, cache)
                for base in range(0, nx, LANES):
                    lo = math.floor(xb[base])
                    sched[0, nblk] = base
                    sched[1, nblk] = int(lo - c0f) - 1
                    sched[2, nblk] = int(math.floor(xb[base + LANES - 1]) - c0f) + 1
                    sched[3, nblk] = c0
                    slo[nblk] = lo
                    nblk += 1
            else:  # run by run, each run's three columns in colx[:, 3 r .. 3 r + 2]
                ne = _ne(ndim)
                prev = -(1 << 40)
                k = -3
                a = 0
                while a < nx:
                    icx = math.floor(xb[a])
                    b = a + 1
                    while b < nx and math.floor(xb[b]) == icx:
                        b += 1
                    ic = int(icx)
                    sh = ic - prev
                    k += 3
                    for t in range(3):  # the window slides: hash the columns it has not seen
                        if k > 0 and 0 <= t + sh <= 2:
                            for e in range(ne):
                                colx[e, k + t] = colx[e, k - 3 + t + sh]
                                colyz[e, k + t] = colyz[e, k - 3 + t + sh]
                        else:
                            _wincol(hs, ndim, ic + t - 1, y, z, w, icy, icz, icw, px, py, pz, pw,
                                    jitter, sq, manhattan, colx, colyz, k + t)
                    prev = ic
                    for b0 in range(a, b, LANES):
                        sched[0, nblk] = b0
                        sched[1, nblk] = k
                        sched[2, nblk] = k + 2
                        sched[3, nblk] = ic - 1 - k
                        slo[nblk] = icx
                        nblk += 1
                    a = b
            # literal metric flags: each inlined copy is a loop without a metric branch
            if sq:
                _blocks(True, False, needk, ndim, nblk, sched, slo, colx, colyz, xb, xr, f1, f2,
                        f3)
            elif manhattan:
                _blocks(False, True, needk, ndim, nblk, sched, slo, colx, colyz, xb, xr, f1, f2,
                        f3)
            else:
                _blocks(False, False, needk, ndim, nblk, sched, slo, colx, colyz, xb, xr, f1, f2,
                        f3)
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
                nbad += fk[i] > gap
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
                for i in range(nx):
                    x = xb[i]
                    t = x - math.floor(x)
                    gap = min(min(t + 1.0, 2.0 - t), gyz)
                    gap = gap * gap if g2 else gap
                    if fk[i] > gap:
                        r1_, r2_, r3_, cid = ck.worley(ndim, x, y, z, w, px, py, pz, pw, metric,
                                                       jitter, seed, needk)
                        nb[i] = ck.combine(combo, r1_, r2_, r3_, cid, c1, c2, c3)
            _combine_block(mode, orow, weight, 0, orow.shape[0], nb, amps[oo], gain, oo == 0)
        if jfix < 0:
            _finish(mode, orow, norm)


@njit(**_OPTS)
def row_work(nx, ne):
    """Row buffers of :func:`_worley_rows` for rows of ``nx`` samples and ``ne`` cells a
    lattice column (:func:`_ne`; and the cache of rows of cells, empty)."""
    nc = int(nx / MIN_SPC) + 4  # columns of a row that goes by blocks
    keys = np.zeros((NSLOT, 11), np.int64)
    return (
        np.empty(nx + LANES),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty(nx + LANES, np.float32),
        np.empty(LANES, np.float32),
        np.empty((ne, max(nc, 3 * nx)), np.float32),  # (runs: three columns each)
        np.empty((ne, max(nc, 3 * nx)), np.float32),
        (keys, np.empty(NSLOT), np.empty((NSLOT, nc), np.float32), np.empty((NSLOT, nc)),
         np.empty((NSLOT, nc)), np.empty((NSLOT, nc) if ne > 9 else (1, 1))),
        np.empty((4, nx), np.int64),  # the blocks: first sample, k0, k1, cb
        np.empty(nx),  # their origins
    )


@njit(**_OPTS)
def row_worley32(ndim, mode, xs, ys, zs, j, m, row, weight, freqs, amps, offs, pers, wpar,
                 gain, work, nb):
    """Row ``(m, j)`` of 2D or 3D Worley noise, every octave summed into ``row`` (float32;
    ridged sums are left unnormalised); ``work``: :func:`row_work`, ``nb`` a float32 row
    buffer (the texture graph's row routine)."""
    row_worley4(ndim, mode, xs, ys, zs, zs, j, m, 0, row, weight, freqs, amps, offs, pers,
                wpar, gain, work, nb)


@njit(**_OPTS)
def row_worley4(ndim, mode, xs, ys, zs, ws, j, m, n, row, weight, freqs, amps, offs, pers,
                wpar, gain, work, nb):
    """:func:`row_worley32` of 2D to 4D grids: row ``(n, m, j)`` (``ws``, ``n``: the w axis
    and the row's place on it, read in 4D only)."""
    # typed ints, not constants: numba would compile a copy per literal value
    _worley_rows(ndim, mode, xs, ys, zs, ws, row.reshape((1, 1, 1, row.shape[0])),
                 np.int64(0), np.int64(1), j, m, n, weight, freqs, amps, offs, pers, wpar, gain,
                 work, nb, ONE)


def supported(wpar) -> bool:
    """Whether the float32 road covers the Worley set-up ``wpar`` (not the cell id, not the
    Poisson process)."""
    return not (wpar[7] > 0.0 or int(wpar[1]) == ck.W_CELL)


@njit(nogil=True, **_OPTS)
def worley_rows32(c0, c1, ndim, mode, xs, ys, zs, ws, out, freqs, amps, offs, pers, wpar, norm,
                  gain):
    """Work items ``c0 .. c1`` (:data:`WROWS` grid rows each) of :func:`worley_grid32`
    (``out``: shape (nw, nz, ny, nx))."""
    nw, nz, ny, nx = out.shape
    nrows = ny * nz * nw
    for c in range(c0, c1):
        weight = np.empty(nx, np.float32)
        nb = np.empty(nx, np.float32)
        work = row_work(nx, _ne(ndim))
        _worley_rows(ndim, mode, xs, ys, zs, ws, out, c * WROWS, min(nrows, (c + 1) * WROWS),
                     np.int64(-1), np.int64(-1), np.int64(-1), weight, freqs, amps, offs, pers,
                     wpar, gain, work, nb, norm)


def worley_grid32(ndim, mode, xs, ys, zs, ws, out, freqs, amps, offs, pers, wpar, norm, gain):
    """Fill ``out`` (float32, shape (nz, ny, nx), or (nw, nz, ny, nx) in 4D) with 2D to 4D
    Worley noise (jittered grid, any output but the cell id), every octave summed per row;
    arguments as for :func:`._gridkernels.worley_grid` and the w axis ``ws`` (``amps``
    already carry ``norm`` unless ridged).  The work items of :func:`worley_rows32` run on
    threads (:func:`._gridplan.run_blocks`: a serial kernel compiles in about half the time
    of a ``parallel=True`` one, issue 25)."""
    from ._gridplan import run_blocks

    out4 = out if out.ndim == 4 else out.reshape((1,) + out.shape)
    nw, nz, ny, _ = out4.shape
    run_blocks(worley_rows32, (ny * nz * nw + WROWS - 1) // WROWS,
               (ndim, mode, xs, ys, zs, ws, out4, freqs, amps, offs, pers, wpar, norm, gain))
