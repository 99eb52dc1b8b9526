"""Noise functions: value, classic and improved Perlin, simplex, Worley; fBm, turbulence,
ridged multifractal and domain warping, point-wise or on grids.

Two ways in:

* **Point-wise** functions (:func:`value_noise`, :func:`perlin`, :func:`improved_perlin`,
  :func:`simplex`, :func:`worley`, :func:`fbm`, :func:`turbulence`, :func:`ridged`)
  take coordinate arrays ``x, y[, z[, w]]`` (broadcast together; 2, 3 or 4 of them pick
  the dimension) and return an array of their broadcast shape.  When every coordinate is
  a scalar they return a Python ``float`` computed in double precision, so reference
  values can be checked exactly::

      >>> improved_perlin(3.14, 42, 7)
      0.13691995878400012

* :func:`noise_grid` fills an image ``(H, W)``, a volume ``(D, H, W)`` or a 4D block with
  a fractal sum of octaves, optionally tileable, animated (``time``) and domain-warped.
  It uses fast kernels that precompute per-axis lattice data.

Tables and seeds
----------------
``seed=None`` (the default) uses Ken Perlin's reference permutation, so
:func:`improved_perlin` is bit-exact with his ``ImprovedNoise.java`` and :func:`simplex`
with Stefan Gustavson's ``SimplexNoise.java`` (2012).  The random tables that have no
reference (value-noise lattice values, classic Perlin gradients) then come from
``numpy.random.default_rng(0)``.  An integer seed draws the permutation and the tables
from ``numpy.random.default_rng(seed)``; Worley feature points come from an integer hash
of the cell and the seed (one jittered point per cell, or with ``density=`` Worley's Poisson
process).  The same seed gives the same texture on every machine.

Output is float32 unless ``dtype=np.float64``; noise is computed in float64 (bit-exact), but
float32 :func:`noise_grid` grids in float32 SIMD kernels, within an absolute 2e-4 of the
float64 road (on values normalised to about [-1, 1]): 2D and 3D grids of every kind, and
4D lattice and simplex grids (``_gridkernels32.TOLERANCE``), and 4D Worley grids (or 3D
with ``time``), tileable simplex and
domain-warped grids (``_points32.TOLERANCE``; only a warped 3D or 4D simplex sample that
rounding moves across a simplex face, where that kernel jumps, can differ by more, and a
warped sample beyond ~1e10 cells, where one float64 step of the point exceeds the warp
fields' float32 rounding; one
octave of 4D Worley cell id is the float64 road's value, ties apart).  Worley's 2D and 3D
cell id, its Poisson process and its orders above F3 are computed in float64 and rounded.
"""

from __future__ import annotations

import contextlib
import functools
import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass

import numba
import numpy as np

from .. import _jit
from ..errors import SylvaError
from . import _gridkernels as _gk
from . import _gridkernels32 as _gk32
from . import _gridplan as _gp
from . import _kernels as _k
from . import _points32 as _p32
from . import _sampling as _s
from . import _worleyfn as _wf
from ._gridplan import grid_plan
from ._worleyfn import MAX_ORDER, worley_order, worley_range

__all__ = [
    "FRACTALS",
    "INTERPOLATIONS",
    "MAX_ORDER",
    "KINDS",
    "METRICS",
    "REFERENCE_PERMUTATION",
    "WORLEY_OUTPUTS",
    "NoiseError",
    "NoiseTables",
    "domain_warp",
    "fbm",
    "improved_perlin",
    "noise_grid",
    "noise_tables",
    "perlin",
    "ridged",
    "simplex",
    "turbulence",
    "value_noise",
    "worley",
    "worley_features",
    "worley_order",
    "worley_range",
]


class NoiseError(SylvaError, ValueError):
    """Invalid noise parameters (unknown kind, bad octave count, unsupported tiling …)."""


# fmt: off
REFERENCE_PERMUTATION = np.array(
    [151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30,
     69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94,
     252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171,
     168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60,
     211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1,
     216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86,
     164, 100, 109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118,
     126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170,
     213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39,
     253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34,
     242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49,
     192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254,
     138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180],
    dtype=np.int32,
)
# fmt: on
REFERENCE_PERMUTATION.setflags(write=False)

KINDS = {
    "value": _k.VALUE,
    "perlin": _k.PERLIN,
    "improved": _k.IMPROVED,
    "simplex": _k.SIMPLEX,
    "worley": _k.WORLEY,
}
"""Noise kinds by name: value, classic Perlin (1985), improved Perlin (2002), simplex, Worley."""

INTERPOLATIONS = {"linear": 0, "cosine": 1, "cubic": 2, "quintic": 3}
"""Interpolation curves: t, (1-cos(pi t))/2, 3t^2-2t^3, 6t^5-15t^4+10t^3."""

FRACTALS = {"fbm": _k.FBM, "turbulence": _k.TURBULENCE, "ridged": _k.RIDGED}
"""Octave sums: fBm, turbulence (sum of |noise|), ridged multifractal."""

METRICS = {"euclidean": 0, "manhattan": 1, "chebyshev": 2, "euclidean2": 3}
"""Worley distance metrics (``euclidean2`` is the squared Euclidean distance)."""

WORLEY_OUTPUTS = {
    "f1": 0,
    "f2": 1,
    "f3": 2,
    "f2-f1": 3,
    "f1+f2": 4,
    "f1*f2": 5,
    "sqrt(f1*f2)": 6,
    "sqrt(f2-f1)": 7,
    "1-f1": 8,
    "1-f2": 9,
    "cell": 10,
    "linear": 11,
}
"""Worley outputs: distances F1..F3, the combinations of seed 003, the nearest cell's id in
[0, 1) (``cell``), and ``linear`` = c1*F1 + c2*F2 + c3*F3 (``coefficients``)."""

_DEFAULT_INTERP = {
    "value": "quintic",
    "perlin": "cubic",
    "improved": "quintic",
    "simplex": "quintic",
    "worley": "quintic",
}
# per-octave coordinate offsets decorrelate octaves (octave 0 is not moved)
_OCTAVE_SHIFT = np.array([37.1934, 17.3871, 53.7159, 29.9173])


@dataclass(frozen=True)
class NoiseTables:
    """The lookup tables of one seed.

    Attributes
    ----------
    perm : ndarray, int32, shape (512,)
        The permutation of 0..255, doubled.
    perm12 : ndarray, int32, shape (512,)
        ``perm % 12`` (simplex gradient indices).
    values : ndarray, float64, shape (256,)
        Value-noise lattice values: the 256 evenly spaced values of [-1, 1], shuffled.
    gradients : ndarray, float64, shape (3, 256, 4)
        Classic Perlin unit gradients for 2D, 3D and 4D (unused components are 0).
    seed : int or None
    """

    perm: np.ndarray
    perm12: np.ndarray
    values: np.ndarray
    gradients: np.ndarray
    seed: int | None


@functools.lru_cache(maxsize=64)
def noise_tables(seed: int | None = None) -> NoiseTables:
    """Build (and cache) the tables for ``seed``; see the module notes on seeds.

    Examples
    --------
    >>> noise_tables(None).perm[:3].tolist()
    [151, 160, 137]
    """
    seed = _check_seed(seed)
    rng = np.random.default_rng(0 if seed is None else seed)
    p = REFERENCE_PERMUTATION if seed is None else rng.permutation(256).astype(np.int32)
    if seed is None:
        rng.permutation(256)  # keep the table draws aligned with the seeded case
    perm = np.concatenate([p, p]).astype(np.int32)
    # evenly spaced lattice values in random order: uniform on [-1, 1] with mean exactly 0
    values = np.linspace(-1.0, 1.0, 256)[rng.permutation(256)]
    grads = np.zeros((3, 256, 4))
    angle = rng.uniform(0.0, 2.0 * np.pi, 256)
    grads[0, :, 0] = np.cos(angle)
    grads[0, :, 1] = np.sin(angle)
    for d, n in ((1, 3), (2, 4)):
        v = rng.normal(size=(256, n))
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        grads[d, :, :n] = v
    out = NoiseTables(perm, (perm % 12).astype(np.int32), values, grads, seed)
    for a in (out.perm, out.perm12, out.values, out.gradients):
        a.setflags(write=False)
    return out


# below this many samples x octaves a call runs on one thread: waking the other threads of
# numba's pool costs more than the work (milliseconds when the other cores are busy)
_SERIAL_WORK = 1 << 16


@contextlib.contextmanager
def _threads(work):
    """Run the block's kernels on the calling thread alone when ``work`` is small, else on
    all threads with dynamic scheduling: the parallel loops hand out their iterations
    (blocks of rows) one at a time, so a thread on a busier core takes fewer of them.
    Both settings are local to the calling thread and restored afterwards."""
    before = numba.get_num_threads()
    if before == 1:
        yield
        return
    if work >= _SERIAL_WORK:
        chunk = numba.set_parallel_chunksize(1)
        try:
            yield
        finally:
            numba.set_parallel_chunksize(chunk)
        return
    numba.set_num_threads(1)
    try:
        yield
    finally:
        numba.set_num_threads(before)


# ----------------------------------------------------------------------------- validation
def _check_seed(seed):
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
        raise NoiseError(f"seed must be an integer or None, got {seed!r}")
    if seed < 0:
        raise NoiseError(f"seed must be >= 0, got {seed}")
    return int(seed)


def _lookup(table: dict, name, what: str) -> int:
    try:
        return table[str(name).lower()]
    except KeyError:
        raise NoiseError(f"unknown {what} {name!r}; expected one of: {', '.join(table)}") from None


def _dtype(dtype):
    dt = np.dtype(np.float32 if dtype is None else dtype)
    if dt not in (np.float32, np.float64):
        raise NoiseError(f"dtype must be float32 or float64, got {dt}")
    return dt


def _octave_params(octaves, persistence, lacunarity):
    if isinstance(octaves, bool) or not isinstance(octaves, int | np.integer) or octaves < 1:
        raise NoiseError(f"octaves must be a positive integer, got {octaves!r}")
    if octaves > 32:
        raise NoiseError(f"octaves must be at most 32, got {octaves}")
    if not np.isfinite(persistence) or persistence <= 0:
        raise NoiseError(f"persistence must be a positive number, got {persistence!r}")
    if not np.isfinite(lacunarity) or lacunarity <= 0:
        raise NoiseError(f"lacunarity must be a positive number, got {lacunarity!r}")
    return int(octaves), float(persistence), float(lacunarity)


# Worley's Poisson density: <= 8 keeps the cap of 32 points per cell negligible (P < 1e-10),
# >= 0.01 keeps the search within 64 rings exact (see _cellkernels.POISSON_MAX_*)
DENSITY_RANGE = (0.01, 8.0)


def _check_density(density) -> float:
    """``density`` as a float (0.0 for None: the jittered grid), or a :class:`NoiseError`."""
    if density is None:
        return 0.0
    if isinstance(density, bool) or not isinstance(density, numbers.Real):
        raise NoiseError(f"density must be a number (points per cell) or None, got {density!r}")
    lam = float(density)
    lo, hi = DENSITY_RANGE
    if not math.isfinite(lam) or not lo <= lam <= hi:
        raise NoiseError(
            f"density must be a finite number in [{lo}, {hi}] (mean feature points per"
            f" cell), got {density!r}"
        )
    return lam


@dataclass(frozen=True)
class _Setup:
    kind: int
    interp: int
    tables: NoiseTables
    wpar: np.ndarray


def _setup(
    kind,
    seed,
    interpolation,
    output="f1",
    metric="euclidean",
    jitter=1.0,
    coefficients=(1.0, 0.0, 0.0),
    density=None,
) -> _Setup:
    kname = str(kind).lower()
    kid = _lookup(KINDS, kname, "noise kind")
    interp = _lookup(INTERPOLATIONS, interpolation or _DEFAULT_INTERP[kname], "interpolation")
    if not 0.0 <= float(jitter) <= 1.0:
        raise NoiseError(f"jitter must lie in [0, 1], got {jitter!r}")
    lam = _check_density(density)
    c = tuple(float(v) for v in coefficients)
    if len(c) != 3:
        raise NoiseError("coefficients must be three numbers (for F1, F2, F3)")
    seed = _check_seed(seed)
    wseed = 0 if seed is None else seed & 0xFFFFFFFF
    # wpar = (metric, output, jitter, seed, c1, c2, c3, density); density 0: jittered grid
    wpar = np.array(
        [
            _lookup(METRICS, metric, "metric"),
            _lookup(WORLEY_OUTPUTS, output, "Worley output"),
            float(jitter),
            wseed,
            *c,
            lam,
        ],
        dtype=np.float64,
    )
    return _Setup(kid, interp, noise_tables(seed), wpar)


def _periods(period, ndim, kind) -> np.ndarray:
    out = np.zeros(4, dtype=np.int64)
    if period is None:
        return out
    if kind == _k.SIMPLEX:
        raise NoiseError(
            "simplex noise has no integer lattice period; use noise_grid(..., tileable=True),"
            " which wraps simplex onto a 4D torus, or a lattice noise (value, perlin, improved,"
            " worley)"
        )
    vals = [period] * ndim if np.ndim(period) == 0 else list(period)
    if len(vals) != ndim:
        raise NoiseError(f"period needs {ndim} values (one per axis), got {len(vals)}")
    for i, v in enumerate(vals):
        if v is None or v == 0:
            continue
        if int(v) != v or v < 1:
            raise NoiseError(f"periods must be positive integers, got {v!r}")
        out[i] = int(v)
    return out


def _coords(x, y, z, w):
    cs = [c for c in (x, y, z, w) if c is not None]
    if z is None and w is not None:
        raise NoiseError("w given without z")
    scalar = all(np.ndim(c) == 0 for c in cs)
    try:
        arrs = np.broadcast_arrays(*[np.asarray(c, dtype=np.float64) for c in cs])
    except ValueError as exc:
        raise NoiseError(f"coordinate arrays do not broadcast: {exc}") from None
    shape = arrs[0].shape
    flat = [np.ascontiguousarray(a).ravel() for a in arrs]
    n = flat[0].shape[0]
    while len(flat) < 4:
        flat.append(np.zeros(n))
    if not all(np.isfinite(f).all() for f in flat):
        raise NoiseError("coordinates must be finite")
    return len(cs), flat, shape, scalar


def _run_points(
    setup,
    mode,
    x,
    y,
    z,
    w,
    octaves,
    persistence,
    lacunarity,
    frequency,
    period,
    normalize,
    gain,
    dtype,
):
    ndim, flat, shape, scalar = _coords(x, y, z, w)
    octaves, persistence, lacunarity = _octave_params(octaves, persistence, lacunarity)
    base = _periods(period, ndim, setup.kind)
    freqs = np.empty((octaves, 4))
    pers = np.zeros((octaves, 4))
    amps = persistence ** np.arange(octaves, dtype=np.float64)
    for o in range(octaves):
        f = float(frequency) * lacunarity**o
        freqs[o] = f
        if base.any():
            # period of octave o: base * f must be a whole number of cells
            per = base * f
            if not np.allclose(per, np.round(per)):
                raise NoiseError(
                    "with a period, frequency * lacunarity**octave * period must be whole; "
                    f"octave {o} gives {per[:ndim].tolist()}"
                )
            pers[o] = np.round(per)
    offs = _octave_offsets(octaves)
    norm = 1.0 / amps.sum() if (normalize and mode != -1) else 1.0
    dt = np.float64 if scalar else _dtype(dtype)
    t = setup.tables
    if _gp.by_arrays(setup.kind, flat[0].shape[0] * octaves, _s.generic_kernel):
        out = _gp.fractal_arrays(setup.kind, max(mode, 0), ndim, *flat, freqs, amps, offs, pers,
                                 setup.interp, t.perm, t.perm12, t.values, t.gradients,
                                 setup.wpar, norm, float(gain))  # fmt: skip
        return float(out[0]) if scalar else out.astype(dt, copy=False).reshape(shape)
    with _threads(flat[0].shape[0] * octaves):
        out = _s.run_points(
            setup.kind,
            max(mode, 0),
            ndim,
            flat[0],
            flat[1],
            flat[2],
            flat[3],
            freqs,
            amps,
            offs,
            pers,
            setup.interp,
            t.perm,
            t.perm12,
            t.values,
            t.gradients,
            setup.wpar,
            norm,
            float(gain),
        )
    if scalar:
        return float(out[0])
    return out.astype(dt, copy=False).reshape(shape)


def _octave_offsets(octaves):
    o = np.arange(octaves, dtype=np.float64)[:, None]
    return o * _OCTAVE_SHIFT[None, :]


# ----------------------------------------------------------------------------- point-wise noise
def _single(kind, x, y, z, w, seed, interpolation, period, dtype, **cell):
    setup = _setup(kind, seed, interpolation, **cell)
    return _run_points(setup, -1, x, y, z, w, 1, 0.5, 2.0, 1.0, period, False, 2.0, dtype)


def value_noise(
    x, y, z=None, w=None, *, seed=None, interpolation="quintic", period=None, dtype=None
):
    """Value noise: random values at lattice points, interpolated.

    Parameters
    ----------
    x, y, z, w : array_like of float
        Coordinates (broadcast together); two, three or four of them give 2D, 3D or 4D noise.
    seed : int, optional
        ``None`` uses the reference permutation and ``default_rng(0)`` lattice values.
    interpolation : {"linear", "cosine", "cubic", "quintic"}
        The curve blending neighbouring lattice values (seed 003 §4.2, seed 000 §4.5).
    period : int or sequence of int, optional
        Integer lattice period per axis; the noise repeats with it (seamless tiling).
    dtype : float32 (default) or float64
        Dtype of an array result.

    Returns
    -------
    ndarray of the broadcast shape, or float for scalar input
        Values in [-1, 1].

    Examples
    --------
    >>> v = value_noise([0.5, 1.5], [0.25, 0.25], seed=3)
    >>> v.shape, v.dtype.name
    ((2,), 'float32')
    """
    return _single("value", x, y, z, w, seed, interpolation, period, dtype)


def perlin(x, y, z=None, w=None, *, seed=None, interpolation="cubic", period=None, dtype=None):
    """Classic Perlin (1985) gradient noise: 256 random unit gradients through a permutation.

    Parameters are those of :func:`value_noise`; the default curve is 3t^2 - 2t^3.  The
    result is 0 at every lattice point and lies within about ±sqrt(n)/2.

    Examples
    --------
    >>> perlin(2.0, 5.0)
    0.0
    """
    return _single("perlin", x, y, z, w, seed, interpolation, period, dtype)


def improved_perlin(
    x, y, z=None, w=None, *, seed=None, interpolation="quintic", period=None, dtype=None
):
    """Improved Perlin noise (2002): 12 edge gradients, quintic fade.

    With ``seed=None`` the 3D noise is bit-exact with Perlin's reference ``ImprovedNoise``;
    2D noise is the 3D noise at z = 0; 4D extends it with the 32 hypercube-edge gradients.
    Parameters are those of :func:`value_noise`.

    Examples
    --------
    >>> improved_perlin(3.14, 42, 7)
    0.13691995878400012
    """
    return _single("improved", x, y, z, w, seed, interpolation, period, dtype)


def simplex(x, y, z=None, w=None, *, seed=None, dtype=None):
    """Simplex noise in 2D, 3D or 4D, value for value Gustavson's SimplexNoise.java (2012).

    For seamless simplex images use :func:`noise_grid` with ``tileable=True``.

    Examples
    --------
    >>> simplex(0.3, 0.7)
    0.2552206334201348
    """
    return _single("simplex", x, y, z, w, seed, None, None, dtype)


def worley(
    x,
    y,
    z=None,
    w=None,
    *,
    seed=None,
    output="f1",
    metric="euclidean",
    jitter=1.0,
    coefficients=(1.0, 0.0, 0.0),
    period=None,
    dtype=None,
    density=None,
):
    """Worley cellular noise (1996): distances to the nearest feature points.

    By default one feature point per unit cell at ``cell + 0.5 + jitter * (u - 0.5)`` with
    ``u`` uniform from a hash of the cell and the seed ("jittered grid"); ``jitter=0``
    gives a regular grid.  With a ``density`` the feature points are Worley's original
    Poisson process instead: each cell holds a Poisson-distributed number of points with
    mean ``density``, each uniform in the cell, so the pattern has no grid regularity.

    Parameters
    ----------
    x, y, z, w : array_like of float
        Coordinates, as for :func:`value_noise`.
    output : str
        One of :data:`WORLEY_OUTPUTS`, or ``fN`` for any order ``N`` up to
        :data:`MAX_ORDER` (the N-th nearest distance): ``f1``, ``f2``, ``f3``, ``f2-f1``, ``f1+f2``,
        ``f1*f2``, ``sqrt(f1*f2)``, ``sqrt(f2-f1)``, ``1-f1``, ``1-f2``, ``cell`` (the
        nearest cell's id in [0, 1), for flat-coloured mosaics) or ``linear``.
    metric : {"euclidean", "manhattan", "chebyshev", "euclidean2"}
    jitter : float in [0, 1]
        Displacement of the one point per cell from the cell centre (ignored when a
        ``density`` is given).
    coefficients : (c1, c2, c3)
        Weights for ``output="linear"``.
    period : int or sequence of int, optional
        Integer period per axis (seamless tiling).
    density : float, optional
        Mean number of feature points per unit cell of a Poisson point process, in
        :data:`DENSITY_RANGE` ([0.01, 8]); ``None`` (the default) is the jittered grid with
        exactly one point per cell.  A cell's point count is drawn from Poisson(density)
        by a hash of the cell and the seed, capped at 32 points per cell; ``jitter`` is
        ignored.  Cells can be empty, so the search for F1..F3 widens as far as needed (up
        to 64 cells, exact in the whole density range); the points repeat with ``period``
        (a tile of ``m`` cells is empty with probability ``exp(-density * m)``: F1..F3 are
        then infinite).  ``output="cell"`` gives an id of the nearest point.  Slower than
        the jittered grid (a full search per sample).

    Examples
    --------
    >>> worley(0.5, 0.5, jitter=0.0)
    0.0
    """
    n = worley_order(output)
    if n is not None:
        return worley_features(x, y, z, w, seed=seed, metric=metric, jitter=jitter,
                               period=period, dtype=dtype, density=density, order=n)[n - 1]
    return _single("worley", x, y, z, w, seed, None, period, dtype, output=output, metric=metric,
                   jitter=jitter, coefficients=coefficients, density=density)


def worley_features(
    x,
    y,
    z=None,
    w=None,
    *,
    seed=None,
    metric="euclidean",
    jitter=1.0,
    period=None,
    dtype=None,
    density=None,
    order=3,
):
    """F1 .. F(``order``) and the cell id at once, as a tuple of ``order + 1`` arrays (see
    :func:`worley`; ``density`` gives the Poisson point process, ``jitter`` is then ignored).
    ``order``: 1 to :data:`MAX_ORDER` (default 3); the search widens until F(order) is exact.

    Examples
    --------
    >>> f1, f2, f3, cell = worley_features([0.2, 3.7], [0.4, 1.1], seed=1)
    >>> bool((f1 <= f2).all() and (f2 <= f3).all())
    True
    >>> fs = worley_features(0.3, 0.6, order=6)
    >>> len(fs), fs[5] >= fs[4] >= fs[0]
    (7, True)
    """
    order = _wf.check_order(order)
    if order != 3:
        return _wf.features(x, y, z, w, seed, metric, jitter, period, dtype, density, order)
    return tuple(worley(x, y, z, w, seed=seed, output=o, metric=metric, jitter=jitter,
                        period=period, dtype=dtype, density=density)
                 for o in ("f1", "f2", "f3", "cell"))


# ----------------------------------------------------------------------------- fractal sums
_FRACTAL_DOC = """

    Parameters
    ----------
    x, y, z, w : array_like of float
        Coordinates (two to four arrays, broadcast together).
    kind : {"value", "perlin", "improved", "simplex", "worley"}
    octaves : int
        Number of octaves ``n``.
    persistence : float
        Amplitude ratio between octaves: octave ``i`` has amplitude ``persistence**i``.
    lacunarity : float
        Frequency ratio: octave ``i`` has frequency ``frequency * lacunarity**i``.
    frequency : float
        Base frequency.
    seed : int, optional
    interpolation : str, optional
        Curve for lattice noises (default: the kind's own).
    period : int or sequence of int, optional
        Base-octave lattice period per axis; every octave then tiles with it (requires
        ``frequency * lacunarity**i * period`` to be whole).
    normalize : bool
        Divide by the sum of the amplitudes, keeping fBm in [-1, 1] (turbulence and ridged
        in [0, 1]).
    output, metric, jitter, density : str, str, float, float or None
        Worley options when ``kind="worley"`` (see :func:`worley`; a ``density`` gives
        Worley's Poisson point process and ``jitter`` is then ignored).
    dtype : float32 (default) or float64
"""


def fbm(
    x,
    y,
    z=None,
    w=None,
    *,
    kind="improved",
    octaves=6,
    persistence=0.5,
    lacunarity=2.0,
    frequency=1.0,
    seed=None,
    interpolation=None,
    period=None,
    normalize=True,
    output="f1",
    metric="euclidean",
    jitter=1.0,
    dtype=None,
    density=None,
):
    setup = _setup(kind, seed, interpolation, output, metric, jitter, density=density)
    return _run_points(
        setup,
        _k.FBM,
        x,
        y,
        z,
        w,
        octaves,
        persistence,
        lacunarity,
        frequency,
        period,
        normalize,
        2.0,
        dtype,
    )


fbm.__doc__ = (
    """Fractional Brownian motion: ``sum_i persistence**i * noise(lacunarity**i * f * p)``
    (seed 003 §4.2: frequency 2^i, amplitude persistence^i for lacunarity 2).
"""
    + _FRACTAL_DOC
    + """
    Examples
    --------
    >>> float(abs(fbm(0.3, 0.6, octaves=4))) <= 1.0
    True
    """
)


def turbulence(
    x,
    y,
    z=None,
    w=None,
    *,
    kind="improved",
    octaves=6,
    persistence=0.5,
    lacunarity=2.0,
    frequency=1.0,
    seed=None,
    interpolation=None,
    period=None,
    normalize=True,
    output="f1",
    metric="euclidean",
    jitter=1.0,
    dtype=None,
    density=None,
):
    setup = _setup(kind, seed, interpolation, output, metric, jitter, density=density)
    return _run_points(
        setup,
        _k.TURBULENCE,
        x,
        y,
        z,
        w,
        octaves,
        persistence,
        lacunarity,
        frequency,
        period,
        normalize,
        2.0,
        dtype,
    )


turbulence.__doc__ = (
    """Perlin's turbulence: ``sum_i persistence**i * |noise(lacunarity**i f p)|``.
"""
    + _FRACTAL_DOC
    + """
    Examples
    --------
    >>> float(turbulence(0.3, 0.6)) >= 0.0
    True
    """
)


def ridged(
    x,
    y,
    z=None,
    w=None,
    *,
    kind="improved",
    octaves=6,
    persistence=0.5,
    lacunarity=2.0,
    frequency=1.0,
    gain=2.0,
    seed=None,
    interpolation=None,
    period=None,
    normalize=True,
    output="f1",
    metric="euclidean",
    jitter=1.0,
    dtype=None,
    density=None,
):
    setup = _setup(kind, seed, interpolation, output, metric, jitter, density=density)
    return _run_points(
        setup,
        _k.RIDGED,
        x,
        y,
        z,
        w,
        octaves,
        persistence,
        lacunarity,
        frequency,
        period,
        normalize,
        gain,
        dtype,
    )


ridged.__doc__ = (
    """Ridged multifractal (Musgrave): ``s_i = (1 - |noise_i|)**2 * w_i``, with the
    weight ``w_i = clip(gain * s_{i-1}, 0, 1)`` (``w_0 = 1``), summed with amplitudes
    ``persistence**i``.  ``gain`` (default 2) sets how strongly ridges suppress detail in
    valleys.
"""
    + _FRACTAL_DOC
    + """
    Examples
    --------
    >>> 0.0 <= float(ridged(0.3, 0.6)) <= 1.0
    True
    """
)


def domain_warp(
    x,
    y,
    z=None,
    *,
    amount=1.0,
    kind="improved",
    octaves=4,
    persistence=0.5,
    lacunarity=2.0,
    frequency=1.0,
    seed=None,
    period=None,
):
    """Displace coordinates by vector fBm (POV-Ray style turbulence, seed 003 §4.3).

    ``p' = p + amount * (fbm(p + o_x), fbm(p + o_y)[, fbm(p + o_z)])`` with fixed, distinct
    offsets ``o`` per component.  Feed the result to any point-wise noise or pattern.

    Returns
    -------
    tuple of ndarray (float64)
        The warped coordinates, one array per input axis.

    Examples
    --------
    >>> wx, wy = domain_warp([0.0, 1.0], [0.0, 0.0], amount=0.0)
    >>> wx.tolist(), wy.tolist()
    ([0.0, 1.0], [0.0, 0.0])
    """
    coords = [np.asarray(c, dtype=np.float64) for c in (x, y, z) if c is not None]
    coords = np.broadcast_arrays(*coords)
    shifts = ((19.31, 7.77, 3.51), (5.23, 13.97, 11.11), (2.71, 31.41, 17.29))
    out = []
    for a, c in enumerate(coords):
        moved = [cc + shifts[a][b] for b, cc in enumerate(coords)]
        d = fbm(
            *moved,
            kind=kind,
            octaves=octaves,
            persistence=persistence,
            lacunarity=lacunarity,
            frequency=frequency,
            seed=None if seed is None else seed + 7919 * (a + 1),
            period=period,
            dtype=np.float64,
        )
        out.append(c + float(amount) * d)
    return tuple(out)


# ----------------------------------------------------------------------------- grids
def _grid_out(shape, dt):
    """The output array and the (float32, float64) pair the grid kernels take: the output
    and an empty array of the other type (one compiled kernel serves both types)."""
    out = np.empty(shape, dtype=dt)
    if dt == np.float32:
        return out, (out, np.empty((0, 0, 0)))
    return out, (np.empty((0, 0, 0), np.float32), out)


def _axis_flags(tileable, naxes):
    if isinstance(tileable, bool | np.bool_):
        return [bool(tileable)] * naxes
    flags = [bool(t) for t in tileable]
    if len(flags) != naxes:
        raise NoiseError(f"tileable needs {naxes} flags (one per array axis), got {len(flags)}")
    return flags


def noise_grid(
    shape: Sequence[int],
    *,
    kind="improved",
    fractal="fbm",
    scale=4.0,
    octaves=1,
    persistence=0.5,
    lacunarity=2.0,
    gain=2.0,
    seed=None,
    interpolation=None,
    tileable=False,
    time=None,
    offset=(0.0, 0.0, 0.0, 0.0),
    warp=0.0,
    normalize=True,
    output="f1",
    metric="euclidean",
    jitter=1.0,
    dtype=None,
    density=None,
):
    """Noise (or a fractal sum of octaves) sampled on a regular grid.

    Parameters
    ----------
    shape : tuple of int
        ``(H, W)`` image, ``(D, H, W)`` volume or ``(T, D, H, W)`` block; array axis -1 is
        x, -2 is y, -3 is z, -4 is w.
    kind : str
        A key of :data:`KINDS`.
    fractal : {"fbm", "turbulence", "ridged"}
        How octaves are summed (one octave of fBm is plain noise).
    scale : float or sequence of float
        Base-octave lattice cells across the width; every axis then uses the same pixel
        size (``scale / W``).  A sequence gives the cells across each axis in (x, y, z, w)
        order, for stretched patterns.
    octaves, persistence, lacunarity, gain : see :func:`fbm` and :func:`ridged`.
    seed : int, optional
    interpolation : str, optional
    tileable : bool or sequence of bool
        Seamless wrap per array axis (``True``: every axis).  Lattice noises and Worley use
        integer lattice periods (the cell counts are rounded to whole numbers per axis and
        per octave); simplex is wrapped onto a flat 4D torus, which tiles the two image
        axes of a 2D image (optionally animated by ``time``).
    time : float, optional
        An extra coordinate after the grid's own: a 2D image becomes a slice of 3D noise,
        a volume a slice of 4D noise, so textures can be animated.  It is measured in
        base-octave lattice cells.
    offset : sequence of float
        Added to (x, y, z, w) before scaling, in lattice cells.
    warp : float
        Domain-warp amount in lattice cells (0: none); the warp field is fBm of the same
        kind and octave settings with other seeds.
    normalize : bool
    output, metric, jitter, density : Worley options (see :func:`worley`; a ``density``
        gives Worley's Poisson point process, ``jitter`` is then ignored).
    dtype : float32 (default) or float64

    Returns
    -------
    ndarray, shape ``shape``

    Examples
    --------
    >>> img = noise_grid((64, 128), kind="simplex", octaves=5, seed=7, tileable=True)
    >>> img.shape, img.dtype.name
    ((64, 128), 'float32')
    """
    plan = grid_plan(shape, kind, fractal, scale, octaves, persistence, lacunarity, gain,
                      seed, interpolation, tileable, time, offset, warp, normalize, output,
                      metric, jitter, dtype, density)
    (shape, ndim, mode, norder, setup, dt, torus, sizes, axes, freqs, amps, offs, pers, norm,
     gain) = (plan.shape, plan.ndim, plan.mode, plan.norder, plan.setup, plan.dt, plan.torus,
              plan.sizes, plan.axes, plan.freqs, plan.amps, plan.offs, plan.pers, plan.norm,
              plan.gain)
    t = setup.tables
    if (not warp and not torus and not norder
            and _gp.by_arrays(setup.kind, math.prod(shape) * len(amps), _gk.lattice_grid)):
        return _gp.grid_arrays(plan).astype(dt, copy=False)

    if norder:
        if warp:
            raise NoiseError(f"domain warping of Worley {output} is not supported")
        return _wf.grid(setup, ndim, axes, freqs, amps, offs, pers, mode, norm, gain,
                        norder).astype(dt, copy=False).reshape(shape)
    with _threads(math.prod(shape) * octaves * (1 + ndim * bool(warp))):
        if dt == np.float32 and (o32 := _p32.grid32(plan, warp, functools.partial(
                _setup, kind, interpolation=interpolation, output=output, metric=metric,
                jitter=jitter, density=density))) is not None:
            return o32  # float32 4D grids, tileable simplex, domain warping
        if warp:
            grids = np.meshgrid(*axes[:ndim][::-1], indexing="ij")[::-1]
            pts = [g.ravel() for g in grids]
            while len(pts) < 4:
                pts.append(np.zeros(pts[0].shape[0]))
            warped = []
            for a in range(ndim):
                wseed = _setup(
                    kind,
                    (0 if seed is None else seed) + 7919 * (a + 1),
                    interpolation,
                    output,
                    metric,
                    jitter,
                    density=density,
                )
                wt = wseed.tables
                d = _s.run_points(
                    setup.kind,
                    _k.FBM,
                    ndim,
                    pts[0],
                    pts[1],
                    pts[2],
                    pts[3],
                    freqs,
                    amps,
                    offs,
                    pers,
                    setup.interp,
                    wt.perm,
                    wt.perm12,
                    wt.values,
                    wt.gradients,
                    wseed.wpar,
                    norm,
                    gain,
                )
                warped.append(pts[a] + float(warp) * d)
            while len(warped) < 4:
                warped.append(np.zeros(pts[0].shape[0]))
            out = _s.run_points(
                setup.kind,
                mode,
                ndim,
                warped[0],
                warped[1],
                warped[2],
                warped[3],
                freqs,
                amps,
                offs,
                pers,
                setup.interp,
                t.perm,
                t.perm12,
                t.values,
                t.gradients,
                setup.wpar,
                norm,
                gain,
            )
            return out.astype(dt, copy=False).reshape(shape)

        full = tuple(len(a) for a in axes[:4])  # nx, ny, nz, nw
        # on a cold cache, small float32 grids take the float64 road (interpreted) and round
        if dt == np.float32 and not _jit.cold(
            _gk32.lattice_grid32, math.prod(shape), _gp.SCALAR_WORK
        ) and (o32 := _gk32.grid32(
                setup, ndim, axes, freqs, amps, offs, pers, mode, norm, gain, torus, full
        )) is not None:
            return o32.reshape(shape)
        if setup.kind in (_k.VALUE, _k.PERLIN, _k.IMPROVED) and ndim in (2, 3):
            tabs = [
                _gk.axis_tables(
                    axes[a],
                    np.ascontiguousarray(freqs[:, a]),
                    np.ascontiguousarray(offs[:, a]),
                    np.ascontiguousarray(pers[:, a]),
                    setup.interp,
                )
                for a in range(ndim)
            ]
            zt = tabs[2] if ndim == 3 else tabs[1]
            out, outs = _grid_out((full[2], full[1], full[0]), dt)
            _gk.lattice_grid(
                setup.kind,
                mode,
                ndim,
                tabs[0],
                tabs[1],
                zt,
                *outs,
                amps,
                t.perm,
                t.values,
                t.gradients[0],
                t.gradients[1],
                norm,
                gain,
            )
            return out.reshape(shape)
        if setup.kind == _k.SIMPLEX and ndim in (2, 3) and not torus:
            out, outs = _grid_out((full[2], full[1], full[0]), dt)
            _gp.run_blocks(_gp.GRID.simplex_grid, -(-full[2] * full[1] // _gk.ROWS), (
                ndim,
                mode,
                axes[0],
                axes[1],
                axes[2],
                *outs,
                freqs,
                amps,
                offs,
                t.perm,
                t.perm12,
                norm,
                gain,
            ))
            return out.reshape(shape)
        if setup.kind == _k.WORLEY and ndim in (2, 3):
            out, outs = _grid_out((full[2], full[1], full[0]), dt)
            _gp.run_blocks(_gp.GRID.worley_grid, -(-full[2] * full[1] // _gk.ROWS), (
                ndim,
                mode,
                axes[0],
                axes[1],
                axes[2],
                *outs,
                freqs,
                amps,
                offs,
                pers,
                setup.wpar,
                norm,
                gain,
            ))
            return out.reshape(shape)
        if torus:
            # x and y become angles; the circumferences (pers) are the octave's cell counts
            axes[0] = 2.0 * np.pi * np.arange(sizes[0], dtype=np.float64) / sizes[0]
            axes[1] = 2.0 * np.pi * np.arange(sizes[1], dtype=np.float64) / sizes[1]
        out = np.empty((full[3], full[2], full[1], full[0]), dtype=np.float64)
        _gp.run_blocks(_gp.SAMPLING.generic_kernel, full[3] * full[2] * full[1], (
            False,
            setup.kind,
            mode,
            ndim,
            axes[0],
            axes[1],
            axes[2],
            axes[3],
            out,
            torus,
            freqs,
            amps,
            offs,
            pers,
            setup.interp,
            t.perm,
            t.perm12,
            t.values,
            t.gradients,
            setup.wpar,
            norm,
            gain,
        ))
        return out.astype(dt, copy=False).reshape(shape)
