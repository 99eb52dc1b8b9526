"""Slots, levels, prototypes and the §5.7 traversal."""

import numpy as np
import pytest

from sylva.tree.components import Component, Context, rotation, translation, traverse


def _chain():
    root = Component(name="root")
    a, b, c = Component(name="a"), Component(name="b"), Component(name="c")
    root.attach(a, root.primary)
    side = root.add_slot(translation([1, 0, 0]))
    root.attach(b, side)
    root.attach(c, side)
    return root, a, b, c, side


def test_reserved_slots_and_level_rule():
    root, a, b, c, side = _chain()
    assert root.primary.index == 0 and root.base.index == 1 and side.index == 2
    assert np.array_equal(root.base.matrix, np.eye(4))
    assert a.level == 0  # primary slot keeps the level
    assert b.level == 1 and c.level == 1  # other slots: level + 1
    d = Component()
    b.attach(d, b.base)
    assert d.level == 2  # the base slot is "another" slot too
    e = Component()
    d.attach(e, d.primary)
    assert e.level == 2


def test_level_propagates_through_a_subtree_and_can_be_overridden():
    sub = Component()
    leaf = Component()
    sub.attach(leaf, sub.add_slot())
    assert leaf.level == 1
    root = Component()
    root.attach(sub, root.add_slot())
    assert (sub.level, leaf.level) == (1, 2)
    other = Component()
    root.attach(other, root.add_slot(), level=7)
    assert other.level == 7


def test_slot_shares_one_transform_and_keeps_its_inverse():
    root, a, b, c, side = _chain()
    m = translation([0, 2, 0]) @ rotation([0, 0, 1], 0.3)
    side.set_transform(m)
    assert np.allclose(side.matrix @ side.inverse, np.eye(4))
    assert np.allclose(b.world_matrix(), m) and np.allclose(c.world_matrix(), m)
    scaled = np.diag([2.0, 1.0, 1.0, 1.0])  # not rigid: falls back to a general inverse
    side.set_transform(scaled)
    assert np.allclose(side.inverse, np.linalg.inv(scaled))
    with pytest.raises(ValueError):
        root.base.set_transform(m)


def test_attach_rejects_cycles_second_parents_and_foreign_slots():
    root, a, b, c, side = _chain()
    with pytest.raises(ValueError, match="cycle"):
        b.attach(root.detach() if False else root, b.primary)
    lone = Component()
    with pytest.raises(ValueError, match="cycle"):  # onto its own slot
        lone.attach(lone, lone.add_slot())
    with pytest.raises(ValueError, match="already has a parent"):
        c.attach(a, c.primary)
    with pytest.raises(ValueError, match="another component"):
        a.attach(Component(), root.primary)


def test_prototype_duplicate_is_a_deep_detached_copy():
    root, a, b, c, side = _chain()
    twin = b.duplicate()
    assert twin.parent is None and twin is not b
    assert {x.id for x in twin.walk()}.isdisjoint({x.id for x in root.walk()})
    holder = Component()
    holder.attach(twin, holder.add_slot())
    assert twin.level == 1 and b.parent is root  # the original stays attached and reusable
    copy_all = root.duplicate()
    assert [x.name for x in copy_all.walk()] == [x.name for x in root.walk()]
    copy_all.slots[2].set_transform(translation([5, 0, 0]))
    assert np.allclose(side.matrix, translation([1, 0, 0]))


def test_detach_and_reattach():
    root, a, b, c, side = _chain()
    b.detach()
    assert b.parent is None and b not in side.children
    a.attach(b, a.primary)
    assert b.level == 0


class _Recorder:
    def __init__(self):
        self.matrix = np.eye(4)
        self.context = Context("m0")
        self.seen = []

    def begin(self, c):
        self.seen.append((c.name, self.matrix.copy(), self.context.material))


class _Paint(Component):
    def generate(self, turtle):
        turtle.context.material = self.name  # children inherit, siblings must not


def test_traversal_order_transforms_and_context_restores():
    root = _Paint(name="root")
    s1 = root.add_slot(translation([1, 0, 0]))
    s2 = root.add_slot(translation([0, 1, 0]))
    kids = [_Paint(name=n) for n in "abc"]
    root.attach(kids[0], s1)
    root.attach(kids[1], s1)
    root.attach(kids[2], s2)
    g = _Paint(name="g")
    kids[0].attach(g, kids[0].add_slot(translation([0, 0, 1])))
    rec = _Recorder()
    stats = traverse(root, rec)
    names = [n for n, _, _ in rec.seen]
    assert names == ["root", "a", "g", "b", "c"]
    mats = {n: m for n, m, _ in rec.seen}
    assert np.allclose(mats["g"][:3, 3], [1, 0, 1])
    assert np.allclose(mats["b"][:3, 3], [1, 0, 0])
    assert np.allclose(mats["c"][:3, 3], [0, 1, 0])  # the pre-slot transform came back
    mat = {n: m for n, _, m in rec.seen}
    # every child sees its parent's context, not a sibling's
    assert mat["a"] == "root" and mat["b"] == "root" and mat["c"] == "root" and mat["g"] == "a"
    # counted saves: one save for slot s1 (two children), none for the last slot's last child
    # and none inside "a" (its only child is the last of its last slot)
    assert stats.context_saves == 1 and stats.context_restores == 2
    assert stats.components == 5


def test_traversal_of_a_long_chain_saves_nothing():
    root = Component()
    c = root
    for _ in range(50):
        n = Component()
        c.attach(n, c.primary)
        c = n
    stats = traverse(root, _Recorder())
    assert stats.components == 51 and stats.context_saves == 0 and stats.transform_pushes == 0
