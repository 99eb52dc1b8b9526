"""Numba kernels of the tree package (loops that must be fast).  Inputs are checked by callers."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def parallel_transport(points, starts, counts, ref):
    """Frames along polylines with minimal twist.

    Parameters
    ----------
    points : float64[n, 3]
        All polylines' points, concatenated.
    starts, counts : int64[s]
        Where each polyline starts in ``points`` and how many points it has.
    ref : float64[s, 3]
        A vector roughly normal to each polyline's first tangent (the ring's u = 0).

    Returns
    -------
    float64[n, 3, 3]
        Columns: normal (x), tangent (y), binormal (z) — a right-handed frame per point.
    """
    n = points.shape[0]
    out = np.zeros((n, 3, 3))
    for s in range(starts.shape[0]):
        a = starts[s]
        m = counts[s]
        nx, ny, nz = ref[s, 0], ref[s, 1], ref[s, 2]
        px, py, pz = 0.0, 0.0, 0.0
        for i in range(m):
            k = a + i
            # tangent: central difference (one-sided at the ends)
            i0 = k - 1 if i > 0 else k
            i1 = k + 1 if i < m - 1 else k
            tx = points[i1, 0] - points[i0, 0]
            ty = points[i1, 1] - points[i0, 1]
            tz = points[i1, 2] - points[i0, 2]
            tl = np.sqrt(tx * tx + ty * ty + tz * tz)
            if tl < 1e-15:
                if i > 0:
                    tx, ty, tz = px, py, pz
                else:
                    tx, ty, tz = 0.0, 1.0, 0.0
            else:
                tx /= tl
                ty /= tl
                tz /= tl
            # remove the tangent component of the carried normal (projection transport)
            d = nx * tx + ny * ty + nz * tz
            nx -= d * tx
            ny -= d * ty
            nz -= d * tz
            nl = np.sqrt(nx * nx + ny * ny + nz * nz)
            if nl < 1e-12:
                # pick any normal
                if abs(tx) < 0.9:
                    nx, ny, nz = 0.0, -tz, ty
                else:
                    nx, ny, nz = tz, 0.0, -tx
                nl = np.sqrt(nx * nx + ny * ny + nz * nz)
            nx /= nl
            ny /= nl
            nz /= nl
            # binormal = normal x tangent  (x, y, z right-handed with y = tangent)
            bx = ny * tz - nz * ty
            by = nz * tx - nx * tz
            bz = nx * ty - ny * tx
            out[k, 0, 0] = nx
            out[k, 1, 0] = ny
            out[k, 2, 0] = nz
            out[k, 0, 1] = tx
            out[k, 1, 1] = ty
            out[k, 2, 1] = tz
            out[k, 0, 2] = bx
            out[k, 1, 2] = by
            out[k, 2, 2] = bz
            px, py, pz = tx, ty, tz
    return out


@njit(cache=True)
def compose_hierarchy(parents, local):
    """World matrices from parent indices (parents before children) and local matrices.

    Parameters
    ----------
    parents : int64[j]
        Index of each node's parent, ``-1`` for roots; every parent precedes its children.
    local : float64[j, 4, 4]
        Node → parent transforms.

    Returns
    -------
    float64[j, 4, 4]
    """
    j = parents.shape[0]
    world = np.empty_like(local)
    for i in range(j):
        p = parents[i]
        if p < 0:
            world[i] = local[i]
        else:
            for r in range(4):
                for c in range(4):
                    acc = 0.0
                    for k in range(4):
                        acc += world[p, r, k] * local[i, k, c]
                    world[i, r, c] = acc
    return world


@njit(cache=True)
def _rotate_into(R, axis, a):
    """``R ← Rot(axis, a) @ R`` (Rodrigues; ``axis`` need not be unit)."""
    n = np.sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2])
    x, y, z = axis[0] / n, axis[1] / n, axis[2] / n
    c, s = np.cos(a), np.sin(a)
    C = 1.0 - c
    m00, m01, m02 = c + x * x * C, x * y * C - z * s, x * z * C + y * s
    m10, m11, m12 = y * x * C + z * s, c + y * y * C, y * z * C - x * s
    m20, m21, m22 = z * x * C - y * s, z * y * C + x * s, c + z * z * C
    for j in range(3):
        a0, a1, a2 = R[0, j], R[1, j], R[2, j]
        R[0, j] = m00 * a0 + m01 * a1 + m02 * a2
        R[1, j] = m10 * a0 + m11 * a1 + m12 * a2
        R[2, j] = m20 * a0 + m21 * a1 + m22 * a2


@njit(cache=True)
def bend_stem(F, P, curve, seg, has_up, up, attraction, has_world, world, clearance):
    """The segment loop of a stem with attraction up and ground clearance (fills ``F[1:]``
    and ``P[1:]`` in place; see :meth:`sylva.tree.weber_penn.Branch._bend`)."""
    f = np.empty((3, 3))
    axis = np.empty(3)
    for i in range(curve.shape[0]):
        c, s = np.cos(curve[i]), np.sin(curve[i])
        for r in range(3):  # f = F[i] @ Rx(curve[i])
            f[r, 0] = F[i, r, 0]
            f[r, 1] = c * F[i, r, 1] + s * F[i, r, 2]
            f[r, 2] = -s * F[i, r, 1] + c * F[i, r, 2]
        if has_up:
            tx, ty, tz = f[0, 1], f[1, 1], f[2, 1]
            axis[0] = ty * up[2] - tz * up[1]
            axis[1] = tz * up[0] - tx * up[2]
            axis[2] = tx * up[1] - ty * up[0]
            sin_d = np.sqrt(axis[0] ** 2 + axis[1] ** 2 + axis[2] ** 2)
            if sin_d > 1e-6:
                _rotate_into(f, axis, attraction * sin_d)
        if has_world:
            t_up = world[1, 0] * f[0, 1] + world[1, 1] * f[1, 1] + world[1, 2] * f[2, 1]
            y_next = world[1, 3]
            for r in range(3):
                y_next += world[1, r] * (P[i, r] + f[r, 1] * seg)
            if t_up < 0 and y_next < clearance:
                ux, uy, uz = world[1, 0], world[1, 1], world[1, 2]
                tx, ty, tz = f[0, 1], f[1, 1], f[2, 1]
                axis[0] = ty * uz - tz * uy
                axis[1] = tz * ux - tx * uz
                axis[2] = tx * uy - ty * ux
                if axis[0] ** 2 + axis[1] ** 2 + axis[2] ** 2 > 1e-12:
                    _rotate_into(f, axis, -np.arcsin(max(-1.0, t_up)))
        for r in range(3):
            P[i + 1, r] = P[i, r] + f[r, 1] * seg
            for k in range(3):
                F[i + 1, r, k] = f[r, k]


@njit(cache=True)
def axis_rotations(a, axis):
    """``float64[n, 3, 3]``: the rotations by the angles ``a`` about x (``axis`` 0) or y
    (1), the matrices of NumPy's ``cos`` and ``sin`` (the C library's, for float64) laid
    out as :func:`sylva.tree.weber_penn._rx_many` and ``_ry_many`` lay them out."""
    n = a.shape[0]
    out = np.zeros((n, 3, 3))
    for i in range(n):
        c, s = np.cos(a[i]), np.sin(a[i])
        if axis == 0:
            out[i, 0, 0] = 1.0
            out[i, 1, 1], out[i, 1, 2], out[i, 2, 1], out[i, 2, 2] = c, -s, s, c
        else:
            out[i, 1, 1] = 1.0
            out[i, 0, 0], out[i, 0, 2], out[i, 2, 0], out[i, 2, 2] = c, s, -s, c
    return out


@njit(cache=True)
def _floor_divide(a, b):
    """NumPy's float64 ``a // b`` (its ``npy_divmod``: fmod, then the correction), for b != 0."""
    mod = np.fmod(a, b)
    div = (a - mod) / b
    if mod and (b < 0) != (mod < 0):
        div -= 1.0
    if div:
        fd = np.floor(div)
        if div - fd > 0.5:
            fd += 1.0
        return fd
    return math.copysign(0.0, a / b)


@njit(cache=True)
def where_points(s, arc0, seg, last, points, frames):
    """``Branch._where_points``: the segment of a run at each arc length ``s`` (float64[n])
    and the point there, ``(int64[n], float64[n, 3])``, with NumPy's numbers (its floor
    division, then ``points[i] + frames[i + 1, :, 1] * ((s - arc0) - i * seg)``); ``last``
    is the run's last segment index."""
    n = s.shape[0]
    idx = np.empty(n, np.int64)
    p = np.empty((n, 3))
    for j in range(n):
        d = s[j] - arc0
        i = min(max(np.int64(_floor_divide(d, seg)), 0), last)
        idx[j] = i
        t = d - i * seg
        for k in range(3):
            p[j, k] = points[i, k] + frames[i + 1, k, 1] * t
    return idx, p


@njit(cache=True)
def _turn(out, k, a, axis):
    c, s = np.cos(a), np.sin(a)
    if axis == 0:
        out[k, 0, 0] = 1.0
        out[k, 1, 1], out[k, 1, 2], out[k, 2, 1], out[k, 2, 2] = c, -s, s, c
    else:
        out[k, 1, 1] = 1.0
        out[k, 0, 0], out[k, 0, 2], out[k, 2, 0], out[k, 2, 2] = c, s, -s, c


@njit(cache=True)
def crown_leaf_turns(a0, a1, u_arc, rot, rot_dev, u_rot, phi0, down, down_dev, u_down,
                     u_twist, seg, last):
    """The arithmetic of :func:`sylva.tree.leaves._crown_leaves` (spiral leaves) on its
    draws, NumPy's numbers: the arc lengths ``a0 + (i + u_arc) / n · (a1 − a0)``, their
    segments (``Branch._segments_at``) and the rotation stacks ``Ry(φ)``, ``Rx(θ)``,
    ``Ry(twist)`` of ``φ = radians(phi0 + cumsum(rot + u_rot · rot_dev))``, ``θ =
    radians(|down + u_down · down_dev|)``, ``twist = radians(u_twist)``; NumPy's radians is
    ``x · (π / 180)``, its float64 cos and sin the C library's."""
    n = u_arc.shape[0]
    arcs = np.empty(n)
    idx = np.empty(n, np.int64)
    ry = np.zeros((n, 3, 3))
    rx = np.zeros((n, 3, 3))
    rt = np.zeros((n, 3, 3))
    d2r = np.pi / 180.0
    acc = 0.0
    for k in range(n):
        a = a0 + (k + u_arc[k]) / n * (a1 - a0)
        arcs[k] = a
        idx[k] = min(max(np.int64(_floor_divide(a - a0, seg)), 0), last)
        step = rot + u_rot[k] * rot_dev
        acc = step if k == 0 else acc + step
        _turn(ry, k, (phi0 + acc) * d2r, 1)
        _turn(rx, k, abs(down + u_down[k] * down_dev) * d2r, 0)
        _turn(rt, k, u_twist[k] * d2r, 1)
    return arcs, idx, ry, rx, rt


@njit(cache=True)
def cone_profile(s, current, taper):
    """``StemPlan.profile`` of a stem with ``Taper`` <= 1 and no flare, NumPy's numbers:
    ``z = min(max(s / current, 0), 1)``, ``max(1 − taper · z, 0.02 · (1 − z) + 0.004)``
    (``np.maximum``/``np.minimum``'s choice: the first operand on ties and NaN)."""
    out = np.empty(s.shape[0])
    for k in range(s.shape[0]):
        z = s[k] / current
        z = z if (z >= 0.0 or np.isnan(z)) else 0.0
        z = z if (z <= 1.0 or np.isnan(z)) else 1.0
        r = 1.0 - taper * z
        floor = 0.02 * (1 - z) + 0.004
        out[k] = r if (r >= floor or np.isnan(r)) else floor
    return out


@njit(cache=True)
def envelope_exit(pts, st, denom, width, peak, low, high):
    """The first of ``pts`` (float64[n, 3], plant frame) outside the pruning envelope, as
    :meth:`sylva.tree.model.Tree.inside_envelope` decides it (``st`` the tree's scale,
    ``denom`` ``st · (1 − BaseSize)``, ``peak`` clamped as :func:`~sylva.tree.weber_penn.envelope`
    clamps it); -1 when every point is inside, -2 when a point before the first outside one
    is within 1e-12 (relative) of the envelope or not finite.

    NumPy raises arrays to a power by its own SIMD routines, whose last bit may differ from
    the C library's ``pow`` used here, so a point that near the envelope is left to the
    caller, which then asks ``Tree.inside_envelope`` itself: every decision is NumPy's."""
    for i in range(pts.shape[0]):
        d = math.hypot(pts[i, 0], pts[i, 2]) / st
        r = (st - pts[i, 1]) / denom
        if not (r >= 0.0 and r <= 1.0):  # the envelope is 0 there (or r is NaN): outside
            return i
        c = r if r != 0.0 else 0.0  # np.maximum(0.0, -0.0) is 0.0
        if c < 1.0 - peak:
            e = width * (c / (1.0 - peak)) ** high
        else:
            e = width * ((1.0 - c) / peak) ** low
        if not (math.isfinite(e) and math.isfinite(d)) or abs(d - e) <= 1e-12 * abs(e) + 1e-300:
            return -2
        if not d < e:
            return i
    return -1


@njit(cache=True)
def seed_state(words):
    """``SeedSequence(words).generate_state(4, np.uint64)``: NumPy's seed hash (its
    ``mix_entropy`` over a pool of 4 words, then ``generate_state``), for a PCG64 stream.

    ``words`` are the entropy as uint32 values (int64[n], each in ``[0, 2³²)``, one word
    per integer: NumPy's coercion of integers below 2³²).  Returns uint64[4]."""
    mask = np.uint64(0xFFFFFFFF)
    mult_a = np.uint64(0x931E8875)
    mix_l = np.uint64(0xCA01F9DD)
    mix_r = np.uint64(0x4973F715)
    pool = np.zeros(4, np.uint64)
    hc = np.uint64(0x43B0D7E5)
    n = words.shape[0]

    for i in range(4):  # hashmix of each entropy word (0 past the end) into the pool
        v = np.uint64(words[i]) if i < n else np.uint64(0)
        v = v ^ hc
        hc = (hc * mult_a) & mask
        v = (v * hc) & mask
        pool[i] = v ^ (v >> np.uint64(16))
    for src in range(4):
        for dst in range(4):
            if src != dst:
                v = pool[src] ^ hc
                hc = (hc * mult_a) & mask
                v = (v * hc) & mask
                v = v ^ (v >> np.uint64(16))
                r = (mix_l * pool[dst] - mix_r * v) & mask
                pool[dst] = r ^ (r >> np.uint64(16))
    for src in range(4, n):
        for dst in range(4):
            v = np.uint64(words[src]) ^ hc
            hc = (hc * mult_a) & mask
            v = (v * hc) & mask
            v = v ^ (v >> np.uint64(16))
            r = (mix_l * pool[dst] - mix_r * v) & mask
            pool[dst] = r ^ (r >> np.uint64(16))
    out = np.zeros(4, np.uint64)
    hb = np.uint64(0x8B51F9DD)
    mult_b = np.uint64(0x58F38DED)
    for i in range(8):  # generate_state: 8 uint32 words, paired little-endian into 4 uint64
        v = pool[i % 4] ^ hb
        hb = (hb * mult_b) & mask
        v = (v * hb) & mask
        v = v ^ (v >> np.uint64(16))
        if i % 2 == 0:
            out[i // 2] = v
        else:
            out[i // 2] |= v << np.uint64(32)
    return out


@njit(cache=True)
def leaf_fill(pos, fr, sx, size, bv, buv, btri, flutter, tint, live, ljoint, base, V, N, UV, C,
              I, J, L, FL):
    """The leaf blades of a mesh written into its float32 arrays from row ``base`` on (see
    :func:`sylva.tree.meshing.build_tree_mesh`, whose NumPy road computes the same numbers
    in float64, in the same order, before the cast).

    Leaf ``q`` (``pos[q]``, frame ``fr[q]``, width ``sx[q]``·``size[q]``, length ``size[q]``)
    gets the blade ``bv`` (uv ``buv``, triangles ``btri``): vertex ``pos + (f₀·x + f₁·y) +
    f₂·z`` of its scaled blade vertex, the normal ``f₂``, the colour ``tint[q]`` with alpha 1,
    joint ``ljoint[q]``, leaf ``live[q]`` and the flutter ``f₂ · ((y_blade · size) ·
    flutter)``; triangles go to ``I`` from row ``q · len(btri)`` of the leaf part."""
    nv = bv.shape[0]
    nt = btri.shape[0]
    for q in range(pos.shape[0]):
        s = size[q]
        w = sx[q] * s
        f2x, f2y, f2z = fr[q, 0, 2], fr[q, 1, 2], fr[q, 2, 2]
        v0 = base + q * nv
        for v in range(nv):
            lx = bv[v, 0] * w
            ly = bv[v, 1] * s
            lz = bv[v, 2] * s
            k = v0 + v
            for i in range(3):
                V[k, i] = np.float32(pos[q, i] + (fr[q, i, 0] * lx + fr[q, i, 1] * ly
                                                  + fr[q, i, 2] * lz))
            N[k, 0] = np.float32(f2x)
            N[k, 1] = np.float32(f2y)
            N[k, 2] = np.float32(f2z)
            UV[k, 0] = np.float32(buv[v, 0])
            UV[k, 1] = np.float32(buv[v, 1])
            for c in range(3):
                C[k, c] = np.float32(tint[q, c])
            C[k, 3] = np.float32(1.0)
            J[k] = ljoint[q]
            L[k] = live[q]
            a = bv[v, 1] * s * flutter
            FL[k, 0] = np.float32(f2x * a)
            FL[k, 1] = np.float32(f2y * a)
            FL[k, 2] = np.float32(f2z * a)
        t0 = q * nt
        for t in range(nt):
            for c in range(3):
                I[t0 + t, c] = np.uint32(btri[t, c] + v0)


@njit(cache=True)
def blade_wind(blade, level, phase, reach, flutter):
    """The ``WIND`` columns of the leaf blades (``blade`` float32[q, nv, 4], written): the
    leaf's level, phase and reach (float32[q], float64[q], float32[q], one per leaf) on
    each of its vertices, and each vertex's flutter (``flutter`` float32[q, nv, 3]) over
    its blade's largest -- :func:`sylva.tree.lod.tree_wind`'s numbers: NumPy's float32 norm
    ``√((x² + y²) + z²)``, the largest (at least 0) in float64, the quotient cast back and
    clipped to [0, 1]."""
    q, nv = blade.shape[0], blade.shape[1]
    fl = np.empty(nv, np.float32)
    for k in range(q):
        top = np.float32(0.0)
        for v in range(nv):
            x, y, z = flutter[k, v, 0], flutter[k, v, 1], flutter[k, v, 2]
            f = np.sqrt((x * x + y * y) + z * z)
            fl[v] = f
            if v == 0 or f > top:
                top = f
        den = max(np.float64(max(top, np.float32(0.0))), 1e-12)
        lv, ph, rc = level[k], np.float32(phase[k]), reach[k]
        for v in range(nv):
            r = np.float32(np.float64(fl[v]) / den)
            blade[k, v, 0] = lv
            blade[k, v, 1] = ph
            blade[k, v, 2] = rc
            blade[k, v, 3] = min(max(r, np.float32(0.0)), np.float32(1.0))


@njit(cache=True)
def turn_frames(m, f, start):
    """``np.einsum("ij,njk->nik", m[:3, :3], f)[start:]`` (the turtle's frames into the plant
    frame), einsum's numbers: each entry the sum over ``j`` of ``m[i, j] · f[n, j, k]``
    added in order to 0.0, ``j = 0, 1, 2`` (``tests/tree/test_clip_speed.py`` holds the two
    equal, ``-0.0`` included)."""
    n = f.shape[0] - start
    out = np.empty((max(n, 0), 3, 3))
    for q in range(n):
        for i in range(3):
            m0, m1, m2 = m[i, 0], m[i, 1], m[i, 2]
            for k in range(3):
                # einsum's sum starts from 0.0 (which only changes an all -0.0 sum)
                out[q, i, k] = 0.0 + m0 * f[q + start, 0, k] + m1 * f[q + start, 1, k] \
                    + m2 * f[q + start, 2, k]
    return out


@njit(cache=True)
def _uniform(d, low, high):
    """NumPy's ``Generator.uniform(low, high)`` of the doubles ``d`` its stream gave:
    ``low + (high − low) · d`` (``random_uniform`` of its distributions)."""
    rng = high - low
    out = np.empty(d.shape[0])
    for k in range(d.shape[0]):
        out[k] = low + rng * d[k]
    return out


@njit(cache=True)
def crown_leaf_spiral(d, a0, a1, rot, rot_dev, down, down_dev, size, size_dev, seg, last):
    """:func:`crown_leaf_turns` and the blade lengths of a run's ``n`` spiral leaves from the
    ``5n + 1`` doubles ``d`` its stream gives in a row (``Generator.random(5n + 1)``): the
    draws :func:`sylva.tree.leaves._crown_leaves` made one ``uniform`` call at a time —
    ``u_arc`` in (0.2, 0.8), ``u_rot`` in (−1, 1), ``phi0`` in (0, 360), ``u_down`` in
    (−1, 1), the twist in (−30, 30) and the size deviation in (−1, 1), ``n`` of each
    (``phi0`` one) — the same doubles, so the same numbers.  Returns ``(arcs, segments, ry,
    rx, rt, sizes)``; ``sizes = size + u · size_dev`` as NumPy adds them."""
    n = (d.shape[0] - 1) // 5
    u_arc = _uniform(d[:n], 0.2, 0.8)
    u_rot = _uniform(d[n:2 * n], -1.0, 1.0)
    phi0 = 0.0 + (360.0 - 0.0) * d[2 * n]
    u_down = _uniform(d[2 * n + 1:3 * n + 1], -1.0, 1.0)
    u_twist = _uniform(d[3 * n + 1:4 * n + 1], -30.0, 30.0)
    u_size = _uniform(d[4 * n + 1:5 * n + 1], -1.0, 1.0)
    arcs, idx, ry, rx, rt = crown_leaf_turns(a0, a1, u_arc, rot, rot_dev, u_rot, phi0, down,
                                             down_dev, u_down, u_twist, seg, last)
    sizes = np.empty(n)
    for k in range(n):
        sizes[k] = size + u_size[k] * size_dev
    return arcs, idx, ry, rx, rt, sizes


@njit(cache=True)
def world_up(w, out):
    """``w[:3, :3].T @ (0, 1, 0)`` into ``out`` when it is exactly ``w[1, :3]``: every entry
    of ``w[:3, :3]`` finite and none of row 1 zero (then the sum ``w[0, i]·0 + w[1, i]·1 +
    w[2, i]·0`` is ``w[1, i]`` in any order and whatever BLAS's ``gemv`` does); ``False``
    (``out`` untouched) where the signs of zeros or a NaN leave it to NumPy."""
    for i in range(3):
        for j in range(3):
            if not math.isfinite(w[i, j]):
                return False
    for i in range(3):
        if w[1, i] == 0.0:
            return False
    for i in range(3):
        out[i] = w[1, i]
    return True


@njit(cache=True)
def _envelope_at(c, width, peak, low, high):
    """The envelope at ``c`` in [0, 1] as :func:`envelope_exit` works it out."""
    c = c if c != 0.0 else 0.0
    if c < 1.0 - peak:
        return width * (c / (1.0 - peak)) ** high
    return width * ((1.0 - c) / peak) ** low


@njit(cache=True)
def envelope_exit_local(P, w, st, denom, width, peak, low, high):
    """:func:`envelope_exit` of the run points ``P`` (float64[n, 3], the run's frame) moved
    by ``w`` (float64[4, 4]) into the plant frame, without those points: NumPy multiplies
    ``P @ w[:3, :3].T`` by BLAS, whose last bits this loop cannot promise, so each point is
    worked out here with a bound on how far BLAS's could lie (``1e-15`` of the sum of the
    terms' sizes, several times the error of either sum) and decided only where every point
    within the bound gets the same answer, with the margin ``envelope_exit`` itself leaves
    to NumPy's powers (1e-12) four times over; the height's test is exact by the
    monotonicity of rounding.  Returns ``envelope_exit``'s answer on NumPy's points (the first
    point outside, -1 all inside) or -3: undecided here, ask ``envelope_exit`` with NumPy's
    points (``tests/tree/test_pruning_speed.py`` holds the two to the same answers)."""
    corner = 1.0 - peak
    for i in range(P.shape[0]):
        x0, x1, x2 = P[i, 0], P[i, 1], P[i, 2]
        v = np.empty(3)
        dv = np.empty(3)
        for k in range(3):
            a, b, c = x0 * w[k, 0], x1 * w[k, 1], x2 * w[k, 2]
            v[k] = a + b + c + w[k, 3]
            dv[k] = 1e-15 * (abs(a) + abs(b) + abs(c) + abs(w[k, 3])) + 1e-300
            if not (math.isfinite(v[k]) and math.isfinite(dv[k])):
                return -3
        r_lo = (st - (v[1] + dv[1])) / denom  # NumPy's r is in [r_lo, r_hi] (monotone)
        r_hi = (st - (v[1] - dv[1])) / denom
        if r_hi < 0.0 or r_lo > 1.0:
            return i  # above the envelope's top or below its base: outside
        if r_lo < 0.0 or r_hi > 1.0 or (r_lo < corner and r_hi >= corner):
            return -3  # astride an end or the widest point
        e_a = _envelope_at(r_lo, width, peak, low, high)
        e_b = _envelope_at(r_hi, width, peak, low, high)
        if not (math.isfinite(e_a) and math.isfinite(e_b)):
            return -3
        e_min, e_max = min(e_a, e_b), max(e_a, e_b)
        ax, az = abs(v[0]), abs(v[2])
        d_hi = math.hypot(ax + dv[0], az + dv[2]) / st
        d_lo = math.hypot(max(ax - dv[0], 0.0), max(az - dv[2], 0.0)) / st
        if d_hi < e_min - 4e-12 * abs(e_min) - 1e-300:
            continue  # inside, however NumPy's point lies
        if d_lo > e_max + 4e-12 * abs(e_max) + 1e-300:
            return i  # outside, however NumPy's point lies
        return -3
    return -1
