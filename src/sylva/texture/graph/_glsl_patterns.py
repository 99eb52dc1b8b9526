"""The pattern nodes as graphs of primitive nodes, for GLSL (private).

Each function of :mod:`sylva.texture.patterns` is ``noise_grid`` calls and element-wise
arithmetic; :func:`lower` writes the same computation as nodes (generators with the
pattern's scales, seeds and offsets; the coordinates the function uses), so the GLSL
emitter compiles a pattern node like any graph, and the shader gives the CPU pattern's
values.  Where a pattern samples a noise with other whole-graph properties than the graph's
(the leaf's optional noise is never tiled or animated; the bark's detail is a slice of 3D
noise even without ``time``), the generator's ``tileable`` and ``time`` are returned as
overrides for the planner.  IFS and L-system textures are not arithmetic of noise: they
have no lowering.
"""

from __future__ import annotations

import inspect
import math

from .. import patterns as _pt
from ._nodes import Node

_LOWERED = ("marble", "wood", "clouds", "granite", "bark", "leaf", "grass")


def _gen(kind, **params):
    return Node(kind, params={k: v for k, v in params.items() if v is not None or k == "seed"})


def _clamp(a, lo=0.0, hi=1.0):
    return Node("clamp", {"source": a}, {"lower": lo, "upper": hi})


def _plus(seed, k):
    return None if seed is None else seed + k


def lower(node, shape, tileable, time):
    """``(node, overrides)``: the pattern ``node`` as primitive nodes for an image of
    ``shape`` (H, W), and ``{id(generator): (tileable, time)}`` for the generators that do
    not follow the graph's properties.  Raises ``KeyError`` for patterns without one."""
    if node.type not in _LOWERED:
        raise KeyError(node.type)
    sig = inspect.signature(getattr(_pt, node.type)).parameters
    p = {k: node.params.get(k, v.default) for k, v in sig.items()
         if k not in ("shape", "dtype", "tileable", "time")}
    h, w = shape
    over = {}
    seed = p.get("seed")
    x = Node("x")
    y = Node("y")  # j / W
    t = node.type
    if t == "marble":
        tn = _gen("improved", fractal="turbulence", scale=p["scale"], octaves=p["octaves"],
                  persistence=p["persistence"], lacunarity=p["lacunarity"], seed=seed)
        k = float(round(p["stripes"]) if tileable else p["stripes"])
        phase = Node("x", params={"closed": not tileable}) * k + tn * float(p["turbulence"])
        return _clamp(0.5 + 0.5 * Node("sin", {"source": phase * (2.0 * math.pi)})), over
    if t == "wood":
        tn = _gen("improved", fractal="turbulence", scale=p["scale"], octaves=p["octaves"],
                  persistence=p["persistence"], lacunarity=p["lacunarity"], seed=seed)
        c = p["center"]
        if tileable:
            bend = _gen("improved", scale=[1.0, float(max(1.0, round(h / w)))], octaves=3,
                        seed=_plus(seed, 2))
            phase = float(max(1, round(p["rings"]))) * (x - float(c[0]) + 0.3 * bend)
        else:
            dx = x - float(c[0])
            dy = (y * (w / h) - float(c[1])) * (h / w)
            phase = float(p["rings"]) * ((dx * dx + dy * dy) ** 0.5)
        ring = Node("smoothstep", {"source": Node("fract", {
            "source": phase + float(p["turbulence"]) * tn})})
        fib = _gen("improved", scale=[p["scale"] * 16.0, p["scale"] * 16.0 * h / w / 12.0],
                   octaves=2, seed=_plus(seed, 1))
        g = float(p["grain"])
        return _clamp((1.0 - g) * ring + g * (0.5 + fib)), over
    if t == "clouds":
        cov = float(p["coverage"])
        if not 0.0 < cov <= 1.0:
            raise ValueError(f"coverage must lie in (0, 1], got {cov}")
        f = _gen("simplex", scale=p["scale"], octaves=p["octaves"],
                 persistence=p["persistence"], lacunarity=p["lacunarity"], seed=seed)
        v = _clamp(0.5 + 0.75 * f)
        v = _clamp((v - (1.0 - cov)) / cov)
        return _clamp(v ** float(p["sharpness"])), over
    if t == "granite":
        cell = _gen("worley", output="cell", scale=p["scale"], seed=seed)
        edge = _gen("worley", output="f2-f1", scale=p["scale"], seed=seed)
        speck = _gen("improved", fractal="turbulence", scale=p["scale"] * 2.0,
                     octaves=p["octaves"], seed=_plus(seed, 2))
        border = _clamp(edge / 0.08)
        v = (0.15 + 0.6 * cell ** 1.5 + 0.25 * (1.0 - speck)) * (0.55 + 0.45 * border)
        return _clamp(v), over
    if t == "bark":
        sx = p["scale"]
        sy = max(p["scale"] * p["stretch"], 1e-9) * h / w
        kw = dict(octaves=p["octaves"], persistence=p["persistence"],
                  lacunarity=p["lacunarity"])
        if p["stretch"] == 0 and not tileable:  # one row of 2D noise, down the image
            s = _gen("improved", scale=[sx, 1e-9 * h], seed=seed, **kw)
            over[id(s)] = (False, None)
        else:
            if tileable:
                sy = max(1.0, round(sy))
            s = _gen("improved", scale=[sx, sy], seed=seed, **kw)
        d = _gen("improved", scale=p["scale"] * 2.0, seed=_plus(seed, 1), **kw)
        over[id(d)] = (tileable, 0.0 if time is None else time)
        a = _clamp(abs(s) / max(p["cracks"], 1e-9))
        det = float(p["detail"])
        v = a * a * (3.0 - 2.0 * a) * ((1.0 - det) + det * (0.5 + d))
        return _clamp(v), over
    if t == "leaf":
        u = Node("x", params={"closed": True}) * 2.0 - 1.0
        v = 1.0 - Node("y", params={"closed": True})
        au = abs(u)
        q = u / float(p["midrib"])
        main = math.e ** (-(q * q))  # (GLSL's pow of a negative base is undefined)
        veins = float(p["veins"])
        phase = veins * (v - float(p["vein_angle"]) * au / max(veins, 1e-9) * 3.0)
        cos = Node("cos", {"source": 2.0 * math.pi * phase})
        sec = Node("max", {"a": 0.0, "b": cos}) ** float(p["vein_width"]) * (1.0 - 0.6 * au)
        shade = 1.0 - float(p["darkening"]) * u * u
        val = 0.5 * shade + 0.45 * main + 0.25 * sec
        if p["noise"]:
            n = _gen("simplex", scale=4.0, octaves=4, seed=seed)
            over[id(n)] = (False, None)
            val = val + float(p["noise"]) * n
        if p["outline"]:
            sv = _clamp(Node("sin", {"source": math.pi * _clamp(v)}))
            half = sv ** 0.8 * (1.0 - 0.25 * v)
            val = Node("select", {"a": 0.0, "b": val, "control": au - half},
                       {"lower": -1e30, "upper": 0.0})
        return _clamp(val), over
    # grass
    scale = p["scale"]

    def layer(fx, fy, k, offset, octaves=1):
        sx, sy = fx * scale, fy * scale * h / w
        if tileable:
            sx, sy = max(1.0, round(sx)), max(1.0, round(sy))
        return _gen("improved", scale=[float(sx), float(sy)], octaves=octaves,
                    seed=_plus(seed, k), offset=list(offset))

    a = layer(1.3, 1.3, 2, (0.0, 0.0, 0.37, 0.0))
    b = layer(5.1, 5.1, 1, (17.31, 41.73, 0.37, 0.0))
    blades = layer(40.0, 43.0 / p["blade_stretch"], 0, (3.1, 7.9, 0.61, 0.0), p["octaves"])
    v = 0.5 + 1.35 * (float(p["patches"]) * a + 0.18 * b + 0.1 * blades)
    return _clamp(v), over
