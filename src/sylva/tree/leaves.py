"""Leaves as components (seed 002 §4.2, §4.7–4.10): the leaves of a stem hang on its base slot.

A :class:`Leaves` component holds the leaves of one run of a stem (a
:class:`~sylva.tree.weber_penn.Branch`).  It is attached to the run's **base slot**: the slot
with the identity transform, so the leaves share the stem's frame, and, being a slot other
than the primary one, the component is of **level + 1** (seed 002 §4.8).  Its parameters come
from the parameter space of that level, then from the global space, exactly as a stem's do:
the leaves on the stems of level *n* read ``[level n+1]`` (the crown's leaves on a 3-level
tree read ``[level 3]``; the leaves of a young trunk's shoots read ``[level 1]``).  They
develop in time like a stem (each leaf is born, unfolds, may fade and fall) and are updated
lazily, and :func:`~sylva.tree.components.traverse` draws them right after their stem (the
base slot is visited first).

One component stands for *all* the leaves of its run, held as arrays: a mature aspen has
about 15,000 leaves, and as many Python objects would cost most of the one-second budget of
``benchmarks/tree.py``.  Each leaf is a row: its arc length on the stem, its frame, its
mature blade length, its birth and death times and (drawn only when a season needs it) its
*autumn rank*, a fixed random value in [0, 1) from its own stream.

The parameters (every one may be set in ``[global]`` or in a ``[level N]`` for that level's
leaves; ranges in :data:`sylva.tree._schema.KEYS`):

* ``LeafScale`` ± deviation, ``LeafScaleX``: blade length (m) and width / length.
* ``LeafDensity``: multiplies the number of leaves.  In ``[global]`` it multiplies
  ``Leaves`` (the crown's leaves, as before); in a ``[level N]`` it multiplies that level's
  leaves, crown leaves (``Leaves · ShapeRatio(4, offset / parent length) · LeafDensity``,
  Weber & Penn's count) or the juvenile leaves of young shoots (their spacing is divided by
  it).
* ``LeafScaleYoung``, ``LeafAdultAge``: leaf size over the tree's age.  A leaf that appears
  when the tree is ``T`` years old is ``LeafScale · (y + (1 − y) · min(T / LeafAdultAge, 1))``
  long, ``y = LeafScaleYoung`` (1, the default: the same size at every age; > 1: a
  sapling's larger leaves).  A leaf keeps its size once it is out, so growth stays
  continuous.
* ``LeafMaterial``, ``AutumnMaterial``: the leaf's colour (material names) in and out of
  autumn.
* ``SpringLeafScale`` (default 0.6): a deciduous tree's leaves in spring, relative to summer.
* ``LeafTurn`` (default 1) and ``LeafFall`` (default 0): the state of autumn.  A leaf whose
  autumn rank is below ``LeafFall`` has fallen; one whose rank is below ``max(LeafTurn,
  LeafFall)`` has turned (``AutumnMaterial``): the first leaves to turn are the first to
  fall.  So ``Season = "autumn"`` alone is today's autumn (every leaf turned, none fallen),
  ``LeafTurn = 0.5`` half of them turned, ``LeafFall = 0.3`` 30 % of them on the ground,
  and ``LeafFall = 1`` (or ``Season = "winter"``) the bare tree: the same stems, no leaves.

Seasons only change a ``Deciduous`` tree; an evergreen keeps its leaves all year.

Examples
--------
>>> from sylva.tree import Tree
>>> t = Tree("quaking_aspen", seed=1, quality=0.3).grow(3.0)
>>> leaves = t.leaf_components()[0]
>>> leaves.level == leaves.parent.level + 1, leaves.parent_slot is leaves.parent.base
(True, True)
>>> bare = Tree("quaking_aspen", seed=1, quality=0.3, season="autumn", leaf_fall=1.0)
>>> bare.grow(3.0).stats()["leaves"], t.stats()["leaves"] > 0
(0, True)
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import SylvaError
from ._kernels import crown_leaf_spiral
from ._streams import stream, uniform
from .components import Component

__all__ = ["LEAF_FALL", "LeafParameterError", "Leaves", "plan_leaves"]


class LeafParameterError(SylvaError, ValueError):
    """A leaf parameter given to :class:`~sylva.tree.model.Tree` outside its range."""

LEAF_FALL = 0.5  # years a shed branch takes to drop its leaves, before its wood goes
_AUTUMN_STREAM = 17  # the random stream of the autumn ranks (after the stems' 7, 11, 13)
# a crown leaf's death (it stays: inf), shared read only by the runs (a view of its first
# n rows instead of a new array per run; nothing writes a death)
_NEVER = np.full(1024, np.inf)
_NEVER.flags.writeable = False


class Leaves(Component):
    """The leaves of one run of a stem, on its base slot (level = the stem's + 1).

    Parameters
    ----------
    branch : Branch
        The run that carries them (the component is attached to its base slot).
    arc, size, birth, death : float64[n]
        Arc length on the stem, mature blade length (m), global time it appears and the time
        it is gone (``inf``: it stays).
    frame : float64[n, 3, 3]
        The leaf's frame in the stem's frame (columns: across, along the blade, normal).
    juvenile : int
        How many of the rows (the last ones) are juvenile leaves (on the young shoots of a
        stem below the leaf level).
    """

    def __init__(self, branch, arc, frame, size, birth, death, juvenile: int = 0) -> None:
        plan = branch.plan
        super().__init__(branch.birth_time, name=f"Leaves{plan.level + 1}")
        self.branch = branch
        self.tree = plan.tree
        self.leaf_level = plan.level + 1
        self.arc = arc
        self._frame: np.ndarray | None = None
        self._turns: _Turns | None = None
        if isinstance(frame, _Turns):  # worked out with the tree's others when first asked
            self._turns = frame
            _pending(self.tree).append(self)
        else:
            self._frame = frame
        self.size = size
        self._birth: np.ndarray | None = birth
        if birth is None:  # worked out with the tree's others when first asked for
            _pending(self.tree, "_leaf_births").append(self)
        self.death = death
        self.juvenile = juvenile
        self._rank: np.ndarray | None = None
        self._span: tuple[float, float] | None = None  # sizes_at's (last birth, first death)
        self._t = 0.0

    def __len__(self) -> int:
        return len(self.arc)

    @property
    def birth(self) -> np.ndarray:
        """``float64[n]``: the global time each leaf appears (its stem reaches it, plus
        ``LeafDelay``).  A crown's leaves are planned without it; the births of all the
        tree's leaves planned so far are worked out together the first time one is asked
        for (:func:`_settle_births`)."""
        if self._birth is None:
            _settle_births(self)
        return self._birth

    @property
    def frame(self) -> np.ndarray:
        """``float64[n, 3, 3]``: each leaf's frame in the stem's frame (columns: across,
        along the blade, normal).  A crown's spiral leaves are planned with their turns
        only; the frames of all the tree's leaves planned so far are worked out together
        the first time one is asked for (:func:`_settle_frames`)."""
        if self._frame is None:
            _settle_frames(self)
        return self._frame

    def rank(self) -> np.ndarray:
        """The autumn rank of every leaf: a fixed random value in [0, 1) drawn once, from the
        run's own stream (the same leaves turn and fall for the same seed)."""
        if self._rank is None:
            tree = self.tree
            rng = stream(tree.seed & 0xFFFFFFFF, *self.branch.key, _AUTUMN_STREAM)
            self._rank = rng.uniform(0.0, 1.0, len(self.arc))
        return self._rank

    def sizes_at(self, t: float) -> np.ndarray:
        """Blade length of every leaf at global time ``t``, 0 for one not out or gone: they
        unfold over ``LeafUnfold`` years, juvenile ones fade in their last year, a shed
        branch's leaves fall (shrink) over half a year before its wood retracts, and the
        season applies (spring's ``SpringLeafScale``, autumn's ``LeafFall``, winter)."""
        tree = self.tree
        plan = self.branch.plan
        unfold = max(tree.leaf_unfold, 1e-6)
        if self._span is None:  # the last birth and the first death (the arrays are fixed)
            n = len(self.birth)
            self._span = (float(self.birth.max()) if n else -math.inf,
                          float(self.death.min()) if n else math.inf)
        last_birth, first_death = self._span
        if (t - last_birth) / unfold >= 1.0 and first_death - t >= 1.0:
            # every leaf unfolded and none fading: the factors below are all exactly 1
            # (1 ** 0.7 == 1, x * 1 == x), so the same numbers without the arithmetic
            size = self.size  # (read only here: what is returned is a new array)
        else:
            age = (t - self.birth) / unfold
            # np.minimum(np.maximum(0, x), 1) is np.clip(x, 0, 1) bit for bit, without its
            # Python-level dispatch (weber_penn.envelope)
            size = self.size * np.minimum(np.maximum(0.0, age), 1.0) ** 0.7
            size = size * np.minimum(np.maximum(0.0, self.death - t), 1.0)
            size[self.birth > t] = 0.0
        if plan.shed is not None:  # a shed branch drops its leaves before it goes
            size = size * min(max(1.0 - (t - plan.shed) / LEAF_FALL, 0.0), 1.0)
        scale, _turn, fall = tree.leaf_season(self.leaf_level)
        if fall > 0.0:
            size = np.where(self.rank() < fall, 0.0, size)
        return size * scale

    def materials(self, shown: np.ndarray) -> str | list[str]:
        """The material of the leaves ``shown`` (bool[n]): one name, or one per leaf when
        autumn has turned only some of them."""
        tree = self.tree
        material, autumn = tree.leaf_materials(self.leaf_level)
        if not (tree.deciduous and tree.season == "autumn"):
            return material
        _scale, turn, fall = tree.leaf_season(self.leaf_level)
        turned = max(turn, fall)
        if turned >= 1.0:
            return autumn
        if turned <= 0.0:
            return material
        r = self.rank()[shown]
        return [autumn if x < turned else material for x in r]

    def update_attributes(self, t: float) -> None:
        self._t = t

    def generate(self, turtle) -> None:
        b = self.branch
        if b._seg_joints is None or not len(self.arc):
            return  # the stem is not out yet
        sizes = self.sizes_at(self._t)
        out = sizes > 0.0
        if out.all():  # every leaf out (a grown tree): the rows as they are, no copies
            size, arc, frame = sizes, self.arc, self.frame
        elif not out.any():
            return
        else:
            size, arc, frame = sizes[out], self.arc[out], self.frame[out]
        i, pos = b._where_points(arc)
        jn = b._seg_joints[np.minimum(i, len(b._seg_joints) - 1)]
        width = self.tree.leaf_width_of(self.leaf_level)
        turtle.leaves(pos, frame, size, width, self.materials(out), jn)


def _young(tree, level: int, size: np.ndarray, birth: np.ndarray) -> np.ndarray:
    """``size`` scaled by ``LeafScaleYoung`` for the tree's age at each leaf's birth."""
    y = tree.pf("LeafScaleYoung", level=level, default=1.0).value
    if y == 1.0 or not len(size):
        return size
    adult = max(tree.pf("LeafAdultAge", level=level, default=10.0).value, 1e-9)
    return size * (y + (1.0 - y) * np.minimum(np.maximum(birth, 0.0) / adult, 1.0))


def plan_leaves(branch, rng) -> Leaves | None:
    """Plan the leaves of a run (``rng``: the run's own stream, after its buds) and attach
    them as a :class:`Leaves` on its base slot; ``None`` when it has none."""
    plan, tree = branch.plan, branch.plan.tree
    arc, frame, size = _crown_leaves(branch, rng)
    birth = None  # worked out later for every leaf of the tree at once (Leaves.birth) ...
    if tree.pf("LeafScaleYoung", level=plan.level + 1, default=1.0).value != 1.0:
        birth = _births(plan, arc)  # ... unless the sizes depend on it now
    death = _NEVER[:len(arc)] if len(arc) <= len(_NEVER) else np.full(len(arc), np.inf)
    if birth is not None:
        size = _young(tree, plan.level + 1, size, birth)
    juvenile = _juvenile_leaves(branch)
    n_juvenile = 0
    if juvenile is not None:
        if birth is None:
            birth = _births(plan, arc)
        j_arc, j_frame, j_size, j_birth, j_death = juvenile
        n_juvenile = len(j_arc)
        arc = np.concatenate([arc, j_arc])
        frame = np.concatenate([frame.frames() if isinstance(frame, _Turns) else frame,
                                j_frame])
        size = np.concatenate([size, _young(tree, plan.level + 1, j_size, j_birth)])
        birth = np.concatenate([birth, j_birth])
        death = np.concatenate([death, j_death])
    if not len(arc):
        return None
    leaves = Leaves(branch, arc, frame, size, birth, death, n_juvenile)
    branch.attach(leaves, branch.base)
    return leaves


def _crown_leaves(branch, rng):
    """The leaves of the last stem level: ``Leaves · ShapeRatio(4, offset / parent length)``
    per stem (the plan's ``n_leaves``), spread over its runs by their share."""
    _rx, _rx_many, _ry_many, _rz = _wp._rx, _wp._rx_many, _wp._ry_many, _wp._rz
    plan, tree = branch.plan, branch.plan.tree
    empty = (np.zeros(0), np.zeros((0, 3, 3)), np.zeros(0))
    if plan.level != tree.levels - 1 or plan.n_leaves <= 0:
        return empty
    lv = plan.level + 1
    scale = tree.pf("LeafScale", level=lv, default=0.2)
    if tree.leaf_arrangement == "fan":
        if branch.k1 < plan.curve_res:
            return empty  # the fan sits at the tip of the stem
        n = int(round(plan.n_leaves))
        spread = math.radians(tree.pf("FanAngle", default=150.0).value)
        tip = branch.frames[-1]
        out_f = []
        for i in range(n):
            a = (i / max(n - 1, 1) - 0.5) * spread + uniform(rng, -0.04, 0.04)
            f = tip @ _rz(a) @ _rx(math.radians(uniform(rng, -8, 8)))
            out_f.append(f)
        arcs = np.full(n, branch.arc1 - 1e-6)
        sizes = np.array([scale.sample(rng) for _ in range(n)])
        return arcs, np.array(out_f).reshape(-1, 3, 3), sizes
    frac = (branch.arc1 - branch.arc0) / plan.length
    want = plan.n_leaves * frac * branch.share
    n = int(math.floor(want + rng.random()))
    if n <= 0:
        return empty
    rot = tree.pf("Rotate", level=lv, default=137.5)
    down = tree.pf("DownAngle", level=lv, default=45.0)
    a0, a1 = branch.arc0, branch.arc1
    if rot.value >= 0:
        # the spiral: its 5n + 1 draws (u_arc, u_rot, phi0, u_down, the petiole twist and
        # the size deviation, each one uniform call in turn before) in one call, their
        # arithmetic in one compiled call; the frames (segment frame @ Ry @ Rx @ Rtwist)
        # are worked out for all the tree's leaves at once when first asked for
        arcs, seg_i, ry, rx, rt, sizes = crown_leaf_spiral(
            rng.random(5 * n + 1), float(a0), float(a1), float(rot.value),
            float(abs(rot.deviation)), float(down.value), float(abs(down.deviation)),
            float(scale.value), float(abs(scale.deviation)), float(plan.seg_length),
            branch.k1 - branch.k0 - 1)
        return arcs, _Turns(branch, seg_i, ry, rx, rt), sizes
    u_arc = rng.uniform(0.2, 0.8, n)
    # two ranks: alternately ±(180 + nRotate) (a pinnate frond, a fern)
    arcs = a0 + (np.arange(n) + u_arc) / n * (a1 - a0)
    sides = np.where(np.arange(n) % 2 == 0, 1.0, -1.0)
    a = 180.0 + rot.value + rng.uniform(-1, 1, n) * abs(rot.deviation)
    phi = np.radians(rng.uniform(0, 360) + sides * a)
    theta = np.radians(np.abs(down.value + rng.uniform(-1, 1, n) * abs(down.deviation)))
    twist = np.radians(rng.uniform(-30, 30, n))  # a petiole twist
    f = branch.frames[branch._segments_at(arcs) + 1]
    frames = f @ _ry_many(phi) @ _rx_many(theta) @ _ry_many(twist)
    sizes = scale.value + rng.uniform(-1, 1, n) * abs(scale.deviation)
    return arcs, frames, sizes


class _Turns:
    """The frames of a run's spiral leaves before they are worked out: ``frames[seg + 1]
    @ ry @ rx @ rt`` of its :class:`~sylva.tree.weber_penn.Branch` (its segments' frames
    are fixed once it is planned).  Matrix products of 3 x 3 stacks are computed matrix by
    matrix, so one product over every leaf of a tree gives each run's numbers bit for
    bit; it saves some thirty thousand small NumPy calls on a mature tree."""

    __slots__ = ("branch", "seg", "ry", "rx", "rt")

    def __init__(self, branch, seg, ry, rx, rt) -> None:
        self.branch, self.seg, self.ry, self.rx, self.rt = branch, seg, ry, rx, rt

    def __len__(self) -> int:
        return len(self.seg)

    def frames(self) -> np.ndarray:
        return self.branch.frames[self.seg + 1] @ self.ry @ self.rx @ self.rt


def _pending(tree, what: str = "_leaf_turns") -> list:
    """The tree's :class:`Leaves` whose frames (``_leaf_turns``) or births
    (``_leaf_births``) are not worked out yet."""
    pending = tree.__dict__.get(what)
    if pending is None:
        pending = tree.__dict__[what] = []
    return pending


def _births(plan, arc: np.ndarray) -> np.ndarray:
    """The birth of a leaf at each arc length ``arc`` of a stem of ``plan``."""
    return np.asarray(plan.time_at_length(arc)) + plan.tree.leaf_delay


def _settle_births(leaves: Leaves) -> None:
    """Work out the births of every pending :class:`Leaves` of ``leaves``' tree in one
    pass of array operations (``leaves``' own included).  :meth:`StemPlan.time_at_length
    <sylva.tree.weber_penn.StemPlan.time_at_length>` on an array is elementwise: each
    leaf's ``birth + inverse(arc / length) * grow_time + LeafDelay`` with its own stem's
    numbers, the same IEEE operations on one long array as on each run's (the growth
    curve is the tree's, shared by every stem), so the same bits
    (``tests/tree/test_leaf_births.py``); it saves some twelve small NumPy calls per run."""
    pending = _pending(leaves.tree, "_leaf_births")
    batch = [x for x in pending if x._birth is None]
    pending.clear()
    if leaves._birth is None and all(x is not leaves for x in batch):
        batch.append(leaves)
    growth = batch[0].branch.plan.growth
    if any(x.branch.plan.growth is not growth for x in batch):  # not one curve: each alone
        for x in batch:
            x._birth = _births(x.branch.plan, x.arc)
        return
    plans = [x.branch.plan for x in batch]
    counts = [len(x.arc) for x in batch]
    arc = np.concatenate([x.arc for x in batch]).astype(np.float64, copy=False)
    length = np.repeat(np.array([p.length for p in plans], np.float64), counts)
    start = np.repeat(np.array([p.birth for p in plans], np.float64), counts)
    years = np.repeat(np.array([p.grow_time for p in plans], np.float64), counts)
    birth = (start + growth.inverse(arc / length) * years) + leaves.tree.leaf_delay
    at = 0
    for x, n in zip(batch, counts):
        x._birth = birth[at:at + n]
        at += n


def _settle_frames(leaves: Leaves) -> None:
    """Work out the frames of every pending :class:`Leaves` of ``leaves``' tree in one
    product (:class:`_Turns`), ``leaves``' own included (alone when it is not among them:
    a copy)."""
    pending = _pending(leaves.tree)
    batch = [x for x in pending if x._frame is None and x._turns is not None]
    pending.clear()
    if leaves._turns is not None and all(x is not leaves for x in batch):
        batch.append(leaves)
    if batch:
        turns = [x._turns for x in batch]
        f = np.concatenate([t.branch.frames[t.seg + 1] for t in turns])
        f = f @ np.concatenate([t.ry for t in turns]) @ np.concatenate(
            [t.rx for t in turns]) @ np.concatenate([t.rt for t in turns])
        at = 0
        for x, t in zip(batch, turns):
            x._frame = f[at:at + len(t)]
            x._turns = None
            at += len(t)
    if leaves._frame is None:
        leaves._frame = np.zeros((len(leaves.arc), 3, 3))


def _juvenile_leaves(branch):
    """Leaves on the young shoots of a stem below the leaf level: every stretch of it
    carries leaves for ``JuvenileLeafLife`` years after it grows (a young tree's buds have
    leaves before they have branches), then they fade over a year; all are gone by the
    species' ``Age`` (or shed with their branch).  ``None`` when there are none."""
    _rx_many, _ry_many = _wp._rx_many, _wp._ry_many
    plan, tree = branch.plan, branch.plan.tree
    if plan.level >= tree.levels - 1 or tree.juvenile_leaf_life <= 0:
        return None
    if plan.level == 0 and not tree.juvenile_trunk_leaves:
        return None
    # leaves that are all gone by the time the simulation is heading for are never seen
    # (time only moves on; growing back regrows from the start): a mature tree plans none
    sim = getattr(tree, "simulation", None)
    target = sim.target if sim is not None else -math.inf
    if target >= tree.default_age - 1.0:
        return None
    lv = plan.level + 1
    scale = tree.pf("LeafScale", level=lv, default=0.2)
    spacing = max(tree.juvenile_leaf_spacing * scale.value, 1e-3)
    density = tree.level_value("LeafDensity", lv)
    if density is not None:
        if density <= 0:
            return None
        spacing /= density
    n = int((branch.arc1 - branch.arc0) / spacing)
    if n <= 0:
        return None
    rng = stream(tree.seed & 0xFFFFFFFF, *branch.key, 13)
    arcs = branch.arc0 + (np.arange(n) + rng.uniform(0.2, 0.8, n)) * spacing
    birth = np.asarray(plan.time_at_length(arcs), np.float64) + tree.leaf_delay
    death = np.minimum(birth + tree.juvenile_leaf_life, tree.default_age - 1.0)
    keep = death > birth + 0.5 * tree.leaf_unfold
    if not keep.any() or (death[keep] <= target).all():
        return None
    arcs, birth, death = arcs[keep], birth[keep], death[keep]
    n = len(arcs)
    rot = tree.pf("Rotate", level=tree.levels, default=137.5)
    down = tree.pf("DownAngle", level=tree.levels, default=45.0)
    phi = np.radians(rng.uniform(0, 360) + np.cumsum(
        np.full(n, rot.value if rot.value >= 0 else 137.5)))
    theta = np.radians(np.abs(down.value + rng.uniform(-1, 1, n) * abs(down.deviation)))
    f = branch.frames[branch._segments_at(arcs) + 1]
    frames = f @ _ry_many(phi) @ _rx_many(theta)
    sizes = scale.value + rng.uniform(-1, 1, n) * abs(scale.deviation)
    return arcs, frames, sizes, birth, death


# the stems' rotation helpers, read at call time (weber_penn imports this module first)
from . import weber_penn as _wp  # noqa: E402
