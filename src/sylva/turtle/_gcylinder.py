"""cpfg's generalised cylinders: Hermite curves through ``@Gs … @Gc … @Ge``.

cpfg (``general.c``: ``SetControlPoint``, ``interpolate_connection``; CPFG manual §6.7.3)
starts a cylinder at ``@Gs``, adds a control point at each ``@Gc(n)`` and ends it at
``@Ge(n)``; ``f`` only moves the turtle between them and ``F`` draws its own segment as
anywhere.  Between two control points ``P0`` (heading ``H0``) and ``P1`` (``H1``), ``d =
|P1 − P0|`` apart, the axis is the cubic Hermite curve

    p(t) = (2t³ − 3t² + 1) P0 + (t³ − 2t² + t) T0 + (−2t³ + 3t²) P1 + (t³ − t²) T1

with the tangents ``T0 = b0·d·H0`` and ``T1 = a1·d·H1``, where ``@Gt(a, b)`` (default 1.2,
1.2; ``@Gt(a)``: ``b = a``) sets a turtle's coefficients for the tangent arriving at its
control points (``a``) and leaving them (``b``), as cpfg from version 3.4 reads them.  The
curve is drawn as ``n`` tube segments through ``p(k/n)``, ``k = 0 … n`` (``n``: the
parameter of the ``@Gc`` / ``@Ge`` that ends it; without one, 4), their radius going
linearly from the width at ``P0`` to the width at ``P1``, in the colour of ``P0``.  The
state is the turtle's: a branch ``[ … ]`` continues a copy of the open cylinder from its
last control point, and after ``]`` the cylinder goes on from its own.

How it is drawn: :func:`control_word` turns each control point's ``@G`` into ``@O`` (a
sphere of the turtle's radius, recording where the point is, its radius and colour), the
word is walked with its trace (the turtle's frame at the point), and :func:`splice` takes
the spheres out again and adds the curve's segments.  ``@Gr`` (radius tangents) and the
view file's contours are read and not drawn: the radius is linear and the section round.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..lsystem.lstring import ModuleString

#: Strips between two control points when the module gives none (cpfg's DEFAULT_RINGS).
DEFAULT_STRIPS = 4
#: cpfg's default tangent coefficients.
DEFAULT_TANGENT = 1.2


@dataclass(frozen=True)
class Cylinders:
    """The curve pieces of a word's cylinders.

    ``spans`` rows: the ``@`` module of the start and end control point, the strips, the
    start's leaving coefficient and the end's arriving one.  ``points``: every control
    point's ``@`` module (their marker spheres are dropped from the drawing).
    """

    spans: list[tuple[int, int, int, float, float]]
    points: np.ndarray
    depth: dict[int, int]


def _param(word: ModuleString, j: int, k: int) -> float | None:
    if word.values.size == 0 or j >= len(word):
        return None
    a, b = int(word.offsets[j]), int(word.offsets[j + 1])
    return float(word.values[a + k]) if b - a > k else None


def control_word(word: ModuleString) -> tuple[ModuleString, Cylinders | None]:
    """``word`` with each control point's ``@G`` made ``@O``, and its cylinders (``word``
    itself and ``None`` when it opens none)."""
    alpha = word.alphabet
    at, g = alpha.get("@"), alpha.get("G")
    if min(at, g) < 0:
        return word, None
    ids = word.ids
    n = ids.shape[0]
    marks = np.flatnonzero((ids[: max(n - 2, 0)] == at) & (ids[1 : max(n - 1, 1)] == g))
    if marks.size == 0:
        return word, None
    letter = {alpha.get(c): c for c in "sceto" if alpha.get(c) >= 0}
    kinds = [letter.get(int(ids[m + 2])) for m in marks.tolist()]
    if not any(k in ("s", "c", "e") for k in kinds):
        return word, None
    kind_of = dict(zip(marks.tolist(), kinds, strict=True))
    events = np.union1d(np.flatnonzero((ids == 0) | (ids == 1)), marks).tolist()
    spans: list[tuple[int, int, int, float, float]] = []
    points: list[int] = []
    depth: dict[int, int] = {}
    # the turtle's cylinder state: open, the last control point and its leaving
    # coefficient, and the coefficients (arriving, leaving) @Gt set
    state = (False, -1, DEFAULT_TANGENT, (DEFAULT_TANGENT, DEFAULT_TANGENT))
    stack = []
    for p in events:
        c = ids[p]
        if c == 0:
            stack.append(state)
            continue
        if c == 1:
            if stack:
                state = stack.pop()
            continue
        kind = kind_of[p]
        open_, last, leave, tan = state
        if kind == "t":
            a = _param(word, p + 2, 0)
            if a is not None:
                b = _param(word, p + 2, 1)
                tan = (a, a if b is None else b)
            state = (open_, last, leave, tan)
            continue
        if kind not in ("s", "c", "e"):
            continue
        points.append(p)
        depth[p] = len(stack)
        if kind == "s" or not open_ or last < 0:
            state = (kind != "e", p, tan[1], tan)  # the first point
            continue
        strips = _param(word, p + 2, 0)
        strips = int(strips) if strips is not None and strips >= 1 else DEFAULT_STRIPS
        spans.append((last, p, strips, leave, tan[0]))
        state = (kind != "e", p, tan[1], tan)
    if not points:
        return word, None
    new = ids.copy()
    new[np.asarray(points) + 1] = alpha.id("O")
    return ModuleString(alpha, new, word.offsets, word.values), Cylinders(
        spans, np.asarray(points, np.int64), depth
    )


def _hermite(p0, t0, p1, t1, t):
    t = t[:, None]
    t2 = t * t
    t3 = t2 * t
    return ((2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * t0 + (-2 * t3 + 3 * t2) * p1
            + (t3 - t2) * t1)  # fmt: skip


def _normal(r, d):
    """``r`` made normal to unit ``d`` (any normal when ``r`` is along ``d``)."""
    o = r - (r @ d) * d
    n = np.linalg.norm(o)
    if n < 1e-9:
        o = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0])
        n = np.linalg.norm(o)
    return o / n


def splice(out: tuple, cyl: Cylinders, keep_trace: bool) -> tuple:
    """The walked word's records ``out`` (:func:`~sylva.turtle._kernels.finish_word`)
    without the marker spheres and with the cylinders' segments; the trace kept only when
    ``keep_trace``."""
    out = list(out)
    tr_pos, tr_frame = out[24], out[25]
    poly_v, poly_off, poly_col, poly_mat, poly_mod = out[15:20]
    marker = np.isin(poly_mod, cyl.points)
    radius, colour, material = {}, {}, {}
    if marker.any():
        for q in np.flatnonzero(marker).tolist():
            m = int(poly_mod[q])
            if m not in radius:
                v = poly_v[poly_off[q]]
                radius[m] = float(np.linalg.norm(v - tr_pos[m]))
                colour[m] = poly_col[q]
                material[m] = poly_mat[q]
        keep = ~marker
        sizes = np.diff(poly_off)
        vkeep = np.repeat(keep, sizes)
        out[15] = poly_v[vkeep]
        out[16] = np.concatenate([[0], np.cumsum(sizes[keep])]).astype(poly_off.dtype)
        out[17], out[18], out[19] = poly_col[keep], poly_mat[keep], poly_mod[keep]
    rows = []  # start, end, r0, r1, colour, material, module, parent (-1 / previous), ref
    end_of = {}
    n0 = out[0].shape[0]
    for m0, m1, strips, b0, a1 in cyl.spans:
        if m0 not in radius or m1 not in radius:  # a point the walk did not reach (% cut)
            continue
        p0, p1 = tr_pos[m0], tr_pos[m1]
        d = float(np.linalg.norm(p1 - p0))
        if d < 1e-5:  # cpfg draws nothing between coinciding points
            continue
        t = np.linspace(0.0, 1.0, strips + 1)
        pts = _hermite(p0, tr_frame[m0, 0] * d * b0, p1, tr_frame[m1, 0] * d * a1, t)
        rad = radius[m0] + (radius[m1] - radius[m0]) * t
        parent = end_of.get(m0, -1)
        ref = tr_frame[m0, 1]
        for k in range(strips):
            seg = pts[k + 1] - pts[k]
            ln = float(np.linalg.norm(seg))
            if ln < 1e-12:
                continue
            ref = _normal(ref, seg / ln)
            rows.append((pts[k], pts[k + 1], rad[k], rad[k + 1], colour[m0], material[m0],
                         m1, parent, ref))  # fmt: skip
            parent = n0 + len(rows) - 1
        end_of[m1] = parent
    if rows:
        start = np.array([r[0] for r in rows])
        end = np.array([r[1] for r in rows])
        seg = (start, end, np.array([[r[2], r[3]] for r in rows]),
               np.array([r[4] for r in rows]), np.array([r[5] for r in rows]),
               np.array([r[6] for r in rows]), np.array([r[7] for r in rows]),
               np.array([cyl.depth[r[6]] for r in rows]),
               np.array([r[8] for r in rows]))  # fmt: skip
        for f in range(9):
            part = seg[f].astype(out[f].dtype, copy=False)
            out[f] = np.concatenate([out[f], part.reshape((-1, *out[f].shape[1:]))])
    if not keep_trace:
        out[24], out[25] = tr_pos[:0], tr_frame[:0]
    return tuple(out)
