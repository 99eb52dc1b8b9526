"""Fractal textures: Mandelbrot, Julia, Burning Ship, Ultra Fractal's "barnsleyj1", and
iterated function systems (Barnsley fern, Sierpinski triangle) by the chaos game.

Escape-time functions return smooth iteration counts (float32 unless ``dtype`` says
otherwise): ``n + 1 - log2(log|z_n| / log R)`` for the quadratic maps, where ``R`` is the
bailout radius, so colour bands blend continuously (seed 003 §4.6).  Points that never
escape within ``maxiter`` iterations are **-1**.  Colour them with :func:`colorize`.

The view is given by ``center`` (a complex number or ``(re, im)``) and ``width``, the
extent of the real axis across the image; pixels are square and the imaginary axis points
up.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SylvaError
from . import _fractal_kernels as _fk
from .colormap import get_colormap, to_uint8

__all__ = [
    "BARNSLEY_FERN",
    "IFS_PRESETS",
    "SIERPINSKI",
    "FractalError",
    "Ifs",
    "barnsley_j1",
    "burning_ship",
    "colorize",
    "ifs",
    "in_mandelbrot",
    "julia",
    "mandelbrot",
]


class FractalError(SylvaError, ValueError):
    """Invalid fractal parameters."""


def _plane(shape, center, width):
    shape = tuple(int(s) for s in shape)
    if len(shape) != 2 or min(shape) < 1:
        raise FractalError(f"shape must be (H, W) with positive sizes, got {shape}")
    if not width > 0:
        raise FractalError(f"width must be positive, got {width}")
    c = complex(*center) if isinstance(center, tuple | list) else complex(center)
    h, w = shape
    px = width / w
    re = c.real + (np.arange(w, dtype=np.float64) - (w - 1) / 2.0) * px
    im = c.imag + ((h - 1) / 2.0 - np.arange(h, dtype=np.float64)) * px
    return shape, re, im


def _escape(kind, shape, center, width, c, maxiter, bailout, smooth, dtype):
    if int(maxiter) < 1:
        raise FractalError(f"maxiter must be at least 1, got {maxiter}")
    if not bailout > 0:
        raise FractalError(f"bailout must be positive, got {bailout}")
    shape, re, im = _plane(shape, center, width)
    c = complex(*c) if isinstance(c, tuple | list) else complex(c)
    out = np.empty(shape, dtype=np.float64)
    _fk.escape_kernel(kind, re, im, c.real, c.imag, int(maxiter), float(bailout), bool(smooth),
                      out)
    return out.astype(np.float32 if dtype is None else dtype, copy=False)


def mandelbrot(shape, *, center=(-0.5, 0.0), width=3.0, maxiter=256, bailout=256.0,
               smooth=True, dtype=None):
    """Mandelbrot set: z0 = 0, z <- z^2 + c with c the pixel.

    Parameters
    ----------
    shape : (H, W)
    center : complex or (float, float)
    width : float
        Extent of the real axis across the image.
    maxiter : int
    bailout : float
        Escape radius (2 suffices; larger radii make the smooth colouring smoother).
    smooth : bool
        Smooth (fractional) counts, or integer counts.
    dtype : float32 (default) or float64

    Returns
    -------
    ndarray, shape (H, W)
        Smooth escape counts; -1 inside the set.

    Examples
    --------
    >>> m = mandelbrot((5, 5), center=0, width=0.1, maxiter=100)
    >>> float(m[2, 2])  # c = 0 is in the set
    -1.0
    """
    return _escape(_fk.MANDELBROT, shape, center, width, 0j, maxiter, bailout, smooth, dtype)


def julia(shape, c=(-0.8, 0.156), *, center=0.0, width=3.2, maxiter=256, bailout=256.0,
          smooth=True, dtype=None):
    """Julia set of ``z <- z^2 + c``: z0 is the pixel.  Parameters as :func:`mandelbrot`.

    Examples
    --------
    >>> j = julia((3, 3), c=0, width=0.2)
    >>> float(j[1, 1])  # |z0| < 1 never escapes for c = 0
    -1.0
    """
    return _escape(_fk.JULIA, shape, center, width, c, maxiter, bailout, smooth, dtype)


def burning_ship(shape, *, center=(-0.45, -0.5), width=3.2, maxiter=256, bailout=256.0,
                 smooth=True, dtype=None):
    """Burning Ship: ``z <- (|Re z| + i |Im z|)^2 + c``, ``z0 = 0``.  Parameters as
    :func:`mandelbrot` (the ship's hull points up with the imaginary axis flipped).

    Examples
    --------
    >>> burning_ship((4, 6)).shape
    (4, 6)
    """
    return _escape(_fk.BURNING_SHIP, shape, center, width, 0j, maxiter, bailout, smooth, dtype)


def barnsley_j1(shape, start=(0.6, 1.1), *, center=0.0, width=4.0, maxiter=149,
                uf_bailout=4.0, variant="z", smooth=True, dtype=None):
    """Ultra Fractal's "barnsleyj1" formula as listed in seed 003 §5.5::

        init:    z = pixel
        loop:    IF real(z) >= 0  z = (z - 1) * @start  ELSE  z = (z + 1) * @start
        bailout: |z| < 4          (Ultra Fractal's |z| is the squared modulus)
        default: maxiter = 149, start = (0.6, 1.1)

    Parameters
    ----------
    start : complex or (float, float)
        The complex parameter ``@start``.
    uf_bailout : float
        The value in Ultra Fractal's ``|z| < value`` (the thesis also tries 3 and 2); the
        escape radius is its square root.
    variant : {"z", "zz"}
        ``"zz"`` is the thesis's modification ``z = (z - 1) * z * @start`` (and
        ``(z + 1) * z * @start``), shown there with ``start=(1.6, 1.1)``.

    Examples
    --------
    >>> b = barnsley_j1((8, 8))
    >>> b.dtype.name, float(b.max()) <= 149
    ('float32', True)
    """
    if variant not in ("z", "zz"):
        raise FractalError(f"variant must be 'z' or 'zz', got {variant!r}")
    if not uf_bailout > 0:
        raise FractalError(f"uf_bailout must be positive, got {uf_bailout}")
    kind = _fk.BARNSLEY_J1 if variant == "z" else _fk.BARNSLEY_J1Z
    return _escape(kind, shape, center, width, start, maxiter, float(np.sqrt(uf_bailout)),
                   smooth, dtype)


def in_mandelbrot(c, *, maxiter=1000) -> np.ndarray | bool:
    """Whether the points ``c`` stay bounded (``|z| <= 2``) for ``maxiter`` iterations.

    Examples
    --------
    >>> in_mandelbrot([0, -1, -2, 1j, 0.26, 1, -0.75 + 0.1j]).tolist()
    [True, True, True, True, False, False, False]
    """
    c = np.asarray(c, dtype=np.complex128)
    if int(maxiter) < 1:
        raise FractalError(f"maxiter must be at least 1, got {maxiter}")
    flat = c.ravel()
    res = np.empty(flat.shape[0], dtype=np.bool_)
    _fk.mandelbrot_members(np.ascontiguousarray(flat.real), np.ascontiguousarray(flat.imag),
                           int(maxiter), res)
    return bool(res[0]) if c.ndim == 0 else res.reshape(c.shape)


def colorize(counts, cmap="fractal", *, cycles=None, inside="#000000", maxiter=None,
             log=False) -> np.ndarray:
    """Colour escape counts: uint8 RGB, shape ``counts.shape + (3,)``.

    Parameters
    ----------
    counts : ndarray
        Output of an escape-time function (-1 inside).
    cmap : str or Colormap
    cycles : float, optional
        Colour cycling: the gradient repeats every ``maxiter / cycles`` iterations (or over
        the data range when ``maxiter`` is not given).
    inside : colour
        Colour of points that never escaped.
    maxiter : int, optional
        Fix the count range to [0, maxiter] instead of the data range.
    log : bool
        Map ``log(1 + n)`` instead of ``n`` (spreads the bands near the set).
    """
    from .colormap import parse_color

    n = np.asarray(counts, dtype=np.float64)
    outside = n >= 0
    v = np.where(outside, n, 0.0)
    if log:
        v = np.log1p(v)
    hi = (np.log1p(maxiter) if log else maxiter) if maxiter else (
        v[outside].max() if outside.any() else 1.0)
    t = v / hi if hi > 0 else v
    rgb = get_colormap(cmap)(t, cycles=cycles)
    rgb[~outside] = parse_color(inside)
    return to_uint8(rgb)


# ----------------------------------------------------------------------------- IFS
@dataclass(frozen=True)
class Ifs:
    """An iterated function system: affine maps ``p <- A_k p + b_k`` with probabilities.

    Attributes
    ----------
    matrices : ndarray, float64, shape (k, 2, 2)
    offsets : ndarray, float64, shape (k, 2)
    probabilities : ndarray, float64, shape (k,)
        Sum to 1.
    bounds : (xmin, xmax, ymin, ymax)
        The attractor's extent, used to frame the image.
    """

    matrices: np.ndarray
    offsets: np.ndarray
    probabilities: np.ndarray
    bounds: tuple[float, float, float, float]

    def __post_init__(self):
        m = np.asarray(self.matrices, dtype=np.float64)
        o = np.asarray(self.offsets, dtype=np.float64)
        p = np.asarray(self.probabilities, dtype=np.float64)
        if m.ndim != 3 or m.shape[1:] != (2, 2) or o.shape != (m.shape[0], 2) \
                or p.shape != (m.shape[0],):
            raise FractalError("an IFS needs k 2x2 matrices, k offsets and k probabilities")
        if np.any(p < 0) or not np.isclose(p.sum(), 1.0):
            raise FractalError(f"IFS probabilities must be >= 0 and sum to 1, got {p.tolist()}")
        object.__setattr__(self, "matrices", m)
        object.__setattr__(self, "offsets", o)
        object.__setattr__(self, "probabilities", p / p.sum())


BARNSLEY_FERN = Ifs(
    matrices=[[[0.0, 0.0], [0.0, 0.16]], [[0.85, 0.04], [-0.04, 0.85]],
              [[0.20, -0.26], [0.23, 0.22]], [[-0.15, 0.28], [0.26, 0.24]]],
    offsets=[[0.0, 0.0], [0.0, 1.6], [0.0, 1.6], [0.0, 0.44]],
    probabilities=[0.01, 0.85, 0.07, 0.07],
    bounds=(-2.1820, 2.6558, 0.0, 9.9983),
)
"""Barnsley's fern (Barnsley, *Fractals Everywhere*)."""

SIERPINSKI = Ifs(
    matrices=[[[0.5, 0.0], [0.0, 0.5]]] * 3,
    offsets=[[0.0, 0.0], [0.5, 0.0], [0.25, 0.5 * np.sqrt(3.0) / 2.0]],
    probabilities=[1 / 3, 1 / 3, 1 / 3],
    bounds=(0.0, 1.0, 0.0, np.sqrt(3.0) / 2.0),
)
"""The Sierpinski triangle: w_k(p) = (p + v_k) / 2 for the vertices of a unit triangle."""

IFS_PRESETS = {"fern": BARNSLEY_FERN, "sierpinski": SIERPINSKI}


def ifs(shape, system="fern", *, points=1_000_000, seed=None, margin=0.05, gamma=0.5,
        dtype=None):
    """Render an IFS attractor by the chaos game: visit density mapped to [0, 1].

    Parameters
    ----------
    shape : (H, W)
    system : Ifs or {"fern", "sierpinski"}
    points : int
        Chaos-game iterations (the first 20 are discarded).
    seed : int, optional
        Seeds the map choices (``default_rng(seed)``; ``None`` means 0).
    margin : float
        Border around the attractor, as a fraction of the image.
    gamma : float
        ``density ** gamma`` after normalising by the maximum (0.5 brightens thin parts).

    Returns
    -------
    ndarray, shape (H, W), values in [0, 1]

    Examples
    --------
    >>> s = ifs((64, 64), "sierpinski", points=20000, seed=1)
    >>> float(s.max())
    1.0
    """
    if isinstance(system, str):
        try:
            system = IFS_PRESETS[system.lower()]
        except KeyError:
            raise FractalError(
                f"unknown IFS {system!r}; expected one of: {', '.join(IFS_PRESETS)}"
            ) from None
    shape = tuple(int(s) for s in shape)
    if len(shape) != 2 or min(shape) < 1:
        raise FractalError(f"shape must be (H, W), got {shape}")
    if int(points) < 1:
        raise FractalError(f"points must be positive, got {points}")
    h, w = shape
    xmin, xmax, ymin, ymax = system.bounds
    dx = (xmax - xmin) or 1.0
    dy = (ymax - ymin) or 1.0
    # uniform scale so the attractor keeps its aspect, centred
    s = min(w * (1 - 2 * margin) / dx, h * (1 - 2 * margin) / dy)
    x0 = xmin - (w / s - dx) / 2.0
    y0 = ymin - (h / s - dy) / 2.0
    rng = np.random.default_rng(0 if seed is None else seed)
    choices = rng.choice(len(system.probabilities), size=int(points) + 20,
                         p=system.probabilities).astype(np.int32)
    hist = np.zeros(shape, dtype=np.float64)
    _fk.chaos_game(system.matrices, system.offsets, choices, 0.0, 0.0, x0, y0, s, s, hist, 20)
    m = hist.max()
    out = (hist / m) ** gamma if m > 0 else hist
    return out.astype(np.float32 if dtype is None else dtype, copy=False)
