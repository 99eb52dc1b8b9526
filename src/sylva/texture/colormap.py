"""Colour maps, gradients, and normal maps from height fields.

A :class:`Colormap` is a piecewise-linear gradient: sorted stop positions in [0, 1] and an
RGB colour (floats in [0, 1]) at each.  Named maps live in :data:`COLORMAPS`;
:func:`gradient` builds one from ``(position, colour)`` pairs where a colour is ``"#rrggbb"``
or an ``(r, g, b)`` triple of 0–255 integers.
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
    "normal_map",
    "normalize",
    "parse_color",
    "to_uint8",
]


class ColormapError(SylvaError, ValueError):
    """An unknown colour map or an unreadable colour."""


def parse_color(color) -> tuple[float, float, float]:
    """A colour as RGB floats in [0, 1].

    Accepts ``"#rrggbb"``, ``"#rgb"`` or a sequence of three numbers 0–255.

    Examples
    --------
    >>> parse_color("#ff8000")
    (1.0, 0.5019607843137255, 0.0)
    """
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


def get_colormap(cmap) -> Colormap:
    """Look up a colour map by name (``"name_r"`` reverses it) or pass one through."""
    if isinstance(cmap, Colormap):
        return cmap
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
