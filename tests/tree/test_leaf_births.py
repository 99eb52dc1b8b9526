"""A crown's leaf births worked out for the whole tree at once (sylva.tree.leaves) are each
run's own ``time_at_length(arc) + LeafDelay``, bit for bit, for every growth curve."""

import numpy as np
import pytest

from sylva.tree import Tree
from sylva.tree._schema import check_species
from sylva.tree.leaves import _births, _pending
from sylva.tree.parameters import ParameterManager
from sylva.tree.species import species_text


def _aspen(curve: str) -> Tree:
    text, _ = species_text("quaking_aspen")
    text = text.replace("[level 0]", f"GrowthCurve = \"{curve}\"\n[level 0]", 1)
    check_species(text, "aspen.txt")
    return Tree(ParameterManager.from_text(text, seed=4), quality=0.3)


@pytest.mark.parametrize("curve", ["cubic", "linear", "sqrt"])
def test_batched_births_are_each_runs_own(curve):
    tree = _aspen(curve).grow(9.0)
    leaves = tree.leaf_components()
    waiting = _pending(tree, "_leaf_births")
    # those with juvenile leaves (young shoots) have theirs already, the crown's wait
    assert len(waiting) > 20 and all(x.juvenile == 0 for x in waiting)
    first = waiting[len(waiting) // 2]
    born = first.birth  # one asked for: all of them worked out
    assert not waiting and all(x._birth is not None for x in leaves)
    assert born is first.birth
    for x in leaves:
        n = len(x.arc) - x.juvenile  # the crown's rows (the juvenile ones come last)
        want = _births(x.branch.plan, x.arc[:n])
        assert x.birth.dtype == want.dtype and x.birth[:n].shape == want.shape
        assert np.array_equal(x.birth[:n].view(np.int64), want.view(np.int64))


def test_a_copy_works_out_its_own():
    import copy

    tree = _aspen("cubic").grow(6.0)
    twin = copy.deepcopy(tree)
    a, b = tree.leaf_components(), twin.leaf_components()
    assert len(a) == len(b) > 0
    for x, y in zip(a, b):
        assert np.array_equal(x.birth, y.birth)
        assert y.birth is not x.birth
