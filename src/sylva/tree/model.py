"""The :class:`Tree`: a species configuration, a seed, and its simulation in time.

Examples
--------
>>> t = Tree("quaking_aspen", seed=3).grow(2.0)
>>> s = t.stats()
>>> s["stems"][0], s["height"] > 0
(1, True)
>>> Tree("quaking_aspen", seed=3).grow(2.0).stats() == s
True
"""

from __future__ import annotations

import contextlib
import gc
import os

import numpy as np

from ._streams import decided
from .components import TraversalStats, traverse
from .events import Simulation, TimeFunction
from .geometry_turtle import TreeGeometry, TreeTurtle
from .leaves import LeafParameterError, Leaves
from .materials import MaterialDatabase
from .meshing import leaf_shape_index
from .parameters import ParameterManager
from .species import load_species
from .weber_penn import Branch, envelope, make_trunk

__all__ = ["SEASONS", "Tree"]

SEASONS = ("spring", "summer", "autumn", "winter")
"""The values of ``Season`` (and of ``Tree(season=...)``, ``sylva tree --season``)."""


class Tree:
    """A Weber–Penn tree of one species, grown by events to any age.

    Parameters
    ----------
    config : str, path or ParameterManager
        A species name (see :func:`~sylva.tree.species.species_names`), a configuration file,
        or a loaded manager (its seed is then used unless ``seed`` is given).
    seed : int, optional
        Everything random (fixed random values, per-stem draws) follows from it.
    materials : MaterialDatabase, optional
        Default: :meth:`MaterialDatabase.default`.
    quality : float, optional
        (0, 1]: the stems of the last level (levels >= 3) are thinned to this fraction and
        each carries ``1 / quality`` times the leaves (the foliage stays, the twigs go): a
        quicker tree with the same silhouette, for previews and tests.
    season : {"spring", "summer", "autumn", "winter"}, optional
        Overrides the species' ``Season``: a ``Deciduous`` tree's leaves are at
        ``SpringLeafScale`` (60 %) in spring, in ``AutumnMaterial`` in autumn and gone in
        winter.
    leaf_turn, leaf_fall : float in [0, 1], optional
        Override every level's ``LeafTurn`` and ``LeafFall``: in autumn, the fraction of the
        leaves that have turned to ``AutumnMaterial`` and the fraction that have fallen (the
        first to turn fall first; ``leaf_fall=1`` is the bare tree).  See
        :mod:`sylva.tree.leaves`.

    Attributes
    ----------
    params : ParameterManager
    simulation : Simulation
    root : Branch
        The trunk's first component.
    """

    def __init__(self, config="quaking_aspen", *, seed: int | None = None,
                 materials: MaterialDatabase | None = None, quality: float = 1.0,
                 season: str | None = None, leaf_turn: float | None = None,
                 leaf_fall: float | None = None) -> None:
        if isinstance(config, ParameterManager):
            pm = config
            if seed is not None and seed != pm.seed:
                raise ValueError("give the seed to the ParameterManager, or pass a species name")
        else:
            pm = load_species(os.fspath(config), seed=0 if seed is None else seed)
        self.params = pm
        self.seed = pm.seed
        self.materials = materials if materials is not None else MaterialDatabase.default()
        g = pm
        self.name = g.text("Name", default="tree")
        self.levels = max(1, g.int("Levels", default=3))
        self.shape = g.int("Shape", default=0)
        self.ratio_power = g.float("RatioPower", default=1.2).value
        self.leaves = g.float("Leaves", default=0.0).value
        self.leaf_density = g.float("LeafDensity", default=1.0).value  # [global]'s
        self.leaf_width = g.float("LeafScaleX", default=1.0).value
        self.leaf_arrangement = g.text("LeafArrangement", default="spiral")
        if self.leaf_arrangement not in ("spiral", "fan"):
            raise ValueError(f"LeafArrangement must be 'spiral' or 'fan', got "
                             f"{self.leaf_arrangement!r}")
        self.leaf_delay = g.float("LeafDelay", default=0.2).value
        self.leaf_unfold = g.float("LeafUnfold", default=0.3).value
        self.bark_material = g.text("BarkMaterial", default="bark")
        self.leaf_material = g.text("LeafMaterial", default="leaf")
        # the season: a deciduous tree's leaves are small in spring, turn to AutumnMaterial
        # in autumn and are gone in winter; an evergreen keeps its own all year
        self.season = season if season is not None else g.text("Season", default="summer")
        if self.season not in SEASONS:
            raise ValueError(f"season must be one of {', '.join(SEASONS)}, got {self.season!r}")
        self.deciduous = bool(g.int("Deciduous", default=1))
        self.autumn_material = g.text("AutumnMaterial", default="leaf.autumn")
        # the state of autumn (sylva.tree.leaves): overrides of every level's LeafTurn and
        # LeafFall, or None for the species' own
        for name, value in (("leaf_turn", leaf_turn), ("leaf_fall", leaf_fall)):
            if value is not None and not 0.0 <= float(value) <= 1.0:
                raise LeafParameterError(f"{name} must be in [0, 1], got {value}")
        self.leaf_turn = None if leaf_turn is None else float(leaf_turn)
        self.leaf_fall = None if leaf_fall is None else float(leaf_fall)
        self.default_age = g.float("Age", default=30.0).value
        if not 0.0 < quality <= 1.0:
            raise ValueError(f"quality must be in (0, 1], got {quality}")
        self.quality = float(quality)
        # the young tree: juvenile branches on the trunk's clear base, shed as it grows, and
        # leaves on young shoots below the leaf level (see sylva.tree.weber_penn)
        self.juvenile_branches = g.float("JuvenileBranches", default=1.0).value
        self.shed_time = g.float("ShedTime", default=2.0).value
        self.juvenile_lag = g.float("JuvenileLag", default=0.6).value
        self.juvenile_leaf_life = g.float("JuvenileLeafLife", default=3.0).value
        self.juvenile_leaf_spacing = g.float("JuvenileLeafSpacing", default=0.35).value
        self.juvenile_trunk_leaves = bool(g.int("JuvenileTrunkLeaves", default=1))
        self.prune = (
            g.float("PruneWidth", default=0.5).value,
            g.float("PruneWidthPeak", default=0.5).value,
            g.float("PrunePowerLow", default=0.5).value,
            g.float("PrunePowerHigh", default=0.5).value,
        )
        self.prune_ratio = float(np.clip(g.float("PruneRatio", default=0.0).value, 0.0, 1.0))
        self.scale_tree = g.float("Scale", default=10.0).fixed
        self.base_size = g.float("BaseSize", default=0.0).value
        zscale = g.float("ZScale", default=1.0).fixed  # ZScale ± ZScaleV, drawn per seed
        if not zscale > 0:
            raise ValueError(f"ZScale must be > 0, got {zscale} (seed {self.seed})")
        self.zscale = float(zscale)
        shape = g.resolve("LeafShape")
        self.leaf_shape = leaf_shape_index(0 if shape is None else shape.value)
        self.growth = TimeFunction(g.text("GrowthCurve", default="cubic"))
        self.thickening = TimeFunction(g.text("ThickenCurve", default="sqrt"))
        self.reset()

    def pf(self, name: str, level: int | None = None, default: float | None = None):
        """``params.float(name, level=level, default=default)``, remembered until the next
        :meth:`reset` (the stems ask for the same few thousand times)."""
        key = ("f", name, level, default)
        p = self._pcache.get(key)
        if p is None:
            p = self._pcache[key] = self.params.float(name, level=level, default=default)
        return p

    def pi(self, name: str, level: int | None = None, default: int | None = None) -> int:
        """``params.int`` remembered like :meth:`pf`."""
        key = ("i", name, level, default)
        p = self._pcache.get(key)
        if p is None:
            p = self._pcache[key] = self.params.int(name, level=level, default=default)
        return p

    def level_value(self, name: str, level: int) -> float | None:
        """The number ``name`` set in ``[level N]`` itself (not inherited), or ``None``."""
        key = ("own", name, level)
        if key not in self._pcache:
            p = None
            if level in self.params.levels:
                p = self.params.level(level).get(name)
            self._pcache[key] = None if p is None or p.kind == "text" else float(p.value)
        return self._pcache[key]

    def leaf_density_of(self, level: int) -> float:
        """``LeafDensity`` of the leaves of ``level`` (its ``[level N]``, else ``[global]``)."""
        return self.pf("LeafDensity", level=level, default=1.0).value

    def leaf_width_of(self, level: int) -> float:
        """``LeafScaleX`` of the leaves of ``level``."""
        return self.pf("LeafScaleX", level=level, default=1.0).value

    def leaf_materials(self, level: int) -> tuple[str, str]:
        """``(LeafMaterial, AutumnMaterial)`` of the leaves of ``level`` (on the stems of
        ``level - 1``): each leaf component is of its level, so ``[level N]`` may set them for
        its own leaves, else ``[global]``'s apply."""
        key = ("materials", level)
        m = self._pcache.get(key)
        if m is None:
            g = self.params
            m = self._pcache[key] = (
                g.text("LeafMaterial", level=level, default=self.leaf_material),
                g.text("AutumnMaterial", level=level, default=self.autumn_material))
        return m

    def leaf_style(self, level: int) -> tuple[float, str]:
        """``(LeafScaleX, material)`` of the leaves of ``level`` in this season (autumn: the
        ``AutumnMaterial`` of a tree whose leaves have all turned)."""
        material, autumn = self.leaf_materials(level)
        if self.deciduous and self.season == "autumn" and max(self.leaf_season(level)[1:]) >= 1:
            material = autumn
        return self.leaf_width_of(level), material

    def leaf_season(self, level: int) -> tuple[float, float, float]:
        """``(scale, turn, fall)`` of the leaves of ``level`` now: the size factor of the
        season (``SpringLeafScale`` in spring, 0 in winter, else 1) and, in autumn, the
        fractions turned (``LeafTurn``) and fallen (``LeafFall``); an evergreen's or a
        summer tree's are ``(1, 0, 0)``."""
        key = ("season", level)
        s = self._pcache.get(key)
        if s is None:
            scale, turn, fall = 1.0, 0.0, 0.0
            if self.deciduous:
                if self.season == "spring":
                    scale = self.pf("SpringLeafScale", level=level, default=0.6).value
                elif self.season == "winter":
                    scale = 0.0
                elif self.season == "autumn":
                    turn = self.pf("LeafTurn", level=level, default=1.0).value
                    fall = self.pf("LeafFall", level=level, default=0.0).value
                    if self.leaf_turn is not None:
                        turn = self.leaf_turn
                    if self.leaf_fall is not None:
                        fall = self.leaf_fall
                    if fall >= 1.0:
                        scale = 0.0  # all of them on the ground: the bare tree
            s = self._pcache[key] = (scale, turn, fall)
        return s

    def reset(self) -> None:
        """Back to time 0: a fresh trunk bud and simulation."""
        self._pcache: dict = {}
        self.simulation = None  # the old one's target is not this one's (leaves.py reads it)
        rng = np.random.default_rng([self.seed & 0xFFFFFFFF, 0])
        self.root = make_trunk(self, rng)
        self.simulation = Simulation(self.root)
        self.root.schedule_own(self.simulation)

    @property
    def age(self) -> float:
        return self.simulation.time

    def grow(self, age: float | None = None) -> Tree:
        """Advance to global time ``age`` (default: the species' ``Age``); going back in time
        regrows from the start (events cannot be undone)."""
        age = self.default_age if age is None else float(age)
        if age < 0:
            raise ValueError(f"age must be >= 0, got {age}")
        if age < self.simulation.time - 1e-12:
            self.reset()
        with _no_cycle_collection(kept=True), decided():
            self.simulation.advance_to(age)
        return self

    def branches(self) -> list[Branch]:
        return [c for c in self.root.walk() if isinstance(c, Branch)]

    def leaf_components(self) -> list[Leaves]:
        """The :class:`~sylva.tree.leaves.Leaves` components now in the graph, in traversal
        order (one per stem run that has leaves planned)."""
        return [c for c in self.root.walk() if isinstance(c, Leaves)]

    def inside_envelope(self, points) -> np.ndarray:
        """``bool[n]``: which plant-frame ``points`` (float[n, 3], +Y up, before ``ZScale``)
        lie inside the pruning envelope: ``√(x² + z²) / scale_tree < PruneWidth ·
        ShapeRatio(8, (scale_tree − y) / (scale_tree · (1 − BaseSize)))``."""
        p = np.asarray(points, np.float64).reshape(-1, 3)
        st = max(self.scale_tree, 1e-9)
        ratio = (st - p[:, 1]) / (st * max(1.0 - self.base_size, 1e-9))
        return np.hypot(p[:, 0], p[:, 2]) / st < envelope(ratio, self.prune)

    def geometry(self, stats: TraversalStats | None = None) -> TreeGeometry:
        """Traverse the graph (seed 002 §5.7) into stems, leaves and joints (``ZScale``
        applied)."""
        turtle = (TreeTurtle(self.bark_material) if self.zscale == 1.0
                  else _ZScaledTurtle(self.zscale, self.bark_material))
        with _no_cycle_collection():
            traverse(self.root, turtle, stats)
        return turtle.finish()

    def mesh(self, **options):
        """The :class:`~sylva.tree.meshing.TreeMesh` of the tree now (options go to
        :func:`~sylva.tree.meshing.build_tree_mesh`; the leaf shape is the species'
        ``LeafShape`` unless ``leaf_shape`` is given)."""
        from .meshing import build_tree_mesh

        options.setdefault("leaf_shape", self.leaf_shape)
        # one pause for both: between them the collector would scan every new joint and leaf
        with _no_cycle_collection():
            geo = self.geometry()
            return build_tree_mesh(geo, self.materials, seed=self.seed, **options)

    def scene(self, **options):
        """A :class:`~sylva.geometry.mesh.Scene` with one mesh (bark and leaf materials)."""
        from ..geometry.mesh import Scene

        return Scene([self.mesh(**options).mesh], name=self.name.replace(" ", "_"))

    def stats(self) -> dict:
        """Counts and extent of the tree now.

        Returns
        -------
        dict
            ``height`` (m, top of wood and leaves), ``width`` (m, largest horizontal
            extent), ``stems`` (list: stems with visible wood per level — a split clone
            counts as a stem, as in the paper), ``components`` (per level), ``leaves``
            (leaves out), ``events`` (delivered so far).
        """
        geo = self.geometry()
        comps = [0] * self.levels
        stems = [0] * self.levels
        for b in self.branches():
            comps[b.level] += 1
            if b.visible_length() > 0 and (b.k0 == 0 or b.clone > 0):
                stems[b.level] += 1
        pts = [geo.joint_matrix[:, :3, 3]]
        if geo.n_leaves:
            tips = geo.leaf_pos + geo.leaf_frame[:, :, 1] * geo.leaf_size[:, None]
            pts.append(tips)
        p = np.concatenate(pts)
        lo, hi = p.min(0), p.max(0)
        return {
            "height": float(hi[1]),
            "width": float(max(hi[0] - lo[0], hi[2] - lo[2])),
            "stems": stems,
            "components": comps,
            "leaves": int(np.count_nonzero(geo.leaf_size > 0)),
            "events": len(self.simulation.delivered),
        }


@contextlib.contextmanager
def _no_cycle_collection(kept: bool = False):
    """Python's cycle collector paused while a tree grows or is drawn: the thousands of
    components it makes (and keeps) would otherwise be scanned again and again, a tenth
    of a big tree's time, for cycles that are not garbage.

    ``kept``: what was made inside is kept (a tree's growth: its components, which live as
    long as the tree), so it goes straight to the collector's oldest generation
    (``gc.freeze()`` then ``gc.unfreeze()``, which moves every tracked object there)
    instead of being scanned by the young generation's collection that would come at the
    next allocation (some 60,000 objects, 4% of a willow's time, none of them garbage).
    They are scanned, and freed once the tree is dropped, by the next full collection as
    any long-lived object is.  Only while nothing else is frozen (``gc.get_freeze_count()``
    is 0): unfreezing would thaw another's frozen objects too."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            if kept and not gc.get_freeze_count():
                gc.freeze()
                gc.unfreeze()
            gc.enable()


def _upright(frames: np.ndarray, zscale: float) -> np.ndarray:
    """Frames (columns x, tangent, z) after scaling plant ``y`` by ``zscale``, kept
    orthonormal: the tangent follows the scaled curve, x is re-orthogonalised to it."""
    S = np.array([1.0, zscale, 1.0])
    t = frames[:, :, 1] * S
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-12)
    x = frames[:, :, 0] * S
    x -= np.sum(x * t, axis=1, keepdims=True) * t
    nx = np.linalg.norm(x, axis=1, keepdims=True)
    bad = nx[:, 0] < 1e-9  # x was parallel to the scaled tangent: use the old z instead
    if np.any(bad):
        alt = np.cross(t[bad], frames[bad, :, 2])
        x[bad] = alt
        nx[bad] = np.linalg.norm(alt, axis=1, keepdims=True)
    x /= np.maximum(nx, 1e-12)
    return np.stack([x, t, np.cross(x, t)], axis=2)


class _ZScaledTurtle(TreeTurtle):
    """A :class:`TreeTurtle` that scales plant ``y`` (up) by ``ZScale``: positions move,
    stem rings stay round (radii are kept) and leaf blades keep their size."""

    def __init__(self, zscale: float, default_material: str = "bark") -> None:
        super().__init__(default_material)
        self.zscale = float(zscale)

    def _to_plant(self, positions, frames):
        m = self.matrix
        p = np.asarray(positions, np.float64).reshape(-1, 3)
        f = np.asarray(frames, np.float64).reshape(-1, 3, 3)
        wp = p @ m[:3, :3].T + m[:3, 3]
        wp[:, 1] *= self.zscale
        return wp, _upright(np.einsum("ij,njk->nik", m[:3, :3], f), self.zscale)

    def stem_points(self, positions, frames, radii, *, parent_joint: int = -1,
                    skip_first: bool = False) -> np.ndarray:
        wp, wf = self._to_plant(positions, frames)
        keep, self.matrix = self.matrix, np.eye(4)
        try:
            return super().stem_points(wp, wf, radii, parent_joint=parent_joint,
                                       skip_first=skip_first)
        finally:
            self.matrix = keep

    def leaves(self, positions, frames, sizes, width: float, material, joints) -> int:
        wp, wf = self._to_plant(positions, frames)
        keep, self.matrix = self.matrix, np.eye(4)
        try:
            return super().leaves(wp, wf, sizes, width, material, joints)
        finally:
            self.matrix = keep
