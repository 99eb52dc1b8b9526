"""Colour maps, gradients, and normal maps from height fields.

A :class:`Colormap` is a piecewise-linear gradient: sorted stop positions in [0, 1] and an
RGB colour (floats in [0, 1]) at each.  Named maps live in :data:`COLORMAPS`;
:func:`gradient` builds one from ``(position, colour)`` pairs where a colour is ``"#rrggbb"``
or an ``(r, g, b)`` triple of 0–255 integers.

Custom colour maps come from a colour list (:func:`parse_colors`, the CLI's ``--colors``)
or a palette file (:func:`load_palette`).  A colour list is comma-separated colours, each
``#rrggbb``, ``#rgb`` or a CSS colour name (``white``, ``darkolivegreen``), optionally
preceded by its stop position and a colon: ``"0.0:#223344,0.7:#88aa55,1:white"``.  Either
every colour has a position or none has (then they are spaced evenly); positions run from
0 to 1 and do not decrease.  Palette files:

* GIMP palettes (``.gpl``): a ``GIMP Palette`` first line, optional ``Name:`` and
  ``Columns:`` lines, ``#`` comments, then one ``R G B [name]`` line per colour (0–255),
  spaced evenly;
* TOML (``.toml``): ``colors = ["#223344", "white"]`` (even) or
  ``stops = [[0.0, "#223344"], [1.0, "white"]]``;
* text (any other name): one colour per line, ``[position] colour`` (position and colour
  separated by blanks or a colon), ``#`` at the start of a line begins a comment.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..errors import SylvaError

__all__ = [
    "COLORMAPS",
    "Colormap",
    "ColormapError",
    "apply_colormap",
    "get_colormap",
    "gradient",
    "load_palette",
    "normal_map",
    "normalize",
    "parse_color",
    "parse_colors",
    "to_uint8",
]


class ColormapError(SylvaError, ValueError):
    """An unknown colour map or an unreadable colour."""


def parse_color(color) -> tuple[float, float, float]:
    """A colour as RGB floats in [0, 1].

    Accepts ``"#rrggbb"``, ``"#rgb"``, a CSS colour name (``"white"``, by Pillow's
    ``ImageColor``) or a sequence of three numbers 0–255.

    Examples
    --------
    >>> parse_color("#ff8000")
    (1.0, 0.5019607843137255, 0.0)
    """
    if isinstance(color, str) and not color.strip().startswith("#") and color.strip():
        from PIL import ImageColor

        try:
            rgb = ImageColor.getrgb(color.strip())
        except ValueError:
            raise ColormapError(f"colour {color!r} is not #rrggbb, #rgb or a colour name"
                                ) from None
        return tuple(v / 255.0 for v in rgb[:3])
    if isinstance(color, str):
        s = color.strip().lstrip("#")
        if len(s) == 3:
            s = "".join(c * 2 for c in s)
        if len(s) != 6:
            raise ColormapError(f"colour {color!r} is not #rrggbb or #rgb")
        try:
            return tuple(int(s[i:i + 2], 16) / 255.0 for i in (0, 2, 4))
        except ValueError:
            raise ColormapError(f"colour {color!r} is not hexadecimal") from None
    vals = list(color)
    if len(vals) != 3 or not all(0 <= float(v) <= 255 for v in vals):
        raise ColormapError(f"colour {color!r} must be three numbers in 0..255")
    return tuple(float(v) / 255.0 for v in vals)


@dataclass(frozen=True)
class Colormap:
    """A piecewise-linear colour gradient.

    Parameters
    ----------
    positions : ndarray, float64, shape (n,)
        Increasing stop positions, from 0 to 1.
    colors : ndarray, float64, shape (n, 3)
        RGB in [0, 1] at each stop.
    name : str
    """

    positions: np.ndarray
    colors: np.ndarray
    name: str = "custom"

    def __post_init__(self):
        p = np.asarray(self.positions, dtype=np.float64)
        c = np.asarray(self.colors, dtype=np.float64)
        if p.ndim != 1 or len(p) < 2 or c.shape != (len(p), 3):
            raise ColormapError("a colour map needs at least 2 stops, each with an RGB colour")
        if np.any(np.diff(p) < 0) or p[0] != 0.0 or p[-1] != 1.0:
            raise ColormapError("stop positions must increase from 0 to 1")
        object.__setattr__(self, "positions", p)
        object.__setattr__(self, "colors", c)

    def __call__(self, t, *, cycles: float | None = None) -> np.ndarray:
        """Map values ``t`` in [0, 1] (clipped) to RGB floats, shape ``t.shape + (3,)``.

        ``cycles`` repeats the gradient that many times over [0, 1] (colour cycling, as
        fractal programs do).
        """
        t = np.asarray(t, dtype=np.float64)
        if cycles:
            t = np.mod(t * cycles, 1.0)
        t = np.clip(np.nan_to_num(t, nan=0.0), 0.0, 1.0)
        out = np.empty(t.shape + (3,))
        for ch in range(3):
            out[..., ch] = np.interp(t, self.positions, self.colors[:, ch])
        return out

    def reversed(self) -> Colormap:
        """The same gradient from 1 to 0."""
        return Colormap(1.0 - self.positions[::-1], self.colors[::-1], self.name + "_r")


def gradient(stops: Iterable, name: str = "custom") -> Colormap:
    """Build a :class:`Colormap` from ``(position, colour)`` pairs or from bare colours
    (spaced evenly).

    Examples
    --------
    >>> cm = gradient(["#000000", "#ffffff"])
    >>> cm(0.5).round(3).tolist()
    [0.5, 0.5, 0.5]
    """
    stops = list(stops)
    if len(stops) < 2:
        raise ColormapError("a gradient needs at least two colours")
    if all(isinstance(s, tuple | list) and len(s) == 2 and not isinstance(s[1], int | float)
           for s in stops):
        pos = [float(s[0]) for s in stops]
        cols = [parse_color(s[1]) for s in stops]
    else:
        pos = list(np.linspace(0.0, 1.0, len(stops)))
        cols = [parse_color(s) for s in stops]
    return Colormap(np.array(pos), np.array(cols), name)


_NAMED = {
    "gray": ["#000000", "#ffffff"],
    "fire": ["#000000", "#5c0b00", "#c42d00", "#ff8a00", "#ffd84a", "#ffffff"],
    "ocean": ["#020b26", "#06306b", "#1267a6", "#3fa7d6", "#bfe9ff"],
    "terrain": [(0.0, "#1b3a6b"), (0.30, "#2f6fb0"), (0.36, "#d9c88f"), (0.42, "#4f8a3a"),
                (0.65, "#2d5a27"), (0.80, "#7a6a55"), (0.92, "#bdb6ad"), (1.0, "#ffffff")],
    "viridis": ["#440154", "#482878", "#3e4989", "#31688e", "#26828e", "#1f9e89", "#35b779",
                "#6ece58", "#b5de2b", "#fde725"],
    "marble": [(0.0, "#3b3a40"), (0.25, "#8d8a92"), (0.6, "#e4e1dc"), (1.0, "#fbfaf7")],
    "wood": [(0.0, "#5a3415"), (0.45, "#8b5a2b"), (0.8, "#c48e55"), (1.0, "#e0b47c")],
    "clouds": [(0.0, "#3d78c9"), (0.45, "#7fb0e8"), (0.7, "#dfeaf7"), (1.0, "#ffffff")],
    "granite": [(0.0, "#1c1a1a"), (0.35, "#6b5f5b"), (0.6, "#a8958b"), (0.85, "#d6c6bb"),
                (1.0, "#f3ece6")],
    "bark": [(0.0, "#1e130c"), (0.35, "#3f2a1c"), (0.7, "#6b4d34"), (1.0, "#8f7357")],
    "leaf": [(0.0, "#0e2a0c"), (0.5, "#2f6b1f"), (0.85, "#6aa84f"), (1.0, "#d3f0a8")],
    "grass": [(0.0, "#1d3b12"), (0.5, "#3f7a22"), (0.8, "#6fae3a"), (1.0, "#b7dc6c")],
    "sand": ["#7a5b32", "#c2a36b", "#ecdcae"],
    "spectral": ["#9e0142", "#f46d43", "#fee08b", "#e6f598", "#66c2a5", "#5e4fa2"],
    "fractal": ["#000764", "#206bcb", "#edffff", "#ffaa00", "#000200"],
}

COLORMAPS: dict[str, Colormap] = {k: gradient(v, k) for k, v in _NAMED.items()}
"""The named colour maps."""


def _stops_colormap(pos, cols, where, name) -> Colormap:
    """A :class:`Colormap` from parsed positions (all or none ``None``) and colours, with
    errors that say ``where`` the bad value is."""
    if len(cols) < 2:
        raise ColormapError(f"{where}: a colour map needs at least two colours, got "
                            f"{len(cols)}")
    if all(p is None for p in pos):
        pos = list(np.linspace(0.0, 1.0, len(cols)))
    elif any(p is None for p in pos):
        raise ColormapError(f"{where}: give a stop position to every colour or to none")
    if pos[0] != 0.0 or pos[-1] != 1.0 or any(b < a for a, b in zip(pos, pos[1:])):
        raise ColormapError(f"{where}: stop positions must not decrease and must run from 0 "
                            f"to 1, got {', '.join(f'{p:g}' for p in pos)}")
    return Colormap(np.array(pos, dtype=np.float64), np.array(cols, dtype=np.float64), name)


def _position(text, where) -> float:
    try:
        p = float(text)
    except ValueError:
        raise ColormapError(f"{where}: stop position {text.strip()!r} is not a number") from None
    if not 0.0 <= p <= 1.0:
        raise ColormapError(f"{where}: stop position {p:g} is outside [0, 1]")
    return p


def _color_at(text, where):
    try:
        return parse_color(text)
    except ColormapError as exc:
        raise ColormapError(f"{where}: {exc}") from None


def parse_colors(text: str, *, option: str = "--colors") -> Colormap:
    """A colour map from a comma-separated colour list (see the module docstring).

    Errors name ``option`` and the 1-based column of the bad item.

    Examples
    --------
    >>> cm = parse_colors("0:#000000, 0.25:#ffffff, 1:black")
    >>> cm.positions.tolist(), cm(0.25).tolist()
    ([0.0, 0.25, 1.0], [1.0, 1.0, 1.0])
    """
    pos, cols = [], []
    col = 1
    for item in str(text).split(","):
        where = f"{option} column {col + len(item) - len(item.lstrip())}"
        if not item.strip():
            raise ColormapError(f"{where}: empty colour (expected #rrggbb, #rgb or a name)")
        head, sep, tail = item.partition(":")
        if sep:
            pos.append(_position(head, where))
            cols.append(_color_at(tail, where))
        else:
            pos.append(None)
            cols.append(_color_at(item, where))
        col += len(item) + 1
    return _stops_colormap(pos, cols, option, "custom")


def _palette_gpl(lines, path):
    pos, cols = [], []
    if not lines or lines[0].strip() != "GIMP Palette":
        raise ColormapError(f"{path}:1:1: a .gpl file starts with the line 'GIMP Palette'")
    for n, line in enumerate(lines[1:], start=2):
        s = line.strip()
        if not s or s.startswith("#") or s.split(":")[0] in ("Name", "Columns"):
            continue
        parts = s.split()
        try:
            rgb = [int(v) for v in parts[:3]]
        except ValueError:
            rgb = []
        if len(rgb) != 3 or not all(0 <= v <= 255 for v in rgb):
            c = len(line) - len(line.lstrip()) + 1
            raise ColormapError(f"{path}:{n}:{c}: expected 'R G B [name]' with R, G, B in "
                                f"0..255, got {s!r}")
        pos.append(None)
        cols.append(tuple(v / 255.0 for v in rgb))
    return pos, cols


def _palette_text(lines, path):
    pos, cols = [], []
    for n, line in enumerate(lines, start=1):
        s = line.strip()
        if not s or (s.startswith("#") and (len(s) < 2 or s[1] in " #!")):
            continue
        where = f"{path}:{n}:{len(line) - len(line.lstrip()) + 1}"
        parts = s.replace(":", " ", 1).split() if ":" in s else s.split()
        if len(parts) == 1:
            pos.append(None)
            cols.append(_color_at(parts[0], where))
        elif len(parts) == 2:
            pos.append(_position(parts[0], where))
            cols.append(_color_at(parts[1], where))
        else:
            raise ColormapError(f"{where}: expected '[position] colour', got {s!r}")
    return pos, cols


def _palette_toml(text, path):
    import tomllib

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ColormapError(f"{path}: not valid TOML: {exc}") from None
    keys = set(data) & {"colors", "stops"}
    if len(keys) != 1 or set(data) - {"colors", "stops", "name"}:
        raise ColormapError(f"{path}: a TOML palette holds 'colors = [...]' or "
                            f"'stops = [[position, colour], ...]' (and optionally 'name')")
    if "colors" in data:
        vals = data["colors"]
        if not isinstance(vals, list):
            raise ColormapError(f"{path}: 'colors' must be a list of colours")
        return [None] * len(vals), [_color_at(v, f"{path}: colors[{i}]")
                                    for i, v in enumerate(vals)]
    pos, cols = [], []
    for i, st in enumerate(data["stops"] if isinstance(data["stops"], list) else [None]):
        where = f"{path}: stops[{i}]"
        if not (isinstance(st, list) and len(st) == 2 and isinstance(st[0], int | float)
                and not isinstance(st[0], bool)):
            raise ColormapError(f"{where}: expected [position, colour]")
        pos.append(_position(str(st[0]), where))
        cols.append(_color_at(st[1], where))
    return pos, cols


def load_palette(path) -> Colormap:
    """A colour map from a palette file: GIMP ``.gpl``, ``.toml`` or text (see the module
    docstring); errors give the file, line and column."""
    from pathlib import Path

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ColormapError(f"cannot read palette {path}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise ColormapError(f"{path}: a palette file must be UTF-8 text") from None
    suffix = path.suffix.lower()
    if suffix == ".gpl":
        pos, cols = _palette_gpl(text.splitlines(), path)
    elif suffix == ".toml":
        pos, cols = _palette_toml(text, path)
    else:
        pos, cols = _palette_text(text.splitlines(), path)
    return _stops_colormap(pos, cols, str(path), path.stem)


def get_colormap(cmap) -> Colormap:
    """Look up a colour map by name (``"name_r"`` reverses it) or pass one through; a list
    of colours or of ``[position, colour]`` pairs (as a preset stores ``--colors``) builds
    a :func:`gradient`."""
    if isinstance(cmap, Colormap):
        return cmap
    if isinstance(cmap, list | tuple):
        return gradient(cmap)
    name = str(cmap).lower()
    rev = name.endswith("_r")
    base = name[:-2] if rev else name
    if base not in COLORMAPS:
        raise ColormapError(
            f"unknown colour map {cmap!r}; expected one of: {', '.join(sorted(COLORMAPS))}"
        )
    cm = COLORMAPS[base]
    return cm.reversed() if rev else cm


def normalize(values, vmin: float | None = None, vmax: float | None = None) -> np.ndarray:
    """Rescale to [0, 1] (float64); ``vmin``/``vmax`` default to the finite data range.

    Examples
    --------
    >>> normalize([2.0, 4.0, 6.0]).tolist()
    [0.0, 0.5, 1.0]
    """
    v = np.asarray(values, dtype=np.float64)
    finite = v[np.isfinite(v)]
    lo = float(finite.min()) if vmin is None and finite.size else (vmin or 0.0)
    hi = float(finite.max()) if vmax is None and finite.size else (vmax or 1.0)
    if hi <= lo:
        return np.zeros_like(v)
    return np.clip((v - lo) / (hi - lo), 0.0, 1.0)


def to_uint8(rgb) -> np.ndarray:
    """Floats in [0, 1] to uint8 0–255 (rounded, clipped)."""
    return (np.clip(np.asarray(rgb, dtype=np.float64), 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def apply_colormap(values, cmap="gray", *, vmin: float | None = None,
                   vmax: float | None = None, cycles: float | None = None) -> np.ndarray:
    """Colour a scalar field: uint8 RGB of shape ``values.shape + (3,)``.

    ``vmin``/``vmax`` fix the range mapped onto the gradient (default: the data range).

    Examples
    --------
    >>> apply_colormap([[0.0, 1.0]], "gray").tolist()
    [[[0, 0, 0], [255, 255, 255]]]
    """
    cm = get_colormap(cmap)
    return to_uint8(cm(normalize(values, vmin, vmax), cycles=cycles))


def normal_map(height, *, strength: float = 1.0, tileable: bool = False,
               encode: bool = True) -> np.ndarray:
    """Tangent-space normal map from a height field (central differences).

    Parameters
    ----------
    height : array_like, shape (H, W)
        Heights; one unit of height equals ``1 / strength`` pixels.
    strength : float
        Bump strength.
    tileable : bool
        Wrap the differences around the edges (use for tileable heights).
    encode : bool
        ``True``: uint8 RGB ``(n * 0.5 + 0.5) * 255`` (OpenGL convention, +y up);
        ``False``: float32 unit normals, shape (H, W, 3).

    Examples
    --------
    >>> normal_map(np.zeros((2, 2)))[0, 0].tolist()
    [128, 128, 255]
    """
    h = np.asarray(height, dtype=np.float64)
    if h.ndim != 2:
        raise ColormapError(f"height must be 2D, got shape {h.shape}")
    if tileable:
        dx = (np.roll(h, -1, axis=1) - np.roll(h, 1, axis=1)) * 0.5
        dy = (np.roll(h, -1, axis=0) - np.roll(h, 1, axis=0)) * 0.5
    else:
        dy, dx = np.gradient(h) if min(h.shape) > 1 else (np.zeros_like(h), np.zeros_like(h))
    # image rows grow downwards; +y of the normal map points up
    n = np.stack([-dx * strength, dy * strength, np.ones_like(h)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    if not encode:
        return n.astype(np.float32)
    return to_uint8(n * 0.5 + 0.5)
