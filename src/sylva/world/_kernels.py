"""Numba kernels behind :mod:`sylva.world`: hashing, height smoothing, column filling,
greedy meshing and plant-block pruning.

Nothing here checks its inputs; the public modules do.  Arrays are indexed ``[x, y, z]``
for voxels and ``[x, z]`` for column fields.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..turtle._kernels import squirrel1d  # seed 004's Squirrel3, one copy for both

# voxel ids that matter to the kernels (the full table lives in blocks.py)
AIR = 0
WATER = 1


@njit(cache=True)
def squirrel2d_grid(x0, z0, w, d, seed):  # pragma: no cover - compiled
    """``hash2D(x, z)`` for ``x in [x0, x0+w)``, ``z in [z0, z0+d)``: int64[w, d]."""
    out = np.empty((w, d), np.int64)
    for i in range(w):
        for k in range(d):
            out[i, k] = squirrel1d(np.int64(x0 + i) + 198491317 * np.int64(z0 + k), seed)
    return out


@njit(cache=True)
def smooth_heights(raw):  # pragma: no cover - compiled
    """Seed 004's height smoothing on ``raw`` float64[w, d] (the border keeps ``floor``).

    With ``hi``/``lo`` the max/min of the four neighbours and ``diff = hi − lo``: when
    ``diff > 3`` the column snaps to ``floor(hi − diff/3)`` or ``floor(lo + diff/3)``,
    whichever is nearer to its own height; otherwise it keeps ``floor(h)``.
    """
    w, d = raw.shape
    out = np.empty((w, d), np.int32)
    for i in range(w):
        for k in range(d):
            h = raw[i, k]
            out[i, k] = np.int32(np.floor(h))
            if i == 0 or k == 0 or i == w - 1 or k == d - 1:
                continue
            a = raw[i - 1, k]
            b = raw[i + 1, k]
            c = raw[i, k - 1]
            e = raw[i, k + 1]
            hi = max(max(a, b), max(c, e))
            lo = min(min(a, b), min(c, e))
            diff = hi - lo
            if diff > 3.0:
                up = hi - diff / 3.0
                dn = lo + diff / 3.0
                if abs(h - up) <= abs(h - dn):
                    out[i, k] = np.int32(np.floor(up))
                else:
                    out[i, k] = np.int32(np.floor(dn))
    return out


@njit(cache=True)
def fill_columns(heights, top, under, deep, sea_level, ny, water_top):  # pragma: no cover
    """Voxels ``uint8[w, ny, d]`` from surface heights and per-column block ids.

    ``y > h``: water up to ``sea_level`` (``water_top`` on the top layer, e.g. ice), air
    above; ``y == h``: ``top``; ``h − 3 < y < h``: ``under``; ``y ≤ h − 3``: ``deep``.
    """
    w, d = heights.shape
    vox = np.zeros((w, ny, d), np.uint8)
    for i in range(w):
        for k in range(d):
            h = heights[i, k]
            for y in range(min(h + 1, ny)):
                if y == h:
                    vox[i, y, k] = top[i, k]
                elif y + 3 <= h:
                    vox[i, y, k] = deep[i, k]
                else:
                    vox[i, y, k] = under[i, k]
            for y in range(max(h + 1, 0), min(sea_level + 1, ny)):
                vox[i, y, k] = water_top[i, k] if y == sea_level else WATER
    return vox


@njit(cache=True)
def carve(vox, density, heights, threshold, floor_y):  # pragma: no cover - compiled
    """Empty solid voxels whose cave ``density`` is above ``threshold``.

    Only below the surface layer (``y < h``), above ``floor_y``, and never under water
    columns' floors (a cave would drain the lake through the skin).
    """
    w, ny, d = vox.shape
    for i in range(w):
        for k in range(d):
            h = heights[i, k]
            for y in range(floor_y, min(h, ny)):
                if density[i, y, k] > threshold and vox[i, y, k] != WATER:
                    if y + 1 < ny and vox[i, y + 1, k] == WATER:
                        continue
                    vox[i, y, k] = AIR
    return vox


# ------------------------------------------------------------------- greedy meshing
# directions: 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.  For axis a the in-face axes (b, c)
# satisfy e_b x e_c = e_a: X -> (Y, Z), Y -> (Z, X), Z -> (X, Y).


@njit(cache=True)
def _face_tex(block, direction, face_tex):  # pragma: no cover - compiled
    if direction == 2:
        return face_tex[block, 0]
    if direction == 3:
        return face_tex[block, 2]
    return face_tex[block, 1]


@njit(cache=True)
def _visible(block, other, opaque):  # pragma: no cover - compiled
    if block == AIR:
        return False
    if opaque[block]:
        return not opaque[other]
    # water and other see-through blocks: only against air
    return other == AIR


@njit(cache=True)
def greedy_quads(vox, face_tex, opaque, lo, hi, greedy):  # pragma: no cover - compiled
    """Greedy-merged visible faces of the voxels in the box ``[lo, hi)`` of ``vox``.

    Parameters
    ----------
    vox : uint8[X, Y, Z]
        Voxels, including a margin of at least one voxel around the box on x and z
        (neighbours outside the array on y count as solid below and air above).
    face_tex : int32[n_blocks, 3]
        Texture id of each block's top, side and bottom face.
    opaque : bool[n_blocks]
    lo, hi : int64[3]
        The box to mesh.
    greedy : bool
        Merge coplanar faces of one texture into rectangles (else one quad per face).

    Returns
    -------
    int32[q, 7]
        ``(direction, layer, b0, c0, b_size, c_size, texture)`` per quad; ``layer`` is the
        coordinate of the face plane on the normal axis, ``b0, c0`` the corner on the in-face
        axes.
    """
    nx, ny, nz = vox.shape
    size = np.empty(3, np.int64)
    for a in range(3):
        size[a] = hi[a] - lo[a]
    cap = 1024
    quads = np.empty((cap, 7), np.int32)
    nq = 0
    pos = np.zeros(3, np.int64)
    for direction in range(6):
        a = direction // 2
        sgn = 1 if direction % 2 == 0 else -1
        b = (a + 1) % 3
        c = (a + 2) % 3
        nb = size[b]
        nc = size[c]
        mask = np.empty((nb, nc), np.int32)
        for s in range(size[a]):
            any_face = False
            for ib in range(nb):
                for ic in range(nc):
                    pos[a] = lo[a] + s
                    pos[b] = lo[b] + ib
                    pos[c] = lo[c] + ic
                    blk = vox[pos[0], pos[1], pos[2]]
                    mask[ib, ic] = -1
                    if blk == AIR:
                        continue
                    pos[a] += sgn
                    if pos[1] < 0:
                        continue  # nothing is seen from below the world
                    if pos[1] >= ny:
                        other = np.uint8(AIR)
                    else:
                        other = vox[pos[0], pos[1], pos[2]]
                    if _visible(blk, other, opaque):
                        mask[ib, ic] = _face_tex(blk, direction, face_tex)
                        any_face = True
            if not any_face:
                continue
            layer = lo[a] + s + (1 if sgn > 0 else 0)
            for ic in range(nc):
                ib = 0
                while ib < nb:
                    t = mask[ib, ic]
                    if t < 0:
                        ib += 1
                        continue
                    wb = 1
                    if greedy:
                        while ib + wb < nb and mask[ib + wb, ic] == t:
                            wb += 1
                    wc = 1
                    if greedy:
                        done = False
                        while ic + wc < nc and not done:
                            for j in range(wb):
                                if mask[ib + j, ic + wc] != t:
                                    done = True
                                    break
                            if not done:
                                wc += 1
                    for jc in range(wc):
                        for jb in range(wb):
                            mask[ib + jb, ic + jc] = -1
                    if nq == cap:
                        cap *= 2
                        grown = np.empty((cap, 7), np.int32)
                        # element by element: a slice assignment compiles numba's
                        # shape-mismatch message (string formatting, seconds of compiling)
                        for r in range(nq):
                            for j in range(7):
                                grown[r, j] = quads[r, j]
                        quads = grown
                    quads[nq, 0] = direction
                    quads[nq, 1] = layer
                    quads[nq, 2] = lo[b] + ib
                    quads[nq, 3] = lo[c] + ic
                    quads[nq, 4] = wb
                    quads[nq, 5] = wc
                    quads[nq, 6] = t
                    nq += 1
                    ib += wb
    return quads[:nq].copy()


# ------------------------------------------------------------------- plant blocks
@njit(cache=True)
def contained(inner_c, inner_s, outer_c, outer_s, eps):  # pragma: no cover - compiled
    """``bool[n]``: block ``i`` of ``inner`` lies entirely inside some block of ``outer``."""
    n = inner_c.shape[0]
    m = outer_c.shape[0]
    out = np.zeros(n, np.bool_)
    for i in range(n):
        hi = 0.5 * inner_s[i]
        for j in range(m):
            ho = 0.5 * outer_s[j]
            ok = True
            for k in range(3):
                if abs(inner_c[i, k] - outer_c[j, k]) + hi > ho + eps:
                    ok = False
                    break
            if ok:
                out[i] = True
                break
    return out


@njit(cache=True)
def local_maxima(field, margin):  # pragma: no cover - compiled
    """``bool[w, d]``: ``field[i, k]`` is at least each of its 8 neighbours.

    Cells closer than ``margin`` (≥ 1) to the border are False.
    """
    w, d = field.shape
    out = np.zeros((w, d), np.bool_)
    for i in range(margin, w - margin):
        for k in range(margin, d - margin):
            v = field[i, k]
            ok = True
            for di in range(-1, 2):
                for dk in range(-1, 2):
                    if (di != 0 or dk != 0) and field[i + di, k + dk] > v:
                        ok = False
            out[i, k] = ok
    return out
