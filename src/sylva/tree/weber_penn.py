"""A Weber–Penn tree (Weber & Penn 1995, seed 002 Appendix B) grown by events in time.

The parameters keep the paper's names: global ``Shape``, ``BaseSize``, ``Scale`` (± ``ScaleV``),
``ZScale`` (± ``ZScaleV``), ``Levels``, ``Ratio``, ``RatioPower``, ``Lobes``, ``LobeDepth``,
``Flare``, ``Scale0`` (the paper's ``0Scale``), ``BaseSplits`` (``0BaseSplits``), ``Leaves``,
``LeafShape``, ``LeafScale``, ``LeafScaleX``, ``AttractionUp``, ``PruneRatio``,
``PruneWidth``, ``PruneWidthPeak``, ``PrunePowerLow``, ``PrunePowerHigh``; per level
``Length``, ``Taper``, ``SegSplits``, ``SplitAngle``, ``CurveRes``, ``Curve``, ``CurveBack``,
``CurveV`` (written as the deviation of ``Curve``), ``DownAngle``, ``Rotate``, ``Branches``.
A paper ``XV`` is the deviation of ``X``.

Growth in time is our design (the thesis's §4.2.5 is not in the seed):

* every stem elongates as ``L(t) = L · f((t − t₀)/GrowTime)`` with the cubic ``f`` of
  :class:`~sylva.tree.events.TimeFunction`, and thickens as
  ``r(t) = r · min(0.08 + 0.92 · g((t − t₀)/ThickenTime), max(L(t)/L, 0.02))`` (no thicker
  for its length than the mature stem); the growing stem is the mature curve cut at
  ``L(t)``, tapering to its current tip;
* a bud at arc length ``o`` breaks — an event ``"bud"`` creates the child stem — at the time
  the parent reaches ``o``, plus ``BudDelay``; a segment split is an event ``"split"`` at
  the time the stem reaches the split point, which attaches the clones to the primary slot;
* a leaf appears ``LeafDelay`` after its stem passes it and unfolds over ``LeafUnfold``
  (the leaves of a run are a component, :mod:`sylva.tree.leaves`);
* **young trees are trees**: a young tree is the mature one scaled down.  The trunk's bare
  base carries *juvenile branches* (``JuvenileBranches`` of the crown's bud density): the one
  at height ``h`` is as long as a mid-crown branch of the tree whose crown base is at ``h``
  when its trunk is ``h / (JuvenileLag · BaseSize)`` long, and it is shed when the trunk
  gets there (after standing grown for at least ``ShedTime`` years, and always before
  ``Age``): its leaves fall over half a year (:data:`LEAF_FALL`), then it retracts from its
  tip over ``ShedTime`` years, its own stems with it, and leaves the graph (event
  ``"shed"``).  Stems below the leaf level carry *juvenile leaves* on their young shoots
  (every ``JuvenileLeafSpacing · LeafScale``, for ``JuvenileLeafLife`` years, fading over
  their last; ``JuvenileTrunkLeaves`` 0: not on the trunk).  Juvenile draws use their own
  random streams, so the mature tree (at ``Age``, when all of it is gone) is exactly the
  tree grown without them; a juvenile branch that would be gone by the simulation's target
  is not grown at all.

``GrowTime``, ``ThickenTime``, ``BudDelay`` (per level), ``LeafDelay``, ``LeafUnfold``,
``Age`` (the default age of a grown tree), ``Sides`` (ring resolution per level),
``LeafArrangement`` (``"spiral"`` or ``"fan"``), ``FanAngle``, ``BarkMaterial`` and
``LeafMaterial`` are our additions, and so is ``GroundClearance`` (m, default 0.15): a stem
whose next segment would dip below it turns level, so hanging whips trail above the ground.

The paper's stem features, and the choices we made where it is silent:

* **Taper** (``nTaper`` 0…3) is the paper's radius formula (:func:`stem_profile`): 0–1 a
  cone, 1–2 a cone ending in a sphere (2: a hemisphere of the stem's radius), 2–3 a periodic
  taper, nodes one stem diameter apart counted from the tip and pinched by ``nTaper − 2`` of
  the radius.  Radii are computed with the *mature* base radius and scaled by the thickening
  factor, so a young stem has the same, slimmer, profile; its rounded end follows the current
  tip while the periodic nodes stay where the mature stem has them.  Extra rings are added
  on a round end and, six per node, along a periodic stem; a stem with more than 32 nodes
  (longer than 64 radii: twigs, usually) is drawn with ``Taper`` 2 instead (its nodes would
  be too fine to see and too many to mesh).  Values up to 1 behave exactly as before.
* **ZScale** ± ``ZScaleV`` (its fixed random value, drawn per seed) scales plant ``y``
  (up) of everything the tree draws (joints, stems, leaves) when the geometry is made; stem
  rings stay round and leaf blades keep their size, frames are kept orthonormal (tangents
  follow the scaled curve).  Growth, pruning and ground clearance work before the scale.
  :meth:`Branch.world_matrix` stays unscaled.
* **Pruning** (``PruneRatio`` > 0): when a bud breaks, the child stem (level ≥ 1) is grown
  in full in advance, its split clones included, and tested point by point against the
  envelope ``√(x² + z²) / scale_tree < PruneWidth · ShapeRatio(8, (scale_tree − y) /
  (scale_tree · (1 − BaseSize)))`` (``scale_tree`` is ``Scale`` ± ``ScaleV``, the trunk at the
  origin).  While some point is outside, the stem is regrown shorter from the same random
  draws: it keeps the segments before the first that leaves (at least half its length, and
  it loses at least 1/15 of the original each time, as in the paper's reimplementations);
  a stem that cannot fit is dropped.  The stem's length is then ``PruneRatio · pruned +
  (1 − PruneRatio) · unpruned``.  The decision is made once, from the mature geometry, so a
  pruned stem is simply a shorter stem in the plan and the tree at time T does not depend
  on how it got there.  Only the stem's own axis points are tested (not its radius, children
  or leaves); the trunk is not pruned.
* **LeafShape** (a number or a name, see :data:`sylva.tree.meshing.LEAF_SHAPES`): 0 the
  pointed blade, 1 ellipse, 2 disc, 3 triangle, 4 palm, 5 square, 6 hexagon.  The paper
  leaves the shapes to the renderer; this set is ours.

Still simplified: the attraction-up rule is a rotation toward (or, negative, away from) the
vertical by ``AttractionUp · sin(declination) / (2 · CurveRes)`` per segment, applied from
level 2 as in the paper.
"""

from __future__ import annotations

import math

import numpy as np

from ._kernels import (
    axis_rotations,
    bend_stem,
    cone_profile,
    envelope_exit,
    envelope_exit_local,
    where_points,
    world_up,
)
from ._streams import stream, uniform
from .components import Component, rigid_frame_inverse
from .leaves import LEAF_FALL, Leaves, plan_leaves

__all__ = ["Branch", "StemPlan", "envelope", "make_trunk", "shape_ratio", "stem_profile"]

_SIDES = (14, 9, 6, 4, 3)
_GROW = (12.0, 5.0, 2.0, 1.0, 0.6)  # default GrowTime per level
_NONE = np.zeros(0)
_NONE33 = np.zeros((0, 3, 3))
_ZERO3 = np.zeros(3)
_EYE4 = np.eye(4)
_EYE3 = np.eye(3)  # copied where a fresh identity frame is needed (cheaper than np.eye)
_UP = np.array([0.0, 1.0, 0.0])
_MAX_NODES = 32  # a periodic taper with more nodes per stem is drawn as Taper 2
_NODE_RINGS = 6  # rings per node of a periodic taper


def shape_ratio(shape: int, ratio: float, prune: tuple[float, float, float, float] | None = None):
    """Weber–Penn ``ShapeRatio(shape, ratio)`` (Appendix B's table; 8 is the envelope).

    Examples
    --------
    >>> shape_ratio(0, 1.0), shape_ratio(3, 0.3), round(shape_ratio(1, 0.5), 3)
    (1.0, 1.0, 1.0)
    """
    r = min(max(float(ratio), 0.0), 1.0)
    if shape == 0:
        return 0.2 + 0.8 * r
    if shape == 1:
        return 0.2 + 0.8 * math.sin(math.pi * r)
    if shape == 2:
        return 0.2 + 0.8 * math.sin(0.5 * math.pi * r)
    if shape == 3:
        return 1.0
    if shape == 4:
        return 0.5 + 0.5 * r
    if shape == 5:
        return r / 0.7 if r <= 0.7 else (1.0 - r) / 0.3
    if shape == 6:
        return 1.0 - 0.8 * r
    if shape == 7:
        return 0.5 + 0.5 * r / 0.7 if r <= 0.7 else 0.5 + 0.5 * (1.0 - r) / 0.3
    if shape == 8:
        return float(envelope(r, prune))
    raise ValueError(f"unknown Weber–Penn shape {shape}: expected 0…8")


def envelope(ratio, prune: tuple[float, float, float, float] | None = None):
    """The pruning envelope ``PruneWidth · ShapeRatio(8, ratio)`` (vectorised).

    ``ratio`` is measured from the top of the envelope (0) down to its base (1); the envelope
    is widest (``PruneWidth``) at ``ratio = 1 − PruneWidthPeak``, follows
    ``(ratio / (1 − PruneWidthPeak))^PrunePowerHigh`` above and
    ``((1 − ratio) / PruneWidthPeak)^PrunePowerLow`` below, and is 0 outside ``[0, 1]``.

    Examples
    --------
    >>> float(envelope(0.5, (0.5, 0.5, 0.5, 0.5))), float(envelope(1.2))
    (0.5, 0.0)
    """
    width, peak, low, high = prune or (0.5, 0.5, 0.5, 0.5)
    peak = min(max(peak, 1e-6), 1 - 1e-6)
    r = np.asarray(ratio, np.float64)
    # np.clip's values bit for bit (NaN and -0 kept; tests/tree/test_clip_speed.py), without
    # its Python-level dispatch: the pruning trials call this thousands of times
    c = np.minimum(np.maximum(0.0, r), 1.0)
    upper = (c / (1.0 - peak)) ** high
    lower = ((1.0 - c) / peak) ** low
    out = width * np.where(c < 1.0 - peak, upper, lower)
    return np.where((r >= 0.0) & (r <= 1.0), out, 0.0)


def _clip03(x: float) -> float:
    """``float(np.clip(x, 0.0, 3.0))`` bit for bit (NaN and -0 kept), without NumPy."""
    if x < 0.0:
        return 0.0
    return 3.0 if x > 3.0 else x


# the rotations are built from flat tuples (a quarter cheaper than nested lists)
def _rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array((1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)).reshape(3, 3)


def _ry(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array((c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)).reshape(3, 3)


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array((c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)).reshape(3, 3)


def _rx_many(a: np.ndarray) -> np.ndarray:
    """Rotations about x by the angles ``a`` (float64[n, 3, 3]; compiled, one call instead
    of nine NumPy ones: ``tests/tree/test_clip_speed.py`` holds it to the NumPy form)."""
    return axis_rotations(np.asarray(a, np.float64), 0)


def _ry_many(a: np.ndarray) -> np.ndarray:
    """Rotations about y by the angles ``a`` (see :func:`_rx_many`)."""
    return axis_rotations(np.asarray(a, np.float64), 1)


def _axis_angle(axis: np.ndarray, a: float) -> np.ndarray:
    x, y, z = axis / np.linalg.norm(axis)
    c, s = math.cos(a), math.sin(a)
    C = 1.0 - c
    return np.array([
        [c + x * x * C, x * y * C - z * s, x * z * C + y * s],
        [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
        [z * x * C - y * s, z * y * C + x * s, c + z * z * C],
    ])


def stem_profile(s, length: float, radius: float, taper: float,
                 mature_length: float | None = None) -> np.ndarray:
    """Weber & Penn's stem radius (section 4.3 of the paper) relative to ``radius``.

    ``s`` are arc lengths from the base of a stem ``length`` long with base radius
    ``radius``; ``Z = s / length``::

        unit_taper = taper (0 ≤ taper < 1), 2 − taper (1 ≤ taper < 2), 0 (2 ≤ taper ≤ 3)
        taper_z = radius · (1 − unit_taper · Z)
        Z2 = (1 − Z) · length                      (distance to the tip)
        depth = 1 if taper < 2 or Z2 < taper_z else taper − 2
        Z3 = Z2 if taper < 2 else |Z2 − 2 · taper_z · int(Z2 / (2 · taper_z) + 0.5)|
        r = taper_z                                           if taper < 2 and Z3 ≥ taper_z
        r = (1 − depth) · taper_z + depth · √(taper_z² − (Z3 − taper_z)²)   otherwise

    so 0–1 is a cone (1 tapers to a point), 1–2 a cone ending in a sphere (2: a hemisphere
    of the stem's radius), 2–3 a periodic taper: nodes every stem diameter, pinched by
    ``taper − 2`` of the radius.  ``mature_length`` (≥ ``length``, a stem still growing)
    places the periodic nodes from the mature tip, so they do not move as the stem grows;
    the end within ``taper_z`` of the current tip is the full hemisphere.

    Examples
    --------
    >>> [round(float(x), 3) for x in stem_profile([0.0, 0.5, 1.0], 1.0, 0.1, 1.0)]
    [1.0, 0.5, 0.0]
    >>> round(float(stem_profile(0.95, 1.0, 0.1, 2.0)), 6), float(stem_profile(1.0, 1.0, 0.1, 2.0))
    (0.866025, 0.0)
    """
    s = np.asarray(s, np.float64)
    L = max(float(length), 1e-12)
    R = max(float(radius), 1e-12)
    nt = min(max(float(taper), 0.0), 3.0)
    Z = np.clip(s / L, 0.0, 1.0)
    unit = nt if nt < 1.0 else (2.0 - nt if nt < 2.0 else 0.0)
    tz = R * (1.0 - unit * Z)
    if nt < 1.0:
        return tz / R
    z2 = (1.0 - Z) * L
    tip = np.sqrt(np.maximum(tz * tz - (z2 - tz) ** 2, 0.0))  # depth 1, Z3 = Z2
    if nt < 2.0:
        return np.where(z2 < tz, tip, tz) / R
    depth = nt - 2.0
    zm = np.maximum(float(mature_length if mature_length is not None else L) - s, 0.0)
    z3 = np.abs(zm - 2.0 * tz * np.floor(zm / (2.0 * tz) + 0.5))
    node = (1.0 - depth) * tz + depth * np.sqrt(np.maximum(tz * tz - (z3 - tz) ** 2, 0.0))
    return np.where(z2 < tz, tip, node) / R


def _level_numbers(tree, lv: int) -> tuple:
    """What :class:`StemPlan` reads of level ``lv``'s parameters: ``(grow_time,
    thicken_time, bud_delay, taper, curve_res, sides, Curve, base curve)`` (the base curve
    float[curve_res]: read only)."""
    grow_time = max(tree.pf("GrowTime", level=lv, default=_GROW[min(lv, 4)]).value, 1e-3)
    thicken_time = max(tree.pf("ThickenTime", level=lv, default=2.5 * grow_time).value, 1e-3)
    bud_delay = max(tree.pf("BudDelay", level=lv, default=0.3).value, 0.0)
    taper = _clip03(float(tree.pf("Taper", level=lv, default=1.0).value))
    res = max(1, tree.pi("CurveRes", level=lv, default=3))
    sides = max(3, tree.pi("Sides", level=lv, default=_SIDES[min(lv, 4)]))
    curve = tree.pf("Curve", level=lv, default=0.0)
    back = tree.pf("CurveBack", level=lv, default=0.0).value
    base = np.full(res, curve.value / res)
    if back:
        half = max(res / 2.0, 1.0)
        base = np.where(np.arange(res) < res / 2.0, curve.value / half, back / half)
    base.flags.writeable = False
    return grow_time, thicken_time, bud_delay, taper, res, sides, curve, base


class StemPlan:
    """The mature dimensions and the growth clock of one stem (shared by its components).

    Attributes
    ----------
    level : int
    length, radius : float
        Mature length and base radius (metres).
    birth : float
        Global time the stem starts growing.
    grow_time, thicken_time : float
        Years to full length and to full thickness.
    curve_res : int
    curve : float64[curve_res]
        Rotation (radians) about the local x axis at each segment.
    offset, parent_length : float
        Where the stem sits on its parent (0 and 0 for the trunk).
    n_children, n_leaves : float
        Expected children and leaves over the whole stem (fractions are error-diffused).
    """

    def __init__(self, tree, level: int, length: float, radius: float, birth: float,
                 rng: np.random.Generator, offset: float = 0.0, parent_length: float = 0.0,
                 n_children: float = 0.0, n_leaves: float = 0.0, shed: float | None = None,
                 parent_plan: StemPlan | None = None) -> None:
        self.tree = tree
        # a juvenile branch (and everything on it) is shed: from time ``shed`` it retracts
        # over ``tree.shed_time`` years (see :meth:`life_at`); None for the lasting tree
        self.shed = shed
        self.parent_plan = parent_plan
        self.level = level
        self.length = max(float(length), 1e-4)
        self.radius = max(float(radius), 1e-4)
        self.birth = float(birth)
        self.offset = offset
        self.parent_length = parent_length
        self.n_children = n_children
        self.n_leaves = n_leaves
        lv = level
        # the level's numbers, worked out once per tree (a tree plans a few thousand stems)
        ck = ("plan", lv)
        numbers = tree._pcache.get(ck)
        if numbers is None:
            numbers = tree._pcache[ck] = _level_numbers(tree, lv)
        (self.grow_time, self.thicken_time, self.bud_delay, self.taper, self.curve_res,
         self.sides, curve, base) = numbers
        # the periodic taper is drawn where its nodes (one per stem diameter) can be seen
        self.taper_drawn = self.taper
        if self.taper > 2.0 and self.length / (2.0 * self.radius) > _MAX_NODES:
            self.taper_drawn = 2.0
        self.growth = tree.growth
        self.thickening = tree.thickening
        res = self.curve_res
        jitter = rng.uniform(-1.0, 1.0, res) * abs(curve.deviation) / res
        self.curve = np.radians(base + jitter)
        self.flare = tree.pf("Flare", default=0.0).value if level == 0 else 0.0
        self.lobes = tree.pi("Lobes", default=0) if level == 0 else 0
        self.lobe_depth = tree.pf("LobeDepth", default=0.0).value if level == 0 else 0.0
        self.base_length = tree.pf("BaseSize", default=0.0).value * self.length if level == 0 \
            else 0.0

    @property
    def seg_length(self) -> float:
        return self.length / self.curve_res

    def length_at(self, t: float) -> float:
        grown = self.length * float(self.growth((t - self.birth) / self.grow_time))
        if self.shed is None:
            return grown
        return min(grown, self.length * self.life_at(t))

    def life_at(self, t: float) -> float:
        """The part (0…1) of a shed stem that is left at time ``t`` (1 for a lasting stem).

        The juvenile branch drops its leaves over :data:`LEAF_FALL` years from ``shed``,
        then retracts from its tip linearly over ``ShedTime`` years; a stem on it keeps the
        part of itself that its parent still has beyond the stem's offset, so the whole
        subtree goes continuously, tips first.
        """
        if self.shed is None:
            return 1.0
        pp = self.parent_plan
        if pp is None or pp.shed is None:
            gone = (t - self.shed - LEAF_FALL) / max(self.tree.shed_time, 1e-6)
            return min(max(1.0 - gone, 0.0), 1.0)
        left = pp.life_at(t) * pp.length - self.offset
        return min(max(left / max(pp.length - self.offset, 1e-9), 0.0), 1.0)

    def time_at_length(self, s):
        """The global time this stem reaches arc length ``s`` (a float or an array)."""
        if isinstance(s, float):  # the same numbers without a 0-d array's detour
            return float(self.birth + self.growth.inverse(s / self.length) * self.grow_time)
        tau = self.growth.inverse(np.asarray(s, np.float64) / self.length)
        out = self.birth + tau * self.grow_time
        return float(out) if np.ndim(out) == 0 else out

    def thickness_at(self, t: float) -> float:
        # never thicker, for its length, than the mature stem: a seedling is a thin stem
        thick = 0.08 + 0.92 * float(self.thickening((t - self.birth) / self.thicken_time))
        grown = float(self.growth((t - self.birth) / self.grow_time))
        return min(thick, max(grown, 0.02))

    def profile(self, s: np.ndarray, current: float) -> np.ndarray:
        """Relative radius at arc lengths ``s`` of a stem ``current`` long (taper + flare).

        The paper's radius formula (see :func:`stem_profile`) with the mature base radius;
        the ends (the cone's point, the spherical end) follow the current tip, the periodic
        nodes of a ``Taper`` in (2, 3] stay where the mature stem has them.
        """
        s = np.asarray(s, np.float64)
        current = max(float(current), 1e-9)
        if self.taper <= 1.0 and not self.flare and s.ndim == 1:  # one compiled call
            return cone_profile(s, current, self.taper)
        z = np.minimum(np.maximum(s / current, 0.0), 1.0)
        if self.taper <= 1.0:
            r = 1.0 - self.taper * z
        else:
            r = stem_profile(s, current, self.radius, self.taper_drawn,
                             mature_length=self.length)
        if self.flare:
            y = np.maximum(0.0, 1.0 - 8.0 * z)
            r = r * (self.flare * (100.0**y - 1.0) / 100.0 + 1.0)
        if self.taper <= 1.0:
            return np.maximum(r, 0.02 * (1 - z) + 0.004)
        return r

    def ring_arcs(self, a0: float, a1: float, current: float) -> np.ndarray:
        """Extra arc lengths in ``(a0, a1)`` where a ``Taper`` above 1 needs rings (the
        spherical end near the current tip, a few rings per node of the periodic taper)."""
        if self.taper <= 1.0 or a1 <= a0:
            return np.zeros(0)
        r = self.radius
        out = []
        unit = 2.0 - self.taper if self.taper < 2.0 else 0.0
        cap = r * (1.0 - unit)  # taper_z at the tip: the spherical end is this long
        if cap > 0:
            th = np.linspace(0.0, 0.5 * np.pi, 7)[1:-1]
            out.append(current - cap * (1.0 - np.cos(th)))
            out.append(current - cap * np.array([1.0, 1.5]))
        if self.taper_drawn > 2.0:  # node-aligned: minima at mature-tip distances 2r·k
            step = 2.0 * r / _NODE_RINGS
            j = np.arange(math.floor((self.length - a1) / step),
                          math.ceil((self.length - a0) / step) + 1)
            out.append(self.length - j * step)
        a = np.concatenate(out) if out else np.zeros(0)
        return np.unique(a[(a > a0 + 1e-9) & (a < a1 - 1e-9)])


def _run_curve(plan: StemPlan, k0: int, frame: np.ndarray, split_error: float,
               parent_world: np.ndarray | None, bend, memo: dict | None = None):
    """The split and the mature curve of a run of ``plan`` from segment ``k0``: ``(k1,
    n_split, split_error, F, P)`` (frames float[m + 1, 3, 3] and points float[m + 1, 3] in
    the run's frame, ``m = k1 − k0``).  ``bend(F, P, curve, seg, up_local, attraction,
    parent_world)`` is the segment loop of attraction up and ground clearance
    (:meth:`Branch._bend`); :class:`Branch` and the pruning trials (:func:`_envelope_exit`)
    both grow their runs here.  ``memo`` (the trials of one stem) remembers the turned
    frames of a run by its curve, segments and first frame: they do not depend on the
    trial's length (a dict the caller keeps; ``None``: none)."""
    tree = plan.tree
    res = plan.curve_res
    seg = plan.seg_length
    lv = plan.level
    # the level's numbers, looked up once per tree (they are asked for every run and trial)
    ck = ("run", lv)
    numbers = tree._pcache.get(ck)
    if numbers is None:
        numbers = tree._pcache[ck] = (
            tree.pf("SegSplits", level=lv, default=0.0).value,
            float(tree.pi("BaseSplits", default=0)),
            tree.pf("AttractionUp", default=0.0).value if lv >= 2 else 0.0,
            tree.pf("GroundClearance", default=0.15).value)
    seg_splits, base_splits, attraction, clearance = numbers
    # -- splits: error-diffused nSegSplits (0BaseSplits at the trunk's first segment) ----
    k1, n_split, err = res, 0, split_error
    stop = res - 1
    if seg_splits <= 0:  # only the trunk's first segment may split (BaseSplits): the rest
        stop = min(stop, 1) if lv == 0 and base_splits > 0 else k0  # would all be skipped
    for k in range(k0, stop):
        want = seg_splits
        if lv == 0 and k == 0:
            want = base_splits
        if want <= 0:
            continue
        if lv == 0 and k == 0:
            n = int(want)
        else:
            n = int(math.floor(want + err + 0.5))
            err += want - n
        if n > 0 and k + 1 < res:
            k1, n_split = k + 1, n
            break
    # -- the mature curve in the local frame ---------------------------------------------
    m = k1 - k0
    F = np.empty((m + 1, 3, 3))
    P = np.zeros((m + 1, 3))
    F[0] = frame
    up_local = None
    if attraction and parent_world is not None:
        up_local = np.empty(3)  # the world's up in the run's frame: parent_world[1, :3]
        if not world_up(parent_world, up_local):  # ... unless a zero's sign is at stake
            up_local = parent_world[:3, :3].T @ _UP
    if up_local is not None:  # the segment loop fills F[1:] and P[1:] from F[0], P[0]
        bend(F, P, plan.curve[k0:k1], seg, up_local, attraction / (2.0 * res), parent_world)
        return k1, n_split, err, F, P
    # fast path: every segment turns about its own x axis, so the turns add up
    if memo is None:
        F[1:] = frame @ _rx_many(np.cumsum(plan.curve[k0:k1]))
    else:
        mk = ("F", plan.curve.tobytes(), k0, k1, frame.tobytes())
        turned = memo.get(mk)
        if turned is None:
            turned = memo[mk] = frame @ _rx_many(np.cumsum(plan.curve[k0:k1]))
        F[1:] = turned
    P[1:] = np.cumsum(F[1:, :, 1] * seg, axis=0)
    sequential = False
    if parent_world is not None:
        y = P[1:] @ parent_world[1, :3] + parent_world[1, 3]
        sequential = bool((y < clearance).any())
    if sequential:
        bend(F, P, plan.curve[k0:k1], seg, up_local, attraction / (2.0 * res), parent_world)
    return k1, n_split, err, F, P


class Branch(Component):
    """A run of segments ``[k0, k1)`` of one stem; a split ends it and its clones continue
    on the primary slot, children hang on their own slots (level + 1), its leaves are a
    :class:`~sylva.tree.leaves.Leaves` component on its base slot (level + 1).

    Parameters
    ----------
    plan : StemPlan
    k0, k1 : int
        Segment range covered (``k1`` is lowered when a split happens inside the range).
    frame : float64[3, 3]
        Initial orientation in the local frame (split clones and the trunk's twist).
    key : tuple of int
        Path from the trunk (seeds this component's random draws).
    clone : int
        0 for the trunk or the stem's main continuation, ``i`` for the i-th split clone.
    """

    def __init__(self, plan: StemPlan, k0: int, frame: np.ndarray, key: tuple, clone: int = 0,
                 split_error: float = 0.0, birth: float | None = None,
                 parent_world: np.ndarray | None = None, share: float = 1.0) -> None:
        super().__init__(plan.birth if birth is None else birth, name=f"Branch{plan.level}")
        self.plan = plan
        self.k0 = k0
        self.key = key
        self.clone = clone
        self.share = share  # this run's share of the stem's children and leaves (split clones)
        tree = plan.tree
        self.rng = stream(tree.seed & 0xFFFFFFFF, *key)
        rng = self.rng
        self._clearance = tree.pf("GroundClearance", default=0.15).value
        k1, n_split, err, F, P = _run_curve(plan, k0, frame, split_error, parent_world,
                                            self._bend)
        m = k1 - k0
        seg = plan.seg_length
        self.k1 = k1
        self.n_split = n_split
        self.split_error = err
        self.points = P
        self.frames = F
        self.arc0 = k0 * seg
        self.arc1 = k1 * seg
        # the inverse as (position, frame): worked out by the slot when first asked for
        self.primary.set_transform(self._matrix(P[m], F[m]), (P[m], F[m]))
        # -- children (buds) and leaves along this run -----------------------------------------
        self.buds = self._plan_children(rng)
        self.n_lasting = len(self.buds)  # buds past this index grow juvenile branches
        self.buds += self._plan_juvenile()
        # the leaves: a component of level + 1 on the base slot (sylva.tree.leaves)
        self.foliage: Leaves | None = plan_leaves(self, rng)
        self._joints: np.ndarray | None = None
        self._seg_joints: np.ndarray | None = None
        self._mature_rows: np.ndarray | None = None  # None: every grown row is a mature one
        self._skip_first = False
        # lazy-update state
        self.current_length = 0.0
        self.current_thickness = 0.0

    def _bend(self, F, P, curve, seg, up_local, attraction, parent_world) -> None:
        """The segment loop with attraction up and ground clearance (fills F[1:], P[1:]);
        compiled (:func:`~sylva.tree._kernels.bend_stem`), :meth:`_bend_py` is the same loop
        in Python."""
        has_up = up_local is not None
        has_world = parent_world is not None
        bend_stem(F, P, np.ascontiguousarray(curve, np.float64), float(seg), has_up,
                  np.asarray(up_local if has_up else _ZERO3, np.float64), float(attraction),
                  has_world, np.asarray(parent_world if has_world else _EYE4, np.float64),
                  float(self._clearance))

    def _bend_py(self, F, P, curve, seg, up_local, attraction, parent_world) -> None:
        """The segment loop of :meth:`_bend` in Python (the reference of the kernel)."""
        for i in range(len(curve)):
            f = F[i] @ _rx(curve[i])
            if up_local is not None:
                t = f[:, 1]
                u = up_local
                axis = np.array([t[1] * u[2] - t[2] * u[1], t[2] * u[0] - t[0] * u[2],
                                 t[0] * u[1] - t[1] * u[0]])
                sin_d = math.sqrt(axis[0] ** 2 + axis[1] ** 2 + axis[2] ** 2)
                if sin_d > 1e-6:
                    f = _axis_angle(axis, attraction * sin_d) @ f
            if parent_world is not None:
                # keep clear of the ground: a stem that would dip below it turns level
                pw = parent_world
                t_up = float(pw[1, :3] @ f[:, 1])
                y_next = float(pw[1, :3] @ (P[i] + f[:, 1] * seg) + pw[1, 3])
                if t_up < 0 and y_next < self._clearance:
                    up_l = pw[:3, :3].T @ np.array([0.0, 1.0, 0.0])
                    axis = np.cross(f[:, 1], up_l)
                    if axis @ axis > 1e-12:
                        f = _axis_angle(axis, -math.asin(max(-1.0, t_up))) @ f
            P[i + 1] = P[i] + f[:, 1] * seg
            F[i + 1] = f

    @staticmethod
    def _matrix(p: np.ndarray, f: np.ndarray) -> np.ndarray:
        m = _EYE4.copy()
        m[:3, :3] = f
        m[:3, 3] = p
        return m

    @staticmethod
    def _inverse(p: np.ndarray, f: np.ndarray) -> np.ndarray:
        """The inverse of :meth:`_matrix` (``f`` is a rotation: its transpose inverts it)."""
        return rigid_frame_inverse(p, f)

    def _where(self, s: float) -> tuple[int, np.ndarray, np.ndarray]:
        """Segment index (local), position and frame at arc length ``s`` of this run."""
        seg = self.plan.seg_length
        i = min(max(int((s - self.arc0) // seg), 0), self.k1 - self.k0 - 1)
        f = self.frames[i + 1]  # orientation of segment i
        p = self.points[i] + f[:, 1] * (s - self.arc0 - i * seg)
        return i, p, f

    def _where_many(self, s: np.ndarray):
        """Vector form of :meth:`_where`: int[n], float[n, 3], float[n, 3, 3]."""
        seg = self.plan.seg_length
        i = self._segments_at(s)
        f = self.frames[i + 1]
        p = self.points[i] + f[:, :, 1] * (s - self.arc0 - i * seg)[:, None]
        return i, p, f

    def _segments_at(self, s: np.ndarray) -> np.ndarray:
        """The local segment index at each arc length ``s`` (of :meth:`_where_many`):
        ``clip((s - arc0) // seg, 0, last)`` (compiled, :func:`_where_points`)."""
        return self._where_points(s)[0]

    def _where_points(self, s: np.ndarray):
        """:meth:`_where_many` without the frames: int[n], float[n, 3] (NumPy's numbers,
        by one compiled call, :func:`~sylva.tree._kernels.where_points`;
        ``tests/tree/test_clip_speed.py`` holds it to the NumPy form)."""
        return where_points(np.asarray(s, np.float64), float(self.arc0),
                            float(self.plan.seg_length), self.k1 - self.k0 - 1,
                            self.points, self.frames)

    def _plan_children(self, rng) -> list[tuple]:
        plan, tree = self.plan, self.plan.tree
        lv = plan.level
        if lv + 1 >= tree.levels or plan.n_children <= 0:
            return []
        per_len = self.share * plan.n_children / max(plan.length - plan.base_length, 1e-9)
        lo = max(self.arc0, plan.base_length)
        return self._bud_run(rng, per_len, lo, self.arc1)

    def _plan_juvenile(self) -> list[tuple]:
        """Buds of the juvenile branches on the trunk's clear base (``JuvenileBranches`` of
        the crown's density); they are grown and shed while the tree is young."""
        plan, tree = self.plan, self.plan.tree
        if plan.level != 0 or tree.levels < 2 or tree.juvenile_branches <= 0 \
                or plan.base_length <= 0 or plan.n_children <= 0:
            return []
        rng = stream(tree.seed & 0xFFFFFFFF, *self.key, 11)
        per_len = tree.juvenile_branches * self.share * plan.n_children / max(
            plan.length - plan.base_length, 1e-9)
        lo = max(self.arc0, 0.04 * plan.length)
        return self._bud_run(rng, per_len, lo, min(self.arc1, plan.base_length), juvenile=True)

    def _bud_run(self, rng, per_len: float, lo: float, hi: float,
                 juvenile: bool = False) -> list[tuple]:
        """``(arc, rotation, down angle)`` of the buds on ``[lo, hi]`` of this run (a
        juvenile branch takes the down angle of mid-crown, where it stands most of its
        life)."""
        plan, tree = self.plan, self.plan.tree
        lv = plan.level
        if hi <= lo:
            return []
        want = per_len * (hi - lo)
        n = int(math.floor(want + rng.random()))
        if n <= 0:
            return []
        rot = tree.pf("Rotate", level=lv + 1, default=140.0)
        down = tree.pf("DownAngle", level=lv + 1, default=45.0)
        phi0 = phi = uniform(rng, 0.0, 360.0)
        side = 1.0
        out = []
        for i in range(n):
            s = lo + (i + uniform(rng, 0.25, 0.75)) / n * (hi - lo)
            if rot.value >= 0:
                phi += rot.sample(rng)
            else:  # the paper's negative nRotate: alternately ±(180 + nRotate ± nRotateV)
                side = -side
                phi = phi0 + side * (180.0 + rot.value + uniform(rng, -1, 1) * abs(rot.deviation))
            if down.deviation >= 0:
                theta = down.sample(rng)
            else:  # the paper's special mode for a negative nDownAngleV
                span = max(plan.length - plan.base_length, 1e-9)
                sr = shape_ratio(0, 0.5 if juvenile else (plan.length - s) / span)
                theta = down.value + down.deviation * (1.0 - 2.0 * sr)
            out.append((s, math.radians(phi), math.radians(theta)))
        return out

    # the leaves, kept readable here for the growth animation (sylva.tree.animation)
    @property
    def leaf_arc(self) -> np.ndarray:
        return self.foliage.arc if self.foliage is not None else _NONE

    @property
    def leaf_frame(self) -> np.ndarray:
        return self.foliage.frame if self.foliage is not None else _NONE33

    @property
    def leaf_size(self) -> np.ndarray:
        return self.foliage.size if self.foliage is not None else _NONE

    @property
    def leaf_birth(self) -> np.ndarray:
        return self.foliage.birth if self.foliage is not None else _NONE

    @property
    def leaf_death(self) -> np.ndarray:
        return self.foliage.death if self.foliage is not None else _NONE

    def leaf_sizes_at(self, t: float) -> np.ndarray:
        """Blade length of this run's leaves at time ``t`` (:meth:`Leaves.sizes_at`)."""
        return self.foliage.sizes_at(t) if self.foliage is not None else _NONE

    # -- events --------------------------------------------------------------------------------
    def schedule_own(self, sim) -> None:
        """Schedule this run's buds and its split (called when it joins a simulation)."""
        plan = self.plan
        arcs = [b[0] for b in self.buds]
        if len(arcs) > 1 and plan.growth.kind in ("cubic", "linear"):
            # the times of all the buds in one array call: the same elementwise operations
            # as the float road of time_at_length (whose clamp only differs at NaN and -0)
            times = plan.time_at_length(np.array(arcs)).tolist()
        else:
            times = [plan.time_at_length(s) for s in arcs]
        for i, t in enumerate(times):
            sim.schedule(self, max(t + plan.bud_delay, sim.time), "bud", i)
        if self.n_split > 0 or self.k1 < plan.curve_res:
            sim.schedule(self, max(plan.time_at_length(self.arc1), sim.time), "split")

    def on_event(self, event, sim) -> None:
        if event.kind == "bud":
            self._spawn_child(event.data, event.time, sim)
        elif event.kind == "split":
            self._spawn_continuations(event.time, sim)
        elif event.kind == "shed":  # a juvenile branch has gone: it leaves the graph
            child = event.data
            child.detach()
            for c in child.walk():
                c.simulation = None

    def _spawn_child(self, i: int, t: float, sim) -> None:
        plan, tree = self.plan, self.plan.tree
        s, phi, theta = self.buds[i]
        _, p, f = self._where(s)
        child_frame = f @ _ry(phi) @ _rx(theta)
        slot = self.add_slot(self._matrix(p, child_frame), (p, child_frame))
        slot.space(tree.seed).set_float("ParentLength", plan.length)
        slot.space(tree.seed).set_float("Offset", s)
        r_here = plan.radius * float(plan.profile(np.array([s]), plan.length)[0])
        slot.space(tree.seed).set_float("ParentRadius", r_here)
        slot.space(tree.seed).set_int("Ordinal", i)
        lv = plan.level + 1
        key = (*self.key, 1, i)
        rng = stream(tree.seed & 0xFFFFFFFF, *key, 7)
        lmax = tree.pf("Length", level=lv, default=0.5).sample(rng)
        shed = plan.shed
        if i >= self.n_lasting:
            # a juvenile branch: as long as a branch of the tree scaled down to the trunk
            # length at which this bud is the crown base (a young tree's crown base lags:
            # at JuvenileLag · BaseSize); it is shed from then on
            lag_base = max(tree.juvenile_lag * tree.base_size, 1e-9)
            young = min(s / lag_base, plan.length)
            # over its life it stands from mid-crown down to the crown base of that tree
            length = young * lmax * max(shape_ratio(tree.shape, r, tree.prune)
                                        for r in (0.5, 0.6, 0.7, 0.8, 0.9, 1.0))
            if tree.prune_ratio > 0:  # a pruned crown is only PruneWidth wide
                length *= 1.0 - tree.prune_ratio + tree.prune_ratio * min(tree.prune[0], 1.0)
            # it stands grown for at least ShedTime years, and is gone by the species' Age;
            # the buds above the one that is the crown base when the trunk is grown go one
            # after another from then until the last moment (not all at once)
            grow = tree.pf("GrowTime", level=lv, default=_GROW[min(lv, 4)]).value
            last = tree.default_age - tree.shed_time - LEAF_FALL - 0.5
            natural = plan.time_at_length(young)
            s_full = lag_base * plan.length
            if s > s_full and last > natural:
                span = max(plan.base_length - s_full, 1e-9)
                natural += (s - s_full) / span * (last - natural)
            shed = min(max(natural, t + grow + tree.shed_time), last)
            if shed <= t + 0.25 or shed + LEAF_FALL + tree.shed_time <= sim.target:
                return  # it would be gone before it is seen: not grown at all
        elif plan.level == 0:
            span = max(plan.length - plan.base_length, 1e-9)
            length = plan.length * lmax * shape_ratio(tree.shape, (plan.length - s) / span,
                                                       tree.prune)
        else:
            length = lmax * (plan.length - 0.6 * s)
        length = max(length, 0.0)
        if length < 1e-3:
            return
        world = self.world_matrix() @ slot.matrix
        if shed is None and tree.prune_ratio > 0.0:  # pruning trials: a plan per trial
            state = rng.bit_generator.state

            def plan_of(length: float) -> StemPlan:
                rng.bit_generator.state = state  # the same draws for every trial length
                return self._child_plan(lv, length, s, lmax, r_here, t, rng, shed)
        else:  # one plan: the stream is where the trials would set it back to

            def plan_of(length: float) -> StemPlan:
                return self._child_plan(lv, length, s, lmax, r_here, t, rng, shed)

        if shed is not None:
            child = Branch(plan_of(length), 0, _EYE3.copy(), key, parent_world=world)
            self.attach(child, slot)
            child.schedule_own(sim)
            if plan.shed is None:  # the juvenile branch itself: it goes when it is gone
                sim.schedule(self, max(shed + LEAF_FALL + tree.shed_time, sim.time), "shed",
                             child)
            return
        if tree.prune_ratio > 0.0:
            pruned = _pruned_length(plan_of, length, key, world)
            length = tree.prune_ratio * pruned + (1.0 - tree.prune_ratio) * length
            if length < 1e-3:
                return
        child = Branch(plan_of(length), 0, _EYE3.copy(), key, parent_world=world)
        self.attach(child, slot)
        child.schedule_own(sim)

    def _child_plan(self, lv: int, length: float, s: float, lmax: float, r_here: float,
                    t: float, rng, shed: float | None = None) -> StemPlan:
        """The plan of a child ``length`` long at arc length ``s`` (born at ``t``)."""
        plan, tree = self.plan, self.plan.tree
        radius = plan.radius * (length / plan.length) ** tree.ratio_power
        radius = min(radius, 0.95 * r_here)
        branches = tree.pf("Branches", level=lv + 1, default=0.0).value
        if lv + 1 >= tree.levels:
            n_children = 0.0
        elif plan.level == 0:
            n_children = branches * (0.2 + 0.8 * (length / plan.length) / max(lmax, 1e-9))
        else:
            n_children = branches * (1.0 - 0.5 * s / plan.length)
        n_leaves = 0.0
        if lv == tree.levels - 1:
            density = tree.leaf_density_of(lv + 1)
            n_leaves = tree.leaves * shape_ratio(4, s / plan.length) * density
            if tree.leaf_arrangement == "fan":
                n_leaves = tree.leaves * density
        if lv >= 2 and lv == tree.levels - 1:
            n_leaves /= tree.quality  # fewer twigs (quality < 1) carry the same foliage
        if lv >= 1 and lv == tree.levels - 2:
            n_children *= tree.quality
        return StemPlan(tree, lv, length, radius, t, rng, offset=s, parent_length=plan.length,
                        n_children=n_children, n_leaves=n_leaves, shed=shed,
                        parent_plan=plan if shed is not None else None)

    def _spawn_continuations(self, t: float, sim) -> None:
        if self.k1 >= self.plan.curve_res:
            return
        for cont in self._continuations(t, self.world_matrix() @ self.primary.matrix):
            self.attach(cont, self.primary)
            cont.schedule_own(sim)

    def _continuations(self, t: float, world: np.ndarray) -> list[Branch]:
        """The runs that continue this one after its split (detached; ``world`` is the
        primary slot's frame in plant coordinates)."""
        plan = self.plan
        n = self.n_split
        out = []
        for c, frame in enumerate(_split_frames(plan, n, self.rng)):
            out.append(Branch(plan, self.k1, frame, (*self.key, 2, c), clone=c,
                              split_error=self.split_error, birth=t, parent_world=world,
                              share=self.share / (n + 1)))
        return out

    # -- lazy update -----------------------------------------------------------------------
    def update_attributes(self, t: float) -> None:
        self.current_length = self.plan.length_at(t)
        self.current_thickness = self.plan.thickness_at(t)
        self._t = t

    def visible_length(self) -> float:
        return min(max(self.current_length - self.arc0, 0.0), self.arc1 - self.arc0)

    def grown_points(self, t: float | None = None):
        """Local points of the grown part at time ``t`` (default: the last update):
        positions float[q, 3], frames float[q, 3, 3], radii float[q], arc float[q] and the
        index of the mature point each one stands for."""
        if t is not None:
            self.update_attributes(t)
        plan = self.plan
        seg = plan.seg_length
        vis = self.visible_length()
        m = self.k1 - self.k0
        full = int(min(m, math.floor(vis / seg + 1e-9)))
        idx = np.arange(full + 1)
        A = self.arc0 + idx * seg
        # the mature rows as they are (read only: the turtle and the animation only read)
        P = self.points[:full + 1]
        F = self.frames[:full + 1]
        if vis - full * seg > 1e-6 * seg and full < m:
            i = full
            tip = self.points[i] + self.frames[i + 1][:, 1] * (vis - i * seg)
            P = np.concatenate([P, tip[None]])
            F = np.concatenate([F, self.frames[i + 1][None]])
            A = np.append(A, self.arc0 + vis)
            idx = np.append(idx, i + 1)
        self._mature_rows = None  # every row a mature one, in order
        extra = plan.ring_arcs(self.arc0, self.arc0 + vis, max(self.current_length, 1e-9))
        if len(extra):  # not where a mature point already is
            near = np.abs(extra[:, None] - A[None, :]).min(1) <= 1e-6 * seg
            extra = extra[~near]
        if len(extra):  # rings for the spherical end or the periodic taper (Taper > 1)
            i, pe, fe = self._where_many(extra)
            A = np.concatenate([A, extra])
            order = np.argsort(A, kind="stable")
            A = A[order]
            P = np.concatenate([P, pe])[order]
            F = np.concatenate([F, fe])[order]
            idx = np.concatenate([idx, i + 1])[order]
            rows = np.empty(len(order), np.int64)
            rows[order] = np.arange(len(order))
            self._mature_rows = rows[:len(order) - len(extra)]
        r = plan.radius * self.current_thickness * plan.profile(A, max(self.current_length,
                                                                      1e-9))
        return P, F, r, A, idx

    # -- geometry ----------------------------------------------------------------------------
    def generate(self, turtle) -> None:
        plan, tree = self.plan, self.plan.tree
        if self.visible_length() <= 0.0:
            self._joints = self._seg_joints = None
            return
        P, F, R, A, _ = self.grown_points()
        parent = self.parent
        parent_joint = -1
        continues = self.k0 > 0 and self.clone == 0 and turtle.context.stem is not None
        if isinstance(parent, Branch) and parent._joints is not None and len(parent._joints):
            if self.parent_slot is parent.primary:
                parent_joint = int(parent._joints[-1])
            else:
                s = self.plan.offset
                i, _, _ = parent._where(s)
                sj = parent._seg_joints
                parent_joint = int(sj[min(i, len(sj) - 1)])
        if not continues:
            material = tree.bark_material
            turtle.new_stem(sides=plan.sides, material=material, lobes=plan.lobes,
                            lobe_depth=plan.lobe_depth, level=plan.level)
        turtle.context.material = tree.bark_material
        self._skip_first = continues and parent_joint >= 0
        self._joints = turtle.stem_points(P, F, R, parent_joint=parent_joint,
                                          skip_first=self._skip_first)
        rows = self._mature_rows
        self._seg_joints = self._joints if rows is None else self._joints[rows]
        # its leaves are drawn by its Leaves component, visited next (the base slot)


def _skip_run_draws(plan: StemPlan, arc0: float, arc1: float, k1: int, share: float,
                    rng: np.random.Generator) -> None:
    """Move ``rng`` (a run's own stream, fresh) past the draws its :class:`Branch` makes
    before its split: its buds (:meth:`Branch._bud_run`) and its crown leaves
    (:func:`~sylva.tree.leaves._crown_leaves`), without planning them.  Each uniform double
    is one step of the PCG64 stream, so the draws whose values do not decide a count are
    skipped by ``advance``; the two that decide the counts are drawn
    (:func:`_skipped_draws`).  Must follow those two functions draw for draw
    (``tests/tree/test_pruning_speed.py`` checks it on every run of several species)."""
    at = [0]

    def uniform_at(pos: int) -> float:
        if pos > at[0]:
            rng.bit_generator.advance(pos - at[0])
        at[0] = pos + 1
        return rng.random()

    end = _skipped_draws(plan, arc0, arc1, share, uniform_at)
    if end > at[0]:
        rng.bit_generator.advance(end - at[0])


def _skipped_draws(plan: StemPlan, arc0: float, arc1: float, share: float,
                   uniform_at) -> int:
    """The number of steps of a run's stream that its buds and crown leaves take (see
    :func:`_skip_run_draws`); ``uniform_at(pos)`` is the uniform double at step ``pos`` of
    the stream (the two that decide the counts)."""
    tree = plan.tree
    lv = plan.level
    pos = 0
    if lv + 1 < tree.levels and plan.n_children > 0:  # Branch._plan_children
        per_len = share * plan.n_children / max(plan.length - plan.base_length, 1e-9)
        lo = max(arc0, plan.base_length)
        if arc1 > lo:
            n = int(math.floor(per_len * (arc1 - lo) + uniform_at(pos)))
            pos += 1
            if n > 0:
                rot = tree.pf("Rotate", level=lv + 1, default=140.0)
                down = tree.pf("DownAngle", level=lv + 1, default=45.0)
                per = 1 + (1 if rot.value < 0 or rot.deviation else 0) + (
                    1 if down.deviation > 0 else 0)
                pos += 1 + n * per
    if lv == tree.levels - 1 and plan.n_leaves > 0:  # leaves._crown_leaves
        if tree.leaf_arrangement == "fan":
            return pos  # the fan sits at the tip: a run that splits (the only one asked) has none
        want = plan.n_leaves * (arc1 - arc0) / plan.length * share
        n = int(math.floor(want + uniform_at(pos)))
        pos += 1
        if n > 0:
            pos += 5 * n + 1
    return pos


class _TrialStream:
    """A run's stream as the pruning trials of one stem read it: the uniform double at a
    step, and the split frames from a step, each drawn once and remembered (the trials of
    one stem regrow the same runs from the same streams; only the lengths, and so the
    counts of the skipped draws, may differ)."""

    __slots__ = ("words", "rng", "pos", "seen")

    def __init__(self, *words: int) -> None:
        self.words = words
        self.rng = None
        self.pos = 0
        self.seen: dict = {}

    def at(self, pos: int) -> np.random.Generator:
        """The generator moved to step ``pos`` (a fresh one when this one is past it)."""
        if self.rng is None or self.pos > pos:
            self.rng, self.pos = stream(*self.words), 0
        if pos > self.pos:
            self.rng.bit_generator.advance(pos - self.pos)
        self.pos = pos
        return self.rng

    def uniform_at(self, pos: int) -> float:
        v = self.seen.get(pos)
        if v is None:
            v = self.seen[pos] = self.at(pos).random()
            self.pos = pos + 1
        return v

    def split_frames(self, plan: StemPlan, n: int, pos: int) -> list[np.ndarray]:
        """:func:`_split_frames` drawn from step ``pos`` (remembered)."""
        k = ("split", pos, n, plan.level)
        frames = self.seen.get(k)
        if frames is None:
            frames = self.seen[k] = _split_frames(plan, n, self.at(pos))
            self.rng = None  # moved on by an unknown number of steps
        return frames


def _envelope_exit(plan: StemPlan, key: tuple, world: np.ndarray,
                   memo: dict | None = None) -> float | None:
    """``None`` when every point of the mature stem (its split clones included) lies inside
    the tree's pruning envelope, else the arc length the stem keeps: the start of the first
    segment that leaves it (the smallest over the clones).

    The runs are grown as :class:`Branch` grows them (:func:`_run_curve`, the split clones
    of :meth:`Branch._continuations` from the same random streams) but without building
    components, buds or leaves: a split clone's angles only need its parent's stream moved
    past the parent's own draws (:func:`_skip_run_draws`).  ``memo`` (a dict kept over the
    trials of one stem by :func:`_pruned_length`) remembers what the trials share: the runs'
    turned frames and their streams' draws (:class:`_TrialStream`)."""
    if memo is None:
        memo = {}
    tree = plan.tree
    seed = tree.seed & 0xFFFFFFFF
    seg = plan.seg_length
    res = plan.curve_res
    clearance = tree.pf("GroundClearance", default=0.15).value

    def bend(F, P, curve, seg, up_local, attraction, parent_world):
        has_up = up_local is not None
        bend_stem(F, P, np.ascontiguousarray(curve, np.float64), float(seg), has_up,
                  np.asarray(up_local if has_up else _ZERO3, np.float64), float(attraction),
                  True, np.asarray(parent_world, np.float64), float(clearance))

    # (k0, frame, key, split error, world, share) of the runs still to test
    # Tree.inside_envelope's numbers, for the compiled test of each run's points
    st = max(tree.scale_tree, 1e-9)
    denom = st * max(1.0 - tree.base_size, 1e-9)
    width, peak, low, high = tree.prune
    peak = min(max(peak, 1e-6), 1 - 1e-6)
    stack = [(0, _EYE3.copy(), key, 0.0, world, 1.0)]
    keep = None
    while stack:
        k0, frame, bkey, err0, w, share = stack.pop()
        k1, n_split, err, F, P = _run_curve(plan, k0, frame, err0, w, bend, memo)
        # decided on the run's points where BLAS's last bits cannot matter, else on NumPy's
        k = envelope_exit_local(P, w, st, denom, width, peak, low, high)
        if k == -3:
            pts = P @ w[:3, :3].T + w[:3, 3]
            k = envelope_exit(pts, st, denom, width, peak, low, high)
            if k == -2:  # a point on the envelope, to the last bits: NumPy's numbers decide
                out = ~tree.inside_envelope(pts)
                k = int(np.argmax(out)) if np.any(out) else -1
        arc0 = k0 * seg
        if k >= 0:
            arc = arc0 + max(k - 1, 0) * seg
            keep = arc if keep is None else min(keep, arc)
            continue  # a clone after the exit cannot keep more than this
        arc1 = k1 * seg
        if k1 < res and (keep is None or arc1 < keep):
            m = k1 - k0
            nxt = w @ Branch._matrix(P[m], F[m])
            draws = memo.get(bkey)
            if draws is None:
                draws = memo[bkey] = _TrialStream(seed, *bkey)
            pos = _skipped_draws(plan, arc0, arc1, share, draws.uniform_at)
            for c, fc in enumerate(draws.split_frames(plan, n_split, pos)):
                stack.append((k1, fc, (*bkey, 2, c), err, nxt, share / (n_split + 1)))
    return keep


def _split_frames(plan: StemPlan, n: int, rng: np.random.Generator) -> list[np.ndarray]:
    """The initial frames of the ``n + 1`` runs that continue a stem after a split (the
    draws of :meth:`Branch._continuations`, from the splitting run's stream)."""
    angle = plan.tree.params.float("SplitAngle", level=plan.level, default=20.0)
    base_phi = uniform(rng, 0, 2 * math.pi)
    if n == 0:
        return [_EYE3.copy()]
    phi, a = np.empty(n + 1), np.empty(n + 1)
    for c in range(n + 1):
        a[c] = math.radians(abs(angle.sample(rng))) * (0.5 if c == 0 else 1.0)
        phi[c] = base_phi + 2 * math.pi * c / (n + 1)
    # Ry(phi) @ Rx(a) @ Ry(-phi) of every clone in one product of rotation stacks (the
    # matrices of _ry and _rx; a stack is multiplied matrix by matrix: the same bits)
    return list(_ry_many(phi) @ _rx_many(a) @ _ry_many(-phi))


def _pruned_length(plan_of, length: float, key: tuple, world: np.ndarray) -> float:
    """Weber & Penn's pruning: shorten the stem until it fits in the envelope (0 if it
    cannot).  Each trial keeps at most the segments inside, at least half the length, and
    loses at least 1/15 of the original length (the scheme of the paper's reimplementations,
    e.g. Arbaro); every trial regrows the stem from the same random draws."""
    L = length
    memo: dict = {}  # what the trials share (see _envelope_exit)
    while L >= 1e-3:
        keep = _envelope_exit(plan_of(L), key, world, memo=memo)
        if keep is None:
            return L
        L = min(max(keep, 0.5 * L), L - length / 15.0)
    return 0.0


def make_trunk(tree, rng: np.random.Generator) -> Branch:
    """The level-0 stem of ``tree`` (its length and radius drawn from the fixed values)."""
    scale = tree.pf("Scale", default=10.0).fixed
    length0 = tree.pf("Length", level=0, default=1.0).fixed * scale
    radius0 = length0 * tree.pf("Ratio", default=0.02).value * tree.pf(
        "Scale0", default=1.0).fixed
    n_children = tree.pf("Branches", level=1, default=0.0).value if tree.levels > 1 else 0.0
    n_leaves = tree.leaves * tree.leaf_density_of(1) if tree.levels == 1 else 0.0
    plan = StemPlan(tree, 0, length0, radius0, 0.0, rng, n_children=n_children,
                    n_leaves=n_leaves)
    frame = _ry(rng.uniform(0, 2 * math.pi))
    return Branch(plan, 0, frame, (0,))

