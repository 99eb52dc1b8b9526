"""The float32 road of the noise grids that :mod:`._gridkernels32` does not cover: 4D
Worley cell id (and 3D grids with ``time``; 4D value, classic and improved noise go by
rows, :mod:`._lattice4_32`, as 4D simplex, :func:`._simplex32.rows4s`, and 4D Worley
F1..F3 do), tileable simplex (its flat 4D torus) and domain warping, of every kind (a
warped 2D or 3D grid of value, classic, improved or simplex noise goes by rows at the
warped points, :mod:`._warp32`, but for lattice periods; its warp fields are made here too)
(private; see :func:`sylva.texture.noise_grid`).

One kernel, :func:`_block`, takes the fractal sum of value, classic Perlin, improved
Perlin, simplex or Worley noise, in 2D, 3D or 4D, at a block of :data:`BLOCK` points, octave
by octave.  Worley (:func:`_worley`: its jittered grid, F1..F3, their combinations and the
cell id) goes by the 3^d cells around each point, every candidate in one straight loop over
the block (hashes on int64 lanes, float32 distances from the point's cell corner); a point
whose k-th distance is not provably final gets the float64 road's full search.  The
gradient and value noises go in three passes per octave:

1. *locate* (float64, SIMD): the octave's coordinates (``x * freq + offset``, or the torus
   embedding), their lattice cells and float32 fractions, or the simplex and its corner
   ranks: the same float64 operations as the float64 road of :mod:`._sampling`, so every
   sample lands in the float64 road's lattice cell and simplex (3D and 4D simplex jump
   across simplex faces: a simplex chosen from float32 coordinates would differ there);
2. *hash* (scalar): the permutation-table chains of every corner (the lookups stay scalar,
   as in :mod:`._gridkernels32`: no vector gathers on this CPU);
3. *blend* (float32, SIMD): every corner's contribution (improved and simplex gradients by
   selects, no tables), then the multilinear blend axis by axis (one straight loop per
   pair of corners) or the simplex sum, and the octave's fBm, turbulence or ridged term.

Driver: :func:`grid_kernel`, rows on threads (:func:`grid_rows`): a grid's rows (with the
torus embedding when asked) or rows of points (domain warping).  The cells are converted to
int32: a grid whose octave coordinates reach 2^29 cells takes the float64 road instead
(:func:`_within_int32`).  Results differ from the float64
road by float32 rounding: below :data:`TOLERANCE` (absolute, values about [-1, 1]);
see ``tests/texture/test_points32.py``.
"""

from __future__ import annotations

import functools
import math
import os
import threading

import numpy as np
from numba import njit, uint64

from .. import _jit
from . import _bytelanes as _bl
from . import _cellkernels as ck
from . import _gridkernels32 as _gk32
from . import _kernels as k
from . import _simplex32 as _s32
from . import _warp32 as _w32

#: bound on the absolute difference from the float64 road (values about [-1, 1]): the
#: lattice cells and simplices are the float64 road's, the fractions are rounded to float32
#: once and blended in float32 (measured up to ~1e-6 on 6 octaves of 4D noise); a warped
#: grid's positions move by the warp field's float32 rounding times ``warp`` (~1e-6 of a
#: cell), so the same bound holds, except where that move carries a sample across a face
#: of a 3D or 4D simplex, whose kernel (r^2 = 0.6) jumps there: a sample within ~1e-6 of a
#: cell of a face, none in the 40,960 samples of 3D and 4D warped simplex measured
TOLERANCE = 2e-4

#: points per block (the buffers stay in L1)
BLOCK = 256
_OPTS = dict(cache=True, fastmath=True, error_model="numpy", pipeline_class=_bl.Wide)
_F = np.float32
ZERO = _F(0.0)
ONE = _F(1.0)
HALF = _F(0.5)
TWO = _F(2.0)
THREE = _F(3.0)
SIX = _F(6.0)
TEN = _F(10.0)
FIFTEEN = _F(15.0)
PI = _F(math.pi)
# simplex: per dimension 2..4 the unskew factor G, the kernel radius r^2 and the scale
_SG = np.array([0.0, 0.0, k.G2, k.G3, k.G4], np.float32)
_SR = np.array([0.0, 0.0, 0.5, 0.6, 0.6], np.float32)
_SS = np.array([0.0, 0.0, 70.0, 32.0, 27.0], np.float32)
# the time direction of the 4D torus (as :mod:`._sampling`)
_TD = (0.3872983346207417, -0.5477225575051661, 0.4472135954999579, 0.5916079783099616)


@njit(inline="always", **_OPTS)
def _g16(h, x, y, z):
    """``GRAD16[h & 15] . (x, y, z)``: improved noise's gradients, and simplex's
    (``GRAD3[g]`` for ``g < 12`` is ``GRAD16[g]``), as the grid roads take them."""
    return _gk32._g16(h, x, y, z)


@njit(inline="always", **_OPTS)
def _g32(h, x, y, z, w):
    """``GRAD4[h & 31] . (x, y, z, w)``, as the 4D simplex rows take it."""
    return _s32._g32(np.int32(h & np.int32(31)), x, y, z, w)


@njit(**_OPTS)
def work():
    """The buffers of :func:`_block`.  Their rows are padded to an odd number of 64-byte
    lines: at 1 KB (or 2 KB) a row, the rows that a pass reads and writes at once shared
    their L1 sets and 4 KB address bits (4D simplex's corner hashes 1.6x slower)."""
    B = BLOCK
    b4 = B + 16  # 4-byte rows: 17 lines
    b8 = B + 8  # 8-byte rows: 33 lines
    return (
        np.empty((4, b8)),  # octave coordinates (float64)
        np.empty((4, b4), np.int32),  # lattice index 0, or simplex cell
        np.empty((4, b4), np.int32),  # lattice index 1, or simplex corner ranks
        np.empty((4, b4), np.float32),  # fractions, or simplex offsets x0..w0
        np.empty((4, b4), np.float32),  # curve weights
        np.empty((16, b4), np.int32),  # corner hashes
        np.empty((16, b4), np.float32),  # corner values / contributions
        np.empty((16, b4), np.float32),  # the blend's other buffer
        np.empty((4, 16, b4), np.float32),  # classic Perlin gradients
        np.empty(B, np.float32),  # ridged weight
        np.empty((3, b4), np.float32),  # Worley F1..F3
        np.empty(B, np.int64),  # Worley: the nearest point's cell hash
        np.empty((9, b8), np.int64),  # Worley: the cell hashes of nine candidates
        np.zeros((25, B + 64), np.uint8),  # byte lanes: lattice indices, corner hashes
        np.zeros(512, np.uint8),  # byte lanes: perm, perm12
    )


@njit(**_OPTS)
def _coords(torus, ndim, P, tz, m, o, freqs, offs, pers, C):
    """Octave ``o``'s coordinates of the block's points ``P`` (float64, as the float64
    road computes them); with ``torus`` ``P`` holds cos x, sin x, cos y, sin y and ``tz``
    the time."""
    if torus:
        rx = pers[o, 0] / k.TWO_PI
        ry = pers[o, 1] / k.TWO_PI
        t = tz * freqs[o, 2] if ndim >= 3 else 0.0
        for q in range(m):
            C[0, q] = rx * P[0, q] + offs[o, 0] + t * _TD[0]
            C[1, q] = rx * P[1, q] + offs[o, 1] + t * _TD[1]
            C[2, q] = ry * P[2, q] + offs[o, 2] + t * _TD[2]
            C[3, q] = ry * P[3, q] + offs[o, 3] + t * _TD[3]
        return
    for a in range(ndim):
        f = freqs[o, a]
        d = offs[o, a]
        for q in range(m):
            C[a, q] = P[a, q] * f + d


@njit(**_OPTS)
def _locate_lattice(nd, m, C, o, pers, interp, I0, I1, FR, CU):
    for a in range(nd):
        per = int(pers[o, a])
        for q in range(m):
            c = C[a, q]
            f = np.floor(c)
            FR[a, q] = _F(c - f)
            I0[a, q] = np.int32(f)
        if per > 0:
            for q in range(m):
                i = I0[a, q] % per
                I0[a, q] = i & 255
                I1[a, q] = ((i + 1) % per) & 255
        else:
            for q in range(m):
                i = I0[a, q]
                I0[a, q] = i & 255
                I1[a, q] = (i + 1) & 255
        if interp == 3:
            for q in range(m):
                t = FR[a, q]
                CU[a, q] = t * t * t * (t * (t * SIX - FIFTEEN) + TEN)
        elif interp == 2:
            for q in range(m):
                t = FR[a, q]
                CU[a, q] = t * t * (THREE - TWO * t)
        elif interp == 1:
            for q in range(m):
                CU[a, q] = (ONE - math.cos(PI * FR[a, q])) * HALF
        else:
            for q in range(m):
                CU[a, q] = FR[a, q]


@njit(**_OPTS)
def _hash_lattice(kind, nd, m, I0, I1, perm, H):
    """Corner ``c`` (bit ``a`` set: index 1 along axis ``a``) of every point: the float64
    road's chain, ``perm[w]`` then x, y, z (the extra ``perm[h + 0]`` of 2D improved noise
    is its z = 0); one straight loop per corner."""
    for c in range(1 << nd):
        X = I1[0] if c & 1 else I0[0]
        Y = I1[1] if c & 2 else I0[1]
        Z = I1[2] if c & 4 else I0[2]
        W = I1[3] if c & 8 else I0[3]
        Hc = H[c]
        if nd == 4:
            for q in range(m):
                h = perm[uint64(W[q])] + X[q]
                Hc[q] = perm[uint64(perm[uint64(perm[uint64(h)] + Y[q])] + Z[q])]
        elif nd == 3:
            for q in range(m):
                Hc[q] = perm[uint64(perm[uint64(perm[uint64(X[q])] + Y[q])] + Z[q])]
        elif kind == k.IMPROVED:
            for q in range(m):
                Hc[q] = perm[uint64(perm[uint64(perm[uint64(X[q])] + Y[q])])]
        else:
            for q in range(m):
                Hc[q] = perm[uint64(perm[uint64(X[q])] + Y[q])]


@njit(**_OPTS)
def _hash_lattice_b(kind, nd, m, I0, I1, BT, BB, H):
    """:func:`_hash_lattice` in byte lanes (:mod:`._bytelanes`, AVX-512 VBMI): the lattice
    indices into byte rows 0..7 of ``BB``, every corner's chain 64 points at a time into
    rows 8.., then into ``H``."""
    for a in range(nd):
        for q in range(m):
            BB[a, q] = np.uint8(I0[a, q])
            BB[4 + a, q] = np.uint8(I1[a, q])
    p = BT.ctypes.data
    rs = uint64(BB.shape[1])
    r0 = BB.ctypes.data
    for o in range(0, m, _bl.LANES):
        a = r0 + uint64(o)
        if nd == 4:
            _bl.lattice_chain4(p, a, rs)
        elif nd == 3:
            _bl.lattice_chain3(p, a, rs)
        elif kind == k.IMPROVED:
            _bl.lattice_chain2i(p, a, rs)
        else:
            _bl.lattice_chain2(p, a, rs)
    for c in range(1 << nd):
        for q in range(m):
            H[c, q] = np.int32(BB[8 + c, q])


@njit(**_OPTS)
def _lattice(kind, nd, m, I0, I1, FR, CU, perm, vals, grad, H, K, L, G):
    """One octave of lattice noise at the block's located and hashed points (``H``:
    :func:`_hash_lattice`), into ``K[0, :m]``."""
    nc = 1 << nd
    if kind == k.VALUE:
        for c in range(nc):
            for q in range(m):
                K[c, q] = vals[H[c, q]]
    elif kind == k.PERLIN:
        for c in range(nc):  # the gathers (scalar), then the dot products (SIMD)
            for q in range(m):
                h = H[c, q]
                for a in range(nd):
                    G[a, c, q] = grad[h, a]
        for c in range(nc):
            dx = ONE if c & 1 else ZERO
            dy = ONE if c & 2 else ZERO
            dz = ONE if c & 4 else ZERO
            dw = ONE if c & 8 else ZERO
            if nd == 2:
                for q in range(m):
                    K[c, q] = G[0, c, q] * (FR[0, q] - dx) + G[1, c, q] * (FR[1, q] - dy)
            elif nd == 3:
                for q in range(m):
                    K[c, q] = (G[0, c, q] * (FR[0, q] - dx) + G[1, c, q] * (FR[1, q] - dy)
                               + G[2, c, q] * (FR[2, q] - dz))
            else:
                for q in range(m):
                    K[c, q] = (G[0, c, q] * (FR[0, q] - dx) + G[1, c, q] * (FR[1, q] - dy)
                               + G[2, c, q] * (FR[2, q] - dz) + G[3, c, q] * (FR[3, q] - dw))
    else:
        for c in range(nc):
            dx = ONE if c & 1 else ZERO
            dy = ONE if c & 2 else ZERO
            dz = ONE if c & 4 else ZERO
            dw = ONE if c & 8 else ZERO
            if nd == 4:
                for q in range(m):
                    K[c, q] = _g32(H[c, q], FR[0, q] - dx, FR[1, q] - dy, FR[2, q] - dz,
                                   FR[3, q] - dw)
            elif nd == 3:
                for q in range(m):
                    K[c, q] = _g16(H[c, q], FR[0, q] - dx, FR[1, q] - dy, FR[2, q] - dz)
            else:
                for q in range(m):
                    K[c, q] = _g16(H[c, q], FR[0, q] - dx, FR[1, q] - dy, ZERO)
    # the blend, axis by axis (x first): pairs of corners into the other buffer
    src, dst = K, L
    for a in range(nd):
        nc >>= 1
        for j in range(nc):
            for q in range(m):
                lo = src[2 * j, q]
                dst[j, q] = lo + CU[a, q] * (src[2 * j + 1, q] - lo)
        src, dst = dst, src
    if nd & 1:  # the result went to L
        for q in range(m):
            K[0, q] = L[0, q]


@njit(**_OPTS)
def _locate_simplex(nd, m, C, I0, R, FR):
    """The simplex of every point (skew, floor, unskew and the ranks of the offsets, in
    float64 as Gustavson's code): cell ``I0``, corner ranks ``R``, offsets ``FR``."""
    if nd == 2:
        for q in range(m):
            x = C[0, q]
            y = C[1, q]
            s = (x + y) * k.F2
            i = np.floor(x + s)
            j = np.floor(y + s)
            t = (i + j) * k.G2
            x0 = x - (i - t)
            y0 = y - (j - t)
            I0[0, q] = np.int32(i) & 255
            I0[1, q] = np.int32(j) & 255
            r = 1 if x0 > y0 else 0
            R[0, q] = r
            R[1, q] = 1 - r
            FR[0, q] = _F(x0)
            FR[1, q] = _F(y0)
    elif nd == 3:
        for q in range(m):
            x0, y0, z0, ga, gb, gc, i, j, kk = _s32._s3_cell64(C[0, q], C[1, q], C[2, q])
            I0[0, q] = np.int32(i) & 255
            I0[1, q] = np.int32(j) & 255
            I0[2, q] = np.int32(kk) & 255
            ca = 1 if ga else 0
            cb = 1 if gb else 0
            cc = 1 if gc else 0
            R[0, q] = ca + cc
            R[1, q] = 1 - ca + cb
            R[2, q] = 2 - cb - cc
            FR[0, q] = _F(x0)
            FR[1, q] = _F(y0)
            FR[2, q] = _F(z0)
    else:
        for q in range(m):
            x0, y0, z0, w0, i, j, kk, ll = _s32._s4_cell64(C[0, q], C[1, q], C[2, q], C[3, q])
            I0[0, q] = np.int32(i) & 255
            I0[1, q] = np.int32(j) & 255
            I0[2, q] = np.int32(kk) & 255
            I0[3, q] = np.int32(ll) & 255
            a = 1 if x0 > y0 else 0
            b = 1 if x0 > z0 else 0
            c = 1 if x0 > w0 else 0
            d = 1 if y0 > z0 else 0
            e = 1 if y0 > w0 else 0
            f = 1 if z0 > w0 else 0
            R[0, q] = a + b + c
            R[1, q] = 1 - a + d + e
            R[2, q] = 2 - b - d + f
            R[3, q] = 3 - c - e - f
            FR[0, q] = _F(x0)
            FR[1, q] = _F(y0)
            FR[2, q] = _F(z0)
            FR[3, q] = _F(w0)


@njit(**_OPTS)
def _simplex(nd, m, I0, R, FR, perm, perm12, H):
    """The corner hashes of simplex noise at the located points (scalar), one straight
    loop per corner: corner ``c`` (0..nd) is offset by 1 along the axes whose rank is at
    least ``nd - c``."""
    if nd == 4:  # the five corners in one loop: the point's cell and ranks loaded once,
        # five independent chains for the out-of-order core (a loop per corner: 1.35x slower);
        # unsigned 64-bit indices throughout (int32 + int64 sums cost sign extensions: 1.5x)
        for q in range(m):
            i0 = uint64(I0[0, q])
            j0 = uint64(I0[1, q])
            k0 = uint64(I0[2, q])
            l0 = uint64(I0[3, q])
            ra = R[0, q]
            rb = R[1, q]
            rc = R[2, q]
            rd = R[3, q]
            for c in range(5):
                lim = np.int32(4 - c)
                ii = i0 + uint64(ra >= lim)
                jj = j0 + uint64(rb >= lim)
                kk = k0 + uint64(rc >= lim)
                ll = l0 + uint64(rd >= lim)
                h = uint64(perm[kk + uint64(perm[ll])])
                H[c, q] = perm[ii + uint64(perm[jj + h])] & 31
        return
    for c in range(nd + 1):
        lim = nd - c
        Hc = H[c]
        if nd == 2:
            for q in range(m):
                ii = I0[0, q] + (1 if R[0, q] >= lim else 0)
                jj = I0[1, q] + (1 if R[1, q] >= lim else 0)
                Hc[q] = perm12[uint64(ii + perm[uint64(jj)])]
        elif nd == 3:
            for q in range(m):
                ii = I0[0, q] + (1 if R[0, q] >= lim else 0)
                jj = I0[1, q] + (1 if R[1, q] >= lim else 0)
                kk = I0[2, q] + (1 if R[2, q] >= lim else 0)
                Hc[q] = perm12[uint64(ii + perm[uint64(jj + perm[uint64(kk)])])]
        else:
            for q in range(m):
                ii = I0[0, q] + (1 if R[0, q] >= lim else 0)
                jj = I0[1, q] + (1 if R[1, q] >= lim else 0)
                kk = I0[2, q] + (1 if R[2, q] >= lim else 0)
                ll = I0[3, q] + (1 if R[3, q] >= lim else 0)
                h = perm[uint64(kk + perm[uint64(ll)])]
                Hc[q] = perm[uint64(ii + perm[uint64(jj + h)])] & 31


@njit(**_OPTS)
def _simplex_b(nd, m, I0, R, BT, BB, H):
    """:func:`_simplex` in byte lanes (:mod:`._bytelanes`): every corner's lattice indices
    into byte rows ``4 c ..`` of ``BB`` (SIMD), the chains 64 points at a time, then into
    ``H``."""
    for c in range(nd + 1):
        lim = nd - c
        for a in range(nd):
            for q in range(m):
                BB[4 * c + a, q] = np.uint8(I0[a, q] + (1 if R[a, q] >= lim else 0))
    p = BT.ctypes.data
    rs = uint64(BB.shape[1])
    r0 = BB.ctypes.data
    for o in range(0, m, _bl.LANES):
        a = r0 + uint64(o)
        if nd == 4:
            _bl.simplex_chain4(p, a, rs)
        elif nd == 3:
            _bl.simplex_chain3(p, a, rs)
        else:
            _bl.simplex_chain2(p, a, rs)
    for c in range(nd + 1):
        for q in range(m):
            H[c, q] = np.int32(BB[20 + c, q])


@njit(**_OPTS)
def _simplex_eval(nd, m, R, FR, H, K):
    """The corners' contributions (SIMD), summed into ``K[0, :m]``."""
    nc = nd + 1
    g = _SG[nd]
    r2 = _SR[nd]
    for q in range(m):
        K[0, q] = ZERO
    for c in range(nc):  # the contributions (SIMD)
        lim = np.int32(nd - c)  # int32 compares with the int32 ranks: full-width lanes
        off = _F(c) * g
        if nd == 2:
            for q in range(m):
                x = FR[0, q] - (ONE if R[0, q] >= lim else ZERO) + off
                y = FR[1, q] - (ONE if R[1, q] >= lim else ZERO) + off
                t = max(r2 - x * x - y * y, ZERO)
                t *= t
                K[0, q] += t * t * _g16(H[c, q], x, y, ZERO)
        elif nd == 3:
            for q in range(m):
                x = FR[0, q] - (ONE if R[0, q] >= lim else ZERO) + off
                y = FR[1, q] - (ONE if R[1, q] >= lim else ZERO) + off
                z = FR[2, q] - (ONE if R[2, q] >= lim else ZERO) + off
                t = max(r2 - x * x - y * y - z * z, ZERO)
                t *= t
                K[0, q] += t * t * _g16(H[c, q], x, y, z)
        else:
            for q in range(m):
                x = FR[0, q] - (ONE if R[0, q] >= lim else ZERO) + off
                y = FR[1, q] - (ONE if R[1, q] >= lim else ZERO) + off
                z = FR[2, q] - (ONE if R[2, q] >= lim else ZERO) + off
                w = FR[3, q] - (ONE if R[3, q] >= lim else ZERO) + off
                t = max(r2 - x * x - y * y - z * z - w * w, ZERO)
                t *= t
                K[0, q] += t * t * _g32(H[c, q], x, y, z, w)
    s = _SS[nd]
    for q in range(m):
        K[0, q] *= s


@njit(inline="always", **_OPTS)
def _h32(a):
    """:func:`._cellkernels.hash32` (the same 32-bit finaliser, on int64 lanes)."""
    a &= 0xFFFFFFFF
    a = ((a ^ (a >> 16)) * 0x7FEB352D) & 0xFFFFFFFF
    a = ((a ^ (a >> 15)) * 0x846CA68B) & 0xFFFFFFFF
    return a ^ (a >> 16)


@njit(inline="always", **_OPTS)
def _jit_off(h, salt, jitter):
    """A feature point's offset from its cell corner along one axis, as in
    :func:`._cellkernels.worley` (``0.5 + jitter (u - 0.5)``), in float32."""
    return _F(0.5 + jitter * (_h32(h ^ salt) * ck.INV32 - 0.5))


@njit(inline="always", **_OPTS)
def _dist(sq, metric, ddx, ddy, ddz, ddw):
    if sq:
        return ddx * ddx + ddy * ddy + ddz * ddz + ddw * ddw
    if metric == ck.MANHATTAN:
        return abs(ddx) + abs(ddy) + abs(ddz) + abs(ddw)
    return max(max(abs(ddx), abs(ddy)), max(abs(ddz), abs(ddw)))


@njit(**_OPTS)
def _offer9(nd, metric, sq, m, oz, ow, jitter, HB9, FR, FK, BEST):
    """Offer nine candidate cells' feature points (the cells at ``dy, dx`` in -1..1 of the
    slice ``oz, ow``; their hashes ``HB9``) to the block's points: float32 offsets from each
    point's cell corner, F1..F3 and the nearest hash kept in registers over the nine (in the
    float64 road's order), one straight loop over the points."""
    for q in range(m):
        o1 = FK[0, q]
        o2 = FK[1, q]
        o3 = FK[2, q]
        b = BEST[q]
        fx = FR[0, q]
        fy = FR[1, q]
        fz = FR[2, q]
        fw = FR[3, q]
        for c9 in range(9):
            h = HB9[c9, q]
            ddx = _F(c9 % 3 - 1) + _jit_off(h, 0x68E31DA4, jitter) - fx
            ddy = _F(c9 // 3 - 1) + _jit_off(h, 0xB5297A4D, jitter) - fy
            ddz = ZERO
            ddw = ZERO
            if nd >= 3:
                ddz = oz + _jit_off(h, 0x1B56C4E9, jitter) - fz
            if nd >= 4:
                ddw = ow + _jit_off(h, 0x7F4A7C15, jitter) - fw
            d = _dist(sq, metric, ddx, ddy, ddz, ddw)
            b = h if d < o1 else b
            o3 = o2 if d < o2 else min(d, o3)
            o2 = o1 if d < o1 else min(d, o2)
            o1 = min(d, o1)
        FK[0, q] = o1
        FK[1, q] = o2
        FK[2, q] = o3
        BEST[q] = b


@njit(**_OPTS)
def _worley(nd, m, C, o, pers, wpar, I0, FR, FK, BEST, HB9, K):
    """One octave of Worley noise (the jittered grid: one point per cell) at the block's
    points into ``K[0, :m]``: the 3^nd cells around each point, every candidate of a cell
    offset for all points in one straight loop (hashes on int64 lanes, distances in float32
    from the point's own cell corner), F1..F3 and the nearest point's cell kept by selects
    in the float64 road's order (ties go to the first, as there).  A point whose k-th
    distance is not provably final after the 3^nd cells (:func:`._cellkernels._ring_gap`)
    takes the float64 road's full search (:func:`._cellkernels.worley`)."""
    metric = int(wpar[0])
    combo = int(wpar[1])
    jitter = wpar[2]
    seed = int(wpar[3])
    needk = ck.NEEDK[combo]
    sq = metric == ck.EUCLIDEAN or metric == ck.EUCLIDEAN_SQ
    per = np.zeros(4, np.int64)
    for a in range(nd):
        per[a] = int(pers[o, a])
    periodic = per[0] > 0 or per[1] > 0 or per[2] > 0 or per[3] > 0
    for a in range(nd):
        for q in range(m):
            c = C[a, q]
            f = np.floor(c)
            FR[a, q] = _F(c - f)
            I0[a, q] = np.int32(f)
    for a in range(nd, 4):
        for q in range(m):
            FR[a, q] = ZERO
            I0[a, q] = 0
    big = _F(1e30)
    for q in range(m):
        FK[0, q] = big
        FK[1, q] = big
        FK[2, q] = big
        BEST[q] = 0
    hs = ck.hash32(seed)
    rz = 1 if nd >= 3 else 0
    rw = 1 if nd >= 4 else 0
    M = 0xFFFFFFFF
    for dw in range(-rw, rw + 1):
        for dz in range(-rz, rz + 1):
            for c9 in range(9):  # the cell hashes of nine candidates (int64 lanes)
                dy = c9 // 3 - 1
                dx = c9 % 3 - 1
                HB = HB9[c9]
                if periodic:  # the periods need a modulo
                    for q in range(m):
                        HB[q] = ck._cell_hash(hs, nd, I0[0, q] + dx, I0[1, q] + dy,
                                              I0[2, q] + dz, I0[3, q] + dw, per[0], per[1],
                                              per[2], per[3])
                elif nd == 2:
                    for q in range(m):
                        h = _h32(hs ^ ((np.int64(I0[0, q]) + dx) & M))
                        HB[q] = _h32(h ^ ((np.int64(I0[1, q]) + dy) & M))
                elif nd == 3:
                    for q in range(m):
                        h = _h32(hs ^ ((np.int64(I0[0, q]) + dx) & M))
                        h = _h32(h ^ ((np.int64(I0[1, q]) + dy) & M))
                        HB[q] = _h32(h ^ ((np.int64(I0[2, q]) + dz) & M))
                else:
                    for q in range(m):
                        h = _h32(hs ^ ((np.int64(I0[0, q]) + dx) & M))
                        h = _h32(h ^ ((np.int64(I0[1, q]) + dy) & M))
                        h = _h32(h ^ ((np.int64(I0[2, q]) + dz) & M))
                        HB[q] = _h32(h ^ ((np.int64(I0[3, q]) + dw) & M))
            _offer9(nd, metric, sq, m, _F(dz), _F(dw), jitter, HB9, FR, FK, BEST)
    for q in range(m):
        if metric == ck.EUCLIDEAN:
            f1 = math.sqrt(FK[0, q])
            f2 = math.sqrt(FK[1, q])
            f3 = math.sqrt(FK[2, q])
        else:
            f1 = FK[0, q]
            f2 = FK[1, q]
            f3 = FK[2, q]
        fk = f1 if needk <= 1 else (f2 if needk == 2 else f3)
        gap = min(min(FR[0, q] + ONE, TWO - FR[0, q]), min(FR[1, q] + ONE, TWO - FR[1, q]))
        if nd >= 3:
            gap = min(gap, min(FR[2, q] + ONE, TWO - FR[2, q]))
        if nd >= 4:
            gap = min(gap, min(FR[3, q] + ONE, TWO - FR[3, q]))
        if metric == ck.EUCLIDEAN_SQ:
            gap *= gap
        if fk <= gap:
            cid = _h32(BEST[q] ^ 0x2545F491) * ck.INV32
            v = ck.combine(combo, f1, f2, f3, cid, wpar[4], wpar[5], wpar[6])
        else:  # the float64 road's full search
            g1, g2, g3, cid = ck.worley(nd, C[0, q], C[1, q], C[2, q], C[3, q], per[0],
                                        per[1], per[2], per[3], metric, jitter, seed, needk)
            v = ck.combine(combo, g1, g2, g3, cid, wpar[4], wpar[5], wpar[6])
        K[0, q] = _F(v)


@njit(**_OPTS)
def _block(kind, mode, ndim, torus, P, tz, m, freqs, amps, offs, pers, interp, perm,
           perm12, vals, grad, wpar, norm, gain, lanes, wk, acc):
    """The fractal sum at the block's ``m`` points into ``acc[:m]`` (``amps`` already
    carry ``norm`` unless ``mode`` is ridged; ``lanes``: the lattice and simplex noises
    hash in byte lanes, :func:`_hash_lattice_b` and :func:`_simplex_b`)."""
    C, I0, I1, FR, CU, H, K, L, G, wgt, FK, BEST, HB9, BB, BT = wk
    if lanes and kind != k.WORLEY:
        for a in range(256):
            BT[a] = perm[a]
            BT[256 + a] = perm12[a]
    nd = 4 if torus else ndim
    for q in range(m):
        acc[q] = ZERO
        wgt[q] = ONE
    for o in range(freqs.shape[0]):
        _coords(torus, ndim, P, tz, m, o, freqs, offs, pers, C)
        if kind == k.WORLEY:
            _worley(nd, m, C, o, pers, wpar, I0, FR, FK, BEST, HB9, K)
        elif kind == k.SIMPLEX:
            _locate_simplex(nd, m, C, I0, I1, FR)
            if lanes:
                _simplex_b(nd, m, I0, I1, BT, BB, H)
            else:
                _simplex(nd, m, I0, I1, FR, perm, perm12, H)
            _simplex_eval(nd, m, I1, FR, H, K)
        else:
            _locate_lattice(nd, m, C, o, pers, interp, I0, I1, FR, CU)
            if lanes:
                _hash_lattice_b(kind, nd, m, I0, I1, BT, BB, H)
            else:
                _hash_lattice(kind, nd, m, I0, I1, perm, H)
            _lattice(kind, nd, m, I0, I1, FR, CU, perm, vals, grad, H, K, L, G)
        a = amps[o]
        if mode == k.FBM:
            for q in range(m):
                acc[q] += a * K[0, q]
        elif mode == k.TURBULENCE:
            for q in range(m):
                acc[q] += a * abs(K[0, q])
        else:
            for q in range(m):
                s = ONE - abs(K[0, q])
                s *= s
                s *= wgt[q]
                wgt[q] = min(max(s * gain, ZERO), ONE)
                acc[q] += a * s
    if mode == k.RIDGED:
        for q in range(m):
            acc[q] *= norm


@njit(nogil=True, **_OPTS)
def grid_rows(r0, r1, points, kind, mode, ndim, torus, xs, ys, zs, ws, out, freqs, amps, offs,
              pers, interp, perm, perm12, vals, grad, wpar, norm, gain, lanes):
    """Fill rows ``r0 .. r1`` of ``out`` (float32, shape (nw, nz, ny, nx); a row: ``(iw, iz,
    iy)``) with the fractal sum (one kernel for every road: one compile; :func:`grid_kernel`
    runs it on threads).

    Grid mode: the product grid of ``xs, ys, zs, ws``; with ``torus`` ``xs`` and ``ys``
    are the angles of the 4D torus and ``zs`` the time.  Point mode (``points``): ``out``
    has shape (1, 1, rows, nx) and sample ``i`` of row ``r`` is the point
    ``(xs, ys, zs, ws)[r * nx + i]``."""
    nw, nz, ny, nx = out.shape
    nb = (nx + BLOCK - 1) // BLOCK
    wk = work()
    P = np.empty((4, BLOCK))
    acc = np.empty(BLOCK, np.float32)
    if torus and not points:  # the angles along x are every row's: their cos and sin once
        cx = np.cos(xs)
        sx = np.sin(xs)
    else:
        cx = sx = xs
    for r in range(r0, r1):
        iy = r % ny
        iz = (r // ny) % nz
        iw = r // (ny * nz)
        row = out[iw, iz, iy]
        for b in range(nb):
            x0 = b * BLOCK
            m = min(BLOCK, nx - x0)
            if points:
                p0 = r * nx + x0
                for q in range(m):
                    P[0, q] = xs[p0 + q]
                    P[1, q] = ys[p0 + q]
                    P[2, q] = zs[p0 + q]
                    P[3, q] = ws[p0 + q]
            elif torus:
                cy = math.cos(ys[iy])
                sy = math.sin(ys[iy])
                for q in range(m):
                    P[0, q] = cx[x0 + q]
                    P[1, q] = sx[x0 + q]
                    P[2, q] = cy
                    P[3, q] = sy
            else:
                for q in range(m):
                    P[0, q] = xs[x0 + q]
                    P[1, q] = ys[iy]
                    P[2, q] = zs[iz]
                    P[3, q] = ws[iw]
            _block(kind, mode, ndim, torus, P, zs[iz], m, freqs, amps, offs, pers, interp,
                   perm, perm12, vals, grad, wpar, norm, gain, lanes, wk, acc)
            for q in range(m):
                row[x0 + q] = acc[q]


def grid_kernel(points, kind, mode, ndim, torus, xs, ys, zs, ws, out, *args):
    """:func:`grid_rows` over every row of ``out`` (its arguments but the row range), rows
    on threads (:func:`._gridplan.run_blocks`; a serial kernel compiles in about half the
    time of a ``parallel=True`` one, issue 25)."""
    from ._gridplan import run_blocks

    nw, nz, ny, _ = out.shape
    run_blocks(grid_rows, nw * nz * ny, (points, kind, mode, ndim, torus, xs, ys, zs, ws, out,
                                         *args))


def _points(kind, mode, ndim, pts, freqs, amps, offs, pers, tail):
    """The fractal sum at the points ``pts`` (four float64 arrays of length n), float32 (n,):
    rows of :data:`BLOCK` points (the last padded) through :func:`grid_kernel`."""
    n = pts[0].shape[0]
    rows = max(1, -(-n // BLOCK))
    size = rows * BLOCK
    padded = []
    for c in pts:
        if size != n:
            c = np.concatenate([c, np.zeros(size - n)])
        padded.append(np.ascontiguousarray(c, np.float64))
    out = np.empty((1, 1, rows, BLOCK), np.float32)
    grid_kernel(True, kind, mode, ndim, False, *padded, out, freqs, amps, offs, pers, *tail)
    return out.reshape(-1)[:n]


# ----------------------------------------------------------------------------- roads
#: the noise kinds of this road (Worley: its jittered grid, F1..F3, their combinations and
#: the cell id, in 4D or warped; its Poisson process and orders above F3 keep the float64
#: road)
KINDS = (k.VALUE, k.PERLIN, k.IMPROVED, k.SIMPLEX, k.WORLEY)


def _tables(setup, ndim, mode, amps, norm, gain):
    """The kernels' arguments after ``pers``: float32 amplitudes (carrying ``norm`` unless
    ridged), the interpolation, the tables of ``setup``, float32 norm and gain, and whether
    to hash in byte lanes (:data:`._bytelanes.USE`)."""
    t = setup.tables
    a32 = (amps if mode == k.RIDGED else amps * norm).astype(np.float32)
    grad = np.ascontiguousarray(t.gradients[ndim - 2], np.float32)
    return (setup.interp, t.perm, t.perm12, t.values.astype(np.float32), grad, setup.wpar,
            np.float32(norm), np.float32(gain), _bl.USE), a32


def road(plan, warp) -> str | None:
    """Which kernel of this module takes the float32 grid ``plan`` (``"grid"``, ``"torus"``,
    ``"warp"``), or None (another road: :mod:`._gridkernels32`, or float64 and rounding)."""
    s = plan.setup
    if plan.dt != np.float32 or s.kind not in KINDS or plan.norder:
        return None
    if s.kind == k.WORLEY and s.wpar[7] > 0.0:  # Worley's Poisson process
        return None
    if warp:
        return "warp"
    if plan.torus:
        return "torus"
    if s.kind == k.WORLEY and plan.ndim == 4 and int(s.wpar[1]) != ck.W_CELL:
        return None  # 4D F1..F3 go by rows (:mod:`._worley32`), as 2D and 3D do
    if s.kind in (k.VALUE, k.PERLIN, k.IMPROVED, k.SIMPLEX):
        return None  # 4D lattice and simplex noise go by rows too (:mod:`._lattice4_32`,
        # :func:`._simplex32.rows4s`)
    # 2D and 3D Worley cell id stays on the float64 road: its runs of samples that share a
    # cell (hashed once per column) measured 3-4x this road's per-point candidates there
    return "grid" if plan.ndim == 4 else None


def _field(ws, plan, axes, pts, n, out=None):
    """One warp field (fBm of the kind with the setup ``ws``) at the grid's own points
    (``pts()``: them flat, built on first need), into the float32 buffer ``out`` where the
    grid road takes it.  Those are a regular grid, so the grid
    roads of :mod:`._gridkernels32` take it where they have a kernel (2D and 3D of every
    kind, 4D lattice and simplex noise; while they are not compiled, small work stays
    here): a warped 2D improved grid then costs one pass of points instead of three."""
    from . import _gridkernels32 as gk32
    from ._gridplan import SCALAR_WORK

    ndim = plan.ndim
    if not _jit.cold(gk32.lattice_grid32, n, SCALAR_WORK):
        full = tuple(len(a) for a in axes[:4])
        g = gk32.grid32(ws, ndim, axes, plan.freqs, plan.amps, plan.offs, plan.pers, k.FBM,
                        plan.norm, plan.gain, False, full, out)
        if g is not None:
            return g.reshape(-1)
    wtail, wa32 = _tables(ws, ndim, k.FBM, plan.amps, plan.norm, plan.gain)
    return _points(ws.kind, k.FBM, ndim, pts(), plan.freqs, wa32, plan.offs, plan.pers, wtail)


def _within_int32(coords, freqs, offs):
    """Whether every octave coordinate ``p * freq + offset`` of the points ``coords`` (one
    array per axis) stays below :data:`._simplex32._BIG`: this road converts lattice cells
    to int32 (and hashes Worley's cells in int32); beyond, the float64 road takes the grid."""
    for a, c in enumerate(coords):
        m = float(np.abs(c).max()) if c.size else 0.0
        if not float(np.max(np.abs(freqs[:, a]) * m + np.abs(offs[:, a]))) < _s32._BIG:
            return False
    return True


#: the most bytes of warp-field buffers :class:`_Scratch` keeps between calls
SCRATCH_BYTES = 64 << 20


class _Scratch:
    """Float32 buffers for the warp fields, handed from one warped grid to the next.  A
    call's fresh multi-megabyte fields, freed at its end, came back from the system every
    time (glibc hands the freed top of its heap back), and on this project's VM their page
    faults cost as much as the fields' arithmetic: a 1024² warped 2D improved grid took
    ~1,500 faults and 13 ms a call, 6.8 ms without them.  Thread-safe (a buffer taken is
    no other call's until given back); the most recently given :data:`SCRATCH_BYTES` are
    kept."""

    def __init__(self):
        self.free = []
        self.lock = threading.Lock()

    def take(self, n):
        """A float32 buffer of ``n`` values (contents undefined)."""
        with self.lock:
            for i, b in enumerate(self.free):
                if b.size == n:
                    return self.free.pop(i)
        return np.empty(n, np.float32)

    def give(self, bufs):
        """Keep ``bufs`` for later calls, dropping the oldest beyond the budget."""
        with self.lock:
            self.free.extend(bufs)
            while sum(b.nbytes for b in self.free) > SCRATCH_BYTES:
                self.free.pop(0)


_SCRATCH = _Scratch()


def _new_scratch() -> None:  # a forked child: the lock may have been held by a thread
    global _SCRATCH
    _SCRATCH = _Scratch()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_new_scratch)


def grid32(plan, warp, setup):
    """The float32 road of :func:`.noise.noise_grid` for ``plan`` (4D grids, tileable
    simplex, domain warping; ``setup(seed)``: the noise set-up of another seed, for the
    warp fields), or None
    where :func:`road` names none, or while the kernel is not compiled and the grid is
    small (the float64 road's interpreted source is then quicker than compiling)."""
    from ._gridplan import SCALAR_WORK, run_tasks

    which = road(plan, warp)
    n = math.prod(plan.shape)
    if which is None or _jit.cold(grid_rows, n, SCALAR_WORK):
        return None
    s, ndim, mode = plan.setup, plan.ndim, plan.mode
    axes = [np.ascontiguousarray(a, np.float64) for a in plan.axes]
    freqs, offs, pers = plan.freqs, plan.offs, plan.pers
    tail, a32 = _tables(s, 4 if plan.torus else ndim, mode, plan.amps, plan.norm, plan.gain)
    if which != "warp":
        if which == "torus":  # x and y become angles (as the float64 road)
            for a in (0, 1):
                axes[a] = 2.0 * np.pi * np.arange(plan.sizes[a], dtype=np.float64) / plan.sizes[a]
        if which == "grid" and not _within_int32(axes[:ndim], freqs, offs):
            return None
        full = tuple(len(a) for a in axes[:4])
        out = np.empty((full[3], full[2], full[1], full[0]), np.float32)
        grid_kernel(False, s.kind, mode, ndim, which == "torus", *axes[:4], out, freqs, a32,
                    offs, pers, *tail)
        return out.reshape(plan.shape)
    made = []
    making = threading.Lock()  # the warp fields may ask for them side by side

    def pts():
        with making:
            if not made:
                grids = np.meshgrid(*axes[:ndim][::-1], indexing="ij")[::-1]
                made.extend(np.ascontiguousarray(g.ravel()) for g in grids)
                while len(made) < 4:
                    made.append(np.zeros(n))
        return made

    base = 0 if s.tables.seed is None else s.tables.seed
    seeds = [base + 7919 * (a + 1) for a in range(ndim)]  # the float64 road's, per axis

    bufs = [_SCRATCH.take(n) for _ in seeds]  # the fields' buffers, back at the end

    def fields():
        # the warp fields, fBm of the kind with the axis's seed: side by side, one a thread
        # (_gridplan.run_tasks: not one after another on every thread)
        wsets = [setup(sd) for sd in seeds]
        if ndim == 2 and s.kind == k.SIMPLEX and not _jit.cold(_s32.simplex_pair_rows32, n,
                                                               SCALAR_WORK):
            # both at once: one locate a block, the kernel weights shared
            pair = _s32.simplex_pair32(wsets, axes, freqs, plan.amps, offs, plan.norm,
                                       plan.gain, bufs)
            return [f.reshape(-1) for f in pair]
        return run_tasks([functools.partial(_field, ws, plan, axes, pts, n, b)
                          for ws, b in zip(wsets, bufs)])

    try:
        if (ndim in (2, 3) and s.kind in _w32.KINDS and (s.kind == k.SIMPLEX or not pers.any())
                and not _jit.cold(_w32.warp_rows, n, SCALAR_WORK)):
            # 2D and 3D: rows at the warped points (:mod:`._warp32`, no point arrays; a
            # lattice period wraps the far corners, which its tables do not)
            out = _w32.warp_grid(s, axes, fields(), warp, freqs, plan.amps, offs, mode,
                                 plan.norm, plan.gain)
            return out.reshape(plan.shape)
        warped = [pts()[a] + float(warp) * d.astype(np.float64)
                  for a, d in enumerate(fields())]
    finally:
        _SCRATCH.give(bufs)  # nothing below reads the fields
    if not _within_int32(warped, freqs, offs):
        return None
    warped += pts()[ndim:]
    out = _points(s.kind, mode, ndim, warped, freqs, a32, offs, pers, tail)
    return out.reshape(plan.shape)


def warm() -> None:
    """Compile this road's kernel (``sylva warmup``) on a tiny 4D grid and a tiny warped
    grid (the same kernel: loaded from the cache the second time), and the 4D lattice
    rows."""
    from .noise import noise_grid

    with _jit.compiled():
        # 4D simplex and lattice noise: their rows (:func:`._simplex32.rows4s`,
        # :mod:`._lattice4_32`, one kernel for every lattice kind)
        noise_grid((1, 1, 2, 8), kind="simplex", octaves=2, dtype=np.float32)
        noise_grid((1, 1, 2, 24), kind="value", octaves=2, dtype=np.float32)
        # a warped 4D grid, so that this group does not compile the texture group's 2D grid
        # kernels as well: its warp fields go by the 4D simplex rows (or, while the texture
        # group's kernels are cold, on points), the warped noise on points
        noise_grid((1, 1, 2, 8), kind="simplex", octaves=2, warp=0.5, dtype=np.float32)
        # 2D noise at warped points (:func:`._warp32.warp_rows`), called directly: a
        # warped 2D grid's fields would compile the texture group's 2D grid kernel here
        from .noise import _setup

        ax = [np.arange(8, dtype=np.float64), np.arange(2, dtype=np.float64)]
        f = np.zeros(16, np.float32)
        _w32.warp_grid(_setup("simplex", 1, None), ax, [f, f], 0.5, np.ones((2, 4)),
                       np.ones(2), np.zeros((2, 4)), k.FBM, 1.0, 0.5)
        # and a warped 2D simplex grid's two fields at once (:func:`._simplex32.simplex_pair32`)
        _s32.simplex_pair32([_setup("simplex", 1, None), _setup("simplex", 2, None)],
                            ax + [np.zeros(1)], np.ones((2, 4)), np.ones(2), np.zeros((2, 4)),
                            1.0, 0.5)
