"""A grown tree's components go straight to the cycle collector's oldest generation
(sylva.tree.model._no_cycle_collection): no young-generation pass scans them after
``grow``, nothing another froze is thawed, and a dropped tree is still freed."""

import gc
import weakref

from sylva.tree import Tree


def _tree() -> Tree:
    return Tree("quaking_aspen", seed=3, quality=0.3)


def test_grown_components_skip_the_young_generation_and_are_freed():
    gc.collect()
    tree = _tree().grow(9.0)
    assert gc.isenabled() and gc.get_freeze_count() == 0
    young = set(map(id, gc.get_objects(generation=0)))
    old = set(map(id, gc.get_objects(generation=2)))
    comps = list(tree.root.walk())
    assert len(comps) > 30
    assert not any(id(c) in young for c in comps) and all(id(c) in old for c in comps)
    root = weakref.ref(tree.root)
    del tree, comps
    gc.collect()
    assert root() is None  # the cycles (parents and children) are collected as before


def test_what_another_froze_stays_frozen():
    gc.collect()
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        tree = _tree().grow(4.0)
        # still frozen (unfreezing would empty it), and none of the tree was frozen
        assert 0 < gc.get_freeze_count() <= frozen and gc.isenabled()
        assert tree.root.simulation is not None
    finally:
        gc.unfreeze()


def test_a_paused_collector_stays_paused():
    gc.disable()
    try:
        _tree().grow(3.0)
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_a_traversal_leaves_no_cycle_behind():
    """The turtle a traversal drew with is freed as soon as it is dropped, without the
    cycle collector (the traversal's recursive closure held it in a cycle)."""
    from sylva.tree.components import traverse
    from sylva.tree.geometry_turtle import TreeTurtle

    tree = _tree().grow(6.0)
    gc.disable()
    try:
        turtle = TreeTurtle(tree.bark_material)
        stats = traverse(tree.root, turtle)
        assert stats.components > 30
        ref = weakref.ref(turtle)
        del turtle
        assert ref() is None
    finally:
        gc.enable()
