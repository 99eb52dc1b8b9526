"""The plant-surface textures as graphs: bark and leaf, in a surface's own ``(u, v)``.

One graph per texture is the single definition of the pattern: the renderer's shaders call
its GLSL (:func:`surface_glsl`, included by ``render/shaders/textures.glsl``), and the
exports bake it on the CPU with the fused kernel (:func:`bake_surface`, used by
:mod:`sylva.assets`), so the bark and leaf a view shows are the function the exported images
hold.  A graph's point ``q`` is ``(u, v, 0)``:

* **bark** — ``u`` runs around the stem (period 1) and ``v`` along it in circumferences of
  the stem's base radius (sylva's branch and tree meshers write both), so the grain follows
  the radius.  Stripes are improved Perlin noise stretched along ``v`` (24 cells around to 2
  along, two octaves), a rounder fBm (8 around, 4 along, three octaves) breaks them into
  cracks of finite length; every lattice repeats once per unit of ``u`` and ``v`` (the graph
  is tileable), so the bark joins around the stem and a baked image tiles along it.
  Channels: ``r`` the tone (multiplies the material's colour), ``g`` the specular map, ``b``
  the relief (for normal maps).
* **leaf** — ``u`` runs across the blade (main vein at ``u = 0.5``), ``v`` from base (0) to
  tip (1); no randomness.  Channels: ``r`` the darkening towards the edges, ``g`` the vein
  mask (the colour moves towards a brighter one there), ``b`` the specular map, ``a`` the
  relief.

Examples
--------
>>> import numpy as np
>>> img = bake_surface("bark", 16)
>>> img.shape, bool(np.isfinite(img).all())
((16, 16, 4), True)
>>> "vec4 sylva_bark_graph(vec3 q)" in surface_glsl()
True
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from ._nodes import Node

__all__ = ["SURFACES", "bark_graph", "bake_surface", "evaluate_uv", "leaf_graph",
           "surface_glsl"]

#: The image the lattices are planned for: every generator gives its cells per unit of
#: ``(u, v)`` explicitly, so the functions do not depend on it.
PLAN_SHAPE = (64, 64)


def _smoothstep(x, e0, e1):
    """GLSL's ``smoothstep(e0, e1, x)`` as nodes."""
    t = Node("scale-bias", {"source": x}, {"scale": 1.0 / (e1 - e0), "bias": -e0 / (e1 - e0)})
    return Node("smoothstep", {"source": t})


def bark_graph(seed: int = 0):
    """The bark of the plant surfaces (see the module), a tileable colour graph."""
    from . import Graph

    stripes = Node("improved", params={"scale": [24.0, 2.0], "octaves": 2, "persistence": 0.5,
                                       "normalize": False, "seed": seed})
    # the same seed (one permutation table in the shader), at other lattice points
    breakup = Node("improved", params={"scale": [8.0, 4.0], "octaves": 3, "persistence": 0.5,
                                       "seed": seed, "offset": [17.31, 41.73, 0.0, 0.0]})
    crack = (1.0 - _smoothstep(abs(stripes), 0.03, 0.17)) * _smoothstep(breakup, -0.35, 0.05)
    tone = 0.78 + 0.5 * stripes * (0.6 + 0.4 * breakup)
    out = Node("rgb", {"r": tone * (1.0 - 0.75 * crack), "g": 0.25 * (1.0 - crack),
                       "b": 0.35 * stripes - crack, "a": 1.0})
    return Graph(out, tileable=True, description="bark in stem coordinates: r tone, "
                                                 "g specular map, b relief")


def leaf_graph():
    """The leaf blade of the plant surfaces (see the module), a colour graph."""
    from . import Graph

    ax = abs(Node("x") - 0.5)
    main = 1.0 - _smoothstep(ax, 0.012, 0.035)
    phase = Node("y") * 7.0 - ax * 5.0  # side veins sweep towards the tip
    side = _smoothstep(Node("sin", {"source": phase * (2.0 * math.pi)}), 0.82, 0.98)
    side = side * (1.0 - _smoothstep(ax, 0.32, 0.48)) * _smoothstep(ax, 0.02, 0.06)
    edge = _smoothstep(ax, 0.18, 0.5)
    veins = Node("max", {"a": main, "b": 0.55 * side})
    out = Node("rgb", {"r": 1.0 - 0.4 * edge, "g": veins, "b": 0.6 * (1.0 - main),
                       "a": veins - 0.3 * edge})
    return Graph(out, description="leaf blade: r edge darkening, g vein mask, b specular "
                                   "map, a relief")


#: ``{texture name: (GLSL function name, graph factory)}``.
SURFACES = {"bark": ("sylva_bark_graph", bark_graph), "leaf": ("sylva_leaf_graph", leaf_graph)}


@cache
def _graph(kind):
    if kind not in SURFACES:
        from ._nodes import GraphError

        raise GraphError(f"no surface texture {kind!r}; expected one of: "
                         f"{', '.join(SURFACES)}")
    return SURFACES[kind][1]()


@cache
def surface_glsl() -> str:
    """GLSL 3.30 of every surface graph: ``vec4 sylva_bark_graph(vec3 q)`` and
    ``vec4 sylva_leaf_graph(vec3 q)`` of ``q = (u, v, 0)``."""
    from .glsl import compile_glsl_library

    return compile_glsl_library({name: _graph(kind) for kind, (name, _) in SURFACES.items()},
                                shape=PLAN_SHAPE)


def evaluate_uv(graph, u, v, *, dtype=np.float64) -> np.ndarray:
    """``graph`` at the points ``(u[k], v[k], 0)`` by the fused CPU kernel: ``(n,)`` for a
    scalar graph, ``(n, 4)`` for a colour one.  Lattices are planned for :data:`PLAN_SHAPE`,
    as in :func:`surface_glsl`: the values the shaders compute at those ``(u, v)``."""
    from ._compile import _Emit, _load, _run
    from ._nodes import COLOUR

    u = np.ascontiguousarray(np.ravel(u), dtype=np.float64)
    v = np.ascontiguousarray(np.ravel(v), dtype=np.float64)
    if u.shape != v.shape:
        raise ValueError(f"u and v differ in size: {u.size} and {v.size}")
    em = _Emit(graph, PLAN_SHAPE, np.dtype(dtype))
    res = em.emit(graph.output, ("X[i]", "Y[i]", "Z[i]"))  # every node samples the points
    colour = graph.output.spec.output == COLOUR
    kernel = _load(em.source([res], colour))
    n = u.size
    out = np.empty((1, 1, 1, n, 4) if colour else (1, 1, 1, n), dtype=dtype)
    if n:
        _run(kernel, 1, (out, u, v, np.zeros(n), np.array(em.P, np.float64), *em.args))
    return out.reshape((n, 4) if colour else (n,))


def bake_surface(kind: str, size: int, *, dtype=np.float64) -> np.ndarray:
    """The surface texture ``kind`` (``"bark"`` or ``"leaf"``) over the unit square of
    ``(u, v)`` at pixel centres: ``(size, size, 4)``, row ``j`` at ``v = (j + 0.5) / size``,
    column ``i`` at ``u = (i + 0.5) / size`` (as the GPU bake of ``render`` samples)."""
    c = (np.arange(size, dtype=np.float64) + 0.5) / size
    uu, vv = np.meshgrid(c, c)
    return evaluate_uv(_graph(kind), uu, vv, dtype=dtype).reshape(size, size, 4)
