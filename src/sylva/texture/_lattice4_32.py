"""Float32 rows of 4D lattice noise on regular grids (private; the 4D part of
:mod:`._gridkernels32`, whose module docstring describes the float32 road).

Value, classic Perlin and improved noise on 4D grids (and 3D grids with ``time``), every
fractal sum and integer period, by rows as the 2D and 3D lattice noises go: a row has its
``y, z, w`` fixed, so the noise along it is, inside each lattice cell,
``lerp(u, p0 x + q0, p1 (x - 1) + q1)`` — the four coefficients of a cell are the
blends over ``y, z, w`` of its sixteen corners' gradients (or values).  An octave with
about four samples a cell or more (two with AVX2's permutes: :data:`_KCELL`) hashes each cell of the
row once (the float64 road's chain ``perm[perm[perm[perm[w] + x] + y] + z]``, scalar;
kept for the next rows in the same lattice rows), reduces it to its coefficients (SIMD
across cells) and evaluates its samples by :func:`._gridkernels32._cell_eval`'s select
chains; a finer octave makes every sample its own cell.  (The per-point road of
:mod:`._points32`, which located, hashed and blended all four axes at every sample, ran
4D value noise at a tenth of FastNoise2's speed.)  The rows go on threads
(:func:`._gridplan.run_blocks`: a serial ``nogil`` kernel compiles in half the time of a
``parallel=True`` one).
"""

from __future__ import annotations

import numpy as np
from numba import njit, uint64

from . import _kernels as k
from ._gridkernels import axis_tables
from ._gridkernels32 import (
    _OPTS,
    _PERM8,
    BLOCK,
    I0,
    I1,
    I2,
    I4,
    KMAX,
    KPERM,
    NOKEY,
    ONE,
    ZERO,
    _cell_eval,
    _combine_block,
    _finish,
    _i32,
    _lerp,
    cell_octaves,
    lattice_tables32,
    x_tables32,
)

#: the cell road takes an octave whose 16-sample blocks span at most this many cells (as
#: :func:`._gridkernels32._lat_rows`: down to two samples a cell with AVX2's permutes)
_KCELL = KPERM if _PERM8 else KMAX
_I3 = np.int32(3)
_I31 = np.int32(31)
#: ``perm`` for :func:`._gridkernels32.x_tables32`: the x tables hold the lattice indices
#: themselves (the 4D chain starts at ``w``: ``perm[perm[w] + x]``)
_IDENTITY = np.arange(512, dtype=np.int32)


@njit(inline="always", **_OPTS)
def _g32c(h, y, z, w):
    """``GRAD4[h & 31]`` (the axis ``h >> 3`` left out, the other three signed by bits 2,
    1, 0, as :func:`._points32._g32`) as ``(gx, gy y + gz z + gw w)``: the coefficient of
    ``x`` and the rest of the dot product (int32 selects, no table)."""
    h = _i32(h & _I31)
    s = _i32(h >> _I3)
    neg = _i32(h & I4) != I0
    gx = ZERO if s == I0 else (-ONE if neg else ONE)
    a = (-y if neg else y) if s == I0 else ZERO
    b = z if s <= I1 else y
    c = z if s == _I3 else w
    return gx, a + (-b if _i32(h & I2) != I0 else b) + (-c if _i32(h & I1) != I0 else c)


@njit(**_OPTS)
def _hash4(kind, base, cnt, x0, x1, perm, vals, grad, y0, y1, z0, z1, pw0, pw1, H, V, G):
    """Scalar pass: the sixteen corners of cells (or samples) ``base .. base + cnt``
    (lattice indices ``x0``, ``x1``; ``pw0, pw1``: ``perm[w0]``, ``perm[w1]``) into column
    ``q - base``: corner ``c`` (bit 0: x1, bit 1: y1, bit 2: z1, bit 3: w1) the float64
    road's chain; improved noise its hash into ``H[c]``, value noise its value into
    ``V[c]``, classic Perlin noise its gradient into ``G[:, c]``."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        for cw in range(2):
            pw = pw1 if cw else pw0
            for cx in range(2):
                a = uint64(perm[pw + uint64(x1[i] if cx else x0[i])])
                for cy in range(2):
                    b = uint64(perm[a + (y1 if cy else y0)])
                    for cz in range(2):
                        h = perm[b + (z1 if cz else z0)]
                        c = cx + 2 * cy + 4 * cz + 8 * cw
                        if kind == k.VALUE:
                            V[c, q] = vals[uint64(h)]
                        elif kind == k.PERLIN:
                            for d in range(4):
                                G[d, c, q] = grad[uint64(h), d]
                        else:
                            H[c, q] = h


@njit(inline="always", **_OPTS)
def _blend8(t0, t1, t2, t3, t4, t5, t6, t7, v, s, t):
    """Eight corner terms (bit 0: y1, bit 1: z1, bit 2: w1) blended along y, z, w."""
    return _lerp(t, _lerp(s, _lerp(v, t0, t1), _lerp(v, t2, t3)),
                 _lerp(s, _lerp(v, t4, t5), _lerp(v, t6, t7)))


@njit(**_OPTS)
def _coef4(kind, cnt, H, V, G, y, v, z, s, w, t, cc):
    """SIMD pass over the hashed cells ``0 .. cnt - 1``: ``cc[:, q] = (p0, q0, p1, q1)``
    (:func:`._gridkernels32._cell_coef`'s form) at the row's fractions ``y, z, w`` and
    curve weights ``v, s, t``.  One loop over the cells per x side (the sides inside the
    cell loop kept LLVM from vectorising it: 65 ns a cell instead of 7.6)."""
    y_1 = y - ONE
    z_1 = z - ONE
    w_1 = w - ONE
    for side in range(2):
        e = 2 * side
        if kind == k.VALUE:
            for q in range(cnt):
                cc[e, q] = ZERO
                cc[e + 1, q] = _blend8(V[side, q], V[side + 2, q], V[side + 4, q],
                                       V[side + 6, q], V[side + 8, q], V[side + 10, q],
                                       V[side + 12, q], V[side + 14, q], v, s, t)
        elif kind == k.PERLIN:
            gx, gy, gz, gw = G[0], G[1], G[2], G[3]
            for q in range(cnt):
                cc[e, q] = _blend8(gx[side, q], gx[side + 2, q], gx[side + 4, q],
                                   gx[side + 6, q], gx[side + 8, q], gx[side + 10, q],
                                   gx[side + 12, q], gx[side + 14, q], v, s, t)
                cc[e + 1, q] = _blend8(
                    gy[side, q] * y + gz[side, q] * z + gw[side, q] * w,
                    gy[side + 2, q] * y_1 + gz[side + 2, q] * z + gw[side + 2, q] * w,
                    gy[side + 4, q] * y + gz[side + 4, q] * z_1 + gw[side + 4, q] * w,
                    gy[side + 6, q] * y_1 + gz[side + 6, q] * z_1 + gw[side + 6, q] * w,
                    gy[side + 8, q] * y + gz[side + 8, q] * z + gw[side + 8, q] * w_1,
                    gy[side + 10, q] * y_1 + gz[side + 10, q] * z + gw[side + 10, q] * w_1,
                    gy[side + 12, q] * y + gz[side + 12, q] * z_1 + gw[side + 12, q] * w_1,
                    gy[side + 14, q] * y_1 + gz[side + 14, q] * z_1 + gw[side + 14, q] * w_1,
                    v, s, t)
        else:
            for q in range(cnt):
                p0, r0 = _g32c(H[side, q], y, z, w)
                p1, r1 = _g32c(H[side + 2, q], y_1, z, w)
                p2, r2 = _g32c(H[side + 4, q], y, z_1, w)
                p3, r3 = _g32c(H[side + 6, q], y_1, z_1, w)
                p4, r4 = _g32c(H[side + 8, q], y, z, w_1)
                p5, r5 = _g32c(H[side + 10, q], y_1, z, w_1)
                p6, r6 = _g32c(H[side + 12, q], y, z_1, w_1)
                p7, r7 = _g32c(H[side + 14, q], y_1, z_1, w_1)
                cc[e, q] = _blend8(p0, p1, p2, p3, p4, p5, p6, p7, v, s, t)
                cc[e + 1, q] = _blend8(r0, r1, r2, r3, r4, r5, r6, r7, v, s, t)


@njit(**_OPTS)
def _eval_own(base, cnt, xf, xu, cc, nb):
    """SIMD pass: samples ``base .. base + cnt``, each its own cell (``cc[:, q - base]``),
    into ``nb``."""
    b0 = uint64(base)
    for q in range(cnt):
        i = b0 + uint64(q)
        x = xf[i]
        nb[q] = _lerp(xu[i], cc[0, q] * x + cc[1, q], cc[2, q] * (x - ONE) + cc[3, q])


@njit(inline="always", **_OPTS)
def _pad(n):
    """A row length of at least ``n`` float32 that is an odd number of 64-byte lines: the
    rows of a corner buffer (sixteen to sixty-four of them, a column written at once) then
    fall in different L1 sets (at 1 KB a row they shared four, and classic Perlin's
    scalar pass ran 6x slower)."""
    lines = (n + 15) // 16
    return 16 * (lines + 1 - lines % 2)


@njit(**_OPTS)
def work4(xt):
    """The buffers of :func:`rows4` for the x tables ``xt`` (one set per work item; the
    cell road keeps each octave's hashed cells for the next row in the same lattice rows,
    ``key`` their ``(y0, y1, z0, z1, w0, w1)``)."""
    coct, nco, ncell = cell_octaves(xt, _KCELL)
    no = coct.shape[0]
    n = max(BLOCK, ncell)
    m = max(nco, 1)
    b = _pad(BLOCK)
    c = _pad(ncell)
    return (
        np.empty((16, b), np.int32),
        np.empty((16, b), np.float32),
        np.empty((4, 16, b), np.float32),
        np.empty(BLOCK, np.float32),
        np.zeros((4, n + 16), np.float32),  # _cell_eval reads up to 15 past the cells
        np.empty((m, 16, c), np.int32),
        np.empty((m, 16, c), np.float32),
        np.empty((m, 4, 16, c), np.float32),
        coct,
        np.full((no, 6), NOKEY, np.uint64),
    )


@njit(nogil=True, **_OPTS)
def rows4(r0, r1, kind, mode, xt, yt, zt, wt, out, amps, perm, vals, grad, norm, gain):
    """Rows ``r0 .. r1`` of ``out`` (float32, shape (nw, nz, ny, nx); row ``r`` is
    ``(r // (ny nz), r // ny % nz, r % ny)``), every octave summed into the row.  ``xt``:
    :func:`._gridkernels32.x_tables32` of the x axis with :data:`_IDENTITY` for ``perm``
    (lattice indices); ``yt, zt, wt``: :func:`._gridkernels32.lattice_tables32`; ``amps``
    carry ``norm`` unless ``mode`` is ridged."""
    H, V, G, nb, cc, Hc, Vc, Gc, coct, key = work4(xt)
    px0, px1, xf, xu, cid, cp0, cp1, kspan = xt
    yi0, yi1, yf, yv = yt
    zi0, zi1, zf, zs = zt
    wi0, wi1, wf, ws = wt
    nw, nz, ny, nx = out.shape
    weight = np.empty(nx, np.float32)
    for r in range(r0, r1):
        j = r % ny
        m = (r // ny) % nz
        n = r // (ny * nz)
        row = out[n, m, j]
        for o in range(px0.shape[0]):
            y0 = uint64(yi0[o, j])
            y1 = uint64(yi1[o, j])
            z0 = uint64(zi0[o, m])
            z1 = uint64(zi1[o, m])
            w0 = uint64(wi0[o, n])
            w1 = uint64(wi1[o, n])
            pw0 = uint64(perm[w0])
            pw1 = uint64(perm[w1])
            fy, cy, fz, cz, fw, cw = yf[o, j], yv[o, j], zf[o, m], zs[o, m], wf[o, n], ws[o, n]
            first = o == 0
            if kspan[o] <= _KCELL:  # by cells: each cell of the row hashed once
                nc = cid[o, nx - 1] + 1
                ci = coct[o]
                if (key[o, 0] != y0 or key[o, 1] != y1 or key[o, 2] != z0 or key[o, 3] != z1
                        or key[o, 4] != w0 or key[o, 5] != w1):
                    _hash4(kind, 0, nc, cp0[o], cp1[o], perm, vals, grad, y0, y1, z0, z1,
                           pw0, pw1, Hc[ci], Vc[ci], Gc[ci])
                    key[o, 0] = y0
                    key[o, 1] = y1
                    key[o, 2] = z0
                    key[o, 3] = z1
                    key[o, 4] = w0
                    key[o, 5] = w1
                _coef4(kind, nc, Hc[ci], Vc[ci], Gc[ci], fy, cy, fz, cz, fw, cw, cc)
                for b in range(0, nx, BLOCK):
                    cnt = min(BLOCK, nx - b)
                    _cell_eval(kind, b, cnt, b, cid[o], xf[o], xu[o], cc, 0, nb)
                    _combine_block(mode, row, weight, b, cnt, nb, amps[o], gain, first)
                continue
            for b in range(0, nx, BLOCK):  # by samples: each sample its own cell
                cnt = min(BLOCK, nx - b)
                _hash4(kind, b, cnt, px0[o], px1[o], perm, vals, grad, y0, y1, z0, z1, pw0,
                       pw1, H, V, G)
                _coef4(kind, cnt, H, V, G, fy, cy, fz, cz, fw, cw, cc)
                _eval_own(b, cnt, xf[o], xu[o], cc, nb)
                _combine_block(mode, row, weight, b, cnt, nb, amps[o], gain, first)
        _finish(mode, row, norm)


def grid4(setup, axes, freqs, amps, offs, pers, mode, norm, gain, full):
    """The float32 4D grid (shape (nw, nz, ny, nx); ``full``: (nx, ny, nz, nw)) of value,
    classic or improved noise, as :func:`._gridkernels32.grid32` takes its arguments."""
    from ._gridplan import run_blocks

    t = setup.tables
    cols = [(np.ascontiguousarray(freqs[:, a]), np.ascontiguousarray(offs[:, a]),
             np.ascontiguousarray(pers[:, a])) for a in range(4)]
    xt = x_tables32(axes[0], *cols[0], setup.interp, _IDENTITY)
    yzw = [lattice_tables32(axis_tables(axes[a], *cols[a], setup.interp), t.perm, False)
           for a in (1, 2, 3)]
    a32 = (amps if mode == k.RIDGED else amps * norm).astype(np.float32)
    out = np.empty((full[3], full[2], full[1], full[0]), np.float32)
    grad = np.ascontiguousarray(t.gradients[2], np.float32)
    run_blocks(rows4, full[1] * full[2] * full[3],
               (setup.kind, mode, xt, *yzw, out, a32, t.perm, t.values.astype(np.float32),
                grad, np.float32(norm), np.float32(gain)))
    return out
