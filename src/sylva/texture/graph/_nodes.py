"""The node set of the texture graph: one :class:`NodeSpec` per node type, and
:class:`Node`, the Python expression tree (operators build combiner nodes).

A node has a ``type`` (a key of :data:`NODE_TYPES`), named *inputs* (other nodes or numbers,
of type scalar or colour) and *parameters* (plain values: numbers, strings, lists).  Nodes
are immutable values; a graph is the output node plus the whole-graph properties
(:class:`~sylva.texture.graph.Graph`).
"""

from __future__ import annotations

import inspect
import numbers
from dataclasses import dataclass, field

from ...errors import SylvaError, _located
from .. import patterns

__all__ = ["NODE_TYPES", "GraphError", "Node", "NodeSpec"]

SCALAR, COLOUR = "scalar", "colour"


class GraphError(SylvaError, ValueError):
    """A bad texture graph or formula: ``file:line:column: what was expected``.

    Attributes ``filename``, ``line``, ``column`` (1-based, ``None`` when unknown) and
    ``message`` hold the parts.
    """

    def __init__(self, message, *, filename=None, line=None, column=None, source_line=None,
                 **_extra):
        self.message = message
        self.filename = filename or "<graph>"
        self.line = line
        self.column = column
        self.source_line = source_line
        super().__init__(_located(message, self.filename, line, column, source_line))


@dataclass(frozen=True)
class NodeSpec:
    """One node type.

    Attributes
    ----------
    name : str
    category : str
        generator, pattern, fractal, modifier, combiner, selector, transformer, colour,
        coordinate.
    inputs : tuple of (name, type, required)
        Input slots; type is ``"scalar"`` or ``"colour"``.
    params : dict
        Parameter names and defaults.
    output : str
        ``"scalar"`` or ``"colour"``.
    formula : str
        The definition, as the reference shows it.
    """

    name: str
    category: str
    inputs: tuple = ()
    params: dict = field(default_factory=dict)
    output: str = SCALAR
    formula: str = ""


NODE_TYPES: dict[str, NodeSpec] = {}


def _spec(name, category, inputs=(), params=None, output=SCALAR, formula=""):
    ins = []
    for i in inputs:  # "@name": a colour input, "name?": optional
        req = not i.endswith("?")
        i = i.rstrip("?")
        ins.append((i[1:], COLOUR, req) if i.startswith("@") else (i, SCALAR, req))
    ins = tuple(ins)
    NODE_TYPES[name] = NodeSpec(name, category, ins, dict(params or {}), output, formula)


_NOISE = {"scale": 4.0, "octaves": 1, "fractal": "fbm", "persistence": 0.5, "lacunarity": 2.0,
          "gain": 2.0, "seed": None, "interpolation": None, "offset": [0.0, 0.0, 0.0, 0.0],
          "normalize": True, "warp": 0.0}
_WORLEY = {"output": "f1", "metric": "euclidean", "jitter": 1.0, "density": None}
GENERATOR_KINDS = ("value", "perlin", "improved", "simplex", "worley")
for _k in GENERATOR_KINDS:
    _spec(_k, "generator", params={**_NOISE, **(_WORLEY if _k == "worley" else {})},
          formula=f"noise_grid(kind={_k!r}, ...): {_k} noise, fractal sum of octaves")
for _f in ("fbm", "turbulence", "ridged"):
    _spec(_f, "generator", params={**_NOISE, "kind": "improved", "octaves": 6, **_WORLEY},
          formula=f"noise_grid(fractal={_f!r}, ...)")
    NODE_TYPES[_f].params.pop("fractal")

PATTERN_TYPES = ("marble", "wood", "clouds", "granite", "bark", "leaf", "grass")
for _p in PATTERN_TYPES:
    _sig = inspect.signature(getattr(patterns, _p)).parameters
    _spec(_p, "pattern", params={k: v.default for k, v in _sig.items()
                                 if k not in ("shape", "dtype", "tileable", "time")},
          formula=f"sylva.texture.{_p}(shape, ...) (evaluated before the kernel, read by it)")
_spec("ifs", "pattern", params={"system": "fern", "points": 1_000_000, "gamma": 0.5,
                                "seed": None}, formula="sylva.texture.ifs(shape, ...)")
_spec("lsystem", "pattern", params={"example": None, "axiom": None, "rules": None,
                                    "iterations": None, "angle": None, "options": {}},
      output=COLOUR, formula="sylva.texture.lsystem_texture(...)")
_spec("worley-fn", "generator", params={**_NOISE, **_WORLEY, "output": "f4"},
      formula="noise_grid(kind='worley', output='fN') for any N")

_PLANE = {"center": [0.0, 0.0], "width": 3.0}
_spec("formula", "fractal", ("in1?", "in2?", "in3?"),
      params={**_PLANE, "source": None, "file": None, "params": {}},
      formula="escape-time formula, or a custom node of #pixel and the inputs #in1..#in3 "
              "(see the formula language)")
for _n, _c, _w in (("mandelbrot", [-0.5, 0.0], 3.0), ("julia", [0.0, 0.0], 3.2),
                   ("burning-ship", [-0.45, -0.5], 3.2), ("barnsley-j1", [0.0, 0.0], 4.0)):
    _spec(_n, "fractal", params={"center": _c, "width": _w, "params": {}},
          formula=f"the built-in formula {_n!r} (same image as sylva.texture.{_n})")

# modifiers: one scalar input
_spec("abs", "modifier", ("source",), formula="|a|")
_spec("clamp", "modifier", ("source",), {"lower": -1.0, "upper": 1.0},
      formula="min(max(a, lower), upper)")
_spec("curve", "modifier", ("source",), {"points": [[-1.0, -1.0], [0.0, 0.0], [1.0, 1.0],
                                                    [2.0, 2.0]]},
      formula="libnoise Curve: cubic interpolation through control points (>= 4)")
_spec("terrace", "modifier", ("source",), {"points": [-1.0, 0.0, 1.0], "invert": False},
      formula="libnoise Terrace: between terraces t0 < t1, t0 + (t1 - t0) s^2, "
              "s = (a - t0) / (t1 - t0) (inverted: 1 - (1 - s)^2, swapped)")
_spec("invert", "modifier", ("source",), formula="-a")
_spec("scale-bias", "modifier", ("source",), {"scale": 1.0, "bias": 0.0},
      formula="a * scale + bias")
_spec("exponent", "modifier", ("source",), {"exponent": 1.0},
      formula="libnoise Exponent: |(a + 1) / 2|^e * 2 - 1")
_spec("sin", "modifier", ("source",), formula="sin(a)")
_spec("cos", "modifier", ("source",), formula="cos(a)")
_spec("fract", "modifier", ("source",), formula="a - floor(a)")
_spec("smoothstep", "modifier", ("source",), formula="s^2 (3 - 2 s), s = clamp(a, 0, 1)")

# combiners
_spec("add", "combiner", ("a", "b"), formula="a + b")
_spec("sub", "combiner", ("a", "b"), formula="a - b")
_spec("multiply", "combiner", ("a", "b"), formula="a * b")
_spec("divide", "combiner", ("a", "b"), formula="a / b")
_spec("min", "combiner", ("a", "b"), formula="min(a, b)")
_spec("max", "combiner", ("a", "b"), formula="max(a, b)")
_spec("power", "combiner", ("a", "b"), formula="a ** b")
_spec("blend", "combiner", ("a", "b", "t"), formula="a + t (b - a)")
_spec("select", "selector", ("a", "b", "control"),
      {"lower": -1.0, "upper": 1.0, "falloff": 0.0},
      formula="libnoise Select: b where lower <= control <= upper, else a; an s-curve "
              "blend of width falloff at both edges")

# transformers: evaluate the source subgraph at moved coordinates (image units: x = i / W)
_spec("translate", "transformer", ("source",), {"by": [0.0, 0.0, 0.0]},
      formula="source(p - by)")
_spec("rotate", "transformer", ("source",), {"angle": 0.0, "center": [0.5, 0.5]},
      formula="source(R(-angle) (p - center) + center), angle in degrees about z")
_spec("scale", "transformer", ("source",), {"by": [1.0, 1.0, 1.0], "center": [0.0, 0.0, 0.0]},
      formula="source((p - center) / by + center)")
_spec("warp", "transformer", ("source", "dx", "dy", "dz?"), {"amount": 1.0},
      formula="source(p + amount (dx(p), dy(p), dz(p)))")

# coordinates (image units: x = i / W, y = j / W, z = k / W) and constants
for _a in ("x", "y", "z"):
    _spec(_a, "coordinate", params={"closed": False},
          formula=f"the sample's {_a} in image units (pixel index / width); closed: "
                  "index / (n - 1), 0 to 1 inclusive along the axis (numpy.linspace)")
_spec("constant", "coordinate", params={"value": 0.0}, formula="value")

# colour
_spec("gradient", "colour", ("source",), {"colors": "gray", "vmin": 0.0, "vmax": 1.0},
      output=COLOUR, formula="colormap((a - vmin) / (vmax - vmin)) (piecewise linear, "
                             "clipped); colors: a map name or a list of colours / stops")
_spec("palette", "colour", ("source",), {"file": None, "colors": None, "vmin": 0.0,
                                         "vmax": 1.0}, output=COLOUR,
      formula="gradient from a palette file (.gpl, .txt, .toml) or a --colors string")
_spec("rgb", "colour", ("r", "g", "b", "a?"), output=COLOUR, formula="(r, g, b, a)")
_spec("color", "colour", params={"value": "#000000", "alpha": 1.0}, output=COLOUR,
      formula="a constant colour")
_spec("layer", "colour", ("@base", "@top", "opacity?"), {"mode": "normal", "opacity": 1.0},
      output=COLOUR, formula="base + opacity * top.alpha * (f(base, top) - base) per channel")
_spec("luminance", "colour", ("@source",), formula="0.2126 r + 0.7152 g + 0.0722 b")

BLEND_MODES = ("normal", "multiply", "screen", "overlay", "difference", "add", "subtract",
               "darken", "lighten", "hard-light", "soft-light")
"""Mystica's layer blend modes, per channel on a = base, b = top in [0, 1]: normal b,
multiply ab, screen 1-(1-a)(1-b), overlay (a<.5: 2ab, else 1-2(1-a)(1-b)), difference |a-b|,
add min(a+b, 1), subtract max(a-b, 0), darken min, lighten max, hard-light (overlay with a, b
swapped), soft-light (1-2b)a^2 + 2ba."""


def _is_num(v):
    return isinstance(v, numbers.Real) and not isinstance(v, bool)


class Node:
    """A node of a texture graph (see :data:`NODE_TYPES`).

    Build nodes with the functions of :mod:`sylva.texture.graph` (``improved(scale=4)``,
    ``clamp(a, 0, 1)`` …) or ``Node(type, inputs, params)``.  Arithmetic operators build
    combiners: ``a + b``, ``a - b``, ``a * b``, ``a / b``, ``a ** b``, ``-a``, ``abs(a)``;
    numbers stand for constants.

    Examples
    --------
    >>> n = Node("improved", params={"scale": 8.0})
    >>> (abs(n) * 0.5 + 0.25).type
    'add'
    """

    __slots__ = ("inputs", "params", "type", "where")

    def __init__(self, type, inputs=None, params=None, where=None):
        if type not in NODE_TYPES:
            raise GraphError(f"unknown node type {type!r}; expected one of: "
                             f"{', '.join(sorted(NODE_TYPES))}", **(where or {}).get("type", {}))
        spec = NODE_TYPES[type]
        self.type = type
        self.where = where or {}
        ins = dict(inputs or {})
        for k, v in ins.items():
            if not (isinstance(v, Node) or _is_num(v)):
                raise GraphError(f"input {k!r} of a {type} node must be a node or a number, "
                                 f"got {v!r}", **self.where.get(k, {}))
        names = {n for n, _, _ in spec.inputs}
        for k in ins:
            if k not in names:
                raise GraphError(f"a {type} node has no input {k!r}; its inputs: "
                                 f"{', '.join(sorted(names)) or 'none'}", **self.where.get(k, {}))
        self.inputs = ins
        ps = dict(params or {})
        for k in ps:
            if k not in spec.params:
                raise GraphError(f"a {type} node has no parameter {k!r}; expected one of: "
                                 f"{', '.join(sorted(spec.params)) or 'none'}",
                                 **self.where.get(k, {}))
        for k, v in ps.items():
            d = spec.params[k]
            if isinstance(d, bool) and not isinstance(v, bool):
                raise GraphError(f"parameter {k!r} of a {type} node must be true or false, got "
                                 f"{v!r}", **self.where.get(k, {}))
            seq = isinstance(v, list | tuple) and v and all(_is_num(x) for x in v)
            if _is_num(d) and not (_is_num(v) or seq):  # (a noise scale may be per axis)
                raise GraphError(f"parameter {k!r} of a {type} node must be a number, got "
                                 f"{v!r}", **self.where.get(k, {}))
        self.params = ps

    # ---- parameters with their defaults
    def param(self, key):
        """The parameter ``key`` (its default when not given)."""
        return self.params.get(key, NODE_TYPES[self.type].params[key])

    @property
    def spec(self) -> NodeSpec:
        return NODE_TYPES[self.type]

    def __repr__(self):
        parts = [f"{k}={v!r}" for k, v in self.inputs.items()]
        parts += [f"{k}={v!r}" for k, v in self.params.items()]
        return f"{self.type}({', '.join(parts)})"

    # ---- operators
    def _bin(self, op, other, swap=False):
        a, b = (other, self) if swap else (self, other)
        return Node(op, {"a": a, "b": b})

    def __add__(self, o):
        return self._bin("add", o)

    def __radd__(self, o):
        return self._bin("add", o, True)

    def __sub__(self, o):
        return self._bin("sub", o)

    def __rsub__(self, o):
        return self._bin("sub", o, True)

    def __mul__(self, o):
        return self._bin("multiply", o)

    def __rmul__(self, o):
        return self._bin("multiply", o, True)

    def __truediv__(self, o):
        return self._bin("divide", o)

    def __rtruediv__(self, o):
        return self._bin("divide", o, True)

    def __pow__(self, o):
        return self._bin("power", o)

    def __rpow__(self, o):
        return self._bin("power", o, True)

    def __neg__(self):
        return Node("invert", {"source": self})

    def __abs__(self):
        return Node("abs", {"source": self})


def walk(node):
    """The nodes reachable from ``node``, each once, inputs before the nodes using them."""
    seen, order = set(), []

    def visit(n):
        if id(n) in seen:
            return
        seen.add(id(n))
        for v in n.inputs.values():
            if isinstance(v, Node):
                visit(v)
        order.append(n)

    visit(node)
    return order
