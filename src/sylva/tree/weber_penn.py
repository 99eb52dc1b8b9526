"""A Weber–Penn tree (Weber & Penn 1995, seed 002 Appendix B) grown by events in time.

The parameters keep the paper's names: global ``Shape``, ``BaseSize``, ``Scale`` (± ``ScaleV``),
``Levels``, ``Ratio``, ``RatioPower``, ``Lobes``, ``LobeDepth``, ``Flare``, ``Scale0``
(the paper's ``0Scale``), ``BaseSplits`` (``0BaseSplits``), ``Leaves``, ``LeafScale``,
``LeafScaleX``, ``AttractionUp``, ``PruneWidth``/``PruneWidthPeak``/``PrunePowerLow``/
``PrunePowerHigh`` (shape 8); per level ``Length``, ``Taper``, ``SegSplits``, ``SplitAngle``,
``CurveRes``, ``Curve``, ``CurveBack``, ``CurveV`` (written as the deviation of ``Curve``),
``DownAngle``, ``Rotate``, ``Branches``.  A paper ``XV`` is the deviation of ``X``.

Growth in time is our design (the thesis's §4.2.5 is not in the seed):

* every stem elongates as ``L(t) = L · f((t − t₀)/GrowTime)`` with the cubic ``f`` of
  :class:`~sylva.tree.events.TimeFunction`, and thickens as
  ``r(t) = r · (0.08 + 0.92 · f((t − t₀)/ThickenTime))``; the growing stem is the mature
  curve cut at ``L(t)``, tapering to its current tip;
* a bud at arc length ``o`` breaks — an event ``"bud"`` creates the child stem — at the time
  the parent reaches ``o``, plus ``BudDelay``; a segment split is an event ``"split"`` at
  the time the stem reaches the split point, which attaches the clones to the primary slot;
* a leaf appears ``LeafDelay`` after its stem passes it and unfolds over ``LeafUnfold``.

``GrowTime``, ``ThickenTime``, ``BudDelay`` (per level), ``LeafDelay``, ``LeafUnfold``,
``Age`` (the default age of a grown tree), ``Sides`` (ring resolution per level),
``LeafArrangement`` (``"spiral"`` or ``"fan"``), ``FanAngle``, ``BarkMaterial`` and
``LeafMaterial`` are our additions, and so is ``GroundClearance`` (m, default 0.15): a stem
whose next segment would dip below it turns level, so hanging whips trail above the ground.

Simplifications, stated: ``Taper`` above 1 (the paper's periodic taper) is read as 1;
``ZScale``, ``PruneRatio`` (pruning against an envelope) and ``LeafShape`` are not used (the
leaf blade is one pointed shape with the width ``LeafScaleX``); the attraction-up rule is a
rotation toward (or, negative, away from) the vertical by ``AttractionUp · sin(declination) /
(2 · CurveRes)`` per segment, applied from level 2 as in the paper.
"""

from __future__ import annotations

import math

import numpy as np

from .components import Component

__all__ = ["Branch", "StemPlan", "make_trunk", "shape_ratio"]

_SIDES = (14, 9, 6, 4, 3)


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
        width, peak, low, high = prune or (0.5, 0.5, 0.5, 0.5)
        peak = min(max(peak, 1e-6), 1 - 1e-6)
        # ratio is measured from the top (Appendix B); the envelope is widest at 1 - peak
        if r < 1.0 - peak:
            return width * (r / (1.0 - peak)) ** high
        return width * ((1.0 - r) / peak) ** low
    raise ValueError(f"unknown Weber–Penn shape {shape}: expected 0…8")


def _rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def _rx_many(a: np.ndarray) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((len(a), 3, 3))
    out[:, 0, 0] = 1.0
    out[:, 1, 1], out[:, 1, 2], out[:, 2, 1], out[:, 2, 2] = c, -s, s, c
    return out


def _ry_many(a: np.ndarray) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((len(a), 3, 3))
    out[:, 1, 1] = 1.0
    out[:, 0, 0], out[:, 0, 2], out[:, 2, 0], out[:, 2, 2] = c, s, -s, c
    return out


def _axis_angle(axis: np.ndarray, a: float) -> np.ndarray:
    x, y, z = axis / np.linalg.norm(axis)
    c, s = math.cos(a), math.sin(a)
    C = 1.0 - c
    return np.array([
        [c + x * x * C, x * y * C - z * s, x * z * C + y * s],
        [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
        [z * x * C - y * s, z * y * C + x * s, c + z * z * C],
    ])


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
                 n_children: float = 0.0, n_leaves: float = 0.0) -> None:
        pm = tree.params
        self.tree = tree
        self.level = level
        self.length = max(float(length), 1e-4)
        self.radius = max(float(radius), 1e-4)
        self.birth = float(birth)
        self.offset = offset
        self.parent_length = parent_length
        self.n_children = n_children
        self.n_leaves = n_leaves
        lv = level
        default_grow = (12.0, 5.0, 2.0, 1.0, 0.6)[min(lv, 4)]
        self.grow_time = max(pm.float("GrowTime", level=lv, default=default_grow).value, 1e-3)
        self.thicken_time = max(
            pm.float("ThickenTime", level=lv, default=2.5 * self.grow_time).value, 1e-3
        )
        self.bud_delay = max(pm.float("BudDelay", level=lv, default=0.3).value, 0.0)
        self.taper = float(np.clip(pm.float("Taper", level=lv, default=1.0).value, 0.0, 1.0))
        self.curve_res = max(1, pm.int("CurveRes", level=lv, default=3))
        self.sides = max(3, pm.int("Sides", level=lv, default=_SIDES[min(lv, 4)]))
        self.growth = tree.growth
        self.thickening = tree.thickening
        curve = pm.float("Curve", level=lv, default=0.0)
        back = pm.float("CurveBack", level=lv, default=0.0).value
        res = self.curve_res
        base = np.full(res, curve.value / res)
        if back:
            half = max(res / 2.0, 1.0)
            base = np.where(np.arange(res) < res / 2.0, curve.value / half, back / half)
        jitter = rng.uniform(-1.0, 1.0, res) * abs(curve.deviation) / res
        self.curve = np.radians(base + jitter)
        self.flare = pm.float("Flare", default=0.0).value if level == 0 else 0.0
        self.lobes = pm.int("Lobes", default=0) if level == 0 else 0
        self.lobe_depth = pm.float("LobeDepth", default=0.0).value if level == 0 else 0.0
        self.base_length = pm.float("BaseSize", default=0.0).value * self.length if level == 0 \
            else 0.0

    @property
    def seg_length(self) -> float:
        return self.length / self.curve_res

    def length_at(self, t: float) -> float:
        return self.length * float(self.growth((t - self.birth) / self.grow_time))

    def time_at_length(self, s):
        """The global time this stem reaches arc length ``s`` (a float or an array)."""
        tau = self.growth.inverse(np.asarray(s, np.float64) / self.length)
        out = self.birth + tau * self.grow_time
        return float(out) if np.ndim(out) == 0 else out

    def thickness_at(self, t: float) -> float:
        return 0.08 + 0.92 * float(self.thickening((t - self.birth) / self.thicken_time))

    def profile(self, s: np.ndarray, current: float) -> np.ndarray:
        """Relative radius at arc lengths ``s`` of a stem ``current`` long (taper + flare)."""
        z = np.minimum(np.maximum(s / max(current, 1e-9), 0.0), 1.0)
        r = 1.0 - self.taper * z
        if self.flare:
            y = np.maximum(0.0, 1.0 - 8.0 * z)
            r = r * (self.flare * (100.0**y - 1.0) / 100.0 + 1.0)
        return np.maximum(r, 0.02 * (1 - z) + 0.004)


class Branch(Component):
    """A run of segments ``[k0, k1)`` of one stem; a split ends it and its clones continue
    on the primary slot, children hang on their own slots (level + 1), leaves are attributes.

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
        self.rng = np.random.default_rng([tree.seed & 0xFFFFFFFF, *key])
        rng = self.rng
        pm = tree.params
        res = plan.curve_res
        seg = plan.seg_length
        lv = plan.level
        # -- splits: error-diffused nSegSplits (0BaseSplits at the trunk's first segment) ----
        seg_splits = pm.float("SegSplits", level=lv, default=0.0).value
        k1, n_split, err = res, 0, split_error
        for k in range(k0, res - 1):
            want = seg_splits
            if lv == 0 and k == 0:
                want = float(pm.int("BaseSplits", default=0))
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
        self.k1 = k1
        self.n_split = n_split
        self.split_error = err
        # -- the mature curve in the local frame ---------------------------------------------
        m = k1 - k0
        F = np.empty((m + 1, 3, 3))
        P = np.zeros((m + 1, 3))
        F[0] = frame
        attraction = pm.float("AttractionUp", default=0.0).value if lv >= 2 else 0.0
        self._clearance = pm.float("GroundClearance", default=0.15).value
        up_local = None
        if attraction and parent_world is not None:
            up_local = parent_world[:3, :3].T @ np.array([0.0, 1.0, 0.0])
        # fast path: every segment turns about its own x axis, so the turns add up
        F[1:] = frame @ _rx_many(np.cumsum(plan.curve[k0:k1]))
        P[1:] = np.cumsum(F[1:, :, 1] * seg, axis=0)
        sequential = up_local is not None
        if parent_world is not None and not sequential:
            y = P[1:] @ parent_world[1, :3] + parent_world[1, 3]
            sequential = bool(np.any(y < self._clearance))
        if sequential:
            self._bend(F, P, plan.curve[k0:k1], seg, up_local, attraction / (2.0 * res),
                       parent_world)
        self.points = P
        self.frames = F
        self.arc0 = k0 * seg
        self.arc1 = k1 * seg
        self.primary.set_transform(self._matrix(P[m], F[m]))
        # -- children (buds) and leaves along this run -----------------------------------------
        self.buds = self._plan_children(rng)
        self.leaf_arc, self.leaf_frame, self.leaf_size = self._plan_leaves(rng)
        self.leaf_birth = np.asarray(plan.time_at_length(self.leaf_arc)) + tree.leaf_delay
        self._joints: np.ndarray | None = None
        self._skip_first = False
        # lazy-update state
        self.current_length = 0.0
        self.current_thickness = 0.0

    def _bend(self, F, P, curve, seg, up_local, attraction, parent_world) -> None:
        """The segment loop with attraction up and ground clearance (fills F[1:], P[1:])."""
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
        m = np.eye(4)
        m[:3, :3] = f
        m[:3, 3] = p
        return m

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
        i = np.minimum(np.maximum(((s - self.arc0) // seg).astype(np.int64), 0),
                       self.k1 - self.k0 - 1)
        f = self.frames[i + 1]
        p = self.points[i] + f[:, :, 1] * (s - self.arc0 - i * seg)[:, None]
        return i, p, f

    def _plan_children(self, rng) -> list[tuple]:
        plan, tree = self.plan, self.plan.tree
        pm = tree.params
        lv = plan.level
        if lv + 1 >= tree.levels or plan.n_children <= 0:
            return []
        per_len = self.share * plan.n_children / max(plan.length - plan.base_length, 1e-9)
        lo = max(self.arc0, plan.base_length)
        hi = self.arc1
        if hi <= lo:
            return []
        want = per_len * (hi - lo)
        n = int(math.floor(want + rng.uniform()))
        if n <= 0:
            return []
        rot = pm.float("Rotate", level=lv + 1, default=140.0)
        down = pm.float("DownAngle", level=lv + 1, default=45.0)
        phi = rng.uniform(0.0, 360.0)
        out = []
        for i in range(n):
            s = lo + (i + rng.uniform(0.25, 0.75)) / n * (hi - lo)
            if rot.value >= 0:
                phi += rot.sample(rng)
            else:
                phi += 180.0 + rng.uniform(-1, 1) * abs(rot.deviation)
            if down.deviation >= 0:
                theta = down.sample(rng)
            else:  # the paper's special mode for a negative nDownAngleV
                span = max(plan.length - plan.base_length, 1e-9)
                sr = shape_ratio(0, (plan.length - s) / span)
                theta = down.value + down.deviation * (1.0 - 2.0 * sr)
            out.append((s, math.radians(phi), math.radians(theta)))
        return out

    def _plan_leaves(self, rng):
        plan, tree = self.plan, self.plan.tree
        empty = (np.zeros(0), np.zeros((0, 3, 3)), np.zeros(0))
        if plan.level != tree.levels - 1 or plan.n_leaves <= 0:
            return empty
        pm = tree.params
        lv = plan.level + 1
        scale = pm.float("LeafScale", default=0.2)
        fan = tree.leaf_arrangement == "fan"
        if fan:
            if self.k1 < plan.curve_res:
                return empty  # the fan sits at the tip of the stem
            n = int(round(plan.n_leaves))
            spread = math.radians(pm.float("FanAngle", default=150.0).value)
            tip = self.frames[-1]
            out_f = []
            for i in range(n):
                a = (i / max(n - 1, 1) - 0.5) * spread + rng.uniform(-0.04, 0.04)
                f = tip @ _rz(a) @ _rx(math.radians(rng.uniform(-8, 8)))
                out_f.append(f)
            arcs = np.full(n, self.arc1 - 1e-6)
            sizes = np.array([scale.sample(rng) for _ in range(n)])
            return arcs, np.array(out_f).reshape(-1, 3, 3), sizes
        frac = (self.arc1 - self.arc0) / plan.length
        want = plan.n_leaves * frac * self.share
        n = int(math.floor(want + rng.uniform()))
        if n <= 0:
            return empty
        rot = pm.float("Rotate", level=lv, default=137.5)
        down = pm.float("DownAngle", level=lv, default=45.0)
        arcs = self.arc0 + (np.arange(n) + rng.uniform(0.2, 0.8, n)) / n * (self.arc1 - self.arc0)
        if rot.value >= 0:
            steps = rot.value + rng.uniform(-1, 1, n) * abs(rot.deviation)
        else:
            steps = np.full(n, 180.0)
        phi = np.radians(rng.uniform(0, 360) + np.cumsum(steps))
        theta = np.radians(np.abs(down.value + rng.uniform(-1, 1, n) * abs(down.deviation)))
        twist = np.radians(rng.uniform(-30, 30, n))  # a petiole twist
        _, _, f = self._where_many(arcs)
        frames = f @ _ry_many(phi) @ _rx_many(theta) @ _ry_many(twist)
        sizes = scale.value + rng.uniform(-1, 1, n) * abs(scale.deviation)
        return arcs, frames, sizes

    # -- events --------------------------------------------------------------------------------
    def schedule_own(self, sim) -> None:
        """Schedule this run's buds and its split (called when it joins a simulation)."""
        plan = self.plan
        for i, (s, _phi, _theta) in enumerate(self.buds):
            sim.schedule(self, max(plan.time_at_length(s) + plan.bud_delay, sim.time), "bud", i)
        if self.n_split > 0 or self.k1 < plan.curve_res:
            sim.schedule(self, max(plan.time_at_length(self.arc1), sim.time), "split")

    def on_event(self, event, sim) -> None:
        if event.kind == "bud":
            self._spawn_child(event.data, event.time, sim)
        elif event.kind == "split":
            self._spawn_continuations(event.time, sim)

    def _spawn_child(self, i: int, t: float, sim) -> None:
        plan, tree = self.plan, self.plan.tree
        pm = tree.params
        s, phi, theta = self.buds[i]
        _, p, f = self._where(s)
        child_frame = f @ _ry(phi) @ _rx(theta)
        slot = self.add_slot(self._matrix(p, child_frame))
        slot.space(tree.seed).set_float("ParentLength", plan.length)
        slot.space(tree.seed).set_float("Offset", s)
        r_here = plan.radius * float(plan.profile(np.array([s]), plan.length)[0])
        slot.space(tree.seed).set_float("ParentRadius", r_here)
        slot.space(tree.seed).set_int("Ordinal", i)
        lv = plan.level + 1
        key = (*self.key, 1, i)
        rng = np.random.default_rng([tree.seed & 0xFFFFFFFF, *key, 7])
        lmax = pm.float("Length", level=lv, default=0.5).sample(rng)
        if plan.level == 0:
            span = max(plan.length - plan.base_length, 1e-9)
            length = plan.length * lmax * shape_ratio(tree.shape, (plan.length - s) / span,
                                                       tree.prune)
        else:
            length = lmax * (plan.length - 0.6 * s)
        length = max(length, 0.0)
        if length < 1e-3:
            return
        radius = plan.radius * (length / plan.length) ** tree.ratio_power
        radius = min(radius, 0.95 * r_here)
        branches = pm.float("Branches", level=lv + 1, default=0.0).value
        if lv + 1 >= tree.levels:
            n_children = 0.0
        elif plan.level == 0:
            n_children = branches * (0.2 + 0.8 * (length / plan.length) / max(lmax, 1e-9))
        else:
            n_children = branches * (1.0 - 0.5 * s / plan.length)
        n_leaves = 0.0
        if lv == tree.levels - 1:
            n_leaves = tree.leaves * shape_ratio(4, s / plan.length) * tree.leaf_density
            if tree.leaf_arrangement == "fan":
                n_leaves = tree.leaves * tree.leaf_density
        child_plan = StemPlan(tree, lv, length, radius, t, rng, offset=s,
                              parent_length=plan.length, n_children=n_children,
                              n_leaves=n_leaves)
        child = Branch(child_plan, 0, np.eye(3), key,
                       parent_world=self.world_matrix() @ slot.matrix)
        self.attach(child, slot)
        child.schedule_own(sim)

    def _spawn_continuations(self, t: float, sim) -> None:
        plan, tree = self.plan, self.plan.tree
        pm = tree.params
        if self.k1 >= plan.curve_res:
            return
        n = self.n_split
        angle = pm.float("SplitAngle", level=plan.level, default=20.0)
        base_phi = self.rng.uniform(0, 2 * math.pi)
        world = self.world_matrix() @ self.primary.matrix
        for c in range(n + 1):
            if n == 0:
                frame = np.eye(3)
            else:
                a = math.radians(abs(angle.sample(self.rng))) * (0.5 if c == 0 else 1.0)
                phi = base_phi + 2 * math.pi * c / (n + 1)
                frame = _ry(phi) @ _rx(a) @ _ry(-phi)
            cont = Branch(plan, self.k1, frame, (*self.key, 2, c), clone=c,
                          split_error=self.split_error, birth=t, parent_world=world,
                          share=self.share / (n + 1))
            self.attach(cont, self.primary)
            cont.schedule_own(sim)

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
        arcs = self.arc0 + np.arange(m + 1) * seg
        full = int(min(m, math.floor(vis / seg + 1e-9)))
        idx = list(range(full + 1))
        P = [self.points[i] for i in idx]
        F = [self.frames[i] for i in idx]
        A = [arcs[i] for i in idx]
        if vis - full * seg > 1e-6 * seg and full < m:
            i = full
            P.append(self.points[i] + self.frames[i + 1][:, 1] * (vis - i * seg))
            F.append(self.frames[i + 1])
            A.append(self.arc0 + vis)
            idx.append(i + 1)
        A = np.array(A)
        r = plan.radius * self.current_thickness * plan.profile(A, max(self.current_length,
                                                                      1e-9))
        return np.array(P), np.array(F), r, A, np.array(idx)

    # -- geometry ----------------------------------------------------------------------------
    def generate(self, turtle) -> None:
        plan, tree = self.plan, self.plan.tree
        if self.visible_length() <= 0.0:
            self._joints = None
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
                parent_joint = int(parent._joints[min(i, len(parent._joints) - 1)])
        if not continues:
            material = tree.bark_material
            turtle.new_stem(sides=plan.sides, material=material, lobes=plan.lobes,
                            lobe_depth=plan.lobe_depth, level=plan.level)
        turtle.context.material = tree.bark_material
        self._skip_first = continues and parent_joint >= 0
        self._joints = turtle.stem_points(P, F, R, parent_joint=parent_joint,
                                          skip_first=self._skip_first)
        # leaves out by now
        if len(self.leaf_arc):
            t = self._t
            out = self.leaf_birth <= t
            if np.any(out):
                age = (t - self.leaf_birth[out]) / max(tree.leaf_unfold, 1e-6)
                size = self.leaf_size[out] * np.clip(age, 0.0, 1.0) ** 0.7
                i, pos, _ = self._where_many(self.leaf_arc[out])
                jn = self._joints[np.minimum(i, len(self._joints) - 1)]
                turtle.leaves(pos, self.leaf_frame[out], size, tree.leaf_width,
                              tree.leaf_material, jn)


def make_trunk(tree, rng: np.random.Generator) -> Branch:
    """The level-0 stem of ``tree`` (its length and radius drawn from the fixed values)."""
    pm = tree.params
    scale = pm.float("Scale", default=10.0).fixed
    length0 = pm.float("Length", level=0, default=1.0).fixed * scale
    radius0 = length0 * pm.float("Ratio", default=0.02).value * pm.float(
        "Scale0", default=1.0).fixed
    n_children = pm.float("Branches", level=1, default=0.0).value if tree.levels > 1 else 0.0
    n_leaves = tree.leaves * tree.leaf_density if tree.levels == 1 else 0.0
    plan = StemPlan(tree, 0, length0, radius0, 0.0, rng, n_children=n_children,
                    n_leaves=n_leaves)
    frame = _ry(rng.uniform(0, 2 * math.pi))
    return Branch(plan, 0, frame, (0,))

