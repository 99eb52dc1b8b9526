"""Worley F1..Fn of any order and the expected range of the Worley outputs (private; the
public names are re-exported by :mod:`sylva.texture.noise`).  The kernel is
:mod:`._worleyn`, imported on first use so that a plain F1 never compiles it."""

from __future__ import annotations

import functools

import numpy as np

MAX_ORDER = 256
"""The highest Worley order ``fN`` (the search is exact up to it at the lowest density)."""


def _error(msg):
    from .noise import NoiseError

    return NoiseError(msg)


def worley_order(output) -> int | None:
    """The order ``n`` of a Worley output ``"fN"`` beyond F3 (``"f4"``, ``"f12"``), else None.

    Examples
    --------
    >>> worley_order("f6"), worley_order("f2"), worley_order("f2-f1")
    (6, None, None)
    """
    s = str(output).strip().lower()
    if len(s) > 1 and s[0] == "f" and s[1:].isdigit() and s[1:].isascii():
        n = int(s[1:])
        if n < 1:
            raise _error(f"Worley output {output!r}: the order starts at f1")
        if n > MAX_ORDER:
            raise _error(f"Worley output {output!r}: the order is at most f{MAX_ORDER}")
        return n if n > 3 else None
    return None


def check_order(order) -> int:
    """``order`` of :func:`~sylva.texture.noise.worley_features` as an int, or an error."""
    import numbers

    if isinstance(order, bool) or not isinstance(order, numbers.Integral) or not (
            1 <= order <= MAX_ORDER):
        raise _error(f"order must be a whole number in 1..{MAX_ORDER}, got {order!r}")
    return int(order)


def points(setup, ndim, xs, ys, zs, ws, pers, n):
    """F1..Fn (shape (m, n)) and the cell ids at the points, by :mod:`._worleyn`."""
    from . import _worleyn

    metric, _, jitter, wseed, *_, lam = setup.wpar
    p = [int(v) for v in pers]
    return _worleyn.worley_n_points(ndim, xs, ys, zs, ws, *p, int(metric), float(jitter),
                                    float(lam), int(wseed), int(n))


def features(x, y, z, w, seed, metric, jitter, period, dtype, density, order):
    """:func:`~sylva.texture.noise.worley_features` of any order: F1..F(order), cell ids."""
    from . import _kernels as _k
    from . import noise as _n

    setup = _n._setup("worley", seed, None, "f1", metric, jitter, density=density)
    ndim, flat, shape, scalar = _n._coords(x, y, z, w)
    f, cell = points(setup, ndim, *flat, _n._periods(period, ndim, _k.WORLEY), order)
    if scalar:
        return (*(float(v) for v in f[0]), float(cell[0]))
    dt = _n._dtype(dtype)
    return (*(f[:, k].astype(dt, copy=False).reshape(shape) for k in range(order)),
            cell.astype(dt, copy=False).reshape(shape))


def grid(setup, ndim, axes, freqs, amps, offs, pers, mode, norm, gain, n):
    """``noise_grid`` of Worley ``fN`` beyond F3: each octave's F_n at the grid points,
    summed as fBm, turbulence (the same: F_n >= 0) or ridged, as the fractal kernels do."""
    from . import _kernels as _k
    from .noise import _threads

    grids = np.meshgrid(*axes[:ndim][::-1], indexing="ij")[::-1]
    pts = [g.ravel() for g in grids]
    while len(pts) < 4:
        pts.append(np.zeros(pts[0].shape[0]))
    total = np.zeros(pts[0].shape[0])
    weight = np.ones_like(total)
    with _threads(total.shape[0] * len(amps)):
        for o in range(len(amps)):
            c = [np.ascontiguousarray(pts[a] * freqs[o, a] + offs[o, a]) for a in range(4)]
            f, _ = points(setup, ndim, *c, pers[o], n)
            v = f[:, n - 1]
            if mode == _k.RIDGED:
                s = (1.0 - np.abs(v)) ** 2 * weight
                weight = np.clip(s * gain, 0.0, 1.0)
                v = s
            total += amps[o] * np.abs(v) if mode == _k.TURBULENCE else amps[o] * v
    return total * norm


def worley_range(output="f1", *, metric="euclidean", ndim=2, jitter=1.0, density=None):
    """The expected range ``(0, hi)`` of a Worley distance output for one metric, dimension
    and point process: ``hi`` is the 99.9th percentile over 16384 fixed sample points, so a
    colour map spread over it saturates about 0.1 % of the pixels.

    (F1 + F2 of the Euclidean 2D jittered grid reaches about 2.06, F6 about 1.73: mapped
    onto [0, 1] they wash out.)  The sample points and the seed are fixed, so the range is
    the same on every call.

    Examples
    --------
    >>> lo, hi = worley_range("f1+f2")
    >>> lo, 1.9 < hi < 2.2
    (0.0, True)
    """
    return _worley_range(str(output).lower(), str(metric), int(ndim), float(jitter),
                         None if density is None else float(density))


@functools.lru_cache(maxsize=128)
def _worley_range(output, metric, ndim, jitter, density):
    from .noise import worley

    if not 2 <= ndim <= 4:
        raise _error(f"ndim must be 2, 3 or 4, got {ndim}")
    p = np.random.default_rng(20251201).uniform(0.0, 64.0, (ndim, 16384))
    v = worley(*p, seed=0, output=output, metric=metric, jitter=jitter, density=density,
               dtype=np.float64)
    v = v[np.isfinite(v)]
    return 0.0, float(np.quantile(v, 0.999)) if v.size else 1.0
