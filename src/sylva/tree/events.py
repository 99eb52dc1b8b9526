"""Event-driven growth in continuous time (seed 002 §4.11).

Events are scheduled for any time and any component.  :meth:`Simulation.advance_to` delivers
every event with ``time <= T`` in time order (ties in scheduling order), all events of one
instant before time jumps to the nearest next event, and then lazily updates attributes and
slots of every component for ``T``.  Between events components interpolate from their own
continuous time functions, so the plant exists at *any* time; asking for ``T`` directly or
stepping through intermediate times gives the same graph because delivery depends only on
the event times and the order in which they were scheduled.

Examples
--------
>>> from sylva.tree.components import Component
>>> class Bud(Component):
...     def on_event(self, event, sim):
...         if event.kind == "grow" and event.time < 3:
...             child = Component()
...             self.attach(child, self.add_slot())
...             sim.schedule(self, event.time + 1.0, "grow")
>>> sim = Simulation(Bud())
>>> _ = sim.schedule(sim.root, 0.5, "grow")
>>> sim.advance_to(10.0); [round(e.time, 1) for e in sim.delivered]
[0.5, 1.5, 2.5, 3.5]
>>> len(list(sim.root.walk()))
4
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .components import Component

__all__ = ["Event", "Simulation", "TimeFunction", "smoothstep", "smoothstep_inverse"]


@dataclass(order=True, frozen=True)
class Event:
    """An action due at ``time`` for ``target`` (ordered by time, then scheduling order)."""

    time: float
    seq: int
    target: Component = field(compare=False)
    kind: str = field(compare=False, default="event")
    data: object = field(compare=False, default=None)


class Simulation:
    """Runs one prototype (``root``) forward in time by delivering events.

    Attributes
    ----------
    root : Component
    time : float
        Global simulation time (the time of the last instant processed, or the last
        :meth:`advance_to` target).
    delivered : list of Event
        Every event delivered so far, in delivery order.
    """

    def __init__(self, root: Component, start_time: float = 0.0) -> None:
        self.root = root
        self.time = float(start_time)
        # (time, seq, event): the heap compares the tuples in C, in the events' own order
        self._queue: list[tuple[float, int, Event]] = []
        self._seq = itertools.count()
        self.delivered: list[Event] = []
        self.components: list[Component] = []
        self.target = self.time  # the furthest time asked for (components may plan by it)
        self.add(root)

    def add(self, component: Component) -> None:
        """Register a component (and its subtree) with the simulation."""
        for c in component.walk():
            if c.simulation is not self:
                c.simulation = self
                self.components.append(c)

    def schedule(self, target: Component, time: float, kind: str = "event", data=None) -> Event:
        """Schedule an event; it may not lie in the past of the simulation clock."""
        time = float(time)
        if time < self.time - 1e-12:
            raise ValueError(f"cannot schedule an event at t={time:g} before now ({self.time:g})")
        ev = Event(time, next(self._seq), target, kind, data)
        heapq.heappush(self._queue, (time, ev.seq, ev))
        return ev

    @property
    def pending(self) -> list[Event]:
        """Scheduled, undelivered events in delivery order."""
        return [ev for _, _, ev in sorted(self._queue)]

    def next_event_time(self) -> float | None:
        return self._queue[0][0] if self._queue else None

    def step(self) -> float | None:
        """Deliver every event of the nearest instant and jump the clock to it.

        Returns the new time, or ``None`` when nothing is scheduled.
        """
        if not self._queue:
            return None
        queue = self._queue
        instant = queue[0][0]
        self.time = instant
        while queue and queue[0][0] <= instant:
            ev = heapq.heappop(queue)[2]
            self.delivered.append(ev)
            if ev.target.simulation is self:
                ev.target.on_event(ev, self)
        return instant

    def advance_to(self, t: float, *, update: bool = True) -> None:
        """Deliver all events up to ``t`` (inclusive), then update every component for ``t``."""
        t = float(t)
        self.target = max(self.target, t)
        while self._queue and self._queue[0][0] <= t:
            self.step()
        self.time = max(self.time, t)
        if update:
            self.update(t)

    def update(self, t: float | None = None, *, attributes: bool = True, slots: bool = True):
        """Lazy update of attributes and/or slot transforms of every live component."""
        t = self.time if t is None else float(t)
        live = [c for c in self.root.walk()]
        if attributes:
            for c in live:
                c.update_attributes(t)
        if slots:
            for c in live:
                c.update_slots(t)


def _clip01(x):
    if not isinstance(x, np.ndarray) or x.ndim == 0:  # scalars: far cheaper than np.clip
        return min(max(float(x), 0.0), 1.0)
    # np.clip(x, 0, 1) bit for bit (NaN and -0 as np.clip gives them), without its
    # Python-level dispatch (tests/tree/test_clip_speed.py)
    return np.minimum(np.maximum(0.0, x), 1.0)


def smoothstep(x):
    """The cubic ``3x² − 2x³`` on ``[0, 1]`` (clamped): the default growth curve."""
    x = _clip01(x)
    return x * x * (3.0 - 2.0 * x)


def smoothstep_inverse(y):
    """The ``x`` in ``[0, 1]`` with ``smoothstep(x) == y`` (closed form)."""
    y = _clip01(y)
    return 0.5 - np.sin(np.arcsin(1.0 - 2.0 * y) / 3.0)


class TimeFunction:
    """A growth curve ``f(τ)`` on ``[0, 1] → [0, 1]``, increasing, with an inverse.

    ``kind`` is ``"cubic"`` (smoothstep, the thesis's example of elongation), ``"linear"``,
    ``"sqrt"`` (fast then slow) or a user curve given as ``points`` (τ_i, f_i), interpolated
    piecewise linearly (the "user-supplied graphs" of §2.3.1).

    Examples
    --------
    >>> f = TimeFunction("cubic")
    >>> float(f(0.5)), round(float(f.inverse(f(0.3))), 6)
    (0.5, 0.3)
    """

    def __init__(self, kind: str = "cubic", points=None) -> None:
        self.kind = kind
        if points is not None:
            p = np.asarray(points, np.float64).reshape(-1, 2)
            if np.any(np.diff(p[:, 0]) <= 0) or np.any(np.diff(p[:, 1]) < 0):
                raise ValueError("a time curve needs increasing times and non-decreasing values")
            self.kind, self._p = "curve", p
        elif kind not in ("cubic", "linear", "sqrt"):
            raise ValueError(f"unknown time function {kind!r}: expected cubic, linear or sqrt")
        self._f: Callable = {
            "cubic": smoothstep,
            "linear": _clip01,
            "sqrt": lambda x: np.sqrt(_clip01(x)),
            "curve": lambda x: np.interp(x, self._p[:, 0], self._p[:, 1]),
        }[self.kind]

    def __call__(self, tau):
        return self._f(tau)

    def inverse(self, y):
        if self.kind == "cubic":
            return smoothstep_inverse(y)
        if self.kind == "linear":
            return _clip01(y)
        if self.kind == "sqrt":
            return _clip01(y) ** 2
        return np.interp(y, self._p[:, 1], self._p[:, 0])
