"""Texture graphs: generators, modifiers, combiners, selectors, transformers and colour nodes,
composed as data (TOML/JSON) or as Python expressions, evaluated by one fused numba kernel
per graph and compiled to GLSL.

A graph is its output :class:`Node` plus whole-graph properties: ``tileable`` (every
generator wraps seamlessly), ``time`` (an extra noise coordinate: 2D images become slices of
3D noise, volumes of 4D, for animation), the default ``size`` and the colouring of a scalar
output (``colormap``, ``vmin``, ``vmax``; fractal ``colorize`` with ``cycles``, ``inside``,
``log``; ``normal_map``).  See :data:`NODE_TYPES` for the node set and
``docs/reference/texture-graph.rst`` for the file format and the formula language.

Examples
--------
>>> from sylva.texture import graph as tg
>>> g = tg.Graph(tg.clamp(tg.fbm(scale=4.0, octaves=4, seed=1) * 2.0, lower=-1, upper=1))
>>> g.evaluate((16, 32)).shape
(16, 32)
>>> tg.loads(g.dumps()).evaluate((16, 32)).tolist() == g.evaluate((16, 32)).tolist()
True
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..._atomic import atomic_write
from .. import colormap as _cm
from .. import fractals as _fr
from ._compile import evaluate as _evaluate
from ._io import dumps as _dumps
from ._io import load, loads
from ._io import to_dict as _to_dict
from ._nodes import (
    BLEND_MODES,
    COLOUR,
    GENERATOR_KINDS,
    NODE_TYPES,
    PATTERN_TYPES,
    SCALAR,
    GraphError,
    Node,
    NodeSpec,
    _is_num,
    walk,
)

__all__ = ["BLEND_MODES", "NODE_TYPES", "Graph", "GraphError", "Node", "NodeSpec",
           "from_recipe", "load", "loads", "node"]

GraphError.__module__ = __name__  # shown as sylva.texture.graph.GraphError
Node.__module__ = __name__

_PROPS = {"tileable": False, "time": None, "size": None, "colormap": None, "vmin": None,
          "vmax": None, "colorize": False, "cycles": None, "inside": "#000000", "log": False,
          "normal_map": None, "description": None}


class Graph:
    """A texture graph: the output node and the whole-graph properties.

    Parameters
    ----------
    output : Node
    tileable : bool
        Seamless tiling of every generator (lattice periods; simplex on a 4D torus).
        Tiling holds for generators that are not under a rotate or scale node.
    time : float, optional
        The animation coordinate, in base-octave lattice cells (see :func:`noise_grid`).
    size : (W, H), optional
        The default image size (512 x 512).
    colormap, vmin, vmax, colorize, cycles, inside, log, normal_map, description :
        How :meth:`image` colours a scalar output (as the texture presets do).
    """

    def __init__(self, output, **props):
        if not isinstance(output, Node):
            raise GraphError(f"a graph's output must be a Node, got {output!r}")
        unknown = set(props) - set(_PROPS) - {"names"}
        if unknown:
            raise GraphError(f"unknown graph propert(ies) {', '.join(sorted(unknown))}; "
                             f"expected: {', '.join(_PROPS)}")
        self.output = output
        self.names = props.pop("names", {}) or {}
        self._where = {}
        for k, v in _PROPS.items():
            setattr(self, k, props.get(k, v))
        self._check_props()
        _check(output)

    @classmethod
    def _from_props(cls, output, props, names, where, gpos):
        unknown = set(props) - set(_PROPS)
        if unknown:
            k = sorted(unknown)[0]
            raise GraphError(f"unknown [graph] key {k!r}; expected one of: output, "
                             f"{', '.join(_PROPS)}", **where.get(k, gpos))
        try:
            return cls(output, names=names, **props)
        except GraphError as exc:
            k = getattr(exc, "prop", None)
            if k and exc.line is None:
                raise GraphError(exc.message, **where.get(k, gpos)) from None
            raise

    def _check_props(self):
        def bad(k, msg):
            e = GraphError(f"graph {k}: {msg}")
            e.prop = k
            return e

        if not isinstance(self.tileable, bool):
            raise bad("tileable", f"must be true or false, got {self.tileable!r}")
        if self.time is not None and not _is_num(self.time):
            raise bad("time", f"must be a number, got {self.time!r}")
        if self.size is not None:
            from ..presets import PresetError, parse_size

            try:
                self.size = list(parse_size(self.size))
            except PresetError as exc:
                raise bad("size", str(exc)) from None
        for k in ("vmin", "vmax", "cycles", "normal_map"):
            v = getattr(self, k)
            if v is not None and not _is_num(v):
                raise bad(k, f"must be a number, got {v!r}")

    def _props(self):
        return {k: getattr(self, k) for k, d in _PROPS.items() if getattr(self, k) != d}

    # ---- evaluation
    def _shape(self, shape):
        if shape is None:
            w, h = self.size or (512, 512)
            return (h, w)
        return tuple(int(s) for s in shape)

    def evaluate(self, shape=None, *, dtype=None):
        """The graph on a grid: float array of ``shape`` ((H, W) or (D, H, W); default from
        ``size``); a colour graph adds a trailing axis of 4 (RGBA in [0, 1])."""
        dt = np.dtype(np.float32 if dtype is None else dtype)
        if dt not in (np.float32, np.float64):
            raise GraphError(f"dtype must be float32 or float64, got {dt}")
        return _evaluate(self, self._shape(shape), dt)

    def image(self, shape=None) -> np.ndarray:
        """An RGB uint8 image: a colour output as it is, a scalar output coloured by the
        graph's ``colormap`` (and ``vmin``/``vmax``, ``colorize``, ``normal_map``)."""
        v = self.evaluate(shape, dtype=np.float64)
        if self.output.spec.output == COLOUR:
            return _cm.to_uint8(v[..., :3])
        if v.ndim != 2:
            raise GraphError("image() needs a 2D graph output; use evaluate() for volumes")
        cmap = self.colormap or ("fractal" if self.colorize else "gray")
        try:
            if self.colorize:
                return _fr.colorize(v, cmap, cycles=self.cycles, inside=self.inside,
                                    log=bool(self.log))
            if self.normal_map:
                h = _cm.normalize(v, self.vmin, self.vmax)
                return _cm.normal_map(h, strength=float(self.normal_map),
                                      tileable=self.tileable)
            return _cm.apply_colormap(v, cmap, vmin=self.vmin, vmax=self.vmax)
        except (_cm.ColormapError, TypeError, ValueError) as exc:
            raise GraphError(f"graph colormap: {exc}") from None

    # ---- files
    def to_dict(self) -> dict:
        """The graph as plain data (what the TOML and JSON files hold)."""
        return _to_dict(self)

    def dumps(self, fmt="toml") -> str:
        """The graph as TOML (default) or JSON text."""
        return _dumps(self, fmt)

    def save(self, path) -> Path:
        """Write the graph to ``path`` (``.json``: JSON, else TOML); returns the path."""
        path = Path(path)
        text = self.dumps("json" if path.suffix.lower() == ".json" else "toml")
        with atomic_write(path, "w") as fh:
            fh.write(text)
        return path

    def glsl(self, name="sylva_texture"):
        """The graph as GLSL source (see :func:`sylva.texture.graph.glsl.compile_glsl`)."""
        from .glsl import compile_glsl

        return compile_glsl(self, name=name)

    def __repr__(self):
        return f"Graph({self.output!r})"


def _check(output):
    """Every required input given, every connection of the right type."""
    for n in walk(output):
        for name, typ, req in n.spec.inputs:
            v = n.inputs.get(name)
            w = n.where.get(name) or n.where.get("type") or {}
            if v is None:
                if req:
                    raise GraphError(f"a {n.type} node needs its input {name!r} (a {typ}: "
                                     f"{'a node' if typ == COLOUR else 'a node or a number'})",
                                     **(n.where.get("_node") or n.where.get("type") or {}))
                continue
            got = v.spec.output if isinstance(v, Node) else SCALAR
            if got != typ:
                raise GraphError(f"input {name!r} of a {n.type} node takes a {typ}, but gets a "
                                 f"{got} ({v.type if isinstance(v, Node) else v!r})", **w)


# ----------------------------------------------------------------------------- constructors
class _NodeFactory:
    """``node.TYPE(*inputs, **params_and_inputs)``: positional arguments fill the input
    slots in order; keywords name inputs or parameters (``-`` in a type is ``_``)."""

    def __getattr__(self, attr):
        typ = attr.replace("_", "-").rstrip("-")
        if typ not in NODE_TYPES:
            raise AttributeError(attr)
        return _maker(typ)

    def __dir__(self):
        return [t.replace("-", "_") for t in NODE_TYPES]


def _maker(typ):
    spec = NODE_TYPES[typ]
    slots = [n for n, _, _ in spec.inputs]

    def make(*args, **kw):
        if len(args) > len(slots):
            raise GraphError(f"{typ} takes at most {len(slots)} inputs, got {len(args)}")
        inputs = dict(zip(slots, args))
        params = {}
        for k, v in kw.items():
            if k in slots and k not in spec.params:
                inputs[k] = v
            else:
                params[k] = v
        return Node(typ, inputs, params)

    make.__name__ = typ.replace("-", "_")
    formula = spec.formula.replace("|", "\\|").replace("*", "\\*")
    make.__doc__ = f"A ``{typ}`` node ({spec.category}): {formula}."
    return make


node = _NodeFactory()
"""Node constructors by type: ``node.improved(scale=8)``, ``node.clamp(a, lower=0)``."""

for _t in NODE_TYPES:
    _n = _t.replace("-", "_")
    if _n in ("min", "max", "abs", "pow"):
        _n += "_"
    globals()[_n] = _maker(_t)
    __all__.append(_n)


# ----------------------------------------------------------------------------- presets
def from_recipe(recipe) -> Graph:
    """The graph of a texture recipe or preset name (:mod:`sylva.texture.presets`): one
    generator, pattern or fractal node and the preset's colouring.  ``graph.image()``
    equals ``presets.render(recipe)``.

    Examples
    --------
    >>> from sylva.texture.presets import render
    >>> g = from_recipe({"kind": "improved", "size": [24, 16], "seed": 2})
    >>> bool((g.image() == render({"kind": "improved", "size": [24, 16], "seed": 2})).all())
    True
    """
    from .. import presets as P

    r = P.resolve(recipe)
    kind = r["kind"]
    props = {"size": r["size"], "tileable": bool(r.get("tileable", False))}
    if r.get("description"):
        props["description"] = r["description"]
    if kind in GENERATOR_KINDS:
        kw = P._pick(r, P._NOISE_KEYS)
        kw.setdefault("octaves", 6 if kind != "worley" else 1)
        if "seed" in r:
            kw["seed"] = r["seed"]
        out = Node(kind, params=kw)
        rng = P._noise_range(kind, kw, 2)
    elif kind in PATTERN_TYPES or kind == "ifs":
        kw = P._pick(r, P._KEYS[kind])
        if "seed" in r:
            kw["seed"] = r["seed"]
        out = Node(kind, params=kw)
        rng = (0.0, 1.0)
    elif kind in ("mandelbrot", "julia", "burning-ship", "barnsley-j1"):
        kw = P._pick(r, ("center", "width"))
        prm = P._pick(r, ("maxiter", "bailout"))
        if kind == "julia" and "c" in r:
            prm["c"] = list(r["c"])
        if kind == "barnsley-j1":
            prm.pop("bailout", None)
            if "start" in r:
                prm["start"] = list(r["start"])
            if "uf_bailout" in r:
                prm["bailout"] = r["uf_bailout"]
            prm["zz"] = 1 if r.get("variant", "z") == "zz" else 0
        if prm:
            kw["params"] = prm
        out = Node(kind, params=kw)
        props.update(colorize=True, colormap=r["colormap"], inside=r.get("inside", "#000000"),
                     log=bool(r.get("log", False)))
        if r.get("cycles") is not None:
            props["cycles"] = r["cycles"]
        return Graph(out, **props)
    else:  # lsystem
        opts = {k: v for k, v in r.items() if k not in ("kind", "size", "description",
                                                         "tileable")}
        if r.get("tileable"):
            opts["tileable"] = True
        return Graph(Node("lsystem", params={"options": opts}), **props)
    props["colormap"] = r["colormap"]
    props["vmin"] = r.get("vmin", rng[0])
    props["vmax"] = r.get("vmax", rng[1])
    if r.get("normal_map"):
        props["normal_map"] = r["normal_map"]
    return Graph(out, **props)
