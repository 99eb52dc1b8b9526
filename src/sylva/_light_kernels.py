"""Numba kernels behind :class:`sylva.environments.Light`: the shadow-propagation grid of
Palubicki et al. (2009) and the least-shaded neighbour of each bud.

Nothing here checks its inputs; :mod:`sylva.environments` does.  Grids are indexed
``[x, y, z]`` with ``y`` up.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def shadow_grid(cells, weights, nx, ny, nz, shadow, falloff, depth):  # pragma: no cover
    """``float64[nx, ny, nz]``: the shadow that the casters at ``cells`` (``int64[m, 3]``,
    inside the grid: buds, leaves, segments) cast: each adds ``weights[b] · shadow ·
    falloff**-q`` to the voxels ``(x ± p, y − q, z ± p)``, ``0 <= p <= q <= depth`` (a
    pyramid below it)."""
    grid = np.zeros((nx, ny, nz), np.float64)
    for b in range(cells.shape[0]):
        x, y, z = cells[b, 0], cells[b, 1], cells[b, 2]
        w = weights[b]
        if w == 0.0:
            continue
        for q in range(depth + 1):
            j = y - q
            if j < 0:
                break
            ds = w * shadow * falloff ** (-q)
            for i in range(max(x - q, 0), min(x + q + 1, nx)):
                for k in range(max(z - q, 0), min(z + q + 1, nz)):
                    grid[i, j, k] += ds
    return grid


@njit(cache=True)
def light_at(grid, cells, heading, full, shadow, cos_cone):  # pragma: no cover - compiled
    """Per bud: its light ``max(full − s + shadow, 0) / full`` (``s`` the shadow of its
    voxel) and the unit direction to the least shaded of its 26 neighbours within the
    cone of half-angle ``acos(cos_cone)`` about ``heading`` (ties: the one nearest the
    heading; voxels outside the grid have no shadow).  Returns ``float64[m, 4]``."""
    nx, ny, nz = grid.shape
    m = cells.shape[0]
    out = np.zeros((m, 4), np.float64)
    for b in range(m):
        x, y, z = cells[b, 0], cells[b, 1], cells[b, 2]
        s = grid[x, y, z]
        out[b, 0] = max(full - s + shadow, 0.0) / full
        hx, hy, hz = heading[b, 0], heading[b, 1], heading[b, 2]
        best = np.inf
        best_dot = -np.inf
        vx = hx
        vy = hy
        vz = hz
        for dx in range(-1, 2):
            for dy in range(-1, 2):
                for dz in range(-1, 2):
                    if dx == 0 and dy == 0 and dz == 0:
                        continue
                    norm = np.sqrt(dx * dx + dy * dy + dz * dz)
                    dot = (dx * hx + dy * hy + dz * hz) / norm
                    if dot < cos_cone - 1e-12:
                        continue
                    i, j, k = x + dx, y + dy, z + dz
                    v = 0.0
                    if 0 <= i < nx and 0 <= j < ny and 0 <= k < nz:
                        v = grid[i, j, k]
                    if v < best - 1e-12 or (abs(v - best) <= 1e-12 and dot > best_dot):
                        best = v
                        best_dot = dot
                        vx = dx / norm
                        vy = dy / norm
                        vz = dz / norm
        out[b, 1] = vx
        out[b, 2] = vy
        out[b, 3] = vz
    return out
