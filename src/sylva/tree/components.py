"""Components joined by slots into a tree-shaped graph (seed 002 §4.2–4.9, §5.7).

A :class:`Component` owns slots.  A :class:`Slot` holds **one** 4×4 transform and its
inverse, shared by every child attached to it.  Slot 0 is the *primary* slot (where the
component's own geometry continues), slot 1 the *base* slot (identity).  A child attached to
the primary slot keeps its parent's level; a child on any other slot gets level + 1.

Coordinates follow sylva (right-handed, +Y up); every component grows along its local +Y
and emits geometry in its local frame, whose origin is where it attaches to its parent.
Matrices act on column vectors: ``p_parent = slot.matrix @ p_child``.

:func:`traverse` walks the final graph exactly as §5.7 prescribes: a context stack with
*counted saves* (one save per slot, however many children it holds) and no save for the last
child of the last slot, and a transform stack apart from the contexts.

Examples
--------
>>> root = Component()
>>> a, b = Component(), Component()
>>> _ = root.attach(a, root.primary); _ = root.attach(b, root.add_slot())
>>> a.level, b.level
(0, 1)
>>> copy = root.duplicate()
>>> len(list(copy.walk())), copy.parent is None
(3, True)
"""

from __future__ import annotations

import copy as _copy
import itertools
from collections.abc import Iterator

import numpy as np

from .parameters import ParameterSpace

__all__ = [
    "Component",
    "Context",
    "Slot",
    "TraversalStats",
    "traverse",
    "rigid_frame_inverse",
    "rotation",
    "translation",
]

_ids = itertools.count(1)


def translation(v) -> np.ndarray:
    """``float64[4, 4]`` translation by ``v`` (3,)."""
    m = np.eye(4)
    m[:3, 3] = v
    return m


def rotation(axis, angle: float) -> np.ndarray:
    """``float64[4, 4]`` rotation by ``angle`` radians about ``axis`` (3,), right-handed."""
    a = np.asarray(axis, np.float64)
    a = a / np.linalg.norm(a)
    x, y, z = a
    c, s = np.cos(angle), np.sin(angle)
    C = 1.0 - c
    m = np.eye(4)
    m[:3, :3] = [
        [c + x * x * C, x * y * C - z * s, x * z * C + y * s],
        [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
        [z * x * C - y * s, z * y * C + x * s, c + z * z * C],
    ]
    return m


_IDENTITY = np.eye(4)
_IDENTITY.flags.writeable = False


def rigid_frame_inverse(p: np.ndarray, f: np.ndarray) -> np.ndarray:
    """``float64[4, 4]``: the inverse of the rigid transform with rotation ``f``
    (float[3, 3]) and translation ``p`` (float[3]): ``fᵀ`` and ``−fᵀp``."""
    m = _IDENTITY.copy()
    m[:3, :3] = f.T
    m[:3, 3] = -(f.T @ p)
    return m


def _rigid_inverse(m: np.ndarray) -> np.ndarray:
    r = m[:3, :3]
    # a rigid or uniformly scaled transform inverts cheaply; anything else goes to LAPACK
    rtr = r.T @ r
    s2 = rtr[0, 0]
    if s2 > 0 and np.abs(rtr - s2 * np.eye(3)).max() <= 1e-9 * max(1.0, s2) \
            and not m[3, :3].any() and m[3, 3] == 1.0:
        inv = np.eye(4)
        inv[:3, :3] = r.T / s2
        inv[:3, 3] = -inv[:3, :3] @ m[:3, 3]
        return inv
    return np.linalg.inv(m)


class Slot:
    """A place on a component where children plug in: one transform for all of them.

    Attributes
    ----------
    owner : Component
    index : int
        0 primary, 1 base, 2… others.
    matrix, inverse : float64[4, 4]
        Child frame → owner frame, and back.  Only the owner should set them
        (:meth:`set_transform`).
    children : list of Component
    params : ParameterSpace or None
        The per-slot space (parent → child information), created on demand.
    """

    __slots__ = ("owner", "index", "matrix", "_inverse", "children", "params")

    def __init__(self, owner: Component, index: int) -> None:
        self.owner = owner
        self.index = index
        self.matrix = _IDENTITY  # shared and read-only until set_transform replaces it
        self._inverse = _IDENTITY
        self.children: list[Component] = []
        self.params: ParameterSpace | None = None

    @property
    def inverse(self) -> np.ndarray:
        """``float64[4, 4]``: owner frame → child frame (worked out when first asked for:
        a tree sets thousands of slot transforms and reads no inverse while it grows)."""
        inv = self._inverse
        if isinstance(inv, tuple):
            inv = self._inverse = rigid_frame_inverse(*inv)
        elif inv is None:
            inv = self._inverse = _rigid_inverse(self.matrix)
        return inv

    @property
    def is_primary(self) -> bool:
        return self.index == 0

    @property
    def is_base(self) -> bool:
        return self.index == 1

    def set_transform(self, matrix: np.ndarray, inverse: np.ndarray | None = None) -> None:
        """Set the shared transform and its cached inverse (the base slot stays identity);
        ``inverse``, when the caller knows it (a rigid frame: ``Rᵀ``, ``−Rᵀp``), is taken as
        it is; a ``(position, frame)`` pair stands for the inverse of that rigid frame
        (:func:`rigid_frame_inverse`), worked out when first asked for (:attr:`inverse`)."""
        if self.is_base:
            raise ValueError("the base slot keeps the identity transform")
        self.matrix = np.asarray(matrix, np.float64).reshape(4, 4).copy()
        self._inverse = inverse  # None: _rigid_inverse(matrix); a callable: its result

    def space(self, seed: int = 0) -> ParameterSpace:
        """The slot's parameter space (created on first use, keyed by owner id and index)."""
        if self.params is None:
            self.params = ParameterSpace((2, self.owner.id, self.index), seed)
        return self.params


class Component:
    """A plant part that develops in time and may emit geometry.

    Subclasses override :meth:`on_event`, :meth:`update_attributes`, :meth:`update_slots` and
    :meth:`generate`; the base class is a pure connector.

    Parameters
    ----------
    birth_time : float
        Global time of creation; :meth:`local_time` is the age.
    name : str
    """

    def __init__(self, birth_time: float = 0.0, name: str = "") -> None:
        self.id = next(_ids)
        self.name = name or type(self).__name__
        self.birth_time = float(birth_time)
        self.level = 0
        self.parent: Component | None = None
        self.parent_slot: Slot | None = None
        self.slots: list[Slot] = [Slot(self, 0), Slot(self, 1)]
        self.simulation = None  # set by Simulation.add

    # -- slots and joints --------------------------------------------------------------------
    @property
    def primary(self) -> Slot:
        return self.slots[0]

    @property
    def base(self) -> Slot:
        return self.slots[1]

    def add_slot(self, matrix: np.ndarray | None = None,
                 inverse: np.ndarray | None = None) -> Slot:
        s = Slot(self, len(self.slots))
        if matrix is not None:
            s.set_transform(matrix, inverse)
        self.slots.append(s)
        return s

    def attach(self, child: Component, slot: Slot, *, level: int | None = None) -> Component:
        """Create a geometric joint ``self → child`` on ``slot``.

        The child's level becomes this component's level on the primary slot and level + 1
        on any other slot (``level=`` overrides: Rose does not enforce the rule).  Its whole
        subtree is renumbered accordingly, and it joins the simulation this component is in.
        """
        if slot.owner is not self:
            raise ValueError("attach: the slot belongs to another component")
        if child.parent is not None:
            raise ValueError("attach: the child already has a parent (detach it or duplicate it)")
        # a parentless child is on the path to the root only as its end (the root): only a
        # child with a subtree of its own, or this component itself, can close a cycle
        if child is self or (any(s.children for s in child.slots) and child is self.root()):
            raise ValueError("attach: that joint would make a cycle")
        child.parent, child.parent_slot = self, slot
        slot.children.append(child)
        new_level = level if level is not None else self.level + (0 if slot.is_primary else 1)
        child._relevel(new_level)
        if self.simulation is not None:
            self.simulation.add(child)
        return child

    def detach(self) -> Component:
        """Remove the joint to the parent; the component becomes the root of a prototype."""
        if self.parent_slot is not None:
            self.parent_slot.children.remove(self)
        self.parent = self.parent_slot = None
        return self

    def _relevel(self, level: int) -> None:
        delta = level - self.level
        if delta:
            for c in self.walk():
                c.level += delta

    def duplicate(self) -> Component:
        """A deep copy of this component and its subtree (a prototype instance), detached,
        with fresh ids and outside any simulation."""
        memo = {id(self.simulation): None} if self.simulation is not None else {}
        if self.parent is not None:
            memo[id(self.parent)] = None
            memo[id(self.parent_slot)] = None
        twin = _copy.deepcopy(self, memo)
        twin.parent = twin.parent_slot = None
        for c in twin.walk():
            c.id = next(_ids)
            c.simulation = None
        return twin

    def __deepcopy__(self, memo):
        cls = type(self)
        new = cls.__new__(cls)
        memo[id(self)] = new
        for k, v in self.__dict__.items():
            setattr(new, k, _copy.deepcopy(v, memo) if k != "simulation" else None)
        return new

    # -- navigation --------------------------------------------------------------------------
    def children(self) -> Iterator[Component]:
        for s in self.slots:
            yield from s.children

    def visit_order(self) -> list[Slot]:
        """The slots in the order :func:`traverse` and :meth:`walk` visit them: the base slot
        first (its children share this component's frame: a stem's leaves, drawn right after
        the stem), then the primary slot, then the others."""
        s = self.slots
        return [s[1], s[0], *s[2:]]

    def walk(self) -> Iterator[Component]:
        """This component and its subtree, depth first, parents before children."""
        stack = [self]
        while stack:
            c = stack.pop()
            yield c
            s = c.slots  # in visit_order(), without building the list
            kids = [*s[1].children, *s[0].children]
            for x in s[2:]:
                kids += x.children
            stack.extend(reversed(kids))

    def path_to_root(self) -> Iterator[Component]:
        c: Component | None = self
        while c is not None:
            yield c
            c = c.parent

    def root(self) -> Component:
        c = self
        while c.parent is not None:
            c = c.parent
        return c

    def world_matrix(self) -> np.ndarray:
        """``float64[4, 4]``: this component's frame → the root's frame (slot transforms)."""
        m = _IDENTITY.copy()  # np.eye(4)'s numbers, without its construction
        c = self
        while c.parent_slot is not None:
            m = c.parent_slot.matrix @ m
            c = c.parent
        return m

    def slot_parameter(self, name: str, kind: str | None = None):
        """The parameter ``name`` from the nearest slot space on the path toward the root."""
        c = self
        while c.parent_slot is not None:
            s = c.parent_slot
            if s.params is not None:
                p = s.params.get(name, kind)
                if p is not None:
                    return p
            c = c.parent
        return None

    # -- time --------------------------------------------------------------------------------
    def local_time(self, t: float) -> float:
        """The component's age at global time ``t``."""
        return float(t) - self.birth_time

    # -- behaviour (override) ----------------------------------------------------------------
    def on_event(self, event, simulation) -> None:
        """React to a delivered event (create components, schedule events, …)."""

    def update_attributes(self, t: float) -> None:
        """Bring the attributes needed for geometry to global time ``t`` (lazy)."""

    def update_slots(self, t: float) -> None:
        """Set the slot transforms for global time ``t``."""

    def generate(self, turtle) -> None:
        """Emit geometry in the local frame through ``turtle``."""

    def __repr__(self) -> str:
        return f"<{self.name} #{self.id} level {self.level}>"


class Context:
    """The traversal state that is *not* the transform: material, current stem, colour.

    Components may read and change it; it is restored when traversal leaves them.
    """

    __slots__ = ("material", "stem", "color", "extra")

    def __init__(self, material: str = "bark", stem=None, color=None, extra=None) -> None:
        self.material = material
        self.stem = stem
        self.color = color
        self.extra = dict(extra) if extra else {}

    def copy(self) -> Context:
        return Context(self.material, self.stem, self.color, self.extra)


class TraversalStats:
    """Counts kept by :func:`traverse` (the optimisations of §5.7 can be checked by them)."""

    def __init__(self) -> None:
        self.components = 0
        self.context_saves = 0
        self.context_restores = 0
        self.transform_pushes = 0
        self.max_context_depth = 0


def traverse(root: Component, turtle, stats: TraversalStats | None = None) -> TraversalStats:
    """Generate the geometry of the graph under ``root`` (seed 002 §5.7).

    For each component: emit its geometry; then for every slot with children (base slot
    first, see :meth:`Component.visit_order`; §5.7 leaves the order open), apply the
    slot transform once (the pre-slot transform is kept on the transform stack), save the
    context **once** for the slot with a count of the children that will restore it, and
    recurse into each child, restoring the context after each.  The last child of the last
    slot neither saves nor restores.

    ``turtle`` needs ``matrix`` (float64[4, 4], read/write), ``context`` (a :class:`Context`),
    and ``begin(component)``; components call its drawing methods from ``generate``.
    """
    stats = stats or TraversalStats()
    ctx_stack: list[list] = []  # entries [context copy, remaining restores]
    xf_stack: list[np.ndarray] = []

    def visit(c: Component) -> None:
        stats.components += 1
        turtle.begin(c)
        c.generate(turtle)
        busy = [s for s in c.visit_order() if s.children]
        for si, slot in enumerate(busy):
            last_slot = si == len(busy) - 1
            if not last_slot:
                xf_stack.append(turtle.matrix)
                stats.transform_pushes += 1
            turtle.matrix = turtle.matrix @ slot.matrix
            at_slot = turtle.matrix
            n = len(slot.children)
            saves = n - 1 if last_slot else n  # the last child of the last slot needs none
            if saves:
                ctx_stack.append([turtle.context.copy(), saves])
                stats.context_saves += 1
                stats.max_context_depth = max(stats.max_context_depth, len(ctx_stack))
            for ci, child in enumerate(slot.children):
                turtle.matrix = at_slot
                visit(child)  # noqa: F821 (its own cell, emptied by the del below)
                if last_slot and ci == n - 1:
                    break
                top = ctx_stack[-1]
                turtle.context = top[0] if top[1] == 1 else top[0].copy()
                top[1] -= 1
                stats.context_restores += 1
                if top[1] == 0:
                    ctx_stack.pop()
            if not last_slot:
                turtle.matrix = xf_stack.pop()

    visit(root)
    # the closure refers to itself (a cycle, holding the turtle and its rows through its
    # cell): emptying the cell frees them now instead of at the collector's next pass
    del visit
    return stats
