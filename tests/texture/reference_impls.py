"""Pure-Python transliterations of the published reference implementations.

* ``improved_noise``: Ken Perlin, ``ImprovedNoise.java`` (2002),
  https://mrl.cs.nyu.edu/~perlin/noise/
* ``simplex2/3/4``: Stefan Gustavson, ``SimplexNoise.java`` (version 2012-03-09, with
  Peter Eastman's optimisations and the 2012 rank-ordering 4D method).

They follow the Java line by line (Java doubles are IEEE binary64 like Python floats, and
``fastfloor`` truncates like Java's ``(int)`` cast), so the library can be compared value
for value.  They are deliberately independent of sylva's code.
"""

from __future__ import annotations

import math

P = [151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30,
     69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94,
     252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171,
     168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122,
     60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161,
     1, 216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159,
     86, 164, 100, 109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147,
     118, 126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183,
     170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129,
     22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228,
     251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239,
     107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4,
     150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215,
     61, 156, 180]
PERM = [P[i & 255] for i in range(512)]
PERM_MOD12 = [v % 12 for v in PERM]


# --------------------------------------------------------------------------- ImprovedNoise.java
def _fade(t):
    return t * t * t * (t * (t * 6 - 15) + 10)


def _lerp(t, a, b):
    return a + t * (b - a)


def _grad(hash_, x, y, z):
    h = hash_ & 15
    u = x if h < 8 else y
    v = y if h < 4 else (x if h == 12 or h == 14 else z)
    return (u if (h & 1) == 0 else -u) + (v if (h & 2) == 0 else -v)


def improved_noise(x, y, z):
    p = PERM
    X = math.floor(x) & 255
    Y = math.floor(y) & 255
    Z = math.floor(z) & 255
    x -= math.floor(x)
    y -= math.floor(y)
    z -= math.floor(z)
    u = _fade(x)
    v = _fade(y)
    w = _fade(z)
    A = p[X] + Y
    AA = p[A] + Z
    AB = p[A + 1] + Z
    B = p[X + 1] + Y
    BA = p[B] + Z
    BB = p[B + 1] + Z
    return _lerp(w, _lerp(v, _lerp(u, _grad(p[AA], x, y, z), _grad(p[BA], x - 1, y, z)),
                          _lerp(u, _grad(p[AB], x, y - 1, z), _grad(p[BB], x - 1, y - 1, z))),
                 _lerp(v, _lerp(u, _grad(p[AA + 1], x, y, z - 1),
                                _grad(p[BA + 1], x - 1, y, z - 1)),
                       _lerp(u, _grad(p[AB + 1], x, y - 1, z - 1),
                             _grad(p[BB + 1], x - 1, y - 1, z - 1))))


# --------------------------------------------------------------------------- SimplexNoise.java
GRAD3 = [(1, 1, 0), (-1, 1, 0), (1, -1, 0), (-1, -1, 0), (1, 0, 1), (-1, 0, 1), (1, 0, -1),
         (-1, 0, -1), (0, 1, 1), (0, -1, 1), (0, 1, -1), (0, -1, -1)]
GRAD4 = [(0, 1, 1, 1), (0, 1, 1, -1), (0, 1, -1, 1), (0, 1, -1, -1), (0, -1, 1, 1),
         (0, -1, 1, -1), (0, -1, -1, 1), (0, -1, -1, -1), (1, 0, 1, 1), (1, 0, 1, -1),
         (1, 0, -1, 1), (1, 0, -1, -1), (-1, 0, 1, 1), (-1, 0, 1, -1), (-1, 0, -1, 1),
         (-1, 0, -1, -1), (1, 1, 0, 1), (1, 1, 0, -1), (1, -1, 0, 1), (1, -1, 0, -1),
         (-1, 1, 0, 1), (-1, 1, 0, -1), (-1, -1, 0, 1), (-1, -1, 0, -1), (1, 1, 1, 0),
         (1, 1, -1, 0), (1, -1, 1, 0), (1, -1, -1, 0), (-1, 1, 1, 0), (-1, 1, -1, 0),
         (-1, -1, 1, 0), (-1, -1, -1, 0)]
F2 = 0.5 * (math.sqrt(3.0) - 1.0)
G2 = (3.0 - math.sqrt(3.0)) / 6.0
F3 = 1.0 / 3.0
G3 = 1.0 / 6.0
F4 = (math.sqrt(5.0) - 1.0) / 4.0
G4 = (5.0 - math.sqrt(5.0)) / 20.0


def _fastfloor(x):
    xi = int(x)  # Java (int) truncates toward zero
    return xi - 1 if x < xi else xi


def simplex2(xin, yin):
    perm, pm12 = PERM, PERM_MOD12
    s = (xin + yin) * F2
    i = _fastfloor(xin + s)
    j = _fastfloor(yin + s)
    t = (i + j) * G2
    X0 = i - t
    Y0 = j - t
    x0 = xin - X0
    y0 = yin - Y0
    if x0 > y0:
        i1, j1 = 1, 0
    else:
        i1, j1 = 0, 1
    x1 = x0 - i1 + G2
    y1 = y0 - j1 + G2
    x2 = x0 - 1.0 + 2.0 * G2
    y2 = y0 - 1.0 + 2.0 * G2
    ii = i & 255
    jj = j & 255
    gi0 = pm12[ii + perm[jj]]
    gi1 = pm12[ii + i1 + perm[jj + j1]]
    gi2 = pm12[ii + 1 + perm[jj + 1]]
    t0 = 0.5 - x0 * x0 - y0 * y0
    if t0 < 0:
        n0 = 0.0
    else:
        t0 *= t0
        n0 = t0 * t0 * (GRAD3[gi0][0] * x0 + GRAD3[gi0][1] * y0)
    t1 = 0.5 - x1 * x1 - y1 * y1
    if t1 < 0:
        n1 = 0.0
    else:
        t1 *= t1
        n1 = t1 * t1 * (GRAD3[gi1][0] * x1 + GRAD3[gi1][1] * y1)
    t2 = 0.5 - x2 * x2 - y2 * y2
    if t2 < 0:
        n2 = 0.0
    else:
        t2 *= t2
        n2 = t2 * t2 * (GRAD3[gi2][0] * x2 + GRAD3[gi2][1] * y2)
    return 70.0 * (n0 + n1 + n2)


def _dot3(g, x, y, z):
    return g[0] * x + g[1] * y + g[2] * z


def simplex3(xin, yin, zin):
    perm, pm12 = PERM, PERM_MOD12
    s = (xin + yin + zin) * F3
    i = _fastfloor(xin + s)
    j = _fastfloor(yin + s)
    k = _fastfloor(zin + s)
    t = (i + j + k) * G3
    x0 = xin - (i - t)
    y0 = yin - (j - t)
    z0 = zin - (k - t)
    if x0 >= y0:
        if y0 >= z0:
            i1, j1, k1, i2, j2, k2 = 1, 0, 0, 1, 1, 0
        elif x0 >= z0:
            i1, j1, k1, i2, j2, k2 = 1, 0, 0, 1, 0, 1
        else:
            i1, j1, k1, i2, j2, k2 = 0, 0, 1, 1, 0, 1
    else:
        if y0 < z0:
            i1, j1, k1, i2, j2, k2 = 0, 0, 1, 0, 1, 1
        elif x0 < z0:
            i1, j1, k1, i2, j2, k2 = 0, 1, 0, 0, 1, 1
        else:
            i1, j1, k1, i2, j2, k2 = 0, 1, 0, 1, 1, 0
    x1 = x0 - i1 + G3
    y1 = y0 - j1 + G3
    z1 = z0 - k1 + G3
    x2 = x0 - i2 + 2.0 * G3
    y2 = y0 - j2 + 2.0 * G3
    z2 = z0 - k2 + 2.0 * G3
    x3 = x0 - 1.0 + 3.0 * G3
    y3 = y0 - 1.0 + 3.0 * G3
    z3 = z0 - 1.0 + 3.0 * G3
    ii, jj, kk = i & 255, j & 255, k & 255
    gi = [pm12[ii + perm[jj + perm[kk]]],
          pm12[ii + i1 + perm[jj + j1 + perm[kk + k1]]],
          pm12[ii + i2 + perm[jj + j2 + perm[kk + k2]]],
          pm12[ii + 1 + perm[jj + 1 + perm[kk + 1]]]]
    n = []
    for g, (x, y, z) in zip(gi, ((x0, y0, z0), (x1, y1, z1), (x2, y2, z2), (x3, y3, z3))):
        tt = 0.6 - x * x - y * y - z * z
        if tt < 0:
            n.append(0.0)
        else:
            tt *= tt
            n.append(tt * tt * _dot3(GRAD3[g], x, y, z))
    return 32.0 * (n[0] + n[1] + n[2] + n[3])


def simplex4(x, y, z, w):
    perm = PERM
    s = (x + y + z + w) * F4
    i = _fastfloor(x + s)
    j = _fastfloor(y + s)
    k = _fastfloor(z + s)
    l = _fastfloor(w + s)
    t = (i + j + k + l) * G4
    x0 = x - (i - t)
    y0 = y - (j - t)
    z0 = z - (k - t)
    w0 = w - (l - t)
    rankx = ranky = rankz = rankw = 0
    if x0 > y0:
        rankx += 1
    else:
        ranky += 1
    if x0 > z0:
        rankx += 1
    else:
        rankz += 1
    if x0 > w0:
        rankx += 1
    else:
        rankw += 1
    if y0 > z0:
        ranky += 1
    else:
        rankz += 1
    if y0 > w0:
        ranky += 1
    else:
        rankw += 1
    if z0 > w0:
        rankz += 1
    else:
        rankw += 1
    off = []
    for r in (3, 2, 1):
        off.append((int(rankx >= r), int(ranky >= r), int(rankz >= r), int(rankw >= r)))
    corners = [(x0, y0, z0, w0)]
    for c, (a, b, cc, d) in enumerate(off, start=1):
        corners.append((x0 - a + c * G4, y0 - b + c * G4, z0 - cc + c * G4, w0 - d + c * G4))
    corners.append((x0 - 1.0 + 4.0 * G4, y0 - 1.0 + 4.0 * G4, z0 - 1.0 + 4.0 * G4,
                    w0 - 1.0 + 4.0 * G4))
    ii, jj, kk, ll = i & 255, j & 255, k & 255, l & 255
    offs = [(0, 0, 0, 0), *off, (1, 1, 1, 1)]
    total = []
    for (a, b, cc, d), (cx, cy, cz, cw) in zip(offs, corners):
        g = perm[ii + a + perm[jj + b + perm[kk + cc + perm[ll + d]]]] % 32
        tt = 0.6 - cx * cx - cy * cy - cz * cz - cw * cw
        if tt < 0:
            total.append(0.0)
        else:
            tt *= tt
            gv = GRAD4[g]
            total.append(tt * tt * (gv[0] * cx + gv[1] * cy + gv[2] * cz + gv[3] * cw))
    return 27.0 * (total[0] + total[1] + total[2] + total[3] + total[4])
