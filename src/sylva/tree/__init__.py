"""Trees as graphs of components that grow by events in time (seed 002: the Rose system).

The pieces, each in its own module:

* :mod:`~sylva.tree.components` — :class:`Component`, :class:`Slot` (one transform and its
  inverse shared by all children; primary and base slots; the level rule), prototypes
  (:meth:`Component.duplicate`), and :func:`traverse` (§5.7 with a context stack and a
  transform stack);
* :mod:`~sylva.tree.parameters` — :class:`ParameterSpace` (global, per level, per slot),
  :class:`IntParameter`, :class:`FloatParameter` (deviation and a fixed random value drawn
  once at registration), :class:`TextParameter`, and :class:`ParameterManager`, which reads
  the block configuration format;
* :mod:`~sylva.tree.events` — :class:`Simulation` (events at any time for any component,
  time jumping from event to event, lazy attribute and slot updates) and
  :class:`TimeFunction`;
* :mod:`~sylva.tree.stem` — :class:`Stem` (points → rings with texture coordinates);
* :mod:`~sylva.tree.materials` — :class:`MaterialDatabase` (name-keyed, text file);
* :mod:`~sylva.tree.weber_penn` and :mod:`~sylva.tree.model` — the Weber–Penn tree grown in
  time, :class:`Tree`; :mod:`~sylva.tree.leaves` — :class:`Leaves`, the leaves of a stem
  as a component on its base slot (size, density, colour and fall by level, age and
  season); :mod:`~sylva.tree.species` — the shipped species;
* :mod:`~sylva.tree.wind` and :mod:`~sylva.tree.animation` — wind, leaf flutter and glTF
  skeletal animation of wind and growth.

Examples
--------
>>> tree = Tree("weeping_willow", seed=2).grow(6.0)
>>> tree.stats()["stems"][0] >= 1
True
"""

from .animation import growth_animation, growth_meshes, wind_animation, wind_meshes
from .components import Component, Context, Slot, TraversalStats, traverse
from .events import Event, Simulation, TimeFunction
from .geometry_turtle import TreeGeometry, TreeTurtle
from .leaves import LeafParameterError, Leaves
from .materials import MaterialDatabase, MaterialError, MaterialSpec
from .meshing import TreeMesh, build_tree_mesh
from .model import Tree
from .parameters import (
    FloatParameter,
    IntParameter,
    ParameterError,
    ParameterManager,
    ParameterSpace,
    TextParameter,
)
from .species import SpeciesError, load_species, species_info, species_names
from .stem import Stem, stems_to_arrays
from .weber_penn import Branch, StemPlan, shape_ratio
from .wind import Wind

__all__ = [
    "Branch",
    "Component",
    "Context",
    "Event",
    "FloatParameter",
    "IntParameter",
    "LeafParameterError",
    "Leaves",
    "MaterialDatabase",
    "MaterialError",
    "MaterialSpec",
    "ParameterError",
    "ParameterManager",
    "ParameterSpace",
    "Simulation",
    "Slot",
    "SpeciesError",
    "Stem",
    "StemPlan",
    "TextParameter",
    "TimeFunction",
    "TraversalStats",
    "Tree",
    "TreeGeometry",
    "TreeMesh",
    "TreeTurtle",
    "Wind",
    "build_tree_mesh",
    "growth_animation",
    "growth_meshes",
    "load_species",
    "shape_ratio",
    "species_info",
    "species_names",
    "stems_to_arrays",
    "traverse",
    "wind_animation",
    "wind_meshes",
]
