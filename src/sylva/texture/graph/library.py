"""Patterns written as graphs of primitive nodes (fused, GLSL-ready), beside the pattern
nodes that call :mod:`sylva.texture.patterns` directly.

Examples
--------
>>> g = marble_graph(seed=11, stripes=3.0, turbulence=2.5, scale=3.0)
>>> g.evaluate((8, 8)).shape
(8, 8)
"""

from __future__ import annotations

import math

from ._nodes import Node

__all__ = ["marble_graph"]


def marble_graph(*, scale=4.0, stripes=4.0, turbulence=2.0, octaves=6, persistence=0.5,
                 lacunarity=2.0, seed=None, tileable=False, time=None, colormap="marble"):
    """:func:`sylva.texture.marble` as a graph:
    ``clamp(0.5 + 0.5 sin(2 pi (stripes x + turbulence T)), 0, 1)`` with ``T`` improved
    Perlin turbulence; the same values as the pattern function up to the last bit of
    ``sin`` (numba's and NumPy's).
    """
    from . import Graph

    t = Node("turbulence", params={"kind": "improved", "scale": scale, "octaves": octaves,
                                   "persistence": persistence, "lacunarity": lacunarity,
                                   "seed": seed})
    k = float(round(stripes) if tileable else stripes)
    x = Node("x", params={"closed": not tileable})
    phase = x * k + t * float(turbulence)
    s = Node("sin", {"source": phase * (2.0 * math.pi)})
    out = Node("clamp", {"source": 0.5 + 0.5 * s}, {"lower": 0.0, "upper": 1.0})
    return Graph(out, tileable=tileable, time=time, colormap=colormap, vmin=0.0, vmax=1.0)
