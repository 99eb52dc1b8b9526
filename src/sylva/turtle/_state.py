"""The turtle kernel's fixed-size helpers: the state copy and the sphere of ``@O``.

Kept apart from :mod:`sylva.turtle._kernels` so that it stays under the size the
architecture test allows; the kernel imports both.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: How many state elements :func:`copy_state` copies (the kernel checks its ``NS``).
COPIED = 33


@njit(cache=True, inline="always")
def copy_state(src, dst):  # pragma: no cover - compiled
    # every element loaded before any is stored: src and dst may alias as far as LLVM
    # knows, and only so can it copy with vector moves (numba's ``dst[:] = src`` made every
    # push and pop cost ~60 ns, a third of the whole walk of a bracketed plant; an element
    # loop is scalar).  Written out for NS = 33 (checked at import).
    s0 = src[0]
    s1 = src[1]
    s2 = src[2]
    s3 = src[3]
    s4 = src[4]
    s5 = src[5]
    s6 = src[6]
    s7 = src[7]
    s8 = src[8]
    s9 = src[9]
    s10 = src[10]
    s11 = src[11]
    s12 = src[12]
    s13 = src[13]
    s14 = src[14]
    s15 = src[15]
    s16 = src[16]
    s17 = src[17]
    s18 = src[18]
    s19 = src[19]
    s20 = src[20]
    s21 = src[21]
    s22 = src[22]
    s23 = src[23]
    s24 = src[24]
    s25 = src[25]
    s26 = src[26]
    s27 = src[27]
    s28 = src[28]
    s29 = src[29]
    s30 = src[30]
    s31 = src[31]
    s32 = src[32]
    dst[0] = s0
    dst[1] = s1
    dst[2] = s2
    dst[3] = s3
    dst[4] = s4
    dst[5] = s5
    dst[6] = s6
    dst[7] = s7
    dst[8] = s8
    dst[9] = s9
    dst[10] = s10
    dst[11] = s11
    dst[12] = s12
    dst[13] = s13
    dst[14] = s14
    dst[15] = s15
    dst[16] = s16
    dst[17] = s17
    dst[18] = s18
    dst[19] = s19
    dst[20] = s20
    dst[21] = s21
    dst[22] = s22
    dst[23] = s23
    dst[24] = s24
    dst[25] = s25
    dst[26] = s26
    dst[27] = s27
    dst[28] = s28
    dst[29] = s29
    dst[30] = s30
    dst[31] = s31
    dst[32] = s32


# @O draws a sphere as polygons: a UV sphere of SPHERE_SLICES longitudes and
# SPHERE_RINGS latitude bands (triangle fans at the poles, quads between)
SPHERE_SLICES = 8
SPHERE_RINGS = 4
SPHERE_NP = SPHERE_SLICES * SPHERE_RINGS
SPHERE_NV = SPHERE_SLICES * (2 * 3 + (SPHERE_RINGS - 2) * 4)


def _sphere_template():
    """Unit-sphere polygons (outward, counter-clockwise seen from outside): vertices
    float64[SPHERE_NV, 3] and offsets int64[SPHERE_NP + 1]."""

    def p(ring, k):
        th = math.pi * ring / SPHERE_RINGS
        ph = 2.0 * math.pi * k / SPHERE_SLICES
        return (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))

    verts, offs = [], [0]
    for ring in range(SPHERE_RINGS):
        for k in range(SPHERE_SLICES):
            if ring == 0:
                quad = [p(0, k), p(1, k), p(1, k + 1)]
            elif ring == SPHERE_RINGS - 1:
                quad = [p(ring, k), p(ring + 1, k), p(ring, k + 1)]
            else:
                quad = [p(ring, k), p(ring + 1, k), p(ring + 1, k + 1), p(ring, k + 1)]
            verts += quad
            offs.append(len(verts))
    return np.array(verts, np.float64), np.array(offs, np.int64)


SPHERE_V, SPHERE_OFF = _sphere_template()
