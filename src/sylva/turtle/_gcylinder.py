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
the spheres out again and adds the curve's segments.  ``@Gr`` (radius tangents) is read and
not drawn: the radius is linear.  The section is round (the branch mesh's tube) unless a
control point at either end of a piece is in a contour: cpfg's ``@#(id)`` selects the view
file's ``contour: id file`` for the control points after it (kept and restored by ``[ ]``;
``@#(0)`` or ``@#`` is the circle; an id the view file lacks draws the circle, as cpfg does,
with a :class:`~sylva.errors.SylvaWarning`), and the piece is drawn as polygons: at each
curve point a ring of the contour's points (:func:`contour_ring`: cpfg's ``MakeContour``, 8
points, cpfg's ``contour sides`` default) scaled by the radius, ``x`` along the turtle's up
``U`` and ``y`` against its left ``L``; between two contours the rings mix linearly.  As in
cpfg, ``F`` cylinders stay round (cpfg's ``F`` ignores ``@#``).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import SylvaWarning
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
    #: each control point's contour id (``@#``), for the points that have one other than 0
    contour: dict[int, int] = field(default_factory=dict)


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
    hash_ = alpha.get("#")
    if hash_ >= 0:  # @#(id): the turtle's contour, for the control points after it
        sel = np.flatnonzero((ids[: max(n - 1, 0)] == at) & (ids[1:] == hash_))
        kind_of.update(dict.fromkeys(sel.tolist(), "#"))
        marks = np.union1d(marks, sel)
    events = np.union1d(np.flatnonzero((ids == 0) | (ids == 1)), marks).tolist()
    spans: list[tuple[int, int, int, float, float]] = []
    points: list[int] = []
    depth: dict[int, int] = {}
    contour: dict[int, int] = {}
    # the turtle's cylinder state: open, the last control point and its leaving
    # coefficient, and the coefficients (arriving, leaving) @Gt set; its contour id
    state = (False, -1, DEFAULT_TANGENT, (DEFAULT_TANGENT, DEFAULT_TANGENT))
    cid = 0
    stack = []
    for p in events:
        c = ids[p]
        if c == 0:
            stack.append((state, cid))
            continue
        if c == 1:
            if stack:
                state, cid = stack.pop()
            continue
        kind = kind_of[p]
        if kind == "#":  # cpfg: @# without a parameter (or @#(0)) is the default circle
            k = _param(word, p + 1, 0)
            cid = 0 if k is None else int(k)
            continue
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
        if cid:
            contour[p] = cid
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
        spans, np.asarray(points, np.int64), depth, contour
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


#: cpfg's B-spline basis (``general.c``'s uniform cubic B-spline), rows for t³, t², t, 1.
_BSPLINE = np.array([[-1.0, 3.0, -3.0, 1.0], [3.0, -6.0, 3.0, 0.0], [-3.0, 0.0, 3.0, 0.0],
                     [1.0, 4.0, 1.0, 0.0]]) / 6.0  # fmt: skip
#: Samples per unit of the contour's parameter for its arc length (cpfg: 10).
_CONTOUR_STEPS = 64


def _bspline(pts: np.ndarray, t: np.ndarray) -> np.ndarray:
    first = np.floor(t).astype(np.int64)
    lt = (t - first)[:, None]
    w = np.hstack([lt**3, lt**2, lt, np.ones_like(lt)]) @ _BSPLINE
    idx = (first[:, None] + np.arange(4)) % pts.shape[0]  # cpfg wraps past the last point
    return np.einsum("nk,nkc->nc", w, pts[idx])


def contour_ring(contour, sides: int) -> np.ndarray:
    """The ``sides + 1`` points ``(x, y, z)`` of a cross-section, as cpfg's ``MakeContour``
    places them: the contour's B-spline stepped at equal arc lengths (in x, y) from its
    start, a closed one turned about z so that its start lies on +x and its last point
    repeating the first; ``None`` (cpfg's contour 0) is the unit circle from +x.
    """
    if contour is None:
        a = 2.0 * np.pi * np.arange(sides + 1) / sides
        ring = np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], axis=1)
        ring[sides] = ring[0]
        return ring
    pts = np.asarray(contour.points, np.float64).reshape(-1, 3)
    closed = bool(contour.closed)
    segments = pts.shape[0] if closed else pts.shape[0] - 3
    if segments < 1:  # an open contour of under 4 points: its polygon
        t = np.arange(pts.shape[0], dtype=np.float64)
        curve, ts = pts, t
    else:
        ts = np.arange(segments * _CONTOUR_STEPS + 1) / _CONTOUR_STEPS
        curve = _bspline(pts, ts)
    step = np.sqrt(np.einsum("ij,ij->i", *(2 * [np.diff(curve[:, :2], axis=0)])))
    length = np.concatenate([[0.0], np.cumsum(step)])
    total = float(length[-1])
    target = total * np.arange(sides + 1) / sides
    t = np.interp(target, length, ts)
    ring = (
        _bspline(pts, t)
        if segments >= 1
        else np.stack([np.interp(t, ts, curve[:, c]) for c in range(3)], axis=1)
    )
    if closed:
        x0, y0 = ring[0, 0], ring[0, 1]
        n0 = float(np.hypot(x0, y0))
        if n0 > 1e-9:
            c, s = x0 / n0, -y0 / n0  # the turn taking the start onto +x
            x, y = ring[:, 0].copy(), ring[:, 1].copy()
            ring[:, 0], ring[:, 1] = c * x - s * y, s * x + c * y
        ring[sides] = ring[0]
    return ring


def _turn1(v: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``v`` turned by the least rotation taking unit ``a`` onto unit ``b``."""
    ax, ay, az = float(a[0]), float(a[1]), float(a[2])
    bx, by, bz = float(b[0]), float(b[1]), float(b[2])
    kx, ky, kz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    sn = math.sqrt(kx * kx + ky * ky + kz * kz)
    cs = ax * bx + ay * by + az * bz
    if sn < 1e-12:
        return v if cs > 0 else -v
    kx, ky, kz = kx / sn, ky / sn, kz / sn
    vx, vy, vz = float(v[0]), float(v[1]), float(v[2])
    kv = (kx * vx + ky * vy + kz * vz) * (1.0 - cs)
    return np.array([vx * cs + (ky * vz - kz * vy) * sn + kx * kv,
                     vy * cs + (kz * vx - kx * vz) * sn + ky * kv,
                     vz * cs + (kx * vy - ky * vx) * sn + kz * kv])  # fmt: skip


def _contour_of(cid: int, table: dict, p: int, unknown: set):
    if cid == 0:
        return None
    c = table.get(cid)
    if c is None and cid not in unknown:
        unknown.add(cid)
        known = ", ".join(str(k) for k in sorted(table)) or "none"
        warnings.warn(
            f"module {p} of the word: a control point in contour {cid}, which the "
            f"view file does not define (its contour: ids: {known}); drawn with "
            "the default circle, as cpfg does",
            SylvaWarning,
            stacklevel=5,
        )
    return c


def _contour_quads(rows, strips, tr_pos, tr_frame, radius, ring):
    """The quads of contoured cylinder pieces of ``strips`` strips each (``rows``: m0, m1,
    |T0|, |T1|, d, ring ids at both ends): at each curve point ``p(k/strips)`` a ring of the
    cross-section mixed between the ends' (``ring``: the rings by id), scaled by the radius,
    in the start's frame turned onto the curve's heading."""
    m0, m1 = rows[:, 0].astype(np.int64), rows[:, 1].astype(np.int64)
    t0, t1, d = rows[:, 2:3], rows[:, 3:4], rows[:, 4]
    h0, l0, u0, spin = tr_frame[m0, 0], rows[:, 7:10], rows[:, 10:13], rows[:, 13]
    h1 = tr_frame[m1, 0]
    p0, p1 = tr_pos[m0], tr_pos[m1]
    t = np.linspace(0.0, 1.0, strips + 1)[None, :, None]
    t2, t3 = t * t, t * t * t
    T0, T1 = (h0 * t0)[:, None], (h1 * t1)[:, None]
    P0, P1 = p0[:, None], p1[:, None]
    pts = ((2 * t3 - 3 * t2 + 1) * P0 + (t3 - 2 * t2 + t) * T0 + (-2 * t3 + 3 * t2) * P1
           + (t3 - t2) * T1)  # fmt: skip
    tan = ((6 * t2 - 6 * t) * P0 + (3 * t2 - 4 * t + 1) * T0 + (-6 * t2 + 6 * t) * P1
           + (3 * t2 - 2 * t) * T1)  # fmt: skip
    norm = np.linalg.norm(tan, axis=2, keepdims=True)
    heads = np.where(norm > 1e-12, tan / np.maximum(norm, 1e-300), h0[:, None])
    heads[:, 0] = h0
    # the least rotation taking H0 onto each heading (cpfg's adjust_up_and_leftS)
    axis = np.cross(h0[:, None], heads)
    sn = np.linalg.norm(axis, axis=2, keepdims=True)
    cs = np.einsum("nkc,nc->nk", heads, h0)[..., None]
    k = axis / np.where(sn < 1e-12, 1.0, sn)

    def turn(v):
        v = v[:, None]
        out = v * cs + np.cross(k, v) * sn + k * np.sum(k * v, axis=2, keepdims=True) * (1 - cs)
        return np.where(sn < 1e-12, np.where(cs > 0, v, -v), out)

    up, left = turn(u0), turn(l0)
    up[:, 0], left[:, 0] = u0, l0
    if np.any(spin != 0.0):  # twist of cylinders: on, the frame turned about the heading
        a = spin[:, None, None] * t
        ca, sa = np.cos(a), np.sin(a)
        up = up * ca + np.cross(heads, up) * sa  # up and left stay normal to the heading
        left = left * ca + np.cross(heads, left) * sa
    w = t[..., None]
    sec = ring[rows[:, 5].astype(np.int64)][:, None] * (1 - w) + ring[
        rows[:, 6].astype(np.int64)][:, None] * w  # fmt: skip
    r0 = np.asarray([radius[m] for m in m0.tolist()])
    r1 = np.asarray([radius[m] for m in m1.tolist()])
    rad = (r0[:, None] + (r1 - r0)[:, None] * t[..., 0])[..., None, None]
    r = rad * sec  # (pieces, strips + 1, sides + 1, 3)
    v = (pts[:, :, None] + r[..., :1] * up[:, :, None] - r[..., 1:2] * left[:, :, None]
         + r[..., 2:3] * heads[:, :, None] / d[:, None, None, None])  # fmt: skip
    i = np.arange(ring.shape[1] - 1)
    quads = np.stack([v[:, :-1, i], v[:, :-1, i + 1], v[:, 1:, i + 1], v[:, 1:, i]], axis=3)
    return quads.reshape(-1, 4, 3)


def splice(
    out: tuple,
    cyl: Cylinders,
    keep_trace: bool,
    contours: dict | None = None,
    sides: int = 8,
    twist: bool = False,
) -> tuple:
    """The walked word's records ``out`` (:func:`~sylva.turtle._kernels.finish_word`)
    without the marker spheres and with the cylinders' segments; the trace kept only when
    ``keep_trace``.  A piece whose control point at either end is in a contour of
    ``contours`` (id -> :class:`~sylva.lsystem.dialects._cpfg_contour.Contour`, ``@#``) is
    drawn as polygons: ``sides`` quads between consecutive rings, each ring the contour
    (between two contours, their points mixed linearly along the piece) scaled by the
    radius and placed as ``position + r·(x·U − y·L)`` in the turtle's frame, the frame at a
    curve point turned from the start's onto the curve's heading (cpfg's twist off)."""
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
    pieces = {}  # strips -> the contoured pieces: m0, m1, |T0|, |T1|, d, ring ids, L, U, spin
    frame_of = {}  # control point -> the cylinder's (L, U) there (twist of cylinders: off)
    table, unknown, rings = dict(contours or {}), set(), {}
    end_of = {}
    n0 = out[0].shape[0]
    for m0, m1, strips, b0, a1 in cyl.spans:
        if m0 not in radius or m1 not in radius:  # a point the walk did not reach (% cut)
            continue
        p0, p1 = tr_pos[m0], tr_pos[m1]
        d = float(np.linalg.norm(p1 - p0))
        if d < 1e-5:  # cpfg draws nothing between coinciding points
            continue
        if cyl.contour:
            # the ring's frame (L, U) at m0: carried along the cylinder from @Gs, turned
            # onto each control point's heading (cpfg's twist of cylinders: off), or the
            # turtle's own at every point, turned about the heading in between (on)
            h0, h1 = tr_frame[m0, 0], tr_frame[m1, 0]
            l0, u0 = (tr_frame[m0, 1], tr_frame[m0, 2]) if twist else frame_of.get(
                m0, (tr_frame[m0, 1], tr_frame[m0, 2]))  # fmt: skip
            u1 = _turn1(u0, h0, h1)
            frame_of[m1] = (_turn1(l0, h0, h1), u1)
            spin = 0.0
            if twist:
                own = tr_frame[m1, 2]
                spin = math.atan2(float(np.cross(u1, own) @ h1), float(u1 @ own))
            c0 = _contour_of(cyl.contour.get(m0, 0), table, m0, unknown)
            c1 = _contour_of(cyl.contour.get(m1, 0), table, m1, unknown)
            if c0 is not None or c1 is not None:
                for c in (c0, c1):
                    if id(c) not in rings:
                        rings[id(c)] = (len(rings), contour_ring(c, sides))
                pieces.setdefault(strips, []).append(
                    (m0, m1, d * b0, d * a1, d, rings[id(c0)][0], rings[id(c1)][0], *l0, *u0,
                     spin))  # fmt: skip
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
    if pieces:
        ring = np.stack([r for _, r in sorted(rings.values(), key=lambda x: x[0])])
        quads, mods = [], []
        for strips, rows_ in pieces.items():
            quads.append(_contour_quads(np.asarray(rows_), strips, tr_pos, tr_frame, radius,
                                        ring))  # fmt: skip
            mods.append(np.repeat(np.asarray([r[:2] for r in rows_], np.int64),
                                  strips * (ring.shape[1] - 1), axis=0))  # fmt: skip
        quads, mods = np.concatenate(quads), np.concatenate(mods)
        base = out[16][-1] if out[16].shape[0] else 0
        off = base + 4 * np.arange(1, quads.shape[0] + 1)
        out[15] = np.concatenate([out[15], quads.reshape(-1, 3).astype(out[15].dtype)])
        out[16] = np.concatenate([out[16] if out[16].shape[0] else [0], off]).astype(out[16].dtype)
        first = mods[:, 0].tolist()
        out[17] = np.concatenate([out[17], np.asarray([colour[m] for m in first],
                                                      out[17].dtype)])  # fmt: skip
        out[18] = np.concatenate([out[18], np.asarray([material[m] for m in first],
                                                      out[18].dtype)])  # fmt: skip
        out[19] = np.concatenate([out[19], mods[:, 1].astype(out[19].dtype)])
    if not keep_trace:
        out[24], out[25] = tr_pos[:0], tr_frame[:0]
    return tuple(out)
