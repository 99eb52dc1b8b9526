"""Event order, time jumps, lazy updates, and the same tree at T asked directly or stepped."""

import numpy as np
import pytest

from sylva.tree import Tree
from sylva.tree.components import Component
from sylva.tree.events import Simulation, TimeFunction, smoothstep, smoothstep_inverse


class _Log(Component):
    def __init__(self, log, name):
        super().__init__(name=name)
        self.log = log
        self.updates = []

    def on_event(self, event, sim):
        self.log.append((event.time, self.name, event.kind, sim.time))
        if event.kind == "spawn":
            child = _Log(self.log, self.name + "+")
            child.birth_time = event.time
            self.attach(child, self.add_slot())
            sim.schedule(child, event.time + 0.5, "hello")

    def update_attributes(self, t):
        self.updates.append(("a", t))

    def update_slots(self, t):
        self.updates.append(("s", t))


def test_events_are_delivered_in_time_order_ties_in_scheduling_order():
    log = []
    root = _Log(log, "r")
    sim = Simulation(root)
    other = _Log(log, "o")
    root.attach(other, root.add_slot())
    sim.schedule(root, 2.0, "late")
    sim.schedule(other, 1.0, "first")
    sim.schedule(root, 1.0, "second")  # same instant, scheduled later
    sim.schedule(root, 1.5, "spawn")
    sim.advance_to(10.0)
    assert [(t, n, k) for t, n, k, _ in log] == [
        (1.0, "o", "first"), (1.0, "r", "second"), (1.5, "r", "spawn"),
        (2.0, "r", "late"), (2.0, "r+", "hello"),
    ]
    # the clock jumped to each event's time when delivering it
    assert [now for *_, now in log] == [1.0, 1.0, 1.5, 2.0, 2.0]
    assert sim.time == 10.0


def test_step_jumps_to_the_nearest_event_and_stops_at_the_target():
    log = []
    root = _Log(log, "r")
    sim = Simulation(root)
    for t in (3.0, 0.25, 7.0):
        sim.schedule(root, t, "tick")
    assert sim.next_event_time() == 0.25
    assert sim.step() == 0.25 and sim.time == 0.25
    assert sim.step() == 3.0
    sim.advance_to(5.0)
    assert [e.time for e in sim.delivered] == [0.25, 3.0] and sim.time == 5.0
    assert [e.time for e in sim.pending] == [7.0]
    with pytest.raises(ValueError, match="before now"):
        sim.schedule(root, 4.0)
    assert sim.step() == 7.0 and sim.step() is None


def test_updates_are_lazy_and_separable():
    log = []
    root = _Log(log, "r")
    sim = Simulation(root)
    sim.schedule(root, 1.0, "x")
    sim.advance_to(2.0, update=False)
    assert root.updates == []
    sim.update(2.0, slots=False)
    assert root.updates == [("a", 2.0)]
    sim.update(3.0, attributes=False)
    assert root.updates[-1] == ("s", 3.0)


def test_local_time_is_the_age():
    c = Component(birth_time=4.0)
    assert c.local_time(10.0) == 6.0


def test_time_functions_and_inverses():
    x = np.linspace(0, 1, 11)
    assert np.allclose(smoothstep_inverse(smoothstep(x)), x)
    for kind in ("cubic", "linear", "sqrt"):
        f = TimeFunction(kind)
        assert f(0.0) == 0.0 and f(1.0) == 1.0 and f(2.0) == 1.0
        assert np.allclose(f.inverse(f(x)), x)
    curve = TimeFunction(points=[(0, 0), (0.5, 0.8), (1, 1)])
    assert curve(0.25) == pytest.approx(0.4) and curve.inverse(0.8) == pytest.approx(0.5)
    with pytest.raises(ValueError):
        TimeFunction(points=[(0, 0), (0, 1)])
    with pytest.raises(ValueError):
        TimeFunction("exponential")


def _snapshot(tree):
    geo = tree.geometry()
    return (tree.stats(), geo.joint_matrix.copy(), geo.leaf_pos.copy(), geo.leaf_size.copy(),
            [e.time for e in tree.simulation.delivered])


@pytest.mark.parametrize("species", ["hazel_shrub", "fan_palm"])
def test_state_at_t_equals_stepping_to_t(species):
    direct = _snapshot(Tree(species, seed=5).grow(3.3))
    stepped_tree = Tree(species, seed=5)
    for t in (0.1, 0.7, 1.25, 2.0, 2.9, 3.3):
        stepped_tree.grow(t)
    stepped = _snapshot(stepped_tree)
    assert direct[0] == stepped[0]
    assert direct[4] == stepped[4]
    for a, b in zip(direct[1:4], stepped[1:4], strict=True):
        assert a.shape == b.shape and np.array_equal(a, b)
    # going back in time regrows from the start and agrees too
    back = Tree(species, seed=5).grow(6.0).grow(3.3)
    assert _snapshot(back)[0] == direct[0]


def test_growth_is_monotone_and_buds_become_branches_through_events():
    tree = Tree("hazel_shrub", seed=2)
    heights, stems, leaves = [], [], []
    for t in (0.3, 1.0, 2.0, 4.0, 8.0):
        s = tree.grow(t).stats()
        heights.append(s["height"])
        stems.append(sum(s["stems"]))
        leaves.append(s["leaves"])
    assert all(b >= a - 1e-9 for a, b in zip(heights, heights[1:], strict=False))
    assert stems[0] < stems[-1] and leaves[0] < leaves[-1]
    kinds = {e.kind for e in tree.simulation.delivered}
    assert kinds <= {"bud", "split"} and "bud" in kinds
    # every branch beyond the trunk was born at the time of the event that made it
    births = sorted(b.birth_time for b in tree.branches() if b.level > 0)
    event_times = sorted(e.time for e in tree.simulation.delivered)
    assert set(np.round(births, 9)) <= set(np.round(event_times, 9))


def test_thickening_and_elongation_in_time():
    tree = Tree("quaking_aspen", seed=1)
    tree.grow(2.0)
    trunk = tree.root
    l2, r2 = trunk.current_length, trunk.current_thickness
    tree.grow(10.0)
    assert trunk.current_length > l2 and trunk.current_thickness > r2
    assert trunk.current_length <= trunk.plan.length + 1e-9


def test_children_read_parent_data_from_their_slot_spaces():
    tree = Tree("hazel_shrub", seed=2).grow(3.0)
    twigs = [b for b in tree.branches() if b.level == 2]
    assert twigs
    for b in twigs[:20]:
        parent_len = tree.params.resolve("ParentLength", b)
        offset = tree.params.resolve("Offset", b)
        assert parent_len.value == pytest.approx(b.parent.plan.length)
        assert 0.0 <= offset.value <= parent_len.value
        assert b.plan.offset == pytest.approx(offset.value)
        # a continuation of a split stem finds the data on the nearest slot toward the root
    clones = [b for b in tree.branches() if b.level == 1 and b.k0 > 0]
    for b in clones[:5]:
        assert tree.params.resolve("ParentLength", b) is not None
