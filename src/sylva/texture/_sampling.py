"""Numba drivers: one noise sample, a fractal sum of octaves, and parallel loops over
grids and point lists (private; see :mod:`sylva.texture.noise`)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import _kernels as k
from ._cellkernels import NEEDK, combine, worley, worley_poisson
from ._gridplan import run_blocks

# a direction for time in the 4D torus embedding of tileable simplex (unit length)
_TD = (0.3872983346207417, -0.5477225575051661, 0.4472135954999579, 0.5916079783099616)


@njit(cache=True, fastmath=False)
def noise_at(kind, ndim, x, y, z, w, px, py, pz, pw, interp, perm, perm12, vals, cg, wpar):
    """One sample of the base noise ``kind`` in ``ndim`` dimensions."""
    if kind == k.IMPROVED:
        if ndim == 2:
            return k.improved2(x, y, px, py, interp, perm)
        if ndim == 3:
            return k.improved3(x, y, z, px, py, pz, interp, perm)
        return k.improved4(x, y, z, w, px, py, pz, pw, interp, perm, k.GRAD4)
    if kind == k.SIMPLEX:
        if ndim == 2:
            return k.simplex2(x, y, perm, perm12)
        if ndim == 3:
            return k.simplex3(x, y, z, perm, perm12)
        return k.simplex4(x, y, z, w, perm)
    if kind == k.PERLIN:
        if ndim == 2:
            return k.perlin2(x, y, px, py, interp, perm, cg[0])
        if ndim == 3:
            return k.perlin3(x, y, z, px, py, pz, interp, perm, cg[1])
        return k.perlin4(x, y, z, w, px, py, pz, pw, interp, perm, cg[2])
    if kind == k.VALUE:
        if ndim == 2:
            return k.value2(x, y, px, py, interp, perm, vals)
        if ndim == 3:
            return k.value3(x, y, z, px, py, pz, interp, perm, vals)
        return k.value4(x, y, z, w, px, py, pz, pw, interp, perm, vals)
    combo = int(wpar[1])
    if wpar[7] > 0.0:  # a Poisson process of wpar[7] points per cell
        f1, f2, f3, cid = worley_poisson(
            ndim, x, y, z, w, px, py, pz, pw, int(wpar[0]), wpar[7], int(wpar[3]), NEEDK[combo]
        )
    else:
        f1, f2, f3, cid = worley(
            ndim, x, y, z, w, px, py, pz, pw, int(wpar[0]), wpar[2], int(wpar[3]), NEEDK[combo]
        )
    return combine(combo, f1, f2, f3, cid, wpar[4], wpar[5], wpar[6])


@njit(cache=True, fastmath=False)
def fractal_at(
    kind,
    mode,
    ndim,
    x,
    y,
    z,
    w,
    torus,
    freqs,
    amps,
    offs,
    pers,
    interp,
    perm,
    perm12,
    vals,
    cg,
    wpar,
    norm,
    gain,
):
    """Sum of octaves at one point.

    Octave ``o`` samples ``noise(freqs[o] * p + offs[o])`` (per-axis frequencies) with
    lattice periods ``int(pers[o])`` (0 = none).  ``mode``: fBm (sum of a*n), turbulence
    (sum of a*|n|) or ridged multifractal (Musgrave: s = (1-|n|)^2 weighted by the previous
    octave's s times ``gain``).  With ``torus`` (simplex only) ``x`` and ``y`` are angles
    and the point is wrapped onto a flat 4D torus whose circumferences are ``pers[o, :2]``
    lattice units, so the result tiles; ``z`` (time) then moves along a fixed 4D direction.
    """
    total = 0.0
    weight = 1.0
    for o in range(freqs.shape[0]):
        if torus:
            rx = pers[o, 0] / k.TWO_PI
            ry = pers[o, 1] / k.TWO_PI
            tz = z * freqs[o, 2] if ndim >= 3 else 0.0
            n = k.simplex4(
                rx * math.cos(x) + offs[o, 0] + tz * _TD[0],
                rx * math.sin(x) + offs[o, 1] + tz * _TD[1],
                ry * math.cos(y) + offs[o, 2] + tz * _TD[2],
                ry * math.sin(y) + offs[o, 3] + tz * _TD[3],
                perm,
            )
        else:
            n = noise_at(
                kind,
                ndim,
                x * freqs[o, 0] + offs[o, 0],
                y * freqs[o, 1] + offs[o, 1],
                z * freqs[o, 2] + offs[o, 2],
                w * freqs[o, 3] + offs[o, 3],
                int(pers[o, 0]),
                int(pers[o, 1]),
                int(pers[o, 2]),
                int(pers[o, 3]),
                interp,
                perm,
                perm12,
                vals,
                cg,
                wpar,
            )
        if mode == k.FBM:
            total += amps[o] * n
        elif mode == k.TURBULENCE:
            total += amps[o] * abs(n)
        else:
            s = 1.0 - abs(n)
            s *= s
            s *= weight
            weight = min(max(s * gain, 0.0), 1.0)
            total += amps[o] * s
    return total * norm


@njit(cache=True, fastmath=False, nogil=True)
def generic_kernel(
    r0,
    r1,
    points,
    kind,
    mode,
    ndim,
    xs,
    ys,
    zs,
    ws,
    out,
    torus,
    freqs,
    amps,
    offs,
    pers,
    interp,
    perm,
    perm12,
    vals,
    cg,
    wpar,
    norm,
    gain,
):
    """Fill rows ``r0 .. r1`` of ``out[nw, nz, ny, nx]`` (a row: ``(iw, iz, iy)``) with the
    fractal sum (:func:`._gridplan.run_blocks` runs the rows on threads).

    Grid mode: the product grid of the axes ``xs[nx], ys[ny], zs[nz], ws[nw]``.
    Point mode (``points``): ``out`` has shape (1, 1, rows, chunk) and sample ``q`` of
    row ``r`` (``q = r * chunk + i``) is the point ``(xs[q], ys[q], zs[q], ws[q])``.
    """
    nw, nz, ny, nx = out.shape
    for r in range(r0, r1):
        iy = r % ny
        iz = (r // ny) % nz
        iw = r // (ny * nz)
        for ix in range(nx):
            if points:
                q = r * nx + ix
                x = xs[q]
                y = ys[q]
                z = zs[q]
                w = ws[q]
            else:
                x = xs[ix]
                y = ys[iy]
                z = zs[iz]
                w = ws[iw]
            out[iw, iz, iy, ix] = fractal_at(
                kind,
                mode,
                ndim,
                x,
                y,
                z,
                w,
                torus,
                freqs,
                amps,
                offs,
                pers,
                interp,
                perm,
                perm12,
                vals,
                cg,
                wpar,
                norm,
                gain,
            )


#: What :func:`sylva._jit.interpreted` puts in this module's copy: :func:`fractal_at`'s
#: ridged weight, ``min(max(s * gain, 0.0), 1.0)``, on whole arrays
#: (:func:`sylva.texture._gridplan.fractal_arrays`).
_INTERPRETED = {"min": "_array_min", "max": "_array_max"}
_array_min = np.minimum
_array_max = np.maximum

CHUNK = 2048  # points per parallel row, at most


def run_points(
    kind,
    mode,
    ndim,
    px,
    py,
    pz,
    pw,
    freqs,
    amps,
    offs,
    pers,
    interp,
    perm,
    perm12,
    vals,
    cg,
    wpar,
    norm,
    gain,
):
    """The fractal sum at ``n`` points (float64 arrays of equal length); returns (n,).

    The points are cut into rows of at most :data:`CHUNK` of equal length, padded by fewer
    than one point per row (a single point costs one evaluation, not a whole row).
    """
    n = px.shape[0]
    rows = max(1, -(-n // CHUNK))
    chunk = max(1, -(-n // rows))
    size = rows * chunk
    coords = []
    for c in (px, py, pz, pw):
        if size != n:
            padded = np.zeros(size)
            padded[:n] = c
            c = padded
        coords.append(c)
    out = np.empty((1, 1, rows, chunk))
    run_blocks(generic_kernel, rows, (
        True,
        kind,
        mode,
        ndim,
        coords[0],
        coords[1],
        coords[2],
        coords[3],
        out,
        False,
        freqs,
        amps,
        offs,
        pers,
        interp,
        perm,
        perm12,
        vals,
        cg,
        wpar,
        norm,
        gain,
    ))
    return out.reshape(-1)[:n]
