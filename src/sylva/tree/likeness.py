"""How much a grown tree looks like its own Weber–Penn envelope, seen from the side.

A species' parameters promise a silhouette: the crown starts at ``BaseSize`` of the trunk
and its half-width at a height follows ``ShapeRatio(Shape, ·)`` of the distance below the
top (Weber & Penn 1995 §4.1: the length of the trunk's branches); with pruning
(``PruneRatio`` > 0) it is the pruning envelope, ``PruneWidth · Scale · ShapeRatio(8, ·)``.
:func:`likeness` rasterises the tree's geometry (stem points and leaf blades, projected on
the ``x``–``y`` plane: a side view) and the envelope's outline on one grid with numpy and
compares them: crown base height, crown width / height and the intersection over union.

Examples
--------
>>> from sylva.tree import Tree
>>> r = likeness(Tree("sphere_tree", seed=1, quality=0.3).grow())
>>> 0.0 <= r.iou <= 1.0 and r.height > 0
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .weber_penn import envelope, shape_ratio

__all__ = ["Likeness", "envelope_mask", "likeness", "side_mask"]


@dataclass
class Likeness:
    """The measured silhouette against the envelope (metres; fractions of the height).

    Attributes
    ----------
    height : float
        Top of the tree.
    crown_base : float
        Height below which at most 3 % of the foliage and branches' side area lies,
        over ``height``.
    expected_base : float
        ``BaseSize`` (of the trunk's length), over ``height``; for a palm (``BaseSize`` >=
        0.8, a rosette of fronds) the lowest point of its fronds laid straight.
    width_ratio : float
        Crown width / height (the 98th percentile of ``|x|`` on each side).
    expected_width_ratio : float
        The envelope's width / height: with pruning ``2 · PruneWidth · Scale / height``;
        without, ``2 · max`` over the trunk of the reach of its branches laid straight at
        their down angle (``Length₁ · L₀ · ShapeRatio · sin DownAngle``), over ``height``;
        for a palm, the span of its rosette envelope.
    iou : float
        Intersection over union of the side silhouette and the envelope outline, the
        envelope's width set to the measured crown's (the shape is what is compared).
    """

    height: float
    crown_base: float
    expected_base: float
    width_ratio: float
    expected_width_ratio: float
    iou: float
    mask: np.ndarray
    envelope: np.ndarray


def _points(tree) -> tuple[np.ndarray, float]:
    geo = tree.geometry()
    pts = [geo.joint_matrix[:, :3, 3]]
    trunk_top = float(pts[0][geo.joint_level == 0, 1].max()) if len(pts[0]) else 0.0
    if geo.n_leaves:
        live = geo.leaf_size > 0
        f, s, p = geo.leaf_frame[live], geo.leaf_size[live], geo.leaf_pos[live]
        for a in (0.5, 1.0):  # the blade's middle and tip
            pts.append(p + f[:, :, 1] * (a * s)[:, None])
    return np.concatenate(pts), trunk_top


def side_mask(points: np.ndarray, extent: tuple[float, float, float], n: int = 64) -> np.ndarray:
    """``bool[n, n]`` (row 0 at the bottom): cells of the side view (``x`` across, ``y`` up)
    covered by ``points``, on the square ``[-half, half] × [y0, y0 + 2·half]`` given as
    ``extent = (half, y0, _)``, closed by one cell (gaps between twigs filled)."""
    half, y0, _ = extent
    cell = 2.0 * half / n
    ix = np.floor((points[:, 0] + half) / cell).astype(np.int64)
    iy = np.floor((points[:, 1] - y0) / cell).astype(np.int64)
    ok = (ix >= 0) & (ix < n) & (iy >= 0) & (iy < n)
    m = np.zeros((n, n), bool)
    m[iy[ok], ix[ok]] = True
    # closing: dilate by one cell then erode by one cell
    d = m.copy()
    d[1:] |= m[:-1]
    d[:-1] |= m[1:]
    d[:, 1:] |= m[:, :-1]
    d[:, :-1] |= m[:, 1:]
    e = d.copy()
    e[1:] &= d[:-1]
    e[:-1] &= d[1:]
    e[:, 1:] &= d[:, :-1]
    e[:, :-1] &= d[:, 1:]
    return e | m


def _expected_half_width(tree, trunk_len: float) -> float:
    """The straight-branch reach of the trunk's branches (see :class:`Likeness`)."""
    pm = tree.params
    if tree.levels < 2:
        return 0.0
    l1 = pm.float("Length", level=1, default=0.5).value
    down = pm.float("DownAngle", level=1, default=45.0)
    base = tree.base_size * trunk_len
    best = 0.0
    for r in np.linspace(0.0, 1.0, 41):  # r: from the top (0) to the crown base (1)
        s = trunk_len - r * (trunk_len - base)
        length = l1 * trunk_len * shape_ratio(tree.shape, r, tree.prune)
        if down.deviation >= 0:
            theta = down.value
        else:
            theta = down.value + down.deviation * (1.0 - 2.0 * shape_ratio(0, r))
        reach = length * abs(np.sin(np.radians(theta)))
        if s >= 0:
            best = max(best, reach)
    return best


def envelope_mask(tree, height: float, half_width: float, extent, n: int = 64,
                  trunk_top: float | None = None) -> np.ndarray:
    """``bool[n, n]``: the envelope outline of ``tree`` (see the module docstring) for a tree
    ``height`` tall whose crown is ``half_width`` wide at its widest, on the grid of
    :func:`side_mask`; ``trunk_top`` (default ``height``) is where a palm's trunk ends."""
    half, y0, _ = extent
    cell = 2.0 * half / n
    y = y0 + (np.arange(n) + 0.5) * cell
    x = -half + (np.arange(n) + 0.5) * cell
    if tree.base_size >= 0.8 and tree.levels >= 2:
        return _rosette_mask(tree, height if trunk_top is None else trunk_top, x, y)
    if tree.prune_ratio > 0:
        st = tree.scale_tree * tree.zscale
        ratio = (st - y) / (st * max(1.0 - tree.base_size, 1e-9))
        w = envelope(ratio, tree.prune)
        w = w / max(float(w.max()), 1e-9) * half_width
    else:
        base = tree.base_size * height
        ratio = (height - y) / max(height - base, 1e-9)
        w = np.array([shape_ratio(tree.shape, min(max(r, 0.0), 1.0), tree.prune) for r in ratio])
        w = np.where((ratio >= 0) & (ratio <= 1), w, 0.0)
        w = w / max(float(w.max()), 1e-9) * half_width
    return np.abs(x)[None, :] <= w[:, None]


def _rosette_mask(tree, trunk_top: float, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """A palm's envelope (``BaseSize`` >= 0.8: the crown is a rosette at the top): the fronds
    laid out at their down angle, bent by their ``Curve`` (and ``CurveBack``), from their
    place on the trunk, with a fan palm's fan (``LeafScale``) round each tip, filled
    across."""
    pm = tree.params
    l1 = pm.float("Length", level=1, default=0.5).value
    down = pm.float("DownAngle", level=1, default=45.0)
    trunk = tree.root.plan.length
    base = tree.base_size * trunk
    lo = np.full(len(y), np.inf)
    hi = np.full(len(y), -np.inf)
    curve = pm.float("Curve", level=1, default=0.0).value
    back = pm.float("CurveBack", level=1, default=0.0).value
    t = np.linspace(0.0, 1.0, 51)
    # the frond's direction along it: Curve over its length (the first half Curve and the
    # second CurveBack when CurveBack is set), as the stems are drawn
    bend = np.where(t < 0.5, 2.0 * curve * t, curve + 2.0 * back * (t - 0.5)) if back \
        else curve * t
    for r in np.linspace(0.0, 1.0, 21):
        length = l1 * trunk * shape_ratio(tree.shape, r, tree.prune)
        theta = down.value if down.deviation >= 0 else \
            down.value + down.deviation * (1.0 - 2.0 * shape_ratio(0, r))
        ys = (trunk - r * (trunk - base)) * trunk_top / max(trunk, 1e-9)
        a = np.radians(np.abs(theta + bend))
        step = length / (len(t) - 1)
        px = np.concatenate([[0.0], np.cumsum(np.sin(a[1:]) * step)])
        py = ys + np.concatenate([[0.0], np.cumsum(np.cos(a[1:]) * step)])
        if tree.leaf_arrangement == "fan":  # the fan of leaves spreads round the tip
            reach = pm.float("LeafScale", default=0.2).value
            c = np.linspace(0.0, 2.0 * np.pi, 24)
            px = np.concatenate([px, px[-1] + reach * np.abs(np.cos(c))])
            py = np.concatenate([py, py[-1] + reach * np.sin(c)])
        iy = np.searchsorted(y, py)
        for a, b in zip(iy, px, strict=True):
            if 0 <= a < len(y):
                lo[a] = min(lo[a], -b)
                hi[a] = max(hi[a], b)
    return (x[None, :] >= lo[:, None]) & (x[None, :] <= hi[:, None])


def likeness(tree, n: int = 64) -> Likeness:
    """Compare a grown tree's side silhouette with its envelope (see :class:`Likeness`)."""
    pts, trunk_top = _points(tree)
    height = float(pts[:, 1].max())
    x = pts[:, 0] - np.median(pts[:, 0])
    pts = np.column_stack([x, pts[:, 1], pts[:, 2]])
    crown = pts[pts[:, 1] > 0.02 * height]
    half_w = 0.5 * (np.percentile(crown[:, 0], 98) - np.percentile(crown[:, 0], 2))
    # the crown base: the height under which 3 % of the silhouette's side area lies (trunk
    # columns excluded: cells within a trunk radius of the axis)
    ext = (max(half_w, 0.5 * height) * 1.1, -0.02 * height, 0)
    mask = side_mask(pts, ext, n)
    cell = 2.0 * ext[0] / n
    cols = np.abs(-ext[0] + (np.arange(n) + 0.5) * cell)
    r0 = tree.root.plan.radius * (1.0 + tree.root.plan.flare)
    off_axis = mask & (cols[None, :] > max(1.5 * r0, cell))
    rows = off_axis.sum(1).astype(np.float64)
    cum = np.cumsum(rows) / max(rows.sum(), 1.0)
    base_row = int(np.searchsorted(cum, 0.03))
    crown_base = (ext[1] + base_row * cell) / height
    trunk_len = tree.root.plan.length
    exp_w = (_expected_half_width(tree, trunk_len) if tree.prune_ratio <= 0
             else tree.prune[0] * tree.scale_tree)
    env = envelope_mask(tree, height, half_w, ext, n, trunk_top)
    expected_base = tree.base_size * trunk_len * tree.zscale / height
    if tree.base_size >= 0.8 and np.any(env):  # a rosette: its lowest frond tips, its span
        expected_base = (ext[1] + int(np.argmax(env.any(1))) * cell) / height
        exp_w = float(cols[env.any(0)].max()) + 0.5 * cell
    inter = np.count_nonzero(mask & env)
    union = np.count_nonzero(mask | env)
    return Likeness(
        height=height, crown_base=crown_base,
        expected_base=expected_base,
        width_ratio=2.0 * half_w / height, expected_width_ratio=2.0 * exp_w / height,
        iou=inter / max(union, 1), mask=mask, envelope=env,
    )
