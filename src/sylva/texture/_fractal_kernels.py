"""Numba kernels for escape-time fractals and the IFS chaos game (private; see
:mod:`sylva.texture.fractals`)."""

from __future__ import annotations

import math

from numba import njit, prange

MANDELBROT, JULIA, BURNING_SHIP, BARNSLEY_J1, BARNSLEY_J1Z = 0, 1, 2, 3, 4
LOG2 = math.log(2.0)


@njit(cache=True, fastmath=False, parallel=True)
def escape_kernel(kind, re, im, cre, cim, maxiter, bailout, smooth, out):
    """Smooth escape-time counts on the grid ``re[nx] x im[ny]`` into ``out[ny, nx]``.

    Kinds: Mandelbrot (z0 = 0, c = pixel), Julia (z0 = pixel, c fixed), Burning Ship
    (z <- (|Re z| + i |Im z|)^2 + c), and Ultra Fractal's "barnsleyj1" (z0 = pixel,
    z <- (z - 1) c if Re z >= 0 else (z + 1) c) with its "z*" variant
    (z <- (z -/+ 1) z c).  Iteration stops when |z|^2 >= bailout^2.  Points that never
    escape get -1.  With ``smooth`` the count is n + 1 - log_d(log|z_n| / log bailout)
    (d = 2 for the quadratic maps, |c| for the linear barnsleyj1), clipped to [n, n + 1).
    """
    ny, nx = out.shape
    b2 = bailout * bailout
    logb = math.log(bailout)
    cabs = math.hypot(cre, cim)
    for j in prange(ny):
        for i in range(nx):
            if kind == MANDELBROT or kind == BURNING_SHIP:  # noqa: SIM109 (numba)
                zr = 0.0
                zi = 0.0
                cr = re[i]
                ci = im[j]
            else:
                zr = re[i]
                zi = im[j]
                cr = cre
                ci = cim
            n = 0
            m2 = zr * zr + zi * zi
            while n < maxiter and m2 < b2:
                if kind == BURNING_SHIP:
                    ar = abs(zr)
                    ai = abs(zi)
                    zr, zi = ar * ar - ai * ai + cr, 2.0 * ar * ai + ci
                elif kind == BARNSLEY_J1 or kind == BARNSLEY_J1Z:  # noqa: SIM109
                    sr = zr - 1.0 if zr >= 0 else zr + 1.0
                    si = zi
                    if kind == BARNSLEY_J1Z:
                        sr, si = sr * zr - si * zi, sr * zi + si * zr
                    zr, zi = sr * cr - si * ci, sr * ci + si * cr
                else:
                    zr, zi = zr * zr - zi * zi + cr, 2.0 * zr * zi + ci
                m2 = zr * zr + zi * zi
                n += 1
            if m2 < b2:
                out[j, i] = -1.0
            elif not smooth or n == 0:
                out[j, i] = n
            else:
                lz = 0.5 * math.log(m2)
                if kind == BARNSLEY_J1 and cabs > 1.0:
                    frac = (lz - logb) / math.log(cabs)
                else:
                    frac = math.log(max(lz / logb, 1.0)) / LOG2
                frac = min(max(frac, 0.0), 0.999999)
                out[j, i] = n + 1.0 - frac


@njit(cache=True, fastmath=False)
def chaos_game(mats, offs, choices, x0, y0, xmin, ymin, sx, sy, hist, skip):
    """Iterate p <- A_k p + b_k for k = choices[n]; count visits in ``hist[ny, nx]``.

    The first ``skip`` points are discarded (transient).  Pixel (i, j) covers
    x in [xmin + i/sx, ...), y in [ymin + j/sy, ...).
    """
    ny, nx = hist.shape
    x = x0
    y = y0
    for n in range(choices.shape[0]):
        k = choices[n]
        x, y = (mats[k, 0, 0] * x + mats[k, 0, 1] * y + offs[k, 0],
                mats[k, 1, 0] * x + mats[k, 1, 1] * y + offs[k, 1])
        if n < skip:
            continue
        i = int(math.floor((x - xmin) * sx))
        j = int(math.floor((y - ymin) * sy))
        if 0 <= i < nx and 0 <= j < ny:
            hist[ny - 1 - j, i] += 1


@njit(cache=True, fastmath=False)
def mandelbrot_members(cre, cim, maxiter, out):
    """``out[i]``: whether c stays within |z| <= 2 for ``maxiter`` iterations of z^2 + c."""
    for i in range(cre.shape[0]):
        zr = 0.0
        zi = 0.0
        cr = cre[i]
        ci = cim[i]
        inside = True
        for _ in range(maxiter):
            zr, zi = zr * zr - zi * zi + cr, 2.0 * zr * zi + ci
            if zr * zr + zi * zi > 4.0:
                inside = False
                break
        out[i] = inside
