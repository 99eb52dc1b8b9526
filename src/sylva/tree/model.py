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

import os

import numpy as np

from .components import TraversalStats, traverse
from .events import Simulation, TimeFunction
from .geometry_turtle import TreeGeometry, TreeTurtle
from .materials import MaterialDatabase
from .parameters import ParameterManager
from .species import load_species
from .weber_penn import Branch, make_trunk

__all__ = ["Tree"]


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

    Attributes
    ----------
    params : ParameterManager
    simulation : Simulation
    root : Branch
        The trunk's first component.
    """

    def __init__(self, config="quaking_aspen", *, seed: int | None = None,
                 materials: MaterialDatabase | None = None) -> None:
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
        self.leaf_density = g.float("LeafDensity", default=1.0).value
        self.leaf_width = g.float("LeafScaleX", default=1.0).value
        self.leaf_arrangement = g.text("LeafArrangement", default="spiral")
        if self.leaf_arrangement not in ("spiral", "fan"):
            raise ValueError(f"LeafArrangement must be 'spiral' or 'fan', got "
                             f"{self.leaf_arrangement!r}")
        self.leaf_delay = g.float("LeafDelay", default=0.2).value
        self.leaf_unfold = g.float("LeafUnfold", default=0.3).value
        self.bark_material = g.text("BarkMaterial", default="bark")
        self.leaf_material = g.text("LeafMaterial", default="leaf")
        self.default_age = g.float("Age", default=30.0).value
        self.prune = (
            g.float("PruneWidth", default=0.5).value,
            g.float("PruneWidthPeak", default=0.5).value,
            g.float("PrunePowerLow", default=0.5).value,
            g.float("PrunePowerHigh", default=0.5).value,
        )
        self.growth = TimeFunction(g.text("GrowthCurve", default="cubic"))
        self.thickening = TimeFunction(g.text("ThickenCurve", default="sqrt"))
        self.reset()

    def reset(self) -> None:
        """Back to time 0: a fresh trunk bud and simulation."""
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
        self.simulation.advance_to(age)
        return self

    def branches(self) -> list[Branch]:
        return [c for c in self.root.walk() if isinstance(c, Branch)]

    def geometry(self, stats: TraversalStats | None = None) -> TreeGeometry:
        """Traverse the graph (seed 002 §5.7) into stems, leaves and joints."""
        turtle = TreeTurtle(self.bark_material)
        traverse(self.root, turtle, stats)
        return turtle.finish()

    def mesh(self, **options):
        """The :class:`~sylva.tree.meshing.TreeMesh` of the tree now (options go to
        :func:`~sylva.tree.meshing.build_tree_mesh`)."""
        from .meshing import build_tree_mesh

        return build_tree_mesh(self.geometry(), self.materials, seed=self.seed, **options)

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
