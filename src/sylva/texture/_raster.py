"""Numba rasteriser for anti-aliased thick line segments (private; see
:mod:`sylva.texture.lsystem_texture`)."""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, fastmath=False)
def draw_segments(rgb, alpha, x0, y0, x1, y1, half, colors, wrap):
    """Composite segments, in order, over ``rgb[H, W, 3]`` / ``alpha[H, W]``.

    Coordinates are in pixels (pixel (i, j) has its centre at (i + 0.5, j + 0.5)); a
    segment covers the pixels within ``half[k]`` of it, with a one-pixel linear fall-off
    (round caps).  With ``wrap`` the pixel indices are taken modulo the image size, so a
    drawing that leaves one edge re-enters at the opposite one (seamless tiles).
    """
    h, w = alpha.shape
    for k in range(x0.shape[0]):
        ax = x0[k]
        ay = y0[k]
        bx = x1[k]
        by = y1[k]
        r = half[k]
        dx = bx - ax
        dy = by - ay
        ll = dx * dx + dy * dy
        i0 = int(math.floor(min(ax, bx) - r - 1.0))
        i1 = int(math.ceil(max(ax, bx) + r + 1.0))
        j0 = int(math.floor(min(ay, by) - r - 1.0))
        j1 = int(math.ceil(max(ay, by) + r + 1.0))
        if not wrap:
            i0 = max(i0, 0)
            j0 = max(j0, 0)
            i1 = min(i1, w)
            j1 = min(j1, h)
        elif i1 - i0 > w + 2 * r + 4 or j1 - j0 > h + 2 * r + 4:
            i1 = min(i1, i0 + w + 1)
            j1 = min(j1, j0 + h + 1)
        for j in range(j0, j1):
            py = j + 0.5
            for i in range(i0, i1):
                px = i + 0.5
                if ll > 0:
                    t = ((px - ax) * dx + (py - ay) * dy) / ll
                    t = min(max(t, 0.0), 1.0)
                else:
                    t = 0.0
                ex = px - (ax + t * dx)
                ey = py - (ay + t * dy)
                d = math.sqrt(ex * ex + ey * ey)
                a = min(max(r + 0.5 - d, 0.0), 1.0)
                if a <= 0.0:
                    continue
                ii = i % w if wrap else i
                jj = j % h if wrap else j
                for c in range(3):
                    rgb[jj, ii, c] = rgb[jj, ii, c] * (1.0 - a) + colors[k, c] * a
                alpha[jj, ii] = alpha[jj, ii] + a * (1.0 - alpha[jj, ii])
