"""cpfg's graphically defined functions and curves, named in the view file.

``function: name.func [samples]`` lines (numbered 1, 2 … in order) and ``function set:
name.fset`` (a gallery of several, numbered in order) give ``func(k, x)``: the value at
``x`` in [0, 1] of function ``k``.  ``curve: name.con`` lines give ``curveX(k, t)``,
``curveY(k, t)``, ``curveZ(k, t)`` (the point at the fraction ``t`` of curve ``k``'s
length) and ``curveGAL(k)`` (its length).  vlab's editors (funcedit, the contour editor)
write both as the control points of a uniform cubic B-spline whose ends are clamped (its
first and last points are on the curve), each point repeated as often as its multiplicity.

A function's value is cpfg's (checked against a cpfg built from vlab's source,
``benchmarks/cpfg_reference.py``): the spline's parameter for ``x`` is found by bisection
until the spline's x is within 0.001 of ``x`` (cpfg's ``SplineFunction::_Value``), and when
the function has a sample count (a ``samples: k`` line in the file, ``fver 1 1``; the
number after the file name on the view file's ``function:`` line for the older ``range:``
files) cpfg tabulates ``k`` such values at ``x = i / (k - 1)`` and interpolates linearly
between them.  A curve's point at a fraction of its length is cpfg's too: an arc-length
table of the ``curve:`` line's sample count (100 without one), the spline parameter
interpolated in it and the spline evaluated there (``CCurveXYZ::calcAValue``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import SylvaError

__all__ = ["load_functions"]

_SAMPLES = 1025
#: cpfg's arc-length table of a curve without a sample count on its ``curve:`` line
_CURVE_SAMPLES = 100


def _bspline(points: np.ndarray, samples: int = _SAMPLES) -> np.ndarray:
    """Points of the clamped uniform cubic B-spline of control ``points`` ``(n, d)``."""
    return _bspline_at(points, np.linspace(0.0, 1.0, samples))


def _bspline_at(points: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The clamped uniform cubic B-spline of control ``points`` ``(n, d)`` at the
    parameters ``u`` in [0, 1] (``u = 1``: the last point)."""
    n = len(points)
    if n < 2:
        return np.repeat(points[:1], len(u), axis=0)
    k = min(3, n - 1)
    inner = n - k - 1
    knots = np.concatenate([np.zeros(k + 1), np.arange(1, inner + 1) / (inner + 1),
                            np.ones(k + 1)])  # fmt: skip
    u = np.asarray(u, np.float64)
    samples = len(u)
    # Cox-de Boor, vectorised over u
    basis = np.zeros((samples, len(knots) - 1))
    for i in range(len(knots) - 1):
        basis[:, i] = (knots[i] <= u) & (u < knots[i + 1])
    last = u >= 1.0  # u = 1 belongs to the last span
    basis[last, n - 1] = 1.0
    basis[last, n:] = 0.0
    for p in range(1, k + 1):
        nxt = np.zeros((samples, len(knots) - 1 - p))
        for i in range(len(knots) - 1 - p):
            d1 = knots[i + p] - knots[i]
            d2 = knots[i + p + 1] - knots[i + 1]
            a = (u - knots[i]) / d1 * basis[:, i] if d1 > 0 else 0.0
            b = (knots[i + p + 1] - u) / d2 * basis[:, i + 1] if d2 > 0 else 0.0
            nxt[:, i] = a + b
        basis = nxt
    return basis[:, :n] @ points


def _numbers(line: str) -> list[float]:
    out = []
    for w in line.replace(",", " ").split():
        try:
            out.append(float(w))
        except ValueError:
            break
    return out


def _read_points(lines: list[str], at: int, path: Path, dims: int) -> tuple[np.ndarray, int]:
    """The control points after a ``points: n`` line at ``at`` (with multiplicities)."""
    try:
        n = int(lines[at].split(":", 1)[1].split()[0])
    except (IndexError, ValueError):
        raise SylvaError(f"{path}:{at + 1}: expected 'points: n'") from None
    pts: list = []
    k = at + 1
    read = 0
    while read < n and k < len(lines):
        nums = _numbers(lines[k])
        k += 1
        if not nums:  # range:, dimension:, type: … between the count and the points
            continue
        read += 1
        coords = (nums + [0.0] * dims)[:dims]
        mult = int(nums[dims]) if len(nums) > dims and nums[dims] >= 1 else 1
        pts.extend([coords] * mult)
    if not pts:
        raise SylvaError(f"{path}:{at + 1}: no points")
    return np.array(pts, np.float64), k


def _bisect(pts: np.ndarray, x: np.ndarray) -> np.ndarray:
    """cpfg's value of the function of control ``pts`` at ``x`` (in [0, 1]): bisect the
    spline's parameter until its x is within 0.001 of ``x``, take its y there."""
    x = np.asarray(x, np.float64)
    low, high = np.zeros_like(x), np.ones_like(x)
    y = np.zeros_like(x)
    todo = np.ones(x.shape, bool)
    for _ in range(64):  # 2**-64: every x is found long before
        if not todo.any():
            break
        check = (low[todo] + high[todo]) / 2.0
        p = _bspline_at(pts, check)
        over = p[:, 0] > x[todo]
        high[todo] = np.where(over, check, high[todo])
        low[todo] = np.where(over, low[todo], check)
        y[todo] = p[:, 1]
        near = np.abs(p[:, 0] - x[todo]) <= 0.001
        idx = np.flatnonzero(todo)
        todo[idx[near]] = False
    return y


def _function(lines: list[str], start: int, path: Path, samples: int = -1):
    """The function (x -> y) whose ``points:`` line is at or after ``start``; ``samples``:
    cpfg's table size (none when 2 or less)."""
    k = start
    while k < len(lines) and not lines[k].strip().lower().startswith("points:"):
        k += 1
    if k == len(lines):
        raise SylvaError(f"{path}: expected a 'points:' line of a function")
    pts, end = _read_points(lines, k, path, 2)
    pts = pts.astype(np.float32).astype(np.float64)  # cpfg reads them as floats
    table = _bisect(pts, np.arange(samples) / (samples - 1)) if samples > 2 else None

    def f(v, _pts=pts, _table=table):
        v = np.clip(np.asarray(v, np.float64), 0.0, 1.0)
        if _table is None:
            return _bisect(_pts, v.reshape(-1)).reshape(v.shape)
        index = v * (len(_table) - 1)
        i = np.minimum(np.floor(index).astype(np.int64), len(_table) - 1)
        j = np.minimum(i + 1, len(_table) - 1)
        w2 = index - i
        return (1.0 - w2) * _table[i] + w2 * _table[j]

    f.cpfg_name = None
    return f, end


def _read_func_file(path: Path, samples: int = -1) -> list:
    lines = path.read_text("latin-1").splitlines()
    out, k = [], 0
    gallery = lines and lines[0].strip().lower().startswith("funcgalleryver")
    name, own = None, None  # a function's own samples: line (fver 1 1) wins over the view's
    while k < len(lines):
        low = lines[k].strip().lower()
        if low.startswith("name:"):
            name = lines[k].split(":", 1)[1].strip() or None
        if low.startswith("samples:"):
            try:
                own = int(low.split(":", 1)[1].split()[0])
            except (IndexError, ValueError):
                raise SylvaError(f"{path}:{k + 1}: expected 'samples: k'") from None
        if low.startswith("points:"):
            f, k = _function(lines, k, path, samples if own is None else own)
            f.cpfg_name = name
            name, own = None, None
            out.append(f)
            if not gallery:
                break
            continue
        k += 1
    if not out:
        raise SylvaError(f"{path}: expected a function ('points:' and its points)")
    return out


def _read_curve(path: Path, samples: int = _CURVE_SAMPLES):
    """``(control points, normalised arc lengths, length)`` of a ``.con`` curve: cpfg's
    arc-length table (``CCurveXYZ::createAPoints``) of ``samples`` spline points at
    ``u = i / (samples - 1)``, chord lengths summed and divided by their total."""
    lines = path.read_text("latin-1").splitlines()
    for k, line in enumerate(lines):
        if line.strip().lower().startswith("points:"):
            pts, _ = _read_points(lines, k, path, 3)
            table = _bspline(pts, max(int(samples), 2))
            seg = np.linalg.norm(np.diff(table, axis=0), axis=1)
            s = np.concatenate([[0.0], np.cumsum(seg)])
            length = float(s[-1])
            return pts, (s / length if length > 0.0 else s), length
    raise SylvaError(f"{path}: expected a curve ('points:' and its points)")


def _curve_point(curve, t) -> np.ndarray:
    """The point at the fraction ``t`` (clipped to [0, 1]) of a curve's length, as cpfg's
    ``calcAValue``: the table's bracket of ``t`` found by bisection, the spline parameter
    interpolated linearly in the table's index, and the spline evaluated there."""
    pts, lnorm, _ = curve
    t = np.clip(np.asarray(t, np.float64).reshape(-1), 0.0, 1.0)
    n = len(lnorm)
    lo = np.clip(np.searchsorted(lnorm, t, side="right") - 1, 0, n - 2)
    span = lnorm[lo + 1] - lnorm[lo]
    frac = np.divide(t - lnorm[lo], span, out=np.zeros_like(t), where=span > 0.0)
    return _bspline_at(pts, np.clip((lo + frac) / (n - 1), 0.0, 1.0))


def load_functions(view: Path | None) -> dict:
    """``func``, ``curveX`` … for the files a view file names (empty without any)."""
    if view is None or not Path(view).is_file():
        return {}
    view = Path(view)
    funcs: list = []
    curves: list = []
    for line in view.read_text("latin-1").splitlines():
        text = line.split("//")[0].split("/*")[0].strip()
        low = text.lower()
        if ":" not in low:
            continue
        key, value = (t.strip() for t in text.split(":", 1))
        key = " ".join(key.lower().split())
        words = value.split()
        if key in ("function", "function set") and words:
            n = int(words[1]) if key == "function" and words[1:] and words[1].isdigit() else -1
            funcs.extend(_read_func_file(view.parent / words[0], n))
        elif key == "curve" and words:
            n = int(words[1]) if words[1:] and words[1].isdigit() else _CURVE_SAMPLES
            curves.append(_read_curve(view.parent / words[0], n))
    out: dict = {}
    if funcs:
        def func(k, x, _f=funcs):
            k = np.asarray(k, np.float64).reshape(-1)
            idx = int(k[0]) if k.size else 0
            if not 1 <= idx <= len(_f):
                raise SylvaError(f"func({idx}, …): the view file names {len(_f)} "
                                 f"function(s); expected 1..{len(_f)}")  # fmt: skip
            return _f[idx - 1](x)

        out["func"] = func
        #: cpfg names a function by its number or by its name: func(BR_ANGLE, x)
        out["__ids__"] = {f.cpfg_name: k + 1 for k, f in enumerate(funcs) if f.cpfg_name}
    if curves:
        def pick(k):
            idx = int(np.asarray(k, np.float64).reshape(-1)[0])
            if not 1 <= idx <= len(curves):
                raise SylvaError(f"curve {idx}: the view file names {len(curves)} curve(s)")
            return curves[idx - 1]

        def coord(axis):
            def f(k, t):
                v = _curve_point(pick(k), t)[:, axis]
                return v[0] if np.ndim(t) == 0 else v.reshape(np.shape(t))

            return f

        out["curveX"], out["curveY"], out["curveZ"] = coord(0), coord(1), coord(2)
        out["curveGAL"] = lambda k: pick(k)[2]
    return out
