"""GLSL from a texture graph: the same node set as the numba kernel, as one GLSL 3.30
function ``float NAME(vec3 q)`` (scalar graphs) or ``vec4 NAME(vec3 q)`` (colour graphs) of
the point ``q`` in image units (``x = i / W``, ``y = j / W``, ``z = k / W``).

Every generator becomes a function with its own tables (the seed's permutation, value-noise
lattice values) and its per-octave frequencies, offsets, lattice periods and amplitudes as
constants, computed by the same planning code as :func:`~sylva.texture.noise_grid`; so the
shader samples the CPU's lattice coordinates, in float32.  Supported: value, classic and
improved Perlin, simplex and Worley generators (2D and 3D, with ``time``; fBm, turbulence,
ridged; tiling for the lattice kinds and Worley; Worley F1-F3 and their combinations, every
metric, on the jittered grid, with the kernel's 32-bit hashes), every modifier, combiner,
selector, transformer and colour node, and the noise patterns (marble, wood, clouds,
granite, bark, leaf, grass: written as graphs of primitives by :mod:`._glsl_patterns`), and
escape-time fractals and formula nodes (the formula language's GLSL, :mod:`._formula_glsl`:
complex values as ``vec2``, the loop with its bailout, the colouring index; float32, so it
matches the CPU away from the set's boundary).  IFS and L-system textures, Worley orders
above F3, Worley's Poisson density, 4D or tileable simplex and generators with their own
``warp`` raise a :class:`GraphError` naming the node.

Examples
--------
>>> from sylva.texture import graph as tg
>>> src = compile_glsl(tg.Graph(tg.clamp(tg.improved(scale=4.0), lower=0.0, upper=1.0)),
...                    shape=(32, 32))
>>> "float sylva_texture(vec3 q)" in src
True
"""

from __future__ import annotations

import math

import numpy as np

from .. import _kernels as _k
from .. import colormap as _cm
from ._compile import _Emit, _err, _f, _points, _vec
from ._nodes import COLOUR, GENERATOR_KINDS, Node
from ._ops import BLEND

__all__ = ["compile_glsl", "compile_glsl_library"]

_COMMON = """
float sylva_curve(float t, int interp) {
    if (interp == 3) return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    if (interp == 2) return t * t * (3.0 - 2.0 * t);
    if (interp == 1) return (1.0 - cos(3.141592653589793 * t)) * 0.5;
    return t;
}
int sylva_wrap(int i, int p) {
    if (p > 0) {  // i mod p, >= 0 (GLSL leaves % of a negative operand undefined)
        i -= p * int(floor(float(i) / float(p)));
        if (i < 0) i += p;
        if (i >= p) i -= p;
    }
    return i & 255;
}
const float SYLVA_G16X[16] = float[16](1.,-1.,1.,-1.,1.,-1.,1.,-1.,0.,0.,0.,0.,1.,0.,-1.,0.);
const float SYLVA_G16Y[16] = float[16](1.,1.,-1.,-1.,0.,0.,0.,0.,1.,-1.,1.,-1.,1.,-1.,1.,-1.);
const float SYLVA_G16Z[16] = float[16](0.,0.,0.,0.,1.,1.,-1.,-1.,1.,1.,-1.,-1.,0.,1.,0.,-1.);
float sylva_grad3(int h, float x, float y, float z) {
    h &= 15;
    return SYLVA_G16X[h] * x + SYLVA_G16Y[h] * y + SYLVA_G16Z[h] * z;
}
float sylva_scurve3(float a) { return a * a * (3.0 - 2.0 * a); }
float sylva_select(float a, float b, float c, float lo, float hi, float falloff) {
    float f = min(falloff, (hi - lo) / 2.0);
    if (f > 0.0) {
        if (c < lo - f) return a;
        if (c < lo + f) return mix(a, b, sylva_scurve3((c - (lo - f)) / (2.0 * f)));
        if (c < hi - f) return b;
        if (c < hi + f) return mix(b, a, sylva_scurve3((c - (hi - f)) / (2.0 * f)));
        return a;
    }
    return (c < lo || c > hi) ? a : b;
}
float sylva_blend(int mode, float a, float b) {
    if (mode == 0) return b;
    if (mode == 1) return a * b;
    if (mode == 2) return 1.0 - (1.0 - a) * (1.0 - b);
    if (mode == 3) return a < 0.5 ? 2.0 * a * b : 1.0 - 2.0 * (1.0 - a) * (1.0 - b);
    if (mode == 4) return abs(a - b);
    if (mode == 5) return min(a + b, 1.0);
    if (mode == 6) return max(a - b, 0.0);
    if (mode == 7) return min(a, b);
    if (mode == 8) return max(a, b);
    if (mode == 9) return b < 0.5 ? 2.0 * a * b : 1.0 - 2.0 * (1.0 - a) * (1.0 - b);
    return (1.0 - 2.0 * b) * a * a + 2.0 * b * a;
}
"""

_G3 = """const float SYLVA_G3X[12] = float[12](1.,-1.,1.,-1.,1.,-1.,1.,-1.,0.,0.,0.,0.);
const float SYLVA_G3Y[12] = float[12](1.,1.,-1.,-1.,0.,0.,0.,0.,1.,-1.,1.,-1.);
const float SYLVA_G3Z[12] = float[12](0.,0.,0.,0.,1.,1.,-1.,-1.,1.,1.,-1.,-1.);
"""

# the lattice kinds' common start: the cell, the position in it, the wrapped corners
_LATTICE = """
float sylva_noise{k}(float x, float y, float z, ivec4 per, int nd) {{
    int fx = int(floor(x)); int fy = int(floor(y)); int fz = int(floor(z));
    x -= float(fx); y -= float(fy); z -= float(fz);
    int x0 = sylva_wrap(fx, per.x); int x1 = sylva_wrap(fx + 1, per.x);
    int y0 = sylva_wrap(fy, per.y); int y1 = sylva_wrap(fy + 1, per.y);
"""

_IMPROVED = _LATTICE + """    if (nd == 2) z = 0.0;
    int z0 = nd == 3 ? sylva_wrap(fz, per.z) : 0;
    int z1 = nd == 3 ? sylva_wrap(fz + 1, per.z) : 0;
    float u = sylva_curve(x, {interp}); float v = sylva_curve(y, {interp});
    float w = nd == 3 ? sylva_curve(z, {interp}) : 0.0;
    int a = PERM{k}[x0]; int b = PERM{k}[x1];
    int aa = PERM{k}[a + y0]; int ab = PERM{k}[a + y1];
    int ba = PERM{k}[b + y0]; int bb = PERM{k}[b + y1];
    float l0 = mix(mix(sylva_grad3(PERM{k}[aa + z0], x, y, z),
                       sylva_grad3(PERM{k}[ba + z0], x - 1.0, y, z), u),
                   mix(sylva_grad3(PERM{k}[ab + z0], x, y - 1.0, z),
                       sylva_grad3(PERM{k}[bb + z0], x - 1.0, y - 1.0, z), u), v);
    if (nd == 2) return l0;
    float l1 = mix(mix(sylva_grad3(PERM{k}[aa + z1], x, y, z - 1.0),
                       sylva_grad3(PERM{k}[ba + z1], x - 1.0, y, z - 1.0), u),
                   mix(sylva_grad3(PERM{k}[ab + z1], x, y - 1.0, z - 1.0),
                       sylva_grad3(PERM{k}[bb + z1], x - 1.0, y - 1.0, z - 1.0), u), v);
    return mix(l0, l1, w);
}}
"""

_VALUE = _LATTICE + """    float u = sylva_curve(x, {interp}); float v = sylva_curve(y, {interp});
    int a = PERM{k}[x0]; int b = PERM{k}[x1];
    if (nd == 2) {{
        return mix(mix(VALS{k}[PERM{k}[a + y0]], VALS{k}[PERM{k}[b + y0]], u),
                   mix(VALS{k}[PERM{k}[a + y1]], VALS{k}[PERM{k}[b + y1]], u), v);
    }}
    int z0 = sylva_wrap(fz, per.z); int z1 = sylva_wrap(fz + 1, per.z);
    float w = sylva_curve(z, {interp});
    int b00 = PERM{k}[a + y0]; int b10 = PERM{k}[b + y0];
    int b01 = PERM{k}[a + y1]; int b11 = PERM{k}[b + y1];
    return mix(mix(mix(VALS{k}[PERM{k}[b00 + z0]], VALS{k}[PERM{k}[b10 + z0]], u),
                   mix(VALS{k}[PERM{k}[b01 + z0]], VALS{k}[PERM{k}[b11 + z0]], u), v),
               mix(mix(VALS{k}[PERM{k}[b00 + z1]], VALS{k}[PERM{k}[b10 + z1]], u),
                   mix(VALS{k}[PERM{k}[b01 + z1]], VALS{k}[PERM{k}[b11 + z1]], u), v), w);
}}
"""

_SIMPLEX = """
float sylva_noise{k}(float xin, float yin, float zin, ivec4 per, int nd) {{
    if (nd == 2) {{
        const float F2 = 0.36602540378443865; const float G2 = 0.21132486540518713;
        float s = (xin + yin) * F2;
        int i = int(floor(xin + s)); int j = int(floor(yin + s));
        float t = float(i + j) * G2;
        float x0 = xin - (float(i) - t); float y0 = yin - (float(j) - t);
        int i1 = x0 > y0 ? 1 : 0; int j1 = 1 - i1;
        float x1 = x0 - float(i1) + G2; float y1 = y0 - float(j1) + G2;
        float x2 = x0 - 1.0 + 2.0 * G2; float y2 = y0 - 1.0 + 2.0 * G2;
        int ii = i & 255; int jj = j & 255;
        int g0 = PERM12{k}[ii + PERM{k}[jj]];
        int g1 = PERM12{k}[ii + i1 + PERM{k}[jj + j1]];
        int g2 = PERM12{k}[ii + 1 + PERM{k}[jj + 1]];
        float t0 = max(0.5 - x0 * x0 - y0 * y0, 0.0); t0 *= t0;
        float t1 = max(0.5 - x1 * x1 - y1 * y1, 0.0); t1 *= t1;
        float t2 = max(0.5 - x2 * x2 - y2 * y2, 0.0); t2 *= t2;
        float n = t0 * t0 * (SYLVA_G3X[g0] * x0 + SYLVA_G3Y[g0] * y0);
        n += t1 * t1 * (SYLVA_G3X[g1] * x1 + SYLVA_G3Y[g1] * y1);
        n += t2 * t2 * (SYLVA_G3X[g2] * x2 + SYLVA_G3Y[g2] * y2);
        return 70.0 * n;
    }}
    const float F3 = 1.0 / 3.0; const float G3 = 1.0 / 6.0;
    float s = (xin + yin + zin) * F3;
    int i = int(floor(xin + s)); int j = int(floor(yin + s)); int k = int(floor(zin + s));
    float t = float(i + j + k) * G3;
    float x0 = xin - (float(i) - t); float y0 = yin - (float(j) - t);
    float z0 = zin - (float(k) - t);
    int ca = x0 >= y0 ? 1 : 0; int cb = y0 >= z0 ? 1 : 0; int cc = x0 >= z0 ? 1 : 0;
    int rx = ca + cc; int ry = 1 - ca + cb; int rz = 2 - cb - cc;
    int i1 = rx >= 2 ? 1 : 0; int j1 = ry >= 2 ? 1 : 0; int k1 = rz >= 2 ? 1 : 0;
    int i2 = rx >= 1 ? 1 : 0; int j2 = ry >= 1 ? 1 : 0; int k2 = rz >= 1 ? 1 : 0;
    float x1 = x0 - float(i1) + G3; float y1 = y0 - float(j1) + G3;
    float z1 = z0 - float(k1) + G3;
    float x2 = x0 - float(i2) + 2.0 * G3; float y2 = y0 - float(j2) + 2.0 * G3;
    float z2 = z0 - float(k2) + 2.0 * G3;
    float x3 = x0 - 1.0 + 3.0 * G3; float y3 = y0 - 1.0 + 3.0 * G3;
    float z3 = z0 - 1.0 + 3.0 * G3;
    int ii = i & 255; int jj = j & 255; int kk = k & 255;
    int g0 = PERM12{k}[ii + PERM{k}[jj + PERM{k}[kk]]];
    int g1 = PERM12{k}[ii + i1 + PERM{k}[jj + j1 + PERM{k}[kk + k1]]];
    int g2 = PERM12{k}[ii + i2 + PERM{k}[jj + j2 + PERM{k}[kk + k2]]];
    int g3 = PERM12{k}[ii + 1 + PERM{k}[jj + 1 + PERM{k}[kk + 1]]];
    float t0 = max(0.6 - x0 * x0 - y0 * y0 - z0 * z0, 0.0); t0 *= t0;
    float t1 = max(0.6 - x1 * x1 - y1 * y1 - z1 * z1, 0.0); t1 *= t1;
    float t2 = max(0.6 - x2 * x2 - y2 * y2 - z2 * z2, 0.0); t2 *= t2;
    float t3 = max(0.6 - x3 * x3 - y3 * y3 - z3 * z3, 0.0); t3 *= t3;
    float n = t0 * t0 * (SYLVA_G3X[g0] * x0 + SYLVA_G3Y[g0] * y0 + SYLVA_G3Z[g0] * z0);
    n += t1 * t1 * (SYLVA_G3X[g1] * x1 + SYLVA_G3Y[g1] * y1 + SYLVA_G3Z[g1] * z1);
    n += t2 * t2 * (SYLVA_G3X[g2] * x2 + SYLVA_G3Y[g2] * y2 + SYLVA_G3Z[g2] * z2);
    n += t3 * t3 * (SYLVA_G3X[g3] * x3 + SYLVA_G3Y[g3] * y3 + SYLVA_G3Z[g3] * z3);
    return 32.0 * n;
}}
"""

_PERLIN = _LATTICE + """    float u = sylva_curve(x, {interp}); float v = sylva_curve(y, {interp});
    int a = PERM{k}[x0]; int b = PERM{k}[x1];
    if (nd == 2) {{
        int h00 = PERM{k}[a + y0]; int h10 = PERM{k}[b + y0];
        int h01 = PERM{k}[a + y1]; int h11 = PERM{k}[b + y1];
        float n00 = CG2{k}[h00].x * x + CG2{k}[h00].y * y;
        float n10 = CG2{k}[h10].x * (x - 1.0) + CG2{k}[h10].y * y;
        float n01 = CG2{k}[h01].x * x + CG2{k}[h01].y * (y - 1.0);
        float n11 = CG2{k}[h11].x * (x - 1.0) + CG2{k}[h11].y * (y - 1.0);
        return mix(mix(n00, n10, u), mix(n01, n11, u), v);
    }}
    int z0 = sylva_wrap(fz, per.z); int z1 = sylva_wrap(fz + 1, per.z);
    float w = sylva_curve(z, {interp});
    int b00 = PERM{k}[a + y0]; int b10 = PERM{k}[b + y0];
    int b01 = PERM{k}[a + y1]; int b11 = PERM{k}[b + y1];
    return mix(
        mix(mix(dot(CG3{k}[PERM{k}[b00 + z0]], vec3(x, y, z)),
                dot(CG3{k}[PERM{k}[b10 + z0]], vec3(x - 1.0, y, z)), u),
            mix(dot(CG3{k}[PERM{k}[b01 + z0]], vec3(x, y - 1.0, z)),
                dot(CG3{k}[PERM{k}[b11 + z0]], vec3(x - 1.0, y - 1.0, z)), u), v),
        mix(mix(dot(CG3{k}[PERM{k}[b00 + z1]], vec3(x, y, z - 1.0)),
                dot(CG3{k}[PERM{k}[b10 + z1]], vec3(x - 1.0, y, z - 1.0)), u),
            mix(dot(CG3{k}[PERM{k}[b01 + z1]], vec3(x, y - 1.0, z - 1.0)),
                dot(CG3{k}[PERM{k}[b11 + z1]], vec3(x - 1.0, y - 1.0, z - 1.0)), u), v),
        w);
}}
"""

# Worley on a jittered grid (texture._cellkernels.worley): the same 32-bit hashes (GLSL's
# uint arithmetic wraps as the kernel's masks do), the ring-by-ring search up to ring 4.
_WORLEY_COMMON = """
uint sylva_hash32(uint a) {
    a = (a ^ (a >> 16u)) * 0x7FEB352Du;
    a = (a ^ (a >> 15u)) * 0x846CA68Bu;
    return a ^ (a >> 16u);
}
int sylva_pmod(int i, int p) {
    if (p > 0) {
        i -= p * int(floor(float(i) / float(p)));
        if (i < 0) i += p;
        if (i >= p) i -= p;
    }
    return i;
}
"""

_WORLEY = """
float sylva_noise{k}(float x, float y, float z, ivec4 per, int nd) {{
    float cx = floor(x); float cy = floor(y); float cz = nd == 3 ? floor(z) : 0.0;
    int icx = int(cx); int icy = int(cy); int icz = int(cz);
    float f1 = 3.4e38; float f2 = 3.4e38; float f3 = 3.4e38;
    uint best = 0u;
    uint hs = sylva_hash32({seed}u);
    const float INV32 = 2.3283064365386963e-10;
    for (int r = 1; r <= 4; r++) {{
        int rz = nd == 3 ? r : 0;
        for (int dz = -rz; dz <= rz; dz++) {{
            for (int dy = -r; dy <= r; dy++) {{
                for (int dx = -r; dx <= r; dx++) {{
                    if (r > 1 && max(max(abs(dx), abs(dy)), abs(dz)) < r) continue;
                    int ix = icx + dx; int iy = icy + dy; int iz = icz + dz;
                    uint h = sylva_hash32(hs ^ uint(sylva_pmod(ix, per.x)));
                    h = sylva_hash32(h ^ uint(sylva_pmod(iy, per.y)));
                    if (nd == 3) h = sylva_hash32(h ^ uint(sylva_pmod(iz, per.z)));
                    vec3 dd = vec3(
                        float(ix) + 0.5 + {jitter} * (float(sylva_hash32(h ^ 0x68E31DA4u)) * INV32
                                                      - 0.5) - x,
                        float(iy) + 0.5 + {jitter} * (float(sylva_hash32(h ^ 0xB5297A4Du)) * INV32
                                                      - 0.5) - y, 0.0);
                    if (nd == 3) dd.z = float(iz) + 0.5 + {jitter} * (
                        float(sylva_hash32(h ^ 0x1B56C4E9u)) * INV32 - 0.5) - z;
                    float d;
                    if ({metric} == 1) d = abs(dd.x) + abs(dd.y) + abs(dd.z);
                    else if ({metric} == 2) d = max(max(abs(dd.x), abs(dd.y)), abs(dd.z));
                    else if ({metric} == 3) d = dot(dd, dd);
                    else d = sqrt(dot(dd, dd));
                    if (d < f1) {{ f3 = f2; f2 = f1; f1 = d; best = h; }}
                    else if (d < f2) {{ f3 = f2; f2 = d; }}
                    else if (d < f3) {{ f3 = d; }}
                }}
            }}
        }}
        float fk = {needk} <= 1 ? f1 : ({needk} == 2 ? f2 : f3);
        float fr = float(r);
        float gx = x - cx; float gy = y - cy;
        float gap = min(min(gx + fr, fr + 1.0 - gx), min(gy + fr, fr + 1.0 - gy));
        if (nd == 3) {{ float gz = z - cz; gap = min(gap, min(gz + fr, fr + 1.0 - gz)); }}
        if ({metric} == 3) gap *= gap;
        if (fk <= gap) break;
    }}
    float cid = float(sylva_hash32(best ^ 0x2545F491u)) * INV32;
    {combine}
}}
"""

_WORLEY_COMBINE = ("return f1;", "return f2;", "return f3;", "return f2 - f1;",
                   "return f1 + f2;", "return f1 * f2;", "return sqrt(f1 * f2);",
                   "return sqrt(f2 - f1);", "return 1.0 - f1;", "return 1.0 - f2;",
                   "return cid;")

_FRACTAL = """
float sylva_gen{k}(float x, float y, float z) {{
    float total = 0.0;
    float weight = 1.0;
    for (int o = 0; o < {no}; o++) {{
        float n = sylva_noise{k}(x * FREQ{k}[o].x + OFF{k}[o].x, y * FREQ{k}[o].y + OFF{k}[o].y,
                                 z * FREQ{k}[o].z + OFF{k}[o].z, PER{k}[o], {nd});
        {combine}
    }}
    return total * {norm};
}}
"""

_COMBINE = {
    _k.FBM: "total += AMP{k}[o] * n;",
    _k.TURBULENCE: "total += AMP{k}[o] * abs(n);",
    _k.RIDGED: ("float s = 1.0 - abs(n); s *= s; s *= weight; "
                "weight = clamp(s * {gain}, 0.0, 1.0); total += AMP{k}[o] * s;"),
}


def _fl(v) -> str:
    v = float(v)
    if not math.isfinite(v):
        raise ValueError(f"a GLSL constant must be finite, got {v}")
    s = repr(v)
    return s if ("." in s or "e" in s) else s + ".0"


def _farr(name, vals, typ="float"):
    vals = list(vals)
    return f"const {typ} {name}[{len(vals)}] = {typ}[{len(vals)}]({', '.join(vals)});"


class _Glsl:
    def __init__(self, graph, shape, tag=""):
        self.graph = graph
        self.tag = tag  # prefixes the names of this graph's tables and functions
        self.shape = shape
        self.nz = shape[0] if len(shape) == 3 else 1
        self.ny, self.nx = shape[-2], shape[-1]
        self.decls, self.body, self.memo = [], [], {}
        self.n = 0
        self.need_g3 = False
        self.need_worley = False
        self.need_complex = False
        self.overrides, self.keep = {}, []  # pattern lowering: per-generator planning
        self.tables = {}

    def table(self, prefix, k, items, typ):
        """The name of a constant table with ``items``: declared once per content (llvmpipe
        spends about half a second compiling each 512-entry table)."""
        key = (typ, tuple(items))
        name = self.tables.get(key)
        if name is None:
            name = self.tables[key] = f"{prefix}{k}"
            self.decls.append(_farr(name, items, typ))
        return name

    def var(self, expr, typ="float"):
        self.n += 1
        self.body.append(f"    {typ} v{self.n} = {expr};")
        return f"v{self.n}"

    def inp(self, node, key, ctx, default=None):
        v = node.inputs.get(key)
        if v is None:
            return _fl(default)
        if isinstance(v, Node):
            return self.emit(v, ctx)
        return _fl(v)

    def emit(self, node, ctx):
        key = (id(node), ctx)
        if key not in self.memo:
            self.memo[key] = self._emit(node, ctx)
        return self.memo[key]

    def _emit(self, node, ctx):
        t, cat = node.type, node.spec.category
        base = ctx or ("q.x", "q.y", "q.z")
        if cat == "generator":
            return self.generator(node, base)
        if cat == "pattern":
            return self.pattern(node, ctx)
        if cat == "fractal":
            return self.formula(node, base, ctx)
        if cat == "transformer":
            return self.transform(node, base, ctx)
        if cat == "colour":
            return self.colour(node, ctx)
        if cat == "coordinate":
            if t == "constant":
                return _fl(_f(node.param("value"), node, "value"))
            a = "xyz".index(t)
            if node.param("closed") and ctx is None:
                n = (self.nx, self.ny, self.nz)[a]
                return self.var(f"{base[a]} * {_fl(self.nx)} / {_fl(max(n - 1, 1))}")
            return base[a]
        a = self.inp(node, "source" if cat == "modifier" else "a", ctx)
        simple = {"abs": "abs({a})", "invert": "-{a}", "sin": "sin({a})", "cos": "cos({a})",
                  "fract": "{a} - floor({a})",
                  "smoothstep": "clamp({a}, 0.0, 1.0) * clamp({a}, 0.0, 1.0) * "
                                "(3.0 - 2.0 * clamp({a}, 0.0, 1.0))"}
        if t in simple:
            return self.var(simple[t].format(a=a))
        if t == "clamp":
            lo, hi = (_fl(_f(node.param(k), node, k)) for k in ("lower", "upper"))
            return self.var(f"min(max({a}, {lo}), {hi})")
        if t == "scale-bias":
            s, b = (_fl(_f(node.param(k), node, k)) for k in ("scale", "bias"))
            return self.var(f"{a} * {s} + {b}")
        if t == "exponent":
            e = _fl(_f(node.param("exponent"), node, "exponent"))
            return self.var(f"pow(abs(({a} + 1.0) / 2.0), {e}) * 2.0 - 1.0")
        if t == "curve":
            return self.curve(node, a)
        if t == "terrace":
            return self.terrace(node, a)
        b = self.inp(node, "b", ctx)
        ops = {"add": "{a} + {b}", "sub": "{a} - {b}", "multiply": "{a} * {b}",
               "divide": "{a} / {b}", "min": "min({a}, {b})", "max": "max({a}, {b})",
               "power": "pow({a}, {b})"}
        if t in ops:
            return self.var(ops[t].format(a=a, b=b))
        if t == "blend":
            c = self.inp(node, "t", ctx)
            return self.var(f"{a} + {c} * ({b} - {a})")
        c = self.inp(node, "control", ctx)
        lo, hi, fo = (_fl(_f(node.param(k), node, k)) for k in ("lower", "upper", "falloff"))
        return self.var(f"sylva_select({a}, {b}, {c}, {lo}, {hi}, {fo})")

    def formula(self, node, base, ctx):
        """An escape-time fractal or formula node: the formula language's GLSL
        (:mod:`._formula_glsl`) at the pixel's point of the complex plane, as the CPU
        kernel maps it (:func:`sylva.texture.fractals._plane`)."""
        from . import _formula
        from ._formula_glsl import formula_glsl

        if len(self.shape) != 2:
            raise _err(node, "type", f"a {node.type} node needs a 2D image")
        code = _formula.for_node(node)
        q = code.values(node)
        c = node.param("center")
        try:
            c = complex(*c) if isinstance(c, list | tuple) else complex(c)
            width = float(node.param("width"))
            if not (width > 0 and math.isfinite(width)):
                raise ValueError(f"width must be positive, got {width}")
        except (TypeError, ValueError) as exc:
            raise _err(node, "center", f"{node.type}: bad center or width: {exc}") from None
        self.n += 1
        fname = f"{self.tag}sylva_formula{self.n}"
        self.decls.append(formula_glsl(code, q, fname))
        self.need_complex = True
        px = width / self.nx
        pr = self.var(f"{_fl(c.real)} + ({base[0]} * {_fl(self.nx)} - "
                      f"{_fl((self.nx - 1) / 2.0)}) * {_fl(px)}")
        pi = self.var(f"{_fl(c.imag)} + ({_fl((self.ny - 1) / 2.0)} - {base[1]} * "
                      f"{_fl(self.nx)}) * {_fl(px)}")
        ins = ", ".join(self.inp(node, k, ctx, 0.0) for k in ("in1", "in2", "in3"))
        return self.var(f"{fname}({pr}, {pi}, {ins})")

    def pattern(self, node, ctx):
        from ._glsl_patterns import lower

        if ctx is not None:
            raise _err(node, "type", f"a {node.type} node is computed on the image grid and "
                                     "cannot sit under a transformer")
        if len(self.shape) != 2:
            raise _err(node, "type", f"a {node.type} node needs a 2D image")
        try:
            low, over = lower(node, self.shape, self.graph.tileable, self.graph.time)
        except KeyError:
            raise _err(node, "type", f"no GLSL for {node.type} nodes (computed on the CPU); "
                                     "GLSL covers the noise patterns") from None
        except (TypeError, ValueError) as exc:
            raise _err(node, "type", f"{node.type} node: {exc}") from None
        self.overrides.update(over)
        self.keep.append(low)  # the overrides are keyed by id: keep the nodes alive
        return self.emit(low, ctx)

    def _plan(self, node, kind, fractal):
        em = _Emit(self.graph, self.shape, np.float32)
        if id(node) not in self.overrides:
            return em._plan(node, kind, fractal)
        from .. import _gridplan as _gp
        from .. import noise as _nz

        tileable, time = self.overrides[id(node)]
        prm = {k: node.param(k) for k in node.spec.params}
        try:
            return _gp.grid_plan(
                self.shape, kind, fractal, prm["scale"], prm["octaves"], prm["persistence"],
                prm["lacunarity"], prm["gain"], prm["seed"], prm["interpolation"], tileable,
                time, prm["offset"], 0.0, prm["normalize"], prm.get("output", "f1"),
                prm.get("metric", "euclidean"), prm.get("jitter", 1.0), None,
                prm.get("density"))
        except (_nz.NoiseError, TypeError, ValueError) as exc:
            raise _err(node, "type", f"{node.type} node: {exc}") from None

    def curve(self, node, a):
        pts = _points(node, "points", 2, 4)
        pts = pts[np.argsort(pts[:, 0], kind="stable")]
        self.n += 1
        k, n = f"{self.tag}{self.n}", len(pts)
        self.decls.append(_farr(f"CX{k}", map(_fl, pts[:, 0])))
        self.decls.append(_farr(f"CY{k}", map(_fl, pts[:, 1])))
        self.decls.append(f"""
float sylva_curve{k}(float v) {{
    int pos = 0;
    for (int q = 0; q < {n}; q++) {{ if (v >= CX{k}[q]) pos = q + 1; }}
    int i0 = clamp(pos - 2, 0, {n - 1}); int i1 = clamp(pos - 1, 0, {n - 1});
    int i2 = clamp(pos, 0, {n - 1}); int i3 = clamp(pos + 1, 0, {n - 1});
    if (i1 == i2) return CY{k}[i1];
    float a = (v - CX{k}[i1]) / (CX{k}[i2] - CX{k}[i1]);
    float n0 = CY{k}[i0]; float n1 = CY{k}[i1]; float n2 = CY{k}[i2]; float n3 = CY{k}[i3];
    float p = (n3 - n2) - (n0 - n1); float qq = (n0 - n1) - p; float r = n2 - n0;
    return p * a * a * a + qq * a * a + r * a + n1;
}}""")
        return self.var(f"sylva_curve{k}({a})")

    def terrace(self, node, a):
        pts = np.sort(_points(node, "points", 1, 2))
        self.n += 1
        k, n = f"{self.tag}{self.n}", len(pts)
        inv = "true" if node.param("invert") else "false"
        self.decls.append(_farr(f"TP{k}", map(_fl, pts)))
        self.decls.append(f"""
float sylva_terrace{k}(float v) {{
    int pos = 0;
    for (int q = 0; q < {n}; q++) {{ if (v >= TP{k}[q]) pos = q + 1; }}
    int i0 = clamp(pos - 1, 0, {n - 1}); int i1 = clamp(pos, 0, {n - 1});
    if (i0 == i1) return TP{k}[i1];
    float a0 = TP{k}[i0]; float a1 = TP{k}[i1];
    float s = (v - a0) / (a1 - a0);
    if ({inv}) {{ s = 1.0 - s; float tmp = a0; a0 = a1; a1 = tmp; }}
    s = s * s;
    return a0 * (1.0 - s) + a1 * s;
}}""")
        return self.var(f"sylva_terrace{k}({a})")

    def generator(self, node, base):
        if node.type in GENERATOR_KINDS:
            kind, fractal = node.type, node.param("fractal")
        elif node.type == "worley-fn":
            kind, fractal = "worley", "fbm"
        else:
            kind, fractal = node.param("kind"), node.type
        if node.param("warp"):
            raise _err(node, "warp", "no GLSL for a generator's own warp; use a warp node")
        plan = self._plan(node, kind, fractal)
        if plan.ndim > 3 or plan.torus:
            raise _err(node, "type", "GLSL covers 2D and 3D generators (tileable simplex and "
                                     "4D are CPU-only)")
        if plan.norder or (plan.setup.kind == _k.WORLEY and plan.setup.wpar[7] > 0):
            raise _err(node, "type", "no GLSL for worley orders above F3 or a Poisson point "
                                     "density (CPU-only); GLSL covers F1-F3 on a jittered grid")
        s = plan.setup
        self.n += 1
        k = f"{self.tag}{self.n}"
        t = s.tables
        names = {}  # the tables this generator reads, shared with equal ones before it

        def table(prefix, items, typ="int"):
            names[f"{prefix}{k}["] = self.table(prefix, k, list(items), typ) + "["

        if s.kind != _k.WORLEY:
            table("PERM", map(str, t.perm.tolist()))
        if s.kind == _k.SIMPLEX:
            self.need_g3 = True
            table("PERM12", map(str, t.perm12.tolist()))
            text = _SIMPLEX.format(k=k)
        elif s.kind == _k.VALUE:
            table("VALS", map(_fl, t.values), "float")
            text = _VALUE.format(k=k, interp=s.interp)
        elif s.kind == _k.PERLIN:
            g2, g3 = t.gradients[0], t.gradients[1]
            table("CG2", [f"vec2({_fl(a)}, {_fl(b)})" for a, b in g2[:, :2]], "vec2")
            table("CG3", [f"vec3({', '.join(map(_fl, r))})" for r in g3[:, :3]], "vec3")
            text = _PERLIN.format(k=k, interp=s.interp)
        elif s.kind == _k.WORLEY:
            from .._cellkernels import NEEDK

            w = s.wpar
            combo = int(w[1])
            comb = (_WORLEY_COMBINE[combo] if combo < len(_WORLEY_COMBINE) else
                    f"return {_fl(w[4])} * f1 + {_fl(w[5])} * f2 + {_fl(w[6])} * f3;")
            self.need_worley = True
            text = _WORLEY.format(k=k, seed=int(w[3]), jitter=_fl(w[2]), metric=int(w[0]),
                                  needk=NEEDK[combo], combine=comb)
        else:
            text = _IMPROVED.format(k=k, interp=s.interp)
        for old, new in names.items():
            text = text.replace(old, new)
        self.decls.append(text)
        no = plan.freqs.shape[0]
        vec = [f"vec4({', '.join(map(_fl, r))})" for r in plan.freqs]
        self.decls.append(_farr(f"FREQ{k}", vec, "vec4"))
        vec = [f"vec4({', '.join(map(_fl, r))})" for r in plan.offs]
        self.decls.append(_farr(f"OFF{k}", vec, "vec4"))
        vec = [f"ivec4({', '.join(str(int(v)) for v in r)})" for r in plan.pers]
        self.decls.append(_farr(f"PER{k}", vec, "ivec4"))
        self.decls.append(_farr(f"AMP{k}", map(_fl, plan.amps)))
        comb = _COMBINE[plan.mode].format(k=k, gain=_fl(plan.gain))
        self.decls.append(_FRACTAL.format(k=k, no=no, nd=plan.ndim, combine=comb,
                                          norm=_fl(plan.norm)))
        pt = []
        for a in range(3):
            if a < len(self.shape):
                step = plan.cells[a] / plan.sizes[a] * self.nx
                pt.append(f"{base[a]} * {_fl(step)} + {_fl(plan.offset[a])}")
            else:
                pt.append(_fl(plan.axes[a][0]))
        return self.var(f"sylva_gen{k}({', '.join(pt)})")

    def transform(self, node, base, ctx):
        t = node.type
        if t == "warp":
            amt = _fl(_f(node.param("amount"), node, "amount"))
            d = [self.inp(node, k, ctx) for k in ("dx", "dy")]
            d.append(self.inp(node, "dz", ctx) if "dz" in node.inputs else "0.0")
            new = tuple(self.var(f"{base[a]} + {amt} * {d[a]}") for a in range(3))
        elif t == "translate":
            by = _vec(node, "by", 3)
            new = tuple(self.var(f"{base[a]} - {_fl(by[a])}") for a in range(3))
        elif t == "scale":
            by = _vec(node, "by", 3)
            cen = _vec(node, "center", 3)
            new = tuple(self.var(f"({base[a]} - {_fl(cen[a])}) / {_fl(by[a])} + "
                                 f"{_fl(cen[a])}") for a in range(3))
        else:
            ang = math.radians(_f(node.param("angle"), node, "angle"))
            cen = _vec(node, "center", 2)
            cs, sn = _fl(math.cos(ang)), _fl(math.sin(ang))
            dx = self.var(f"{base[0]} - {_fl(cen[0])}")
            dy = self.var(f"{base[1]} - {_fl(cen[1])}")
            new = (self.var(f"{cs} * {dx} + {sn} * {dy} + {_fl(cen[0])}"),
                   self.var(f"-{sn} * {dx} + {cs} * {dy} + {_fl(cen[1])}"), base[2])
        return self.inp(node, "source", new)

    def colour(self, node, ctx):
        t = node.type
        if t == "luminance":
            c = self.inp(node, "source", ctx)
            return self.var(f"dot({c}.rgb, vec3(0.2126, 0.7152, 0.0722))")
        if t == "color":
            rgb = _cm.parse_color(node.param("value"))
            a = _f(node.param("alpha"), node, "alpha")
            return self.var(f"vec4({', '.join(map(_fl, [*rgb, a]))})", "vec4")
        if t == "rgb":
            ch = [self.inp(node, k, ctx, 1.0 if k == "a" else None) for k in "rgba"]
            return self.var(f"vec4({', '.join(ch)})", "vec4")
        if t in ("gradient", "palette"):
            if t == "gradient":
                cm = _cm.get_colormap(node.param("colors"))
            elif node.param("file"):
                cm = _cm.load_palette(node.param("file"))
            else:
                cm = _cm.parse_colors(str(node.param("colors")), option="colors")
            v = self.inp(node, "source", ctx)
            lo, hi = (_fl(_f(node.param(k), node, k)) for k in ("vmin", "vmax"))
            self.n += 1
            k, n = f"{self.tag}{self.n}", len(cm.positions)
            self.decls.append(_farr(f"GP{k}", map(_fl, cm.positions)))
            self.decls.append(_farr(f"GC{k}", [f"vec3({', '.join(map(_fl, c))})"
                                               for c in cm.colors], "vec3"))
            self.decls.append(f"""
vec4 sylva_gradient{k}(float v) {{
    float t = {hi} > {lo} ? (v - {lo}) / ({hi} - {lo}) : 0.0;
    if (isnan(t)) t = 0.0;
    t = clamp(t, 0.0, 1.0);
    if (t <= GP{k}[0]) return vec4(GC{k}[0], 1.0);
    for (int q = 1; q < {n}; q++) {{
        if (t <= GP{k}[q]) {{
            if (GP{k}[q] == GP{k}[q - 1]) return vec4(GC{k}[q], 1.0);
            float f = (t - GP{k}[q - 1]) / (GP{k}[q] - GP{k}[q - 1]);
            return vec4(GC{k}[q - 1] + f * (GC{k}[q] - GC{k}[q - 1]), 1.0);
        }}
    }}
    return vec4(GC{k}[{n - 1}], 1.0);
}}""")
            return self.var(f"sylva_gradient{k}({v})", "vec4")
        mode = str(node.param("mode")).lower()
        if mode not in BLEND:
            raise _err(node, "mode", f"layer: unknown blend mode {mode!r}")
        a = self.inp(node, "base", ctx)
        b = self.inp(node, "top", ctx)
        op = (self.inp(node, "opacity", ctx) if "opacity" in node.inputs
              else _fl(_f(node.param("opacity"), node, "opacity")))
        kk = self.var(f"{op} * {b}.a")
        ch = [f"{a}.{c} + {kk} * (sylva_blend({BLEND[mode]}, {a}.{c}, {b}.{c}) - {a}.{c})"
              for c in "rgb"]
        return self.var(f"vec4({', '.join(ch)}, {a}.a + {kk} * (1.0 - {a}.a))", "vec4")


def _function(graph, name, shape, tag):
    """``(declarations and function text, needs the G3 tables)`` of one graph."""
    import re

    from ._nodes import GraphError

    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise GraphError(f"a GLSL function name is letters, digits and _, got {name!r}")
    shape = graph._shape(shape)
    g = _Glsl(graph, shape, tag)
    res = g.emit(graph.output, None)
    typ = "vec4" if graph.output.spec.output == COLOUR else "float"
    text = "\n".join([*g.decls, "", f"{typ} {name}(vec3 q) {{", *g.body,
                      f"    return {res};", "}", ""])
    return text, (g.need_g3, g.need_worley, g.need_complex)


def compile_glsl(graph, *, name="sylva_texture", shape=None) -> str:
    """GLSL 3.30 source of ``graph`` as the function ``NAME(vec3 q)``.

    Parameters
    ----------
    graph : Graph
    name : str
        The function's name (letters, digits, underscores).
    shape : (H, W) or (D, H, W), optional
        The image the lattice coordinates are planned for (default: the graph's size); it
        fixes the tileable cell counts, as :meth:`Graph.evaluate` does for that shape.

    Returns
    -------
    str
        Declarations and the function (no ``#version`` line: prepend it, or include the
        text in a larger shader).
    """
    return compile_glsl_library({name: graph}, shape=shape)


def compile_glsl_library(graphs, *, shape=None) -> str:
    """GLSL 3.30 source of several graphs, one function ``NAME(vec3 q)`` each, sharing one
    copy of the common helpers (each graph's tables are prefixed by its name, so the
    functions sit side by side in one shader).

    Parameters
    ----------
    graphs : dict
        ``{function name: Graph}``.
    shape : (H, W) or (D, H, W), optional
        As :func:`compile_glsl` (default: each graph's size).

    Examples
    --------
    >>> from sylva.texture import graph as tg
    >>> src = compile_glsl_library({"a": tg.Graph(tg.improved(seed=1)),
    ...                             "b": tg.Graph(tg.simplex(seed=2))}, shape=(8, 8))
    >>> "float a(vec3 q)" in src and "float b(vec3 q)" in src
    True
    """
    from ._formula_glsl import COMPLEX_HELPERS

    parts, g3, worley, cplx = [], False, False, False
    for name, graph in graphs.items():
        text, (n3, nw, nc) = _function(graph, name, shape,
                                       "" if len(graphs) == 1 else name + "_")
        parts.append(text)
        g3, worley, cplx = g3 or n3, worley or nw, cplx or nc
    head = _COMMON + (_G3 if g3 else "") + (_WORLEY_COMMON if worley else "") + (
        COMPLEX_HELPERS if cplx else "")
    return "\n".join([head, *parts])
