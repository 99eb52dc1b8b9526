"""Texture recipes: one flat parameter set renders one image; presets save and reload them.

A recipe is a mapping with a ``kind`` (see :data:`TEXTURE_KINDS`) and that kind's
parameters; :func:`render` turns it into an RGB image and :func:`render_frames` into an
animation.  Recipes are stored as TOML (:func:`save_preset` / :func:`load_preset`): flat
``key = value`` lines, plus ``[rules]`` for L-systems — the "project file" the reviewed
tools offered (seed 003 §7: NF, LSE, UFR, MYS).  :data:`PRESETS` holds named recipes.

Common keys: ``kind``, ``size`` (``[W, H]`` or ``"WxH"``), ``seed``, ``colormap``,
``tileable`` (``colormap`` is a name or a custom map: a list of colours, or of
``[position, colour]`` pairs, as ``sylva texture --colors`` stores it); noise keys
``scale``, ``octaves``, ``persistence``, ``lacunarity``,
``fractal``, ``interpolation``, ``warp``, ``output``/``metric``/``jitter``/``density`` (Worley;
``density`` gives Worley's Poisson point process, see :func:`.noise.worley`),
``vmin``/``vmax`` (the value range mapped onto the colour map); ``normal_map`` (a bump
strength: output a normal map of the height field instead of colours); ``speed`` (time
per frame).  Unknown keys are an error, so a typo does not pass silently.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from .._atomic import atomic_write
from ..errors import SylvaError
from . import fractals, noise, patterns
from .colormap import ColormapError, apply_colormap, gradient, normal_map, normalize
from .lsystem_texture import LSYSTEM_EXAMPLES, lsystem_texture

__all__ = [
    "PRESETS",
    "TEXTURE_KINDS",
    "PresetError",
    "dumps_toml",
    "load_preset",
    "parse_size",
    "render",
    "render_frames",
    "resolve",
    "save_preset",
]


class PresetError(SylvaError, ValueError):
    """A bad recipe: unknown kind or key, wrong value type, unreadable preset file."""


_NOISE = ("value", "perlin", "improved", "simplex", "worley")
_PATTERNS = ("marble", "wood", "clouds", "granite", "bark", "leaf", "grass")
_ESCAPE = ("mandelbrot", "julia", "burning-ship", "barnsley-j1")

TEXTURE_KINDS: dict[str, str] = {
    "value": "value noise (linear/cosine/cubic/quintic interpolation)",
    "perlin": "classic Perlin gradient noise (1985)",
    "improved": "improved Perlin noise (2002)",
    "simplex": "simplex noise (Gustavson 2012)",
    "worley": "Worley cellular noise (F1, F2, F3 and combinations, cell ids)",
    "marble": "marble veins: sine of stripes plus turbulence",
    "wood": "wood rings with turbulence and grain",
    "clouds": "clouds: simplex fBm with coverage",
    "granite": "granite: Worley crystals, borders and speckle",
    "bark": "bark with longitudinal cracks (seed 000)",
    "leaf": "leaf blade with midrib and sine veins (seed 000)",
    "grass": "grass from two shifted Perlin noises (seed 000)",
    "mandelbrot": "Mandelbrot set, smooth escape-time colouring",
    "julia": "Julia set of z^2 + c",
    "burning-ship": "Burning Ship fractal",
    "barnsley-j1": "Ultra Fractal's barnsleyj1 formula (seed 003 §5.5)",
    "ifs": "iterated function system by the chaos game (fern, sierpinski)",
    "lsystem": "2D L-system drawn with a turtle (tileable)",
}

_COMMON = {"kind", "size", "seed", "colormap", "tileable", "normal_map", "speed", "vmin",
           "vmax", "frames", "fps", "description"}
_NOISE_KEYS = {"scale", "octaves", "persistence", "lacunarity", "fractal", "interpolation",
               "warp", "output", "metric", "jitter", "density", "gain"}
_KEYS = {
    **{k: _NOISE_KEYS for k in _NOISE},
    "marble": {"scale", "stripes", "turbulence", "octaves", "persistence", "lacunarity"},
    "wood": {"scale", "rings", "turbulence", "center", "grain", "octaves", "persistence",
             "lacunarity"},
    "clouds": {"scale", "coverage", "sharpness", "octaves", "persistence", "lacunarity"},
    "granite": {"scale", "octaves"},
    "bark": {"scale", "stretch", "cracks", "detail", "octaves", "persistence", "lacunarity"},
    "leaf": {"veins", "vein_angle", "vein_width", "midrib", "darkening", "outline", "noise"},
    "grass": {"scale", "blade_stretch", "patches", "octaves"},
    "mandelbrot": {"center", "width", "maxiter", "bailout", "cycles", "log", "inside", "zoom"},
    "julia": {"c", "center", "width", "maxiter", "bailout", "cycles", "log", "inside"},
    "burning-ship": {"center", "width", "maxiter", "bailout", "cycles", "log", "inside",
                     "zoom"},
    "barnsley-j1": {"start", "center", "width", "maxiter", "uf_bailout", "variant", "cycles",
                    "log", "inside"},
    "ifs": {"system", "points", "gamma"},
    "lsystem": {"example", "axiom", "rules", "iterations", "angle", "start_angle", "draw",
                "move", "width", "width_factor", "width_increment", "color_start",
                "color_increment", "palette", "background", "count", "size_fraction",
                "random_step", "step_scale", "angle_scale", "dot", "dot_size", "dot_color"},
}

_DEFAULT_CMAP = {"value": "gray", "perlin": "gray", "improved": "gray", "simplex": "gray",
                 "worley": "gray", "marble": "marble", "wood": "wood", "clouds": "clouds",
                 "granite": "granite", "bark": "bark", "leaf": "leaf", "grass": "grass",
                 "mandelbrot": "fractal", "julia": "fractal", "burning-ship": "fire",
                 "barnsley-j1": "fractal", "ifs": "leaf"}

PRESETS: dict[str, dict] = {
    "sky-clouds": {"kind": "clouds", "scale": 3.0, "octaves": 8, "coverage": 0.65, "seed": 3,
                   "tileable": True, "description": "tileable sky with clouds"},
    "runicsoft-clouds": {"kind": "value", "interpolation": "cosine", "persistence": 0.5,
                         "octaves": 6, "scale": 10.0, "size": [512, 512],
                         "description": "Perlin Noise Generator's test (seed 003 §5.1): "
                                        "value noise, cosine, persistence 0.5, frequency 10"},
    "arabescato-marble": {"kind": "marble", "stripes": 3.0, "turbulence": 2.5, "scale": 3.0,
                          "seed": 11, "description": "white marble with grey veins"},
    "beech-wood": {"kind": "wood", "rings": 14.0, "turbulence": 0.12, "center": [0.5, -0.6],
                   "grain": 0.25, "seed": 5, "description": "straight-grained beech"},
    "pink-granite": {"kind": "granite", "scale": 28.0, "seed": 8, "tileable": True},
    "oak-bark": {"kind": "bark", "scale": 8.0, "stretch": 0.04, "seed": 2, "tileable": True},
    "leaf-blade": {"kind": "leaf", "size": [256, 512]},
    "lawn": {"kind": "grass", "scale": 6.0, "seed": 4, "tileable": True},
    "cells": {"kind": "worley", "output": "f1", "scale": 12.0, "colormap": "ocean",
              "seed": 1, "tileable": True},
    "cracks": {"kind": "worley", "output": "f2-f1", "scale": 10.0, "vmax": 0.5,
               "colormap": "gray", "seed": 1, "tileable": True},
    "mosaic": {"kind": "worley", "output": "cell", "scale": 14.0, "colormap": "spectral",
               "seed": 9, "tileable": True},
    "worley-a": {"kind": "worley", "output": "f2-f1", "scale": 16.0, "size": [640, 480],
                 "colormap": "fire", "description": "Worley Texture Generator texture A "
                 "(seed 003 Table 2: D2 - D1, 640x480, ~200 points)"},
    "worley-b": {"kind": "worley", "output": "f1*f2", "scale": 11.5, "size": [640, 480],
                 "colormap": "sand", "description": "texture B (D1 * D2, ~100 points)"},
    "ridged-terrain": {"kind": "simplex", "fractal": "ridged", "octaves": 8, "scale": 3.0,
                       "colormap": "terrain", "seed": 21},
    "warped-marble": {"kind": "improved", "octaves": 5, "warp": 1.5, "scale": 3.0,
                      "colormap": "marble", "seed": 6},
    "seahorse-valley": {"kind": "mandelbrot", "center": [-0.745, 0.105], "width": 0.03,
                        "maxiter": 800, "cycles": 6.0, "log": True},
    "julia-dendrite": {"kind": "julia", "c": [0.0, 1.0], "maxiter": 300, "cycles": 3.0},
    "julia-spiral": {"kind": "julia", "c": [-0.8, 0.156], "maxiter": 400, "cycles": 4.0},
    "burning-ship-armada": {"kind": "burning-ship", "center": [-1.762, -0.028], "width": 0.08,
                            "maxiter": 500},
    "ultra-barnsley": {"kind": "barnsley-j1", "start": [0.6, 1.1], "maxiter": 149,
                       "description": "seed 003 §5.5, Ultra Fractal barnsleyj1 defaults"},
    "ultra-barnsley-zz": {"kind": "barnsley-j1", "start": [1.6, 1.1], "variant": "zz",
                          "description": "seed 003 fig. 51: (z - 1) * z * @start"},
    "fern": {"kind": "ifs", "system": "fern", "points": 2000000, "colormap": "leaf"},
    "sierpinski": {"kind": "ifs", "system": "sierpinski", "points": 1000000,
                   "colormap": "gray"},
    **{name: {"kind": "lsystem", "example": name} for name in LSYSTEM_EXAMPLES},
    "bush-tile": {"kind": "lsystem", "example": "bush", "tileable": True, "count": 4,
                  "size_fraction": 0.6, "width": 3.0, "width_factor": 0.7, "seed": 1},
}
"""Named recipes (``sylva texture --list`` shows them)."""


def parse_size(size) -> tuple[int, int]:
    """``"1024x768"``, ``[1024, 768]`` or ``1024`` to ``(width, height)``.

    Examples
    --------
    >>> parse_size("640x480")
    (640, 480)
    """
    try:
        if isinstance(size, str):
            parts = size.lower().replace("*", "x").split("x")
            w, h = (int(parts[0]), int(parts[1])) if len(parts) == 2 else (int(parts[0]),) * 2
        elif isinstance(size, int | np.integer):
            w = h = int(size)
        else:
            w, h = (int(v) for v in size)
    except (ValueError, TypeError):
        raise PresetError(f"size must look like 1024x768, got {size!r}") from None
    if not (1 <= w <= 32768 and 1 <= h <= 32768):
        raise PresetError(f"size must be between 1 and 32768 pixels per side, got {w}x{h}")
    return w, h


def resolve(recipe: Mapping | str) -> dict:
    """A recipe (or a preset name) checked and completed with its defaults."""
    if isinstance(recipe, str):
        if recipe in PRESETS:
            recipe = PRESETS[recipe]
        elif recipe in TEXTURE_KINDS:
            recipe = {"kind": recipe}
        else:
            raise PresetError(
                f"unknown texture kind or preset {recipe!r}; see `sylva texture --list`"
            )
    r = dict(recipe)
    kind = r.get("kind")
    if kind not in TEXTURE_KINDS:
        raise PresetError(f"unknown texture kind {kind!r}; expected one of: "
                          f"{', '.join(TEXTURE_KINDS)}")
    if kind == "lsystem" and "example" in r:
        ex = r["example"]
        if ex not in LSYSTEM_EXAMPLES:
            raise PresetError(f"unknown L-system example {ex!r}; expected one of: "
                              f"{', '.join(LSYSTEM_EXAMPLES)}")
        base = {k: v for k, v in LSYSTEM_EXAMPLES[ex].items() if k != "source"}
        r = {**base, **r}
    unknown = set(r) - _COMMON - _KEYS[kind]
    if unknown:
        raise PresetError(f"unknown parameter(s) for {kind}: {', '.join(sorted(unknown))}; "
                          f"allowed: {', '.join(sorted(_COMMON | _KEYS[kind]))}")
    r.setdefault("size", [512, 512])
    r["size"] = list(parse_size(r["size"]))
    if kind in _DEFAULT_CMAP:
        r.setdefault("colormap", _DEFAULT_CMAP[kind])
        cm = r["colormap"]
        if isinstance(cm, list | tuple):  # a custom map: colours or [position, colour] pairs
            try:
                cmap = gradient(cm)
            except (ColormapError, TypeError, ValueError) as exc:
                raise PresetError(f"colormap: {exc}") from None
            r["colormap"] = [[float(p), _hex(c)] for p, c in zip(cmap.positions, cmap.colors)]
        elif not isinstance(cm, str):
            raise PresetError(f"colormap must be a name or a list of colours, got {cm!r}")
    elif "colormap" in r:
        raise PresetError(f"{kind} textures take no colour map (colormap)")
    if kind == "lsystem":
        for key in ("axiom", "rules", "iterations", "angle"):
            if key not in r:
                raise PresetError(f"an lsystem recipe needs {key!r} (or an 'example')")
        if not isinstance(r["rules"], Mapping):
            raise PresetError("lsystem 'rules' must be a table of symbol = successor")
        try:
            r["rules"] = {str(k): v if isinstance(v, str) else [[float(p), str(w)] for p, w in v]
                          for k, v in r["rules"].items()}
        except (TypeError, ValueError):
            raise PresetError("a stochastic rule is a list of [probability, successor] "
                              "pairs") from None
    return r


# Worley outputs whose colour map spans their expected range (noise.worley_range), not [0, 1]
_SPREAD = ("f2", "f3", "f1+f2")


def _hex(rgb) -> str:
    return "#" + "".join(f"{round(float(v) * 255):02x}" for v in rgb)


def _pick(r, keys):
    return {k: r[k] for k in keys if k in r}


def _noise_range(kind, kw, ndim) -> tuple[float, float]:
    """The value range a noise recipe's colour map spans."""
    frac = kw.get("fractal", "fbm")
    out = str(kw.get("output", "f1")).lower()
    if kind == "worley" and frac != "ridged" and (out in _SPREAD or noise.worley_order(out)):
        # distances beyond F1 (and F1 + F2) reach past 1: spread the map over their range
        return noise.worley_range(out, metric=kw.get("metric", "euclidean"), ndim=ndim,
                                  jitter=kw.get("jitter", 1.0), density=kw.get("density"))
    if kind == "worley" or frac != "fbm":
        return (0.0, 1.0)
    return (-1.0, 1.0) if kind in ("value", "simplex") else (-0.75, 0.75)


def _field(r: dict, time: float | None) -> tuple[np.ndarray, tuple[float, float] | None]:
    """The scalar field of a recipe and its value range (None: use the data range)."""
    kind = r["kind"]
    w, h = r["size"]
    shape = (h, w)
    seed = r.get("seed")
    tile = bool(r.get("tileable", False))
    if kind in _NOISE:
        kw = _pick(r, _NOISE_KEYS)
        kw.setdefault("octaves", 6 if kind != "worley" else 1)
        g = noise.noise_grid(shape, kind=kind, seed=seed, tileable=tile, time=time,
                             dtype=np.float64, **kw)
        return g, _noise_range(kind, kw, len(shape) + (time is not None))
    if kind in _PATTERNS:
        fn = getattr(patterns, kind)
        kw = _pick(r, _KEYS[kind])
        if kind == "leaf":
            return fn(shape, seed=seed, dtype=np.float64, **kw), (0.0, 1.0)
        return fn(shape, seed=seed, tileable=tile, time=time, dtype=np.float64, **kw), (0.0, 1.0)
    if kind == "ifs":
        kw = _pick(r, ("system", "points", "gamma"))
        if time is not None:
            kw["points"] = max(1000, int(kw.get("points", 1_000_000) * min(1.0, time)))
        return fractals.ifs(shape, seed=seed, dtype=np.float64, **kw), (0.0, 1.0)
    raise AssertionError(kind)


def _escape(r: dict, frame: int | None, frames: int) -> np.ndarray:
    kind = r["kind"]
    w, h = r["size"]
    shape = (h, w)
    kw = _pick(r, ("center", "width", "maxiter", "bailout"))
    if "center" in kw and isinstance(kw["center"], list):
        kw["center"] = tuple(kw["center"])
    phase = 0.0 if frame is None else frame / max(frames, 1)
    if kind in ("mandelbrot", "burning-ship"):
        if frame is not None:
            kw["width"] = kw.get("width", 3.0 if kind == "mandelbrot" else 3.2) * float(
                r.get("zoom", 0.97)) ** frame
        fn = fractals.mandelbrot if kind == "mandelbrot" else fractals.burning_ship
        counts = fn(shape, dtype=np.float64, **kw)
    elif kind == "julia":
        c = complex(*r.get("c", (-0.8, 0.156)))
        c *= np.exp(2j * np.pi * phase)
        counts = fractals.julia(shape, c, dtype=np.float64, **kw)
    else:
        start = complex(*r.get("start", (0.6, 1.1)))
        start *= np.exp(2j * np.pi * phase * 0.25)
        kw.pop("bailout", None)
        counts = fractals.barnsley_j1(shape, start, dtype=np.float64,
                                      **kw, **_pick(r, ("uf_bailout", "variant")))
    return fractals.colorize(counts, r["colormap"], cycles=r.get("cycles"),
                             inside=r.get("inside", "#000000"), log=bool(r.get("log", False)))


def _lsystem(r: dict, frame: int | None, frames: int) -> np.ndarray:
    w, h = r["size"]
    it = int(r["iterations"])
    if frame is not None:
        it = min(it, round(frame * it / max(frames - 1, 1)))
    kw = _pick(r, ("start_angle", "draw", "move", "width", "width_factor", "width_increment",
                   "color_start", "color_increment", "palette", "background", "count",
                   "step_scale", "angle_scale", "dot", "dot_size", "dot_color"))
    if "random_step" in r:
        kw["random_step"] = tuple(float(v) for v in r["random_step"])
    if "size_fraction" in r:
        kw["size"] = r["size_fraction"]
    rules = {k: (v if isinstance(v, str) else [tuple(p) for p in v])
             for k, v in dict(r["rules"]).items()}
    return lsystem_texture((h, w), r["axiom"], rules, it, float(r["angle"]), seed=r.get("seed"),
                           tileable=bool(r.get("tileable", False)), **kw)


def render(recipe: Mapping | str, *, frame: int | None = None, frames: int = 1) -> np.ndarray:
    """Render a recipe (or preset name) to an RGB image.

    Parameters
    ----------
    recipe : mapping or str
    frame, frames : int
        Frame ``frame`` of an animation of ``frames`` frames: noise and patterns advance
        ``time`` by ``speed`` (default 0.05 lattice cells) per frame, Julia and barnsleyj1
        turn their parameter round, Mandelbrot and Burning Ship zoom in by ``zoom`` per
        frame, IFS accumulate points, and L-systems grow one iteration after another.

    Returns
    -------
    ndarray, uint8, shape (H, W, 3)

    Examples
    --------
    >>> render({"kind": "simplex", "size": [16, 8], "seed": 1}).shape
    (8, 16, 3)
    """
    r = resolve(recipe)
    kind = r["kind"]
    if kind in _ESCAPE:
        return _escape(r, frame, frames)
    if kind == "lsystem":
        return _lsystem(r, frame, frames)
    t = None
    if frame is not None:
        t = frame * float(r.get("speed", 0.05))
        if kind == "ifs":
            t = (frame + 1) / max(frames, 1)
    field, rng = _field(r, t)
    strength = r.get("normal_map")
    if strength:
        h = normalize(field, *(rng or (None, None)))
        return normal_map(h, strength=float(strength), tileable=bool(r.get("tileable", False)))
    vmin = r.get("vmin", rng[0] if rng else None)
    vmax = r.get("vmax", rng[1] if rng else None)
    return apply_colormap(field, r["colormap"], vmin=vmin, vmax=vmax)


def render_frames(recipe: Mapping | str, frames: int) -> list[np.ndarray]:
    """All frames of an animation (see :func:`render`)."""
    if int(frames) < 1:
        raise PresetError(f"frames must be at least 1, got {frames}")
    return [render(recipe, frame=i, frames=int(frames)) for i in range(int(frames))]


# ----------------------------------------------------------------------------- TOML
def _toml_value(v) -> str:
    if isinstance(v, bool | np.bool_):
        return "true" if v else "false"
    if isinstance(v, int | np.integer):
        return str(int(v))
    if isinstance(v, float | np.floating):
        f = float(v)
        if math.isnan(f) or math.isinf(f):
            return "nan" if math.isnan(f) else ("inf" if f > 0 else "-inf")
        return repr(f)
    if isinstance(v, str):
        esc = v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
        return f'"{esc}"'
    if isinstance(v, tuple | list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise PresetError(f"cannot write {type(v).__name__} value {v!r} to TOML")


def _toml_key(k: str) -> str:
    if k and all(c.isalnum() or c in "-_" for c in k):
        return k
    return _toml_value(str(k))


def dumps_toml(recipe: Mapping) -> str:
    """A recipe as TOML: scalars and arrays first, then one table per mapping value.

    Examples
    --------
    >>> print(dumps_toml({"kind": "lsystem", "angle": 22.5, "rules": {"F": "F[+F]F"}}))
    kind = "lsystem"
    angle = 22.5
    <BLANKLINE>
    [rules]
    F = "F[+F]F"
    <BLANKLINE>
    """
    lines = []
    tables = []
    for k, v in recipe.items():
        if isinstance(v, Mapping):
            tables.append((k, v))
        else:
            lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
    for name, tab in tables:
        lines.append("")
        lines.append(f"[{_toml_key(name)}]")
        for k, v in tab.items():
            if isinstance(v, Mapping):
                raise PresetError("preset tables cannot nest")
            lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
    return "\n".join(lines) + "\n"


def save_preset(recipe: Mapping | str, path) -> Path:
    """Write a recipe (checked by :func:`resolve`) to a TOML file; returns the path."""
    r = resolve(recipe)
    path = Path(path)
    with atomic_write(path, "w") as fh:
        fh.write("# sylva texture preset\n" + dumps_toml(r))
    return path


def load_preset(path) -> dict:
    """Read a TOML preset written by :func:`save_preset` (or by hand) and check it."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise PresetError(f"cannot read preset {path}: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise PresetError(f"{path}: not valid TOML: {exc}") from None
    return resolve(data)
