"""Compiled mesh builders behind :mod:`sylva.geometry.build` (no input checking here)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange, uint64

from ._simd import index_patterns, ring_table, write_indices, write_ring

TWO_PI = 2.0 * math.pi
# LLVM may multiply by a reciprocal and fuse multiply-adds (~20 % off the tube fill); no
# assumptions about NaN or infinity, which the kernels test for
FAST = {"arcp", "contract", "nsz"}


# --------------------------------------------------------------------------- tubes
@njit(cache=True, fastmath=FAST, parallel=True)
def tube_plan(start, end, radius, parent, depth, material, color, cos_limit, split_colors, d,
              cont, prev, dup, v1, voff, toff):  # fmt: skip
    """Choose axis continuations and lay out vertices and triangles of continuous tubes.

    A segment continues its parent's tube when it is the parent's child of lowest bracket
    depth (first drawn on ties) and bends by less than ``acos(cos_limit)``.  A continuing
    segment of another material (or colour, with ``split_colors``) starts with its own copy
    of the parent's end ring, so the surface stays closed where the colour changes.
    Writes, for ``n`` segments:

    cont : int64[n]      the continuing child (-1: the tube ends with a cap)
    prev : bool[n]       True when the segment continues its parent (no start cap)
    dup : bool[n]        True when it continues with its own copy of the parent's end ring
    v1 : float64[n]      texture v at the segment's end (length / mean circumference)
    voff, toff : int64[n+1]  first vertex / triangle of each segment
    """
    n = start.shape[0]
    ok = prev  # until the continuations are chosen: may s continue its parent?
    lens = v1  # until the texture lengths are summed: each segment's length
    for s in prange(n):
        ax = end[s, 0] - start[s, 0]
        ay = end[s, 1] - start[s, 1]
        az = end[s, 2] - start[s, 2]
        la = math.sqrt(ax * ax + ay * ay + az * az)
        lens[s] = la
        ok[s] = False
        cont[s] = -1
        p = parent[s]
        if p < 0:
            continue
        bx = end[p, 0] - start[p, 0]
        by = end[p, 1] - start[p, 1]
        bz = end[p, 2] - start[p, 2]
        lb = math.sqrt(bx * bx + by * by + bz * bz)
        ok[s] = (ax * bx + ay * by + az * bz) / (la * lb) >= cos_limit
    for s in range(n):
        if ok[s]:
            p = parent[s]
            q = cont[p]
            if q < 0 or depth[s] < depth[q]:
                cont[p] = s
    r = d + 1
    for s in prange(n):  # each segment's own part: v1 holds its texture length for now
        p = parent[s]
        pv = p >= 0 and cont[p] == s
        prev[s] = pv
        dup[s] = pv and (
            material[s] != material[p]
            or (
                split_colors
                and (
                    color[s, 0] != color[p, 0]
                    or color[s, 1] != color[p, 1]
                    or color[s, 2] != color[p, 2]
                )
            )
        )
        rm = 0.5 * (radius[s, 0] + radius[s, 1])
        v1[s] = lens[s] / (TWO_PI * max(rm, 1e-12))
        nv = r
        nt = 2 * d
        if not pv:
            nv += r + 1
            nt += d
        elif dup[s]:
            nv += r
        if cont[s] < 0:
            nv += 1
            nt += d
        voff[s + 1] = nv
        toff[s + 1] = nt
    voff[0] = 0
    toff[0] = 0
    for s in range(n):  # parents come first: texture v runs on along each tube
        if prev[s]:
            v1[s] += v1[parent[s]]
        voff[s + 1] += voff[s]
        toff[s + 1] += toff[s]


@njit(cache=True, fastmath=FAST, inline="always")
def _frame(s, start, end, radius, ref):
    """Segment ``s``: unit axis, ring reference r, b = axis × r, radii, taper slope."""
    ax = end[s, 0] - start[s, 0]
    ay = end[s, 1] - start[s, 1]
    az = end[s, 2] - start[s, 2]
    ln = math.sqrt(ax * ax + ay * ay + az * az)
    ax /= ln
    ay /= ln
    az /= ln
    rx = np.float64(ref[s, 0])
    ry = np.float64(ref[s, 1])
    rz = np.float64(ref[s, 2])
    bx = ay * rz - az * ry
    by = az * rx - ax * rz
    bz = ax * ry - ay * rx
    r0 = np.float64(radius[s, 0])
    r1 = np.float64(radius[s, 1])
    slope = (r0 - r1) / ln  # outward tilt of the normal on a frustum
    return ax, ay, az, rx, ry, rz, bx, by, bz, r0, r1, slope


@njit(cache=True, fastmath=FAST, inline="always")
def _end_basis(fr, s, q, start, end):
    """The end ring of segment ``s`` of frame ``fr`` (:func:`_frame`), mitred toward its
    continuation ``q`` when q >= 0.

    Ring vertex j is ``centre + cos·P + sin·Q``, its normal ``(G + cos·A + sin·B)·k`` with
    ``k = 1 / sqrt(1 - (cos·alpha + sin·beta)²)``.  Returns (centre, P, Q, A, B, G, alpha,
    beta) as 20 floats."""
    ax, ay, az, rx, ry, rz, bx, by, bz, r0, r1, slope = fr
    if q >= 0:
        # mitre: slide each circle point along the axis onto the plane bisecting the
        # joint (normal m); its normal is the ring direction with m projected out
        qx = end[q, 0] - start[q, 0]
        qy = end[q, 1] - start[q, 1]
        qz = end[q, 2] - start[q, 2]
        ql = math.sqrt(qx * qx + qy * qy + qz * qz)
        mx = ax + qx / ql
        my = ay + qy / ql
        mz = az + qz / ql
        ml = math.sqrt(mx * mx + my * my + mz * mz)
        mx /= ml
        my /= ml
        mz /= ml
        am = ax * mx + ay * my + az * mz
        alpha = rx * mx + ry * my + rz * mz
        beta = bx * mx + by * my + bz * mz
        return (
            end[s, 0], end[s, 1], end[s, 2],
            r1 * (rx - alpha / am * ax), r1 * (ry - alpha / am * ay), r1 * (rz - alpha / am * az),
            r1 * (bx - beta / am * ax), r1 * (by - beta / am * ay), r1 * (bz - beta / am * az),
            rx - alpha * mx, ry - alpha * my, rz - alpha * mz,
            bx - beta * mx, by - beta * my, bz - beta * mz,
            0.0, 0.0, 0.0, alpha, beta,
        )  # fmt: skip
    inv = 1.0 / math.sqrt(1.0 + slope * slope)
    return (
        end[s, 0], end[s, 1], end[s, 2],
        r1 * rx, r1 * ry, r1 * rz, r1 * bx, r1 * by, r1 * bz,
        rx * inv, ry * inv, rz * inv, bx * inv, by * inv, bz * inv,
        slope * ax * inv, slope * ay * inv, slope * az * inv, 0.0, 0.0,
    )  # fmt: skip


@njit(cache=True, fastmath=FAST, inline="always")
def _start_basis(fr, s, start):
    """The start ring of a tube's first segment (see :func:`_end_basis`)."""
    ax, ay, az, rx, ry, rz, bx, by, bz, r0, r1, slope = fr
    inv = 1.0 / math.sqrt(1.0 + slope * slope)
    return (
        start[s, 0], start[s, 1], start[s, 2],
        r0 * rx, r0 * ry, r0 * rz, r0 * bx, r0 * by, r0 * bz,
        rx * inv, ry * inv, rz * inv, bx * inv, by * inv, bz * inv,
        slope * ax * inv, slope * ay * inv, slope * az * inv, 0.0, 0.0,
    )  # fmt: skip


@njit(cache=True, fastmath=FAST)
def _tube_range(lo, hi, start, end, radius, ref, color, material, parent, cont, prev, dup, v1,
                voff, toff, table, p_mantle, p_start, p_end, d, want_colors, V, N, UV, C, I,
                M):  # fmt: skip
    """Tubes of segments ``lo`` … ``hi - 1`` (see :func:`tube_fill`).

    Every ring comes from bases set once per ring (:func:`_end_basis`) and is written as a
    vector block (:func:`~sylva.geometry._simd.write_ring`); a segment that changes colour
    on its tube copies its parent's end ring from the same bases, so the copy lies exactly
    on the original."""
    want_m = M.shape[0] > 0
    # unsigned vertex and triangle numbers spare numba's negative-index checks
    r = uint64(d + 1)
    du = uint64(d)
    one = uint64(1)
    two = uint64(2)
    nr = d + 1
    for s in range(lo, hi):
        v = uint64(voff[s])
        t = uint64(toff[s])
        mat = material[s]
        p = parent[s]
        fr = _frame(s, start, end, radius, ref)
        if prev[s]:
            vs = v1[p]
            if dup[s]:  # own copy of the parent's end ring (another colour or material)
                frp = _frame(p, start, end, radius, ref)
                write_ring(v, _end_basis(frp, p, s, start, end), vs, nr, table, V, N, UV)
                a0 = v
                e = v + r
            else:
                a0 = uint64(voff[p])  # the parent's end ring
                if not prev[p]:
                    a0 += r + one
                elif dup[p]:
                    a0 += r
                e = v
        else:  # ------------------------------------------------ start ring + cap
            vs = 0.0
            bs = _start_basis(fr, s, start)
            write_ring(v, bs, vs, nr, table, V, N, UV)
            a0 = v
            e = v + r + one
            center = v + r
            V[center, 0] = bs[0]
            V[center, 1] = bs[1]
            V[center, 2] = bs[2]
            N[center, 0] = -fr[0]
            N[center, 1] = -fr[1]
            N[center, 2] = -fr[2]
            UV[center, 0] = 0.5
            UV[center, 1] = vs
            write_indices(t, 3 * d, a0, a0, p_start, I)
            if want_m:
                for j in range(du):
                    M[t + j] = mat
            t += du
        # ---------------------------------------------------- end ring and mantle
        q = cont[s]
        bs = _end_basis(fr, s, q, start, end)
        ve = v1[s]
        write_ring(e, bs, ve, nr, table, V, N, UV)
        write_indices(t, 6 * d, a0, e, p_mantle, I)
        if want_m:
            for j in range(two * du):
                M[t + j] = mat
        t += two * du
        if q < 0:  # ------------------------------------------------ end cap
            center = e + r
            V[center, 0] = bs[0]
            V[center, 1] = bs[1]
            V[center, 2] = bs[2]
            N[center, 0] = fr[0]
            N[center, 1] = fr[1]
            N[center, 2] = fr[2]
            UV[center, 0] = 0.5
            UV[center, 1] = ve
            write_indices(t, 3 * d, e, e, p_end, I)
            if want_m:
                for j in range(du):
                    M[t + j] = mat
        if want_colors:
            for k in range(voff[s], voff[s + 1]):
                C[k, 0] = color[s, 0]
                C[k, 1] = color[s, 1]
                C[k, 2] = color[s, 2]
                C[k, 3] = 1.0


TUBE_CHUNK = 1024  # segments per task of the parallel fill


@njit(cache=True, fastmath=FAST, parallel=True)
def tube_fill(start, end, radius, ref, color, material, parent, cont, prev, dup, v1, voff, toff,
              d, want_colors, V, N, UV, C, I, M):  # fmt: skip
    """Write the tube vertices (V, N, UV, C) and triangles (I, M) laid out by tube_plan.

    ``M`` may be empty (one material: no per-triangle ids are written).  Positions and
    normals are computed in float32, the mesh's type (within an ulp or two of rounding
    float64 results)."""
    n = start.shape[0]
    table = ring_table(d)
    p_mantle, p_start, p_end = index_patterns(d)
    chunks = (n + TUBE_CHUNK - 1) // TUBE_CHUNK
    for c in prange(chunks):
        _tube_range(c * TUBE_CHUNK, min(n, (c + 1) * TUBE_CHUNK), start, end, radius, ref, color,
                    material, parent, cont, prev, dup, v1, voff, toff, table, p_mantle, p_start,
                    p_end, d, want_colors, V, N, UV, C, I, M)  # fmt: skip


@njit(cache=True, fastmath=FAST)
def leonardo(parent, radius, exponent):
    """Radii by Leonardo's rule: ``r(s)^e = Σ r(child)^e``; tips keep their end radius.

    Returns float32[n, 2]: the radius at the start of every segment and at its end (the
    start radius of its thickest child, or the tip radius).
    """
    n = parent.shape[0]
    acc = np.zeros(n)
    has_child = np.zeros(n, np.bool_)
    thick_child = np.full(n, -1, np.int64)
    for s in range(n - 1, -1, -1):
        if not has_child[s]:
            acc[s] = np.float64(radius[s, 1]) ** exponent
        p = parent[s]
        if p >= 0:
            acc[p] += acc[s]
            has_child[p] = True
            if thick_child[p] < 0 or acc[s] > acc[thick_child[p]]:
                thick_child[p] = s
    out = np.empty((n, 2), np.float32)
    for s in range(n):
        out[s, 0] = acc[s] ** (1.0 / exponent)
    for s in range(n):
        c = thick_child[s]
        out[s, 1] = out[c, 0] if c >= 0 else radius[s, 1]
    return out


# --------------------------------------------------------------------------- prisms and cones
@njit(cache=True, fastmath=FAST)
def prism_fill(start, end, radius, ref, color, material, d, want_colors, V, N, UV, C, I, M):
    """Seed 001: the mantle of a regular prism per segment, ``d`` flat faces (4 vertices and
    2 triangles each); ``d == 1`` is one rectangle in the (H, ref) plane, both sides."""
    n = start.shape[0]
    faces = d if d >= 3 else 2
    for s in range(n):  # fidelity mode: serial (cheap to compile)
        ax, ay, az, rx, ry, rz, bx, by, bz, r0, r1, _ = _frame(s, start, end, radius, ref)
        v = s * faces * 4
        t = s * faces * 2
        for f in range(faces):
            if d >= 3:
                p0 = TWO_PI * f / d
                p1 = TWO_PI * (f + 1) / d
                c0 = math.cos(p0)
                s0 = math.sin(p0)
                c1 = math.cos(p1)
                s1 = math.sin(p1)
                pm = 0.5 * (p0 + p1)
                ncx = math.cos(pm) * rx + math.sin(pm) * bx
                ncy = math.cos(pm) * ry + math.sin(pm) * by
                ncz = math.cos(pm) * rz + math.sin(pm) * bz
            else:  # a flat strip across ref, seen from both sides
                sign = 1.0 if f == 0 else -1.0
                c0 = -sign
                s0 = 0.0
                c1 = sign
                s1 = 0.0
                ncx = sign * bx
                ncy = sign * by
                ncz = sign * bz
            e0x = c0 * rx + s0 * bx
            e0y = c0 * ry + s0 * by
            e0z = c0 * rz + s0 * bz
            e1x = c1 * rx + s1 * bx
            e1y = c1 * ry + s1 * by
            e1z = c1 * rz + s1 * bz
            V[v, 0] = start[s, 0] + r0 * e0x
            V[v, 1] = start[s, 1] + r0 * e0y
            V[v, 2] = start[s, 2] + r0 * e0z
            V[v + 1, 0] = start[s, 0] + r0 * e1x
            V[v + 1, 1] = start[s, 1] + r0 * e1y
            V[v + 1, 2] = start[s, 2] + r0 * e1z
            V[v + 2, 0] = end[s, 0] + r1 * e1x
            V[v + 2, 1] = end[s, 1] + r1 * e1y
            V[v + 2, 2] = end[s, 2] + r1 * e1z
            V[v + 3, 0] = end[s, 0] + r1 * e0x
            V[v + 3, 1] = end[s, 1] + r1 * e0y
            V[v + 3, 2] = end[s, 2] + r1 * e0z
            u0 = f / faces
            u1 = (f + 1) / faces
            UV[v, 0] = u0
            UV[v, 1] = 0.0
            UV[v + 1, 0] = u1
            UV[v + 1, 1] = 0.0
            UV[v + 2, 0] = u1
            UV[v + 2, 1] = 1.0
            UV[v + 3, 0] = u0
            UV[v + 3, 1] = 1.0
            for k in range(4):
                N[v + k, 0] = ncx
                N[v + k, 1] = ncy
                N[v + k, 2] = ncz
                if want_colors:
                    C[v + k, 0] = color[s, 0]
                    C[v + k, 1] = color[s, 1]
                    C[v + k, 2] = color[s, 2]
                    C[v + k, 3] = 1.0
            I[t, 0] = v
            I[t, 1] = v + 1
            I[t, 2] = v + 2
            I[t + 1, 0] = v
            I[t + 1, 1] = v + 2
            I[t + 1, 2] = v + 3
            M[t] = material[s]
            M[t + 1] = material[s]
            v += 4
            t += 2


@njit(cache=True, fastmath=FAST)
def cone_fill(start, end, radius, ref, color, material, d, h, want_colors, V, N, UV, C, I, M):
    """Seed 000: a frustum per segment whose bottom base is a hemisphere of the base radius
    (``h`` rings of latitude) and whose top is a flat disc.  Closed; no shared vertices."""
    n = start.shape[0]
    r = d + 1
    nv = r * (h + 2) + 2
    nt = 2 * d * h + 2 * d + d + d
    for s in range(n):  # fidelity mode: serial (cheap to compile)
        ax, ay, az, rx, ry, rz, bx, by, bz, r0, r1, slope = _frame(s, start, end, radius, ref)
        v0 = s * nv
        t = s * nt
        # rings 0..h-1: hemisphere latitudes from the pole side up to the equator (ring h)
        # ring h: the bottom equator (frustum bottom), ring h+1: the top
        for i in range(h + 2):
            if i <= h:
                lat = (0.5 * math.pi) * (1.0 - (i + 1.0) / (h + 1.0))  # angle below equator
                cr = r0 * math.cos(lat)
                off = -r0 * math.sin(lat)
                cx = start[s, 0] + off * ax
                cy = start[s, 1] + off * ay
                cz = start[s, 2] + off * az
                vv = (i + 1.0) / (h + 1.0) * 0.25
            else:
                cr = r1
                lat = 0.0
                cx = end[s, 0]
                cy = end[s, 1]
                cz = end[s, 2]
                vv = 1.0
            for j in range(r):
                phi = TWO_PI * j / d
                c = math.cos(phi)
                sn = math.sin(phi)
                nx = c * rx + sn * bx
                ny = c * ry + sn * by
                nz = c * rz + sn * bz
                k = v0 + i * r + j
                V[k, 0] = cx + cr * nx
                V[k, 1] = cy + cr * ny
                V[k, 2] = cz + cr * nz
                if i < h:
                    gx = math.cos(lat) * nx - math.sin(lat) * ax
                    gy = math.cos(lat) * ny - math.sin(lat) * ay
                    gz = math.cos(lat) * nz - math.sin(lat) * az
                else:
                    gx = nx + slope * ax
                    gy = ny + slope * ay
                    gz = nz + slope * az
                gl = math.sqrt(gx * gx + gy * gy + gz * gz)
                N[k, 0] = gx / gl
                N[k, 1] = gy / gl
                N[k, 2] = gz / gl
                UV[k, 0] = j / d
                UV[k, 1] = vv
        pole = v0 + r * (h + 2)
        V[pole, 0] = start[s, 0] - r0 * ax
        V[pole, 1] = start[s, 1] - r0 * ay
        V[pole, 2] = start[s, 2] - r0 * az
        N[pole, 0] = -ax
        N[pole, 1] = -ay
        N[pole, 2] = -az
        UV[pole, 0] = 0.5
        UV[pole, 1] = 0.0
        top = pole + 1
        V[top, 0] = end[s, 0]
        V[top, 1] = end[s, 1]
        V[top, 2] = end[s, 2]
        N[top, 0] = ax
        N[top, 1] = ay
        N[top, 2] = az
        UV[top, 0] = 0.5
        UV[top, 1] = 1.0
        for j in range(d):  # pole fan
            I[t, 0] = pole
            I[t, 1] = v0 + j + 1
            I[t, 2] = v0 + j
            t += 1
        for i in range(h + 1):  # hemisphere bands and the frustum (ring h to h+1)
            a0 = v0 + i * r
            b0 = a0 + r
            for j in range(d):
                I[t, 0] = a0 + j
                I[t, 1] = a0 + j + 1
                I[t, 2] = b0 + j + 1
                I[t + 1, 0] = a0 + j
                I[t + 1, 1] = b0 + j + 1
                I[t + 1, 2] = b0 + j
                t += 2
        e = v0 + (h + 1) * r
        for j in range(d):  # top disc
            I[t, 0] = top
            I[t, 1] = e + j
            I[t, 2] = e + j + 1
            t += 1
        for k in range(s * nt, (s + 1) * nt):
            M[k] = material[s]
        if want_colors:
            for k in range(v0, v0 + nv):
                C[k, 0] = color[s, 0]
                C[k, 1] = color[s, 1]
                C[k, 2] = color[s, 2]
                C[k, 3] = 1.0


# --------------------------------------------------------------------------- polygons
@njit(cache=True)
def polygon_planes(vertices, offsets):  # pragma: no cover - compiled
    """Each polygon's plane: its unit Newell normal, its vertices in a 2D basis of the
    plane (``e1 x e2 = n``, so the polygon runs counter-clockwise there) and whether it is
    convex (no reflex vertex; collinear vertices are allowed).

    Parameters
    ----------
    vertices : float64[v, 3]; offsets : int64[p + 1]

    Returns
    -------
    normals : float64[p, 3]
    flat : float64[v, 2]
    convex : bool[p]
        (polygons of fewer than 3 vertices count as convex: they make no triangle)
    """
    p = offsets.shape[0] - 1
    normals = np.zeros((p, 3))
    flat = np.zeros((vertices.shape[0], 2))
    convex = np.ones(p, np.bool_)
    for i in range(p):
        o = offsets[i]
        k = offsets[i + 1] - o
        if k < 3:
            continue
        nx = 0.0
        ny = 0.0
        nz = 0.0
        for a in range(k):
            b = (a + 1) % k
            va = vertices[o + a]
            vb = vertices[o + b]
            nx += (va[1] - vb[1]) * (va[2] + vb[2])
            ny += (va[2] - vb[2]) * (va[0] + vb[0])
            nz += (va[0] - vb[0]) * (va[1] + vb[1])
        nl = math.sqrt(nx * nx + ny * ny + nz * nz)
        if nl < 1e-300:
            nx, ny, nz, nl = 0.0, 0.0, 1.0, 1.0
        nx /= nl
        ny /= nl
        nz /= nl
        normals[i, 0] = nx
        normals[i, 1] = ny
        normals[i, 2] = nz
        if abs(nx) < 0.9:
            e1x, e1y, e1z = 0.0, -nz, ny  # (1,0,0) x n
        else:
            e1x, e1y, e1z = nz, 0.0, -nx  # (0,1,0) x n
        el = math.sqrt(e1x * e1x + e1y * e1y + e1z * e1z)
        e1x /= el
        e1y /= el
        e1z /= el
        e2x = ny * e1z - nz * e1y
        e2y = nz * e1x - nx * e1z
        e2z = nx * e1y - ny * e1x
        lo0 = lo1 = math.inf
        hi0 = hi1 = -math.inf
        for a in range(k):
            va = vertices[o + a]
            x = va[0] * e1x + va[1] * e1y + va[2] * e1z
            y = va[0] * e2x + va[1] * e2y + va[2] * e2z
            flat[o + a, 0] = x
            flat[o + a, 1] = y
            lo0 = min(lo0, x)
            hi0 = max(hi0, x)
            lo1 = min(lo1, y)
            hi1 = max(hi1, y)
        ext = max(hi0 - lo0, hi1 - lo1)
        eps = 1e-10 * ext * ext  # turns below this are straight (collinear vertices)
        for a in range(k):
            pa = flat[o + (a + k - 1) % k]
            pb = flat[o + a]
            pc = flat[o + (a + 1) % k]
            turn = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (pb[1] - pa[1])
            if turn < -eps:
                convex[i] = False
                break
    return normals, flat, convex


# --------------------------------------------------------------------------- tangents
@njit(cache=True)
def vertex_tangents(V, N, UV, I):  # pragma: no cover - compiled
    """glTF ``TANGENT`` (float32[n, 4]) of a mesh: per-triangle uv gradients dP/du and
    dP/dv summed at the vertices, dP/du made orthogonal to the normal and unit (any
    orthogonal direction where there is no gradient), w = ±1 the handedness that makes
    ``cross(N, T) * w`` point towards smaller v.  The loop of
    :func:`sylva.geometry.exchange._textures.tangents_numpy`, the reference it equals."""
    nv = V.shape[0]
    ts = np.zeros((nv, 3))
    bs = np.zeros((nv, 3))
    for f in range(I.shape[0]):
        i0, i1, i2 = I[f, 0], I[f, 1], I[f, 2]
        d1u = np.float64(UV[i1, 0]) - UV[i0, 0]
        d1v = np.float64(UV[i1, 1]) - UV[i0, 1]
        d2u = np.float64(UV[i2, 0]) - UV[i0, 0]
        d2v = np.float64(UV[i2, 1]) - UV[i0, 1]
        det = d1u * d2v - d2u * d1v
        if abs(det) <= 1e-14:
            continue
        r = 1.0 / det
        for c in range(3):
            e1 = np.float64(V[i1, c]) - V[i0, c]
            e2 = np.float64(V[i2, c]) - V[i0, c]
            t = (e1 * d2v - e2 * d1v) * r
            b = (e2 * d1u - e1 * d2u) * r
            ts[i0, c] += t
            ts[i1, c] += t
            ts[i2, c] += t
            bs[i0, c] += b
            bs[i1, c] += b
            bs[i2, c] += b
    out = np.empty((nv, 4), np.float32)
    for k in range(nv):
        nx, ny, nz = np.float64(N[k, 0]), np.float64(N[k, 1]), np.float64(N[k, 2])
        tx, ty, tz = ts[k, 0], ts[k, 1], ts[k, 2]
        dn = nx * tx + ny * ty + nz * tz
        tx -= nx * dn
        ty -= ny * dn
        tz -= nz * dn
        ln = math.sqrt(tx * tx + ty * ty + tz * tz)
        if ln < 1e-12:  # no uv gradient: any direction orthogonal to the normal
            if abs(nx) < 0.9:
                tx, ty, tz = 1.0, 0.0, 0.0
            else:
                tx, ty, tz = 0.0, 1.0, 0.0
            dn = nx * tx + ny * ty + nz * tz
            tx -= nx * dn
            ty -= ny * dn
            tz -= nz * dn
            ln = math.sqrt(tx * tx + ty * ty + tz * tz)
        ln = max(ln, 1e-30)
        tx /= ln
        ty /= ln
        tz /= ln
        cx = ny * tz - nz * ty
        cy = nz * tx - nx * tz
        cz = nx * ty - ny * tx
        s = -(cx * bs[k, 0] + cy * bs[k, 1] + cz * bs[k, 2])
        out[k, 0] = tx
        out[k, 1] = ty
        out[k, 2] = tz
        out[k, 3] = -1.0 if s < 0.0 else 1.0
    return out
